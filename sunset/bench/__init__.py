"""``make bench``: time the renderer against the Cray-1 and a brute-force caster.

Each measurement runs in a fresh process (so caches, memory and JIT state of
one measurement cannot help or hurt another): one warm-up, then at least five
timed runs, of which the median is reported, with the peak resident memory of
that process. Ratios are against the Cray-1's 34 s for one Figure 6 frame and
against the project's brute-force ray caster measured in the same run (scaled
per pixel).

Measured: the Figure 6 frame (two reflections, default scene) at 1020 × 1023
and 1024 × 1024, split into stages (the sea's scan line, the islands, points
and normals, reflections with secondary reflections, codes, the film
recorder); the same frame with the NumPy reference kernels only; a 64-frame
wave cycle coded (both cores) and filmed; the brute-force caster; how the cost
of the vector stage grows with the picture size and with the number of wave
trains and islands; and a profile of one frame (the functions where the time
goes). Everything lands in one JSON file (``figures/bench.json``), which the
book's "Speed" chapter reads from a committed snapshot.

Also measured (:mod:`sunset.bench.extra`): the frame on one thread (the
baseline of "both cores inside one frame", in the same run), the peak memory
one frame adds per pixel at several sizes, checked against
:data:`~sunset.bench.extra.BYTES_PER_PIXEL_BOUND` (the bench fails when it is
broken), the film's encoder settings against the old ones (time and PSNR),
POV-Ray on the exported scene at the frame's size when ``povray`` is
installed, and the machine's load average before and after (the machine may
be shared: the ratios in one run are what to read). And Stokes' series by
computer, exact and in float64 (:mod:`sunset.bench.series`), and the wind
sea's FFT tile (:mod:`sunset.bench.ocean`). And the RGB back end (:mod:`sunset.bench.rgb`): re-shading a stored frame, the light of
an hour, and a 4-sample frame, split into its vector stage and the back end.
And the explorer (:mod:`sunset.bench.explorer`): one update of
:func:`sunset.explore`'s 512 × 512 picture per kind of slider. And the ripples of light
(:mod:`sunset.bench.ripples`): a post's and the shores' textures, a film frame's light, their bytes.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

from ..constants import CRAY1_SECONDS_FIGURE6
from ..errors import SunsetError
from ..guard import one_line
from ..kernels import keep_freed_memory
from . import explorer as explorer_bench, extra, memory as memory_bench, ocean as ocean_bench
from .extra import timed
from .frame import _frame_once, _measure_frame, _measure_paths  # noqa: F401 (the frame's rows; the profile times the same frame)
from . import ripples as ripples_bench
from .profile import _function_name, _measure_profile  # noqa: F401 (the profile's row; tests use the name)
from . import colour as colour_bench, rgb as rgb_bench, series as stokes_bench

#: Repeats per measurement (after one warm-up run).
REPEATS = 5

#: The picture sizes of the Figure 6 frame: the paper's and a power of two.
FRAME_SIZES = ((1020, 1023), (1024, 1024))

#: The picture's width and height of a row timed alone (``--measure``) when none is given.
MEASURE_SIZE = 1024

#: Stages of one frame, in pipeline order (names as they appear in the table and the JSON).
STAGES = ("sea scan line", "islands", "points & normals", "reflections", "codes", "film recorder")

#: Frames of the wave cycle, and its picture size.
CYCLE_FRAMES = 64
CYCLE_SIZE = (1020, 1023)

#: Picture sizes, wave-train counts and island counts of the scaling study (vector stage only).
SCALING_SIZES = (128, 256, 512, 768, 1024)
SCALING_TRAINS = (1, 2, 4, 8)
SCALING_ISLANDS = (0, 1, 2, 3, 6)
SCALING_SIZE = 512


def _measure_brute(width: int, height: int, repeats: int) -> dict:
    from ..vector.bruteforce import trace_direct_bruteforce
    from ..model.scene import Scene

    scene = Scene.default().with_size(width, height)
    return {"total": timed(lambda: trace_direct_bruteforce(scene, 0.0), repeats)}


def _measure_cycle(width: int, height: int, repeats: int, frames: int = CYCLE_FRAMES) -> dict:
    """A wave cycle coded (both cores) and filmed: the two steps and their sum."""
    import tempfile

    from ..pipeline.film import render_cycle, write_film
    from ..model.scene import Scene

    scene = Scene.default().with_size(width, height)
    out = {"coded": [], "filmed": [], "total": []}
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(repeats + 1):  # the first is the warm-up
            t0 = time.perf_counter()
            tape = render_cycle(scene, frames, progress=False)
            t1 = time.perf_counter()
            write_film(tape, Path(tmp) / "f.mp4", None, progress=False)
            t2 = time.perf_counter()
            if i:
                for k, v in zip(out, (t1 - t0, t2 - t1, t2 - t0)):
                    out[k].append(v)
    return out


def _vector_stage_seconds(scene, repeats: int) -> float:
    """Median seconds of render + encode (the vector stage) for one scene, after a warm-up."""
    from ..pipeline.frame import encode, render

    return statistics.median(timed(lambda: encode(scene, render(scene, 0.0, 2)), repeats))


def _scaled_sea(sea, count: int):
    """A sea of ``count`` trains: the default's, then shorter ones (λ/n², so it stays periodic)."""
    from ..model.waves import Sea, WaveTrain

    base = list(sea.trains)
    trains = base[:count]
    n = len(base) + 1
    while len(trains) < count:
        longest = base[0]
        trains.append(WaveTrain(0.01, longest.wavelength / n**2, direction=(37.0 * n) % 360.0, phase=float(n)))
        n += 1
    return Sea(tuple(trains))


