"""The benchmark's other measurements: memory per pixel, the film's look, POV-Ray timed beside us.

* :func:`measure_memory` (a fresh process per picture size): the peak
  resident memory one frame adds (render, codes, film recorder), per pixel,
  against :data:`BYTES_PER_PIXEL_BOUND`.
* :func:`measure_film_look`: the same film frames encoded with the film's
  x264 settings and with the settings it had before (``medium``), the
  encoder's CPU time and the PSNR of the decoded film against the frames sent.
* :func:`povray_comparison`: POV-Ray renders the exported default scene at
  the frame's size on all cores (:mod:`sunset.figures.povray`), timed once,
  and its picture's destinations are compared with this package's frame.
"""

from __future__ import annotations

import os
import resource
import time
from pathlib import Path

import numpy as np

from ..kernels import AVAILABLE


def timed(fn, repeats: int) -> list[float]:
    """Wall-clock seconds of ``repeats`` calls of ``fn``, after one warm-up call."""
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return times


#: The most memory one frame may add, bytes per pixel (render + codes + film recorder).
BYTES_PER_PIXEL_BOUND = 100

#: Picture sizes (square) of the memory measurement.
MEMORY_SIZES = (1024, 2048, 4000)

#: The x264 settings the film used before (the look and speed baseline of :func:`measure_film_look`).
OLD_X264_PARAMS = ["-preset", "medium", "-crf", "18", "-threads", "2", "-x264-params", "threads=2",
                   "-fflags", "+bitexact", "-flags:v", "+bitexact", "-map_metadata", "-1"]


def _frame(scene):
    """One frame of the 8-bit pipeline: scene → tape (:func:`~sunset.pipeline.frame.code_frame`) → film recorder."""
    from ..pipeline.frame import code_frame, expose

    return expose(scene, code_frame(scene, 0.0), 0.35)


def measure_memory(width: int, height: int, repeats: int = 1) -> dict:
    """Peak memory of one frame at ``width`` × ``height``, over what the process held before it.

    The process first renders a tiny frame (the compiled kernels, the thread
    pool and the colour tables are loaded), reads its peak resident memory,
    then renders the frame; the growth of the peak is the frame's.
    """
    from ..model.scene import Scene

    _frame(Scene.default().with_size(64, 64))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    start = time.perf_counter()
    _frame(Scene.default().with_size(width, height))
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return {"width": width, "height": height, "base_mib": before / 2**20, "added_mib": (after - before) / 2**20,
            "bytes_per_pixel": (after - before) / (width * height), "seconds": seconds,
            "bound": BYTES_PER_PIXEL_BOUND}


def _encode(frames, size, params, path) -> tuple[float, float]:
    """Encode ``frames`` with x264 ``params``: (wall seconds, the encoder's CPU seconds)."""
    import imageio_ffmpeg

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    writer = imageio_ffmpeg.write_frames(str(path), size, fps=24, codec="libx264", pix_fmt_in="rgb24",
                                         pix_fmt_out="yuv420p", quality=None, macro_block_size=1,
                                         ffmpeg_log_level="error", output_params=params)
    writer.send(None)
    for f in frames:
        writer.send(f)
    writer.close()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return time.perf_counter() - start, cpu


def _psnr(path, frames) -> float:
    """PSNR (dB) of the decoded film against the frames that were sent, over all frames and channels."""
    import imageio_ffmpeg

    reader = imageio_ffmpeg.read_frames(str(path), pix_fmt="rgb24")
    next(reader)
    sq, n = 0.0, 0
    for sent, raw in zip(frames, reader):
        got = np.frombuffer(raw, np.uint8).reshape(sent.shape)
        sq += float(np.sum((got.astype(np.float64) - sent) ** 2))
        n += sent.size
    return float(10.0 * np.log10(255.0**2 / (sq / n)))


def measure_film_look(width: int, height: int, repeats: int = 1) -> dict:
    """The film's x264 settings against the old ones, on the same 24 film frames (8-frame cycle, 3 times)."""
    import tempfile

    from ..model.scene import Scene
    from ..pipeline.film import render_cycle
    from ..recorder.film import _even, _X264_PARAMS, film_frames

    scene = Scene.default().with_size(width, height)
    tape = render_cycle(scene, 8, progress=False)
    frames = [_even(rgb) for _, rgb in film_frames(tape, cycles=3)]
    size = (frames[0].shape[1], frames[0].shape[0])
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, params in (("before", OLD_X264_PARAMS), ("now", _X264_PARAMS)):
            path = Path(tmp) / f"{name}.mp4"
            wall, cpu = _encode(frames, size, params, path)
            out[name] = {"preset": params[params.index("-preset") + 1], "crf": params[params.index("-crf") + 1],
                         "wall_s": wall, "cpu_s": cpu, "bytes": path.stat().st_size, "psnr_db": _psnr(path, frames),
                         "frames": len(frames)}
    return out


