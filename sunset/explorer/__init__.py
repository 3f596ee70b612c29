"""Play with a scene: :func:`explore`, sliders that re-render the picture as they move.

In a notebook (JupyterLab, with ``pip install sunset-waves[explore]``)::

    import sunset
    sunset.explore()                     # Carla's Island; or "storm-swell", "my.toml", a Scene

The explorer's parts: what the controls change in the scene
(:mod:`~sunset.explorer.settings`), the pictures, the code under the pointer
and the saved scene file (:mod:`~sunset.explorer.picture`), the render
thread where the newest request wins (:mod:`~sunset.explorer.worker`), and
the widgets (:mod:`~sunset.explorer.widget`, which alone imports ipywidgets
and anywidget).
"""

from __future__ import annotations

from ..model.scene import SceneLike

__all__ = ["explore"]


def explore(scene: SceneLike = "carlas-island", size: tuple[int, int] = (512, 512), hours: float = 0.35,
            t: float = 0.0, reflections: int = 2, shading: str = "codes", seed: int = 0):
    """An explorer of ``scene``: its picture, re-rendered whenever a control moves.

    The controls: hours before sunset, the time in the sea's cycle, the sun's
    azimuth, each wave train's amplitude, wavelength rung and direction, the
    camera's height, heading and pitch, reflections 0/1/2 and the shading
    (the paper's 8-bit codes, or RGB); the pointer over the picture shows what
    its code means, as in the colour-table player; "save scene" writes the
    settings as a scene file from which ``sunset render`` draws the same
    picture (its first comment gives the command). A setting the scene
    refuses shows its one-line error and the last good picture stays.

    Parameters
    ----------
    scene : Scene, str or path
        A :class:`~sunset.Scene`, the name of a packaged scene (see
        :func:`sunset.scene_names`) or a scene TOML file; Carla's Island by default.
    size : (int, int)
        (width, height) of the picture in pixels (512 × 512).
    hours, t, reflections, shading, seed
        The first settings: hours before sunset, the sea's time (s), the
        reflection mode 0/1/2, ``"codes"`` or ``"rgb"``, the dither seed.

    Returns
    -------
    Explorer
        An ipywidgets box: show it in a notebook (the last expression of a
        cell). Its ``controls``, ``picture``, ``error``, ``wait()``, ``save_scene()``
        and ``readout()`` drive it from Python too.
    """
    from ..errors import SunsetError
    from .settings import Start

    start = Start.of(scene, size=size, hours=hours, t=t, reflections=reflections, shading=shading, seed=seed)
    try:
        from .widget import Explorer
    except ImportError as exc:   # pragma: no cover - the explore extra is in the test environment
        raise SunsetError(f"the explorer needs ipywidgets and anywidget (pip install 'sunset-waves[explore]'): "
                          f"{exc}") from None
    return Explorer(start)
