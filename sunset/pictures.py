"""One call from a scene to a picture: :func:`picture`.

The whole pipeline of the paper at once, for a notebook or a script: the
vector stage (:func:`sunset.render`, :func:`sunset.encode`: a scene and a time
to 8-bit codes) and the film recorder (:func:`sunset.expose`: codes and an
hour to RGB).
"""

from __future__ import annotations

import os

import numpy as np

from .model.scene import Scene

__all__ = ["picture"]


def picture(scene: Scene | str | os.PathLike[str], t: float = 0.0, hours: float = 0.35,
            size: tuple[int, int] | None = (400, 400), reflections: int = 2, seed: int = 0) -> np.ndarray:
    """Render a scene at time ``t`` and expose it for ``hours`` before sunset.

    Parameters
    ----------
    scene : Scene, str or path
        A :class:`~sunset.Scene`, the name of a packaged scene (see
        :func:`sunset.scene_names`, e.g. ``"storm-swell"``) or a scene TOML file.
    t : float
        Time of the sea, seconds.
    hours : float
        Hours before sunset of the colour tables (negative after sunset).
    size : (int, int) or None
        (width, height) in pixels; None keeps the scene camera's size.
    reflections : {0, 1, 2}
        Reflection mode (see :func:`sunset.render`).
    seed : int
        Dither seed.

    Returns
    -------
    ndarray (height, width, 3) uint8
        The picture, RGB.

    Examples
    --------
    >>> rgb = picture("carlas-island", size=(64, 48))
    >>> rgb.shape, rgb.dtype
    ((48, 64, 3), dtype('uint8'))
    """
    from .pipeline.frame import code_frame, expose
    from .errors import real_number, require_size, require_time
    from .model.scene import as_scene

    scene = as_scene(scene)
    real_number("hours", hours)
    require_time("t", real_number("t", t))
    if size is not None:
        scene = scene.with_size(*require_size("size", size))
    codes = code_frame(scene, t, reflections, seed)
    return expose(scene, codes, hours)
