"""``make bench``: time the renderer against the Cray-1 and a brute-force caster.

Each measurement runs in a fresh process (so caches, memory and JIT state of
one measurement cannot help or hurt another): one warm-up, then at least five
timed runs, of which the median is reported, with the peak resident memory of
that process. Ratios are against the Cray-1's 34 s for one Figure 6 frame and
against the project's brute-force ray caster measured in the same run (scaled
per pixel).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from .constants import CRAY1_SECONDS_FIGURE6

#: Repeats per measurement (after one warm-up run).
REPEATS = 5


def _timed(fn, repeats: int):
    fn()  # warm-up
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return times


def _measure_frame(width: int, height: int, repeats: int) -> dict:
    """Time a Figure 6 frame (two reflections, default scene), stage by stage."""
    from .codes import encode
    from .dicomed import expose
    from .heightfield import trace_direct
    from .pierce import trace_reflections
    from .scene import Scene

    scene = Scene.default().with_size(width, height)
    stages = {"direct": [], "reflections": [], "codes": [], "film recorder": [], "total": []}

    def once(record: bool):
        t0 = time.perf_counter()
        frame = trace_direct(scene, 0.0)
        frame.reflections = 2
        frame.finish_direct()
        t1 = time.perf_counter()
        trace_reflections(scene, frame, 2)
        t2 = time.perf_counter()
        codes = encode(scene, frame, seed=0)
        t3 = time.perf_counter()
        expose(scene, codes, 0.35)
        t4 = time.perf_counter()
        if record:
            for k, v in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t4 - t0)):
                stages[k].append(v)

    once(False)
    for _ in range(repeats):
        once(True)
    return {k: v for k, v in stages.items()}


def _measure_brute(width: int, height: int, repeats: int) -> dict:
    from .bruteforce import trace_direct_bruteforce
    from .scene import Scene

    scene = Scene.default().with_size(width, height)
    return {"total": _timed(lambda: trace_direct_bruteforce(scene, 0.0), repeats)}


def _measure_cycle(width: int, height: int, repeats: int, frames: int = 64) -> dict:
    import tempfile

    from .film import make_film
    from .scene import Scene

    scene = Scene.default().with_size(width, height)
    with tempfile.TemporaryDirectory() as tmp:
        def run():
            make_film(scene, Path(tmp) / "f.mp4", None, frames=frames, progress=False)
        return {"total": _timed(run, repeats)}


MEASUREMENTS = {"frame": _measure_frame, "brute": _measure_brute, "cycle": _measure_cycle}


def _child(args) -> None:
    result = MEASUREMENTS[args.measure](args.width, args.height, args.repeats)
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"times": result, "peak_rss_mib": peak_kib / 1024.0}))


def measure(kind: str, width: int, height: int, repeats: int = REPEATS) -> dict:
    """Run one measurement in a fresh Python process; returns its JSON result."""
    cmd = [sys.executable, "-m", "sunset.bench", "--measure", kind, "--width", str(width),
           "--height", str(height), "--repeats", str(repeats)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def run_benchmark(out: Path, repeats: int = REPEATS, brute_size: int = 96, cycle: bool = True) -> dict:
    """Measure everything, print the table, write ``out`` (JSON)."""
    rows = []
    log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731

    log(f"brute-force reference at {brute_size}x{brute_size} ...")
    brute = measure("brute", brute_size, brute_size, max(3, repeats // 2 + 1))
    brute_per_px = statistics.median(brute["times"]["total"]) / (brute_size * brute_size)
    rows.append({"what": f"brute-force ray caster {brute_size}x{brute_size}", "stage": "total",
                 "median_s": statistics.median(brute["times"]["total"]), "pixels": brute_size * brute_size,
                 "peak_rss_mib": brute["peak_rss_mib"]})

    for w, h in ((1020, 1023), (1024, 1024)):
        log(f"Figure 6 frame at {w}x{h} ...")
        res = measure("frame", w, h, repeats)
        for stage, times in res["times"].items():
            rows.append({"what": f"Figure 6 frame {w}x{h}", "stage": stage, "median_s": statistics.median(times),
                         "runs_s": times, "pixels": w * h, "peak_rss_mib": res["peak_rss_mib"]})
    if cycle:
        log("64-frame wave cycle plus film at 1020x1023 ...")
        res = measure("cycle", 1020, 1023, max(1, repeats // 2))
        rows.append({"what": "64-frame cycle, coded and filmed, 1020x1023", "stage": "total",
                     "median_s": statistics.median(res["times"]["total"]), "runs_s": res["times"]["total"],
                     "pixels": 64 * 1020 * 1023, "peak_rss_mib": res["peak_rss_mib"]})

    for r in rows:
        r["cray1_ratio"] = CRAY1_SECONDS_FIGURE6 / r["median_s"] if r["stage"] == "total" and "Figure 6" in r["what"] else None
        r["brute_ratio"] = brute_per_px * r["pixels"] / r["median_s"]

    report = {
        "machine": {"python": platform.python_version(), "platform": platform.platform(),
                    "cpus": os.cpu_count()},
        "repeats": repeats, "brute_seconds_per_pixel": brute_per_px, "rows": rows,
    }
    print(format_table(rows))
    from .io import write_bytes
    write_bytes(out, (json.dumps(report, indent=2) + "\n").encode())
    return report


def format_table(rows) -> str:
    """A plain-text table of the benchmark rows."""
    lines = [f"{'measurement':46s} {'stage':14s} {'median s':>9s} {'× Cray-1':>9s} {'× brute':>9s} {'peak MiB':>9s}"]
    for r in rows:
        cray = f"{r['cray1_ratio']:9.1f}" if r.get("cray1_ratio") else f"{'':9s}"
        lines.append(f"{r['what']:46s} {r['stage']:14s} {r['median_s']:9.3f} {cray} {r['brute_ratio']:9.1f} "
                     f"{r['peak_rss_mib']:9.0f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m sunset.bench", description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("figures/bench.json"))
    p.add_argument("--repeats", type=int, default=REPEATS)
    p.add_argument("--brute-size", type=int, default=96)
    p.add_argument("--no-cycle", action="store_true")
    p.add_argument("--measure", choices=list(MEASUREMENTS), help=argparse.SUPPRESS)
    p.add_argument("--width", type=int, help=argparse.SUPPRESS)
    p.add_argument("--height", type=int, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.measure:
        _child(args)
        return 0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    run_benchmark(args.out, args.repeats, args.brute_size, cycle=not args.no_cycle)
    return 0


if __name__ == "__main__":
    sys.exit(main())
