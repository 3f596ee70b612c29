"""The pipeline's worker processes: how many, how they start, and a map over them in order.

Frames of a wave cycle, hours of the player's tables and frames of an RGB
film are independent: each is computed by the same deterministic code in a
worker process as in one process, and the results are collected in order, so
the outputs are the same bytes for any number of workers (tests).
"""

from __future__ import annotations

from ..errors import require_int_range

__all__ = ["usable_cpus", "frame_workers", "start_method", "process_map"]


def usable_cpus() -> int:
    """The CPUs this process may run on (:func:`sunset.guard.usable_cpus`)."""
    from ..guard import usable_cpus as cpus

    return cpus()


def frame_workers(workers: int | None = None, frames: int = 1) -> int:
    """How many processes render frames: ``workers`` (``--jobs``), else ``$SUNSET_WORKERS``, else every usable CPU.

    Never more than ``frames`` nor than the usable CPUs: more processes buy nothing. A bad
    ``$SUNSET_WORKERS`` (a sign, a word, non-ASCII digits, 0) raises (:func:`sunset.guard.env_count`).
    """
    from ..guard import env_count

    if workers is None:
        workers = env_count("SUNSET_WORKERS") or usable_cpus()
    require_int_range("workers", workers, 1)
    return max(1, min(int(workers), int(frames), usable_cpus()))


def start_method() -> str:
    """How worker processes start: forked where the platform allows (cheapest: the children share the loaded
    kernels and the parent's data); Python 3.12+ warns about forking a process that has threads (BLAS has), so
    there the forkserver starts them, else spawn."""
    import multiprocessing
    import sys

    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and sys.version_info < (3, 12):
        return "fork"
    return "forkserver" if "forkserver" in methods else "spawn"


def process_map(fn, tasks, n: int):
    """Yield ``fn(task)`` for every task, in order: here, one after the other, when ``n`` <= 1, else over ``n``
    worker processes (:func:`start_method`)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    tasks = list(tasks)
    if n <= 1 or len(tasks) <= 1:
        for task in tasks:
            yield fn(task)
        return
    with ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context(start_method())) as pool:
        yield from pool.map(fn, tasks)
