"""The work budget, where the pipeline keeps it: checked once where a frame, a cycle, a film or the player
begins, and passed down.

The stages predict their own cost (:mod:`sunset.vector.budget` the vector
stage's samples and memory, :mod:`sunset.light.budget` the RGB back end's);
the pipeline checks the prediction against the budgets of
:mod:`sunset.constants` before any work is done, and a request over budget
ends with one line naming what to change.
"""

from __future__ import annotations

import math

from ..constants import INTERPRETER_BYTES, MAX_FRAME_BYTES, MAX_PIXELS
from ..errors import SunsetError
from ..light.budget import GEOMETRY_BYTES_PER_RAY, rgb_bytes
from ..light.render import check_samples, supersampled
from ..vector.budget import Work, check_work

__all__ = ["check_rgb_work", "rgb_work", "MAX_GEOMETRY_BYTES", "check_geometry_bytes", "workers_within_budget"]

#: Most bytes the stored geometries of one RGB film's wave cycle may take.
MAX_GEOMETRY_BYTES = 3 * 2**30


def check_rgb_work(scene, samples: int = 1, frames: int = 0) -> int:
    """Raise :class:`SunsetError` when the RGB back end would exceed its budget; else the predicted bytes.

    Checked before the picture is supersampled: the rays (k² per pixel) may be
    at most MAX_PIXELS, and the predicted peak (:func:`sunset.light.budget.rgb_bytes`)
    with the interpreter's INTERPRETER_BYTES at most MAX_FRAME_BYTES. Then the
    supersampled frame's own work (samples of the sea, the islands, the clouds
    and the posts) is checked as any frame's (:func:`sunset.vector.budget.check_work`).
    """
    return _checked(scene, samples, frames)[0]


def rgb_work(scene, samples: int = 1, frames: int = 0) -> Work:
    """:func:`check_rgb_work`'s checks, once where an RGB frame or film begins; the supersampled frame's
    :class:`~sunset.vector.budget.Work`, which the pipeline passes down to every frame it traces."""
    return _checked(scene, samples, frames)[1]


def _checked(scene, samples: int, frames: int) -> tuple[int, Work]:
    k = check_samples(samples)
    cam = scene.camera
    W, H = cam.width, cam.height
    size = f"{W}x{H}"
    per = "" if samples == 1 else f" at {samples} samples per pixel"
    one = rgb_bytes(W, H, samples)
    if W * H * samples > MAX_PIXELS or INTERPRETER_BYTES + one > MAX_FRAME_BYTES:
        raise SunsetError(f"samples: a {size} picture{per} needs about {math.ceil(one / 2**20):,} MiB and traces "
                          f"{W * H * samples:,} rays (at most {MAX_FRAME_BYTES // 2**20:,} MiB and "
                          f"{MAX_PIXELS:,} rays): use fewer samples or a smaller picture")
    need = rgb_bytes(W, H, samples, frames)
    if INTERPRETER_BYTES + need > MAX_FRAME_BYTES:
        raise SunsetError(f"frames: {frames} frames of a {size} picture{per} keep about {math.ceil(need / 2**20):,} "
                          f"MiB of geometry and light (at most {MAX_FRAME_BYTES // 2**20:,} MiB): use fewer frames, "
                          f"fewer samples or a smaller picture")
    try:
        work = check_work(supersampled(scene, k) if k > 1 else scene)
    except SunsetError as exc:
        if k == 1:
            raise
        raise SunsetError(f"samples: {samples} samples per pixel trace the picture at {W * k}x{H * k}: "
                          f"{exc}") from None
    return need, work


def check_geometry_bytes(scene, samples: int, frames: int) -> None:
    """Raise :class:`SunsetError` when ``frames`` geometries of ``scene`` at ``samples`` would pass MAX_GEOMETRY_BYTES."""
    cam = scene.camera
    need = frames * cam.width * cam.height * samples * GEOMETRY_BYTES_PER_RAY
    if need > MAX_GEOMETRY_BYTES:
        per = f"{samples} sample{'s' * (samples != 1)} per pixel"
        raise SunsetError(f"frames: {frames} frames at {cam.width}x{cam.height}, {per}, would keep up to "
                          f"{need / 2**30:.1f} GiB of geometry (at most "
                          f"{MAX_GEOMETRY_BYTES / 2**30:g} GiB): use fewer frames, fewer samples or a smaller picture")


def workers_within_budget(n: int, geometries) -> int:
    """At most ``n`` workers that, each shading one frame, keep the film within MAX_FRAME_BYTES.

    The cycle's geometries are held once (the workers are forked and share them); each worker adds one
    frame's light and shading (:func:`sunset.light.budget.rgb_bytes` with no geometry kept), and its own copy
    of the geometries where the workers cannot be forked. A large film is shaded by fewer processes rather
    than by more memory than the budget.
    """
    import multiprocessing
    import sys

    from ..constants import MAX_FRAME_BYTES, RGB_BYTES_PER_RAY, RGB_LIGHT_BYTES   # read now (the tests set them)

    if n <= 1 or not geometries:
        return max(1, n)
    kept = sum(g.nbytes for g in geometries)
    per_worker = RGB_LIGHT_BYTES + geometries[0].final_kind.size * RGB_BYTES_PER_RAY
    if not ("fork" in multiprocessing.get_all_start_methods() and sys.version_info < (3, 12)):
        per_worker += kept
    return max(1, min(n, (MAX_FRAME_BYTES - kept) // per_worker))
