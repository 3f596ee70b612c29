"""How much memory one frame takes per pixel, measured (the budget is FRAME_BYTES_PER_PIXEL in sunset/constants.py)."""

from __future__ import annotations

__all__ = ["measure_bytes_per_pixel", "measure_rgb_bytes", "measure_command_peak", "measure_budget", "budget_scene"]


def measure_bytes_per_pixel(scene, sizes=((100, 80), (300, 240)), compiled: bool = False) -> float:
    """Measure how the peak memory of one frame grows per pixel: render, code and expose at two sizes.

    The peak is traced with :mod:`tracemalloc` (NumPy reports its arrays to
    it; arrays the compiled kernels make inside themselves are not seen, so
    the NumPy reference, ``compiled=False``, is the honest and the hungrier
    measurement). The difference of the peaks over the difference of the
    pixel counts leaves out what does not grow with the picture (tables,
    kernels, one strip of sea samples).
    """
    import tracemalloc

    from ..kernels import use_compiled
    from ..pipeline.frame import encode, expose, render

    def peak(w, h):
        s = scene.with_size(w, h)
        expose(s, encode(s, render(s, 0.0, 2)), 0.35)          # tables and kernels made once
        tracemalloc.start()
        try:
            expose(s, encode(s, render(s, 0.0, 2)), 0.35)
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    (w0, h0), (w1, h1) = sizes
    with use_compiled(compiled):
        p0, p1 = peak(w0, h0), peak(w1, h1)
    return (p1 - p0) / (w1 * h1 - w0 * h0)


def _traced_peak(fn) -> int:
    import tracemalloc

    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def measure_rgb_bytes(scene, samples: int = 4, sizes=((100, 80), (200, 160))) -> tuple[int, float]:
    """Measure the RGB back end's memory: (the hour's light, bytes; peak bytes per traced ray).

    The light (:func:`sunset.light.render.frame_light`: its sky grid, and the
    islands' shore textures, which grow with the picture only up to their
    finest, :data:`~sunset.constants.SHORE_TEXELS` across) is measured alone,
    for a frame of 1024 × 1024, where they are at their finest. The rest of a
    frame is traced, shaded and encoded the three ways ``render --shading
    rgb`` writes (8-bit PNG, 16-bit PNG, float32 .npy) with the light made
    beforehand; the difference of the peaks over the difference of the rays
    (samples × pixels) is the growth per ray. NumPy reference kernels, as in
    :func:`measure_bytes_per_pixel`. The budget is RGB_LIGHT_BYTES +
    rays × RGB_BYTES_PER_RAY (:mod:`sunset.light.budget`).
    """
    from ..io import png_bytes
    from ..kernels import use_compiled
    from ..light.output import png16_bytes, to_uint16, to_uint8
    from ..light.render import check_samples, frame_light, shade_display, shade_scene_linear
    from ..pipeline.rgb import trace_geometry

    k = check_samples(samples)

    def frame(s, light):
        g = trace_geometry(s, 0.0, 2, samples)
        display = shade_display(g, light, k)
        png_bytes(to_uint8(display))
        png16_bytes(to_uint16(display))
        shade_scene_linear(g, light, k)

    with use_compiled(False):
        large = scene.with_size(1024, 1024)             # the light only: no ray of it is traced
        frame_light(large, 0.0, 0.35)
        light_peak = _traced_peak(lambda: frame_light(large, 0.0, 0.35))
        peaks = []
        for w, h in sizes:
            s = scene.with_size(w, h)
            light = frame_light(s, 0.0, 0.35)
            frame(s, light)
            peaks.append(_traced_peak(lambda: frame(s, light)))
    (w0, h0), (w1, h1) = sizes
    return light_peak, (peaks[1] - peaks[0]) / ((w1 * h1 - w0 * h0) * samples)


# --------------------------------------------------------------------------- the peak of a whole command, measured
def measure_command_peak(scene, args=(), compiled: bool | None = None, threads: int | None = None,
                         timeout: float = 600.0, limit: int | None = None) -> dict:
    """The resident memory of ``sunset render`` on ``scene``, measured in a fresh process: the interpreter's, the work's.

    A fresh Python (started through ``/bin/sh``, which forks it: a process
    started straight from a large one inherits that one's peak in its
    ``ru_maxrss``) renders an 8 × 8 frame of the scene with the same options
    (``args``, e.g. ``["--shading", "rgb"]``), so that the kernels, the
    tables and the thread pool are loaded; its peak resident memory then
    (``resource.getrusage(...).ru_maxrss``) is the interpreter's own. It then
    forks, and the child renders the scene at its size: the child's
    ``ru_maxrss`` starts at what it holds at the fork, and its growth during
    the render is the work's peak. ``compiled`` sets ``SUNSET_COMPILED``,
    ``threads`` ``SUNSET_THREADS`` (default: the environment's). The child
    may grow its address space by at most ``limit`` bytes (``RLIMIT_AS``;
    default twice ``MAX_FRAME_BYTES``), so that a prediction gone wrong
    fails the render (out of memory, exit status 2) instead of the machine.
    Returns ``{"rc", "interpreter", "work", "seconds", "stderr"}`` (bytes,
    the exit status of the render).
    """
    import json
    import os
    import subprocess
    import sys
    import tempfile
    from pathlib import Path

    env = dict(os.environ)
    if compiled is not None:
        env["SUNSET_COMPILED"] = "1" if compiled else "0"
    if threads is not None:
        env["SUNSET_THREADS"] = str(threads)
    if limit is None:
        from ..constants import MAX_FRAME_BYTES
        limit = 2 * MAX_FRAME_BYTES
    env["SUNSET_PEAK_LIMIT"] = str(int(limit))
    with tempfile.TemporaryDirectory(prefix="sunset-peak-") as tmp:
        path = Path(tmp) / "scene.toml"
        path.write_text(scene.to_toml(), encoding="utf-8")
        cam = scene.camera
        cmd = ["/bin/sh", "-c", '"$@"; exit $?', "sh", sys.executable, "-c",
               "import sys; from sunset.bench.memory import _peak_child; _peak_child(sys.argv[1:])",
               str(path), f"{cam.width}x{cam.height}", tmp, *map(str, args)]
        done = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    lines = done.stdout.strip().splitlines()
    if done.returncode or not lines:
        raise RuntimeError(f"the measuring process failed ({done.returncode}): {done.stderr[-2000:]}")
    return {**json.loads(lines[-1]), "stderr": done.stderr}