def _scaled_islands(islands, count: int):
    """``count`` islands: the default's, then copies shifted sideways and farther out."""
    out = list(islands)[:count]
    j = 0
    while len(out) < count:
        src = islands[j % len(islands)]
        k = j // len(islands) + 1
        out.append(replace(src, x=src.x + 260.0 * k * (1 if j % 2 else -1), y=src.y + 900.0 * k,
                           name=f"{src.name}-{k}"))
        j += 1
    return tuple(out)


def _measure_scaling(width: int, height: int, repeats: int) -> dict:
    """Vector-stage seconds against picture size, wave trains and islands (small repeats)."""
    from ..model.scene import Scene

    base = Scene.default()
    sizes = [s for s in SCALING_SIZES if s <= max(width, height)]
    out = {"size": {"n": sizes, "seconds": [], "sea_samples": [], "island_samples": []},
           "trains": {"n": list(SCALING_TRAINS), "seconds": []},
           "islands": {"n": list(SCALING_ISLANDS), "seconds": []}, "size_for_counts": SCALING_SIZE}
    from ..pipeline.frame import trace_direct

    for n in sizes:
        sc = base.with_size(n, n)
        out["size"]["seconds"].append(_vector_stage_seconds(sc, repeats))
        info: dict = {}
        trace_direct(sc, 0.0, info=info)
        out["size"]["sea_samples"].append(info["sea_samples"] * n)
        out["size"]["island_samples"].append(info["island_samples"])
    sc = base.with_size(SCALING_SIZE, SCALING_SIZE)
    for n in SCALING_TRAINS:
        out["trains"]["seconds"].append(_vector_stage_seconds(replace(sc, sea=_scaled_sea(sc.sea, n)), repeats))
    for n in SCALING_ISLANDS:
        out["islands"]["seconds"].append(
            _vector_stage_seconds(replace(sc, islands=_scaled_islands(sc.islands, n)), repeats))
    return {"scaling": out}


