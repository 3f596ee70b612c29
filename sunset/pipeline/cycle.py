"""A wave cycle's tape through the pipeline: what stays still computed once, the frames over worker processes.

In a wave cycle only the sea moves. The islands' share of the direct rays
(:func:`sunset.pipeline.frame.island_pass`) does not change with time, and
neither does anything the 8-bit code of a pixel depends on where the sea does
not reach it: a direct ray that ends in the sky is coded by its direction
alone, one that ends on an island by the island's part and normal there, and
the dither is the same for every frame (:func:`sunset.tape.codes.dither`).
So :func:`cycle_pass` codes, once per cycle, the frame of the islands and the
sky alone (their depth buffer, with no sea merged in, through the strip
kernel of every frame, :func:`sunset.pipeline.frame.code_rows`): every pixel
the sea does not take has that code in every frame. A frame of the cycle
(:func:`sunset.pipeline.frame.code_frame` with the :class:`CyclePass`) then
traces and codes only its sea pixels, strip by strip of rows; the codes are
byte-identical to the whole frame's (tests). Scenes with clouds or posts in
the water are coded the whole way: their sky and posts are not still in the
same sense.

:func:`code_frames` codes the frames of a cycle in a pool of processes
(:func:`sunset.pipeline.workers.frame_workers`), byte-identical to a serial run.
"""

from __future__ import annotations

import numpy as np

from ..errors import require_int_range
from ..kernels import keep_freed_memory, row_strips, run_strips, use_threads
from ..model.scene import Scene
from ..vector.direct import DepthBuffer, IslandPass, check_island_pass, ray_directions, row_heights
from ..vector.budget import check_work
from .frame import CyclePass, check_cycle_pass, code_frame, code_rows, island_pass, still_key  # noqa: F401
from .workers import frame_workers, start_method

__all__ = ["CyclePass", "cycle_pass", "still_key", "check_cycle_pass", "code_frames"]


def cycle_pass(scene, seed: int = 0, islands: IslandPass | None = None, *, work=None) -> CyclePass:
    """The still part of every frame of ``scene``'s wave cycle coded with ``seed`` (:class:`CyclePass`).

    ``islands``: the scene's island pass, when it is already there; ``work``: the budget, checked already.
    """
    require_int_range("seed", seed, 0, 2**32 - 1)
    if islands is None:
        islands = island_pass(scene, work=work)
    check_island_pass(scene, islands)
    cam = scene.camera
    W, H = cam.width, cam.height
    s, zeta = cam.s_centres(), row_heights(cam)
    depth = DepthBuffer(islands.u, islands.code, s, zeta)     # no sea merged in
    codes = code_rows(scene, 0.0, 0, seed, depth)
    direction = np.empty((H, W, 3), np.float32)

    def rays(r0: int, r1: int) -> None:
        ray_directions(s, zeta[H - r1:H - r0], direction[r0:r1])

    run_strips(rays, row_strips(H, W))
    for a in (direction, codes):
        a.flags.writeable = False
    return CyclePass(key=still_key(scene, seed), islands=islands, direction=direction, codes=codes, seed=int(seed))


#: What a worker process of :func:`code_frames` keeps for all its frames: the islands' pass, and the
#: cycle's codes where they are shared with the parent.
_WORKER: dict = {}


def _start_worker(islands, work=None, out=None) -> None:
    _WORKER["islands"] = islands
    _WORKER["work"] = work
    _WORKER["out"] = out
    # the frames' large arrays are the same size every frame: the allocator keeps them instead of handing them
    # back to the system and faulting them in again, page by page, for the next frame (the worker's peak
    # memory is one frame's, as before)
    keep_freed_memory()
    release_inherited_memory()


def release_inherited_memory() -> bool:
    """Hand the free blocks of the allocator's heap, inherited from the parent at the fork, back to the system.

    A forked worker shares its parent's pages until it writes them; the
    parent's freed frame arrays are in its heap's free lists, so a worker's
    first frame would reuse them and copy every page it writes, 4 KiB at a
    time (about 14 000 faults for a 1020 × 1023 frame, 30–50 ms of system
    time). Released (glibc's ``malloc_trim(0)``), they come back as fresh
    pages, which NumPy's large arrays take as huge pages. The bytes computed
    are the same; True where it was done, a no-op off glibc.
    """
    import ctypes

    try:
        trim = ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):       # pragma: no cover - not glibc
        return False
    trim(0)
    return True


def _code_frame_task(args):
    # the frames run side by side in the processes, one thread each
    i, args = args
    with use_threads(1):
        codes = code_frame(*args, islands=_WORKER.get("islands"), work=_WORKER.get("work"))
    out = _WORKER.get("out")
    if out is None:
        return codes
    out[i] = codes                           # straight into the parent's memory: nothing to send back
    return None


def _worker_ignores_interrupts():
    """Ctrl-C (or a signal to the process group) reaches the workers too: only the parent reports it.

    The parent then cancels the frames not yet begun, and the workers end
    after the frame they are rendering (:func:`code_frames`).
    """
    import signal

    for sig in _STOP_SIGNALS:
        signal.signal(sig, signal.SIG_IGN)
    if _STOP_SIGNALS and hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)     # blocked by the parent around the fork