def povray_comparison(width: int, height: int, our_seconds: float, out_dir: Path) -> dict | None:
    """POV-Ray on the exported default scene at ``width`` × ``height`` beside this package's frame; None without povray.

    POV-Ray runs once, on all cores, with no anti-aliasing; ``ratio`` is its
    time over ``our_seconds`` (this package's median for the same frame,
    scene to film-recorder colours). Its picture is saved in ``out_dir``.
    """
    from ..figures.povray import compare, povray_path, render_pov
    from ..model.scene import Scene
    from ..pipeline.frame import render

    if povray_path() is None:
        return None
    scene = Scene.default().with_size(width, height)
    picture = Path(out_dir) / f"povray-{width}x{height}.png"
    threads = os.cpu_count() or 1
    rgb, seconds = render_pov(scene, 0.0, out_png=picture, threads=threads)
    agree = compare(render(scene, 0.0, 2), rgb)
    return {"width": width, "height": height, "seconds": seconds, "threads": threads, "ours_s": our_seconds,
            "ratio": seconds / our_seconds, "picture": picture.name, **agree}


def measure_limits(width: int, height: int, repeats: int = 5) -> dict:
    """A floor under the frame's time on this machine, from two things it cannot avoid, measured here.

    * memory: the frame's fields (:class:`~sunset.vector.frame.Frame`), the
      codes and the RGB picture must be written once; at the machine's copy
      bandwidth (``np.copyto`` of 256 MiB, reading and writing) that takes
      bytes / bandwidth;
    * arithmetic: the sea's profile is one single-precision cosine per sample
      and wave train; at the faster of NumPy's float32 cosine and the compiled
      cosine (:mod:`sunset.vector.sincos_numba`) on every core that takes
      samples × trains / rate.

    Both are per core count and optimistic (nothing else is counted), so the
    frame cannot be faster than the larger of the two.
    """
    from ..model.scene import Scene
    from ..pipeline.frame import render, trace_direct

    cores = os.cpu_count() or 1
    big = np.ones(32 * 2**20)               # 256 MiB
    dst = np.empty_like(big)
    copies = []
    for _ in range(repeats):
        start = time.perf_counter()
        np.copyto(dst, big)
        copies.append(time.perf_counter() - start)
    bandwidth = 2 * big.nbytes / float(np.median(copies))          # bytes read + written per second, one core
    del big, dst
    x = np.linspace(0, 100, 2**22, dtype=np.float32)
    out = np.empty_like(x)
    cosines = []
    for _ in range(repeats):
        start = time.perf_counter()
        np.cos(x, out=out)
        cosines.append(time.perf_counter() - start)
    cos_rate = x.size / float(np.median(cosines))                   # per second, one core
    compiled_rate = 0.0
    if AVAILABLE:                                                    # the compiled kernels' own cosine
        from ..vector.sincos_numba import cos_into

        cos_into(x, out)
        compiled = []
        for _ in range(repeats):
            start = time.perf_counter()
            cos_into(x, out)
            compiled.append(time.perf_counter() - start)
        compiled_rate = x.size / float(np.median(compiled))
    scene = Scene.default().with_size(width, height)
    info: dict = {}
    trace_direct(scene, 0.0, info=info)
    frame = render(scene, 0.0, 2, sea_bounces=False)
    frame_bytes = sum(getattr(frame, f).nbytes for f in ("direction", "surface", "part", "distance", "point",
                                                         "normal", "bounces", "ray", "final_surface", "final_part",
                                                         "final_normal"))
    out_bytes = frame_bytes + width * height * 4                    # + the codes and the RGB picture
    trains = sum(1 for t in scene.sea.trains if t.amplitude > 0)
    samples = info["sea_samples"] * width
    best_rate = max(cos_rate, compiled_rate)
    return {"cores": cores, "copy_bandwidth_gbs": bandwidth / 1e9, "cos_per_s": cos_rate,
            "cos_per_s_compiled": compiled_rate, "bytes_written": out_bytes,
            "memory_s": out_bytes / (bandwidth * cores),
            "sea_samples": samples, "trains": trains, "cosine_s": samples * trains / (best_rate * cores),
            "bytes_per_pixel_written": out_bytes / (width * height)}


#: How many times the benchmark runs ``sunset figures`` (what ``make figures`` runs when every file is stale).
FIGURES_RUNS = 3


def measure_figures(runs: int = FIGURES_RUNS, args=()) -> dict:
    """Wall-clock and CPU seconds of ``sunset figures`` writing every figure and the film, a fresh process each run.

    What ``make figures`` runs when every file in ``figures/`` is out of date,
    from a warm environment (the compiled kernels cached on disk by a first,
    untimed run), into a temporary folder, so the user's ``figures/`` is never
    touched. CPU time is the children's user + system time, the second
    process of :mod:`sunset.figures.lanes` and the film's encoder included.
    ``args``: more options for ``sunset figures`` (the tests ask for two small figures).
    """
    import subprocess
    import sys
    import tempfile

    cmd = [sys.executable, "-m", "sunset", "figures", "--quiet", "--out"]
    walls, cpus, files = [], [], 0
    with tempfile.TemporaryDirectory(prefix="sunset-bench-figures-") as tmp:
        for i in range(runs + 1):
            out = Path(tmp) / f"run{i}"
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            subprocess.run(cmd + [str(out), *args], check=True, stdout=subprocess.DEVNULL)
            wall = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            files = sum(1 for p in out.iterdir() if p.is_file())
            if i:                                 # the first run warms the kernels' cache; not timed
                walls.append(wall)
                cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return {"runs_s": walls, "cpu_s": cpus, "median_s": float(np.median(walls)),
            "median_cpu_s": float(np.median(cpus)), "files": files, "cores": len(os.sched_getaffinity(0))
            if hasattr(os, "sched_getaffinity") else os.cpu_count()}
