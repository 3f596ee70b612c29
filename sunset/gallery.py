"""The packaged scenes, and how the gallery shows each of them.

Scenes ship as TOML files in ``sunset/scenes/``; any of them can be named
wherever a scene is expected (``sunset.picture("storm-swell")``,
``sunset render storm-swell -o f.png``). :data:`GALLERY` says at what hour
and time the book's gallery page shows each one.
"""

from __future__ import annotations

from dataclasses import dataclass

from .model.scene import scene_names

__all__ = ["Showing", "GALLERY", "scene_names"]


@dataclass(frozen=True)
class Showing:
    """How the gallery shows one packaged scene.

    Attributes
    ----------
    name : str
        The scene's name (its file ``sunset/scenes/<name>.toml`` without ``.toml``).
    hours : float
        Hours before sunset of the colour tables (negative: after sunset).
    t : float
        Time of the sea, seconds.
    """

    name: str
    hours: float
    t: float = 0.0


#: Every packaged scene, in the order the gallery shows them.
GALLERY: tuple[Showing, ...] = (
    Showing("carlas-island", 0.35),
    Showing("carlas-island-clouds", 0.35),
    Showing("still-lake-at-noon", 6.0),
    Showing("storm-swell", 1.0, 1.5),
    Showing("archipelago-at-dusk", -0.15),
    Showing("post-in-the-swell", 1.0),
    Showing("carlas-island-in-the-wind", 0.35),
    Showing("fresh-gale", 1.0),
)
