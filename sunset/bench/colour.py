"""The benchmark's colour rows: what colour-science costs a process, paid once, the first time colour is computed.

The sky's spectra, the film's XYZ → sRGB and the 8-bit test's CIEDE2000 come
from colour-science, imported where colour is first computed
(:func:`sunset.model.sky.spectral_data`, not ``import sunset``). Each run here
is a fresh Python that has NumPy and the sky's module loaded already, as a
rendering process has: ``import colour`` alone, and the first
``spectral_data()`` (the import, the datasets and the spectra on the 10 nm
grid), wall-clock and CPU seconds.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

__all__ = ["measure_colour_import", "rows", "STAGES", "WHAT"]

#: The rows' name in the table and the JSON.
WHAT = "colour-science, once per process"

#: The two stages timed, as they appear in the table.
STAGES = ("import colour", "first spectra")

_CODE = """
import json, resource, time
import numpy
import sunset.model.sky as sky
c0, t0 = time.process_time(), time.perf_counter()
import colour
c1, t1 = time.process_time(), time.perf_counter()
sky.spectral_data()
c2, t2 = time.process_time(), time.perf_counter()
print(json.dumps({"wall": [t1 - t0, t2 - t0], "cpu": [c1 - c0, c2 - c0],
                  "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))
"""


def measure_colour_import(repeats: int) -> dict:
    """``repeats`` fresh processes (after one warm-up, which fills the disk cache): seconds per stage.

    Returns ``{stage: {"wall": [...], "cpu": [...], "peak_rss_mib": ...}}`` for each of :data:`STAGES` (the
    peak resident memory of the processes, the same for both).
    """
    out = {stage: {"wall": [], "cpu": [], "peak_rss_mib": 0.0} for stage in STAGES}
    for i in range(repeats + 1):
        run = subprocess.run([sys.executable, "-c", _CODE], check=True, capture_output=True, text=True)
        res = json.loads(run.stdout.strip().splitlines()[-1])
        if i:
            for j, stage in enumerate(STAGES):
                out[stage]["wall"].append(res["wall"][j])
                out[stage]["cpu"].append(res["cpu"][j])
                out[stage]["peak_rss_mib"] = max(out[stage]["peak_rss_mib"], res["peak_rss_mib"])
    return out


def rows(repeats: int, log=lambda msg: None) -> list[dict]:
    """The benchmark's rows (:data:`WHAT`, one per stage): median and runs, wall-clock and CPU, peak memory."""
    log("colour-science's import, once per process ...")
    return [{"what": WHAT, "stage": stage, "median_s": statistics.median(t["wall"]), "runs_s": t["wall"],
             "median_cpu_s": statistics.median(t["cpu"]), "runs_cpu_s": t["cpu"], "pixels": 0,
             "peak_rss_mib": t["peak_rss_mib"]} for stage, t in measure_colour_import(repeats).items()]