MEASUREMENTS = {"frame": _measure_frame, "paths": _measure_paths, "brute": _measure_brute, "cycle": _measure_cycle,
                "scaling": _measure_scaling, "profile": _measure_profile, "rgb": rgb_bench.measure_rgb,
                "memory": extra.measure_memory, "filmlook": extra.measure_film_look, "limits": extra.measure_limits,
                "series": stokes_bench.measure_series, "explorer": explorer_bench.measure_explorer,
                "ocean": ocean_bench.measure_ocean, "windframe": ocean_bench.measure_wind_frames, "budget": lambda w, h, r: memory_bench.measure_budget(),
                "ripples": ripples_bench.measure_ripples, "ripples-convergence": ripples_bench.measure_convergence}


def _child(args) -> None:
    result = MEASUREMENTS[args.measure](args.width, args.height, args.repeats)
    from .. import kernels

    print(json.dumps({"times": result, **_peak(), "compiled": kernels.enabled(), "kernels": kernels.path()}))


def _peak() -> dict:
    """Peak resident memory of this process and of the largest of its children (the cycle's workers), MiB."""
    return {"peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "peak_rss_children_mib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0}


def measure(kind: str, width: int, height: int, repeats: int = REPEATS, numpy_only: bool = False,
            threads: int | None = None, env: dict | None = None) -> dict:
    """Run one measurement in a fresh Python process; returns its JSON result.

    ``numpy_only`` runs it with the compiled kernels off (``SUNSET_COMPILED=0``);
    ``threads`` sets the threads of a frame (``SUNSET_THREADS``; default: all cores);
    ``env``: more environment variables for the process.
    """
    cmd = [sys.executable, "-m", "sunset.bench", "--measure", kind, "--width", str(width),
           "--height", str(height), "--repeats", str(repeats)]
    env = dict(os.environ, **(env or {}))
    if numpy_only:
        env["SUNSET_COMPILED"] = "0"
    env.pop("SUNSET_THREADS", None)
    if threads is not None:
        env["SUNSET_THREADS"] = str(threads)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out.strip().splitlines()[-1])


def machine() -> dict:
    """What the benchmark ran on: CPU, cores, Python and library versions, date."""
    import numpy

    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        import numba
        numba_version = numba.__version__
    except ImportError:
        numba_version = None
    return {"cpu": cpu, "cpus": os.cpu_count(), "platform": platform.platform(),
            "python": platform.python_version(), "numpy": numpy.__version__, "numba": numba_version,
            "numpy_simd": numpy_simd(), "date": datetime.date.today().isoformat(), "load_before": _load()}


def numpy_simd() -> list[str]:
    """The CPU extensions NumPy dispatches its kernels to here (AVX-512 changes its float64 exp and power)."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:                      # pragma: no cover - another NumPy layout
        return []
    return [name for name in __cpu_dispatch__ if __cpu_features__.get(name)]


def _load() -> list[float]:
    """The machine's load average over 1, 5 and 15 minutes (runnable processes; 2 cores are busy at 2)."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - platforms without it
        return []


def _row(what: str, stage: str, times, pixels: int, res: dict) -> dict:
    return {"what": what, "stage": stage, "median_s": statistics.median(times), "runs_s": list(times),
            "pixels": pixels, "peak_rss_mib": max(res["peak_rss_mib"], res.get("peak_rss_children_mib", 0.0))}