def _start_quiet_worker(islands, work=None, out=None) -> None:
    _worker_ignores_interrupts()
    _start_worker(islands, work, out)


def _stop_signals():
    import signal

    return tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


_STOP_SIGNALS = _stop_signals()


#: The kinds of frame (:func:`_warm_key`) this process has coded: their compiled kernels are loaded.
_WARM: set = set()


def _warm_key(scene: Scene) -> tuple:
    """What decides which kernels a frame of ``scene`` loads: the sea alone or the whole frame, compiled or not."""
    from ..kernels import enabled

    return (scene.clouds is None and not scene.posts, enabled())


def code_frames(scene: Scene, times, reflections: int = 2, seed: int = 0, workers: int | None = None,
                on_frame=None):
    """Code the frames at ``times`` (seconds), in order, over ``workers`` processes.

    Frames are independent, so they are shared out to a process pool (frames
    i, i + w, … go to whichever worker is free); the results are collected in
    order, and each frame is computed by the same deterministic code as in
    one process, so the codes are byte-identical to the serial path. The first
    frame is rendered here first, so that the workers (forked where the
    platform allows) inherit compiled kernels instead of loading them each;
    once this process has coded a frame of the same kind, the kernels are
    loaded and every frame goes to the workers (no frame waits for another).

    The islands do not move: their share of the direct rays
    (:func:`sunset.pipeline.frame.island_pass`) and the codes of what the
    sea does not reach (:func:`cycle_pass`) are computed once, here, and
    handed to every worker when it starts, instead of once per frame; so is
    the budget, checked once for the cycle (:func:`sunset.vector.budget.check_work`).

    Each worker holds one frame at a time, so the workers are at most
    MAX_FRAME_BYTES over the frame's predicted bytes: a large picture is
    coded by fewer processes rather than by more memory than the budget.

    Parameters
    ----------
    on_frame : callable, optional
        Called with (index, codes) as each frame arrives (a progress bar).

    Where the workers are forked, they write their frames straight into
    the returned array, which lives in memory shared with them, instead of
    sending each back through a pipe; each keeps its freed frame arrays for
    the next frame (:func:`sunset.kernels.keep_freed_memory`).

    Returns
    -------
    ndarray (N, H, W) uint8
    """
    import multiprocessing
    import threading
    from concurrent.futures import ProcessPoolExecutor

    times = [float(t) for t in times]
    cam = scene.camera
    out = np.empty((len(times), cam.height, cam.width), np.uint8)
    n = frame_workers(workers, len(times))
    work = check_work(scene) if times else None     # the budget, once for the cycle, passed to every frame
    if n > 1 and work is not None:           # every worker holds a frame: together they keep to the budget
        from ..constants import MAX_FRAME_BYTES

        n = max(1, min(n, MAX_FRAME_BYTES // max(work.bytes, 1)))

    def put(i, codes):
        out[i] = codes
        if on_frame is not None:
            on_frame(i, codes)

    if not times:
        return out
    method = start_method()
    shared = n > 1 and len(times) > 1 and method == "fork"
    if shared:
        # forked workers write their frames into memory shared with this process (an anonymous shared
        # mapping they inherit) instead of pickling a frame back through a pipe each
        import mmap

        out = np.frombuffer(mmap.mmap(-1, max(out.nbytes, 1)), np.uint8, count=out.size).reshape(out.shape)
    islands = cycle_pass(scene, seed, work=work)
    first = 0
    if n <= 1 or _warm_key(scene) not in _WARM:
        # rendered here first: the workers inherit the loaded kernels (and so does the next call)
        put(0, code_frame(scene, times[0], reflections, seed, islands=islands, work=work))
        _WARM.add(_warm_key(scene))
        first = 1
    rest = [(i, (scene, t, reflections, seed)) for i, t in enumerate(times[first:], start=first)]
    if n <= 1 or not rest:
        for i, args in rest:
            put(i, code_frame(*args, islands=islands, work=work))
        return out
    import signal

    pool = ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context(method),
                               initializer=_start_quiet_worker, initargs=(islands, work, out if shared else None))
    # A signal that arrives while the workers are forked would run the parent's handler inside an
    # at-fork callback, which swallows its exception (the interrupt would be lost) or kill a child
    # before it ignores signals: they are held back until the workers exist, then delivered here.
    block = hasattr(signal, "pthread_sigmask") and threading.current_thread() is threading.main_thread()
    if block:
        held = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    try:
        try:
            results = pool.map(_code_frame_task, rest)
        finally:
            if block:
                signal.pthread_sigmask(signal.SIG_SETMASK, held)
        for i, codes in enumerate(results, start=first):
            if codes is None:                # written in place by the worker
                if on_frame is not None:
                    on_frame(i, out[i])
            else:
                put(i, codes)
    except BaseException:                    # Ctrl-C, SIGTERM, an error: no new frames; the workers finish theirs
        # (killing a worker while it sends its frame back would leave the pool's reader waiting forever)
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
    return out