def _peak_child(argv) -> None:
    """In the measuring process: warm up, then render in a forked child; print one JSON line (see above)."""
    import json
    import os
    import resource
    import time

    from ..cli import main

    scene, size, tmp, *args = argv

    def maxrss() -> int:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024

    main(["render", scene, "--size", "8x8", "-o", os.path.join(tmp, "warm.png"), "-q", *args])
    interpreter = maxrss()
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:                                   # pragma: no cover - the child reports through the pipe
        try:
            os.close(read)
            _limit_growth(int(os.environ.get("SUNSET_PEAK_LIMIT", "0")))
            base = maxrss()
            start = time.perf_counter()
            rc = main(["render", scene, "--size", size, "-o", os.path.join(tmp, "frame.png"), "-q", *args])
            seconds = time.perf_counter() - start
            os.write(write, json.dumps({"rc": rc, "work": maxrss() - base, "seconds": seconds}).encode())
        finally:
            os._exit(0)
    os.close(write)
    with os.fdopen(read, "rb") as fh:
        report = json.loads(fh.read() or b"{}")
    os.waitpid(pid, 0)
    print(json.dumps({"interpreter": interpreter, **report}))


#: The bench's "budget" row: (what, scene, size, extra ``sunset render`` options), each on both kernel paths.
BUDGET_CASES = (("the paper's frame", "carlas-island", (512, 512), ()),
                ("the issue's sliver above the horizon", "sliver", (64, 64), ()),
                ("a window 1e-6 tall across the horizon", "micro", (256, 256), ()),
                ("clouds", "carlas-island-clouds", (512, 512), ()),
                ("posts", "post-in-the-swell", (512, 512), ()),
                ("RGB, 4 samples", "carlas-island", (256, 256), ("--shading", "rgb", "--samples", "4")))


def budget_scene(name: str, size: tuple[int, int]):
    """A scene of :data:`BUDGET_CASES`: a packaged one, or the default with a sliver of a window."""
    from dataclasses import replace

    from ..model.scene import as_scene

    windows = {"sliver": (0.35, 0.35000002), "micro": (-5e-7, 5e-7)}
    scene = as_scene("carlas-island" if name in windows else name).with_size(*size)
    if name in windows:
        lo, hi = windows[name]
        scene = replace(scene, camera=replace(scene.camera, zy_min=lo, zy_max=hi))
    return scene


def measure_budget(cases=BUDGET_CASES) -> list[dict]:
    """Each case's measured peak (:func:`measure_command_peak`) beside its prediction, compiled and NumPy.

    Rows: ``what``, ``compiled``, ``interpreter`` and ``work`` (bytes measured), ``predicted`` (the
    work's bytes: :func:`sunset.vector.budget.predict_work`, or :func:`sunset.light.budget.rgb_bytes`
    for ``--shading rgb``), ``ratio`` (work / predicted) and ``seconds``.
    """
    from ..guard import usable_cpus
    from ..light.budget import rgb_bytes
    from ..vector.budget import predict_work

    rows = []
    for what, name, size, args in cases:
        scene = budget_scene(name, size)
        threads = usable_cpus()
        predicted = (rgb_bytes(*size, int(args[-1])) if "rgb" in args
                     else predict_work(scene, threads=threads).bytes)
        for compiled in (True, False):
            got = measure_command_peak(scene, args, compiled=compiled, threads=threads)
            rows.append({"what": what, "size": list(size), "compiled": compiled, "rc": got["rc"],
                         "interpreter": got["interpreter"], "work": got["work"], "predicted": predicted,
                         "ratio": got["work"] / predicted, "seconds": got["seconds"], "threads": threads})
    return rows


def _limit_growth(limit: int) -> None:
    """Let this process's address space grow by at most ``limit`` bytes from now (0: no limit)."""
    import resource

    if limit <= 0:
        return
    with open("/proc/self/status", encoding="ascii") as fh:
        size = next(int(line.split()[1]) * 1024 for line in fh if line.startswith("VmSize:"))
    hard = resource.getrlimit(resource.RLIMIT_AS)[1]
    soft = size + limit if hard == resource.RLIM_INFINITY else min(size + limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