def run_benchmark(out: Path, repeats: int = REPEATS, brute_size: int = 96, cycle: bool = True, *,
                  frame_sizes=FRAME_SIZES, cycle_size=CYCLE_SIZE, cycle_frames: int = CYCLE_FRAMES,
                  numpy_reference: bool = True, scaling: bool = True, profile: bool = True,
                  rgb: bool = True, memory_sizes=extra.MEMORY_SIZES, film_look: bool = True,
                  povray: bool = True, series: bool = False, figures: bool = False,
                  explorer_size=explorer_bench.EXPLORER_SIZE, ocean: bool = False, budget: bool = True,
                  ripples: bool = False) -> dict:
    """Measure everything, print the table, write ``out`` (JSON)."""
    rows = []
    log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
    mach = machine()

    log(f"brute-force reference at {brute_size}x{brute_size} ...")
    brute = measure("brute", brute_size, brute_size, repeats)
    brute_per_px = statistics.median(brute["times"]["total"]) / (brute_size * brute_size)
    rows.append(_row(f"brute-force ray caster {brute_size}x{brute_size} (direct rays)", "total",
                     brute["times"]["total"], brute_size * brute_size, brute))

    compiled_on = path_taken = None
    for w, h in frame_sizes:
        log(f"Figure 6 frame at {w}x{h} ...")
        res = measure("frame", w, h, repeats)
        compiled_on, path_taken = res["compiled"], res["kernels"]
        for stage, times in res["times"].items():
            rows.append(_row(f"Figure 6 frame {w}x{h}", stage, times, w * h, res))
    w, h = frame_sizes[-1]
    log(f"Figure 6 frame at {w}x{h}, one thread ...")
    res = measure("frame", w, h, repeats, threads=1)
    for stage, times in res["times"].items():
        rows.append(_row(f"Figure 6 frame {w}x{h}, one thread", stage, times, w * h, res))
    log(f"Figure 6 frame at {w}x{h}, NumPy's AVX-512 and AVX2 code off ...")   # the compiled path still runs
    res = measure("frame", w, h, repeats, env={"NPY_DISABLE_CPU_FEATURES": "AVX512_ICL AVX512_SPR X86_V4 X86_V3"})
    for stage, times in res["times"].items():
        rows.append(_row(f"Figure 6 frame {w}x{h}, NumPy's SIMD off", stage, times, w * h, res))
    for threads, label in ((None, ""), (1, ", one thread")):
        log(f"Figure 6 frame at {w}x{h}, the 8-bit path and the API{label} ...")
        res = measure("paths", w, h, repeats, threads=threads)
        for stage, times in res["times"].items():
            rows.append(_row(f"Figure 6 frame {w}x{h}, paths{label}", stage, times, w * h, res))
    if numpy_reference:
        log(f"Figure 6 frame at {w}x{h}, NumPy reference kernels only ...")
        res = measure("frame", w, h, repeats, numpy_only=True)
        for stage, times in res["times"].items():
            rows.append(_row(f"Figure 6 frame {w}x{h}, NumPy kernels", stage, times, w * h, res))
        res = measure("paths", w, h, max(1, repeats // 2), numpy_only=True)
        for stage, times in res["times"].items():
            rows.append(_row(f"Figure 6 frame {w}x{h}, paths, NumPy kernels", stage, times, w * h, res))
    if rgb:
        w, h = frame_sizes[-1]
        log(f"RGB back end at {w}x{h} ...")
        res = measure("rgb", w, h, repeats)
        for stage, times in res["times"].items():
            rows.append(_row(f"RGB {w}x{h}", stage, times, w * h, res))
    if explorer_size:
        w, h = explorer_size
        log(f"the explorer's updates at {w}x{h} ...")
        res = measure("explorer", w, h, repeats)
        cpu = res["times"].pop("cpu")
        for stage, times in res["times"].items():
            rows.append({**_row(f"explorer update {w}x{h}", stage, times, w * h, res),
                         "median_cpu_s": statistics.median(cpu[stage]), "runs_cpu_s": cpu[stage]})
    if cycle:
        w, h = cycle_size
        log(f"{cycle_frames}-frame wave cycle, coded and filmed, at {w}x{h} ...")
        res = _measure_cycle_child(w, h, repeats, cycle_frames)
        for stage, times in res["times"].items():
            rows.append(_row(f"{cycle_frames}-frame cycle {w}x{h}", stage, times, cycle_frames * w * h, res))

    rows += colour_bench.rows(repeats, log)

    for r in rows:
        figure6 = "Figure 6" in r["what"] and r["stage"] in ("total", "vector stage")
        r["cray1_ratio"] = CRAY1_SECONDS_FIGURE6 / r["median_s"] if figure6 else None
        r["brute_ratio"] = brute_per_px * r["pixels"] / r["median_s"]

    report = {"machine": mach, "compiled": compiled_on, "kernels": path_taken, "repeats": repeats,
              "cray1_seconds": CRAY1_SECONDS_FIGURE6, "brute_seconds_per_pixel": brute_per_px,
              "brute_size": brute_size, "rows": rows, "threads": os.cpu_count()}
    memory = []
    for n in memory_sizes:
        log(f"memory of one frame at {n}x{n} ...")
        memory.append(measure("memory", n, n, 1)["times"])
    report["memory"] = {"bound_bytes_per_pixel": extra.BYTES_PER_PIXEL_BOUND, "sizes": memory,
                        "ok": all(m["bytes_per_pixel"] <= extra.BYTES_PER_PIXEL_BOUND for m in memory)}
    if budget:                       # the work budget's prediction against the peak, in fresh processes
        log("the work budget: measured peaks against the predictions ...")
        report["budget"] = memory_bench.measure_budget()
        for b in report["budget"]:
            path = "compiled" if b["compiled"] else "NumPy"
            print(f"budget: {b['what']}, {path}: {b['work'] / 2**20:.1f} MiB of {b['predicted'] / 2**20:.1f} "
                  f"predicted (x{b['ratio']:.2f}), interpreter {b['interpreter'] / 2**20:.0f} MiB")
    w, h = frame_sizes[-1]
    log(f"the floor under a {w}x{h} frame: memory bandwidth and cosine rate ...")
    report["limits"] = measure("limits", w, h, repeats)["times"]
    if film_look:
        w, h = cycle_size
        log(f"film encoder settings, now and before, at {w}x{h} ...")
        report["film_look"] = measure("filmlook", w, h, 1)["times"]
    if povray:
        w, h = frame_sizes[-1]
        ours = statistics.median(next(r for r in rows if r["what"] == f"Figure 6 frame {w}x{h}"
                                      and r["stage"] == "total")["runs_s"])
        log(f"POV-Ray on the exported scene at {w}x{h} (once) ...")
        report["povray"] = extra.povray_comparison(w, h, ours, Path(out).parent)
    if scaling:
        log("scaling with picture size, wave trains and islands ...")
        report.update(measure("scaling", max(SCALING_SIZES), max(SCALING_SIZES), 5)["times"])
    if profile:
        w, h = frame_sizes[-1]
        log(f"profile of a {w}x{h} frame (one thread: cProfile sees only its own) ...")
        report.update(measure("profile", w, h, 3, threads=1)["times"])
    if series:
        log("Stokes' series by computer, exact and float64 ...")
        report["series"] = stokes_bench.rows(measure("series", 0, 0, repeats))
    if ripples:
        log("the ripples of light: textures, a film frame's light, bytes ...")
        report["ripples"] = ripples_bench.rows(measure("ripples", 0, 0, repeats))
    if ocean:
        log("the wind sea's FFT tile: sizes, component counts, sampling ...")
        report["ocean"] = ocean_bench.rows(measure("ocean", 0, 0, repeats))
        size = ocean_bench.WIND_FRAME_SIZE
        report["ocean"] += ocean_bench.rows(measure("windframe", size, size, repeats), "frame")
    if figures:
        log(f"sunset figures, every figure and the film, {extra.FIGURES_RUNS} runs ...")
        report["figures"] = extra.measure_figures()
    mach["load_after"] = _load()
    print(format_table(rows))
    print(stokes_bench.format_rows(report.get("series", [])))
    print(ocean_bench.format_rows(report.get("ocean", [])))
    print(ripples_bench.format_rows(report.get("ripples", [])))
    for m in report["memory"]["sizes"]:
        print(f"memory of one frame at {m['width']}x{m['height']}: {m['bytes_per_pixel']:.1f} bytes/pixel "
              f"(bound {extra.BYTES_PER_PIXEL_BOUND})")
    if report.get("povray"):
        p = report["povray"]
        print(f"POV-Ray {p['width']}x{p['height']}: {p['seconds']:.1f} s, {p['ratio']:.0f} × ours; "
              f"direct rays agree on {100 * p['direct_agree']:.2f} % of pixels")
    if report.get("figures"):
        f = report["figures"]
        print(f"sunset figures ({f['files']} files): {f['median_s']:.1f} s, {f['median_cpu_s']:.1f} s of CPU (medians)")
    print(f"load average before {mach['load_before']}, after {mach['load_after']}")
    from ..io import write_bytes

    write_bytes(out, (json.dumps(report, indent=2) + "\n").encode())
    return report


def _measure_cycle_child(width, height, repeats, frames):
    cmd = [sys.executable, "-m", "sunset.bench", "--measure", "cycle", "--width", str(width), "--height",
           str(height), "--repeats", str(repeats), "--cycle-frames", str(frames)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def format_table(rows) -> str:
    """A plain-text table of the benchmark rows."""
    lines = [f"{'measurement':48s} {'stage':16s} {'median s':>9s} {'× Cray-1':>9s} {'× brute':>9s} {'peak MiB':>9s}"]
    for r in rows:
        cray = f"{r['cray1_ratio']:9.1f}" if r.get("cray1_ratio") else f"{'':9s}"
        lines.append(f"{r['what']:48s} {r['stage']:16s} {r['median_s']:9.3f} {cray} {r['brute_ratio']:9.1f} "
                     f"{r['peak_rss_mib']:9.0f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m sunset.bench", description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("figures/bench.json"))
    p.add_argument("--repeats", type=int, default=REPEATS)
    p.add_argument("--brute-size", type=int, default=96)
    p.add_argument("--no-cycle", action="store_true")
    p.add_argument("--no-povray", action="store_true", help="do not time POV-Ray even where it is installed")
    p.add_argument("--no-figures", action="store_true", help="do not time `sunset figures` (what make figures runs)")
    p.add_argument("--measure", choices=list(MEASUREMENTS), metavar="ROW",
                   help="time one row only, in this process, and print its JSON (rows: %(choices)s)")
    p.add_argument("--width", type=int, default=MEASURE_SIZE, help="with --measure: picture width, pixels")
    p.add_argument("--height", type=int, default=MEASURE_SIZE, help="with --measure: picture height, pixels")
    p.add_argument("--cycle-frames", type=int, default=CYCLE_FRAMES, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    keep_freed_memory()          # as the sunset command does: freed frames' blocks are reused, not re-faulted
    if args.repeats < 1 or args.brute_size < 1:
        print("sunset.bench: error: --repeats and --brute-size must be at least 1", file=sys.stderr)
        return 2
    if args.measure:
        try:
            if args.measure == "cycle":
                result = _measure_cycle(args.width, args.height, args.repeats, args.cycle_frames)
                print(json.dumps({"times": result, **_peak()}))
            else:
                _child(args)
        except SunsetError as exc:                   # a size or count out of range: one line, as the command's
            print(f"sunset.bench: error: {one_line(exc)}", file=sys.stderr)
            return 2
        return 0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    report = run_benchmark(args.out, args.repeats, args.brute_size, cycle=not args.no_cycle,
                           povray=not args.no_povray, series=True, figures=not args.no_figures, ocean=True,
                           ripples=True)
    if not report["memory"]["ok"]:
        print(f"sunset.bench: FAILED: one frame needs more than {extra.BYTES_PER_PIXEL_BOUND} bytes per pixel",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
