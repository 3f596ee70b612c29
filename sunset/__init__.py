"""sunset: Nelson Max's 1981 "Waves and Islands in the Sunset", reproduced.

The public API, in the order of the paper's pipeline::

    scene = sunset.Scene.default()            # or Scene.from_toml("my.toml")
    frame = sunset.render(scene, t=0.0, reflections=2)   # vector stage
    codes = sunset.encode(scene, frame)       # the 8-bit tape
    rgb = sunset.expose(scene, codes, hours=0.5)          # film recorder
    sunset.make_film(scene, "sunset.mp4")     # one wave cycle, filmed as the sun sets
    wave = sunset.solve_stokes(0.12)          # an exact Stokes wave, H/λ = 0.12
    series = sunset.stokes_series(30)         # Stokes' expansion to α³⁰, exact fractions

and everything at once, for a notebook (a packaged scene's name works
wherever a scene does; ``sunset.scene_names()`` lists them)::

    rgb = sunset.picture("storm-swell", t=0.0, hours=1.0, size=(400, 400))
    sunset.explore("storm-swell")             # sliders that re-render it (the explore extra)
"""

from importlib import metadata as _metadata

from .provenance import DISTRIBUTION as _DISTRIBUTION

try:
    #: The version, read from the installed distribution's metadata (pyproject.toml is its one source).
    __version__: str = _metadata.version(_DISTRIBUTION)
except _metadata.PackageNotFoundError:  # pragma: no cover - running from a source tree that was never installed
    __version__ = "0+unknown"

import importlib

#: Where each name of the public API lives. The names are loaded on first use
#: (PEP 562), so that ``import sunset.cli`` is quick and a Ctrl-C while the
#: renderer's modules load is caught by the command line (one line, exit 130).
_API = {
    "Camera": ".model.camera", "encode": ".pipeline.frame", "expose": ".pipeline.frame", "SunsetError": ".errors",
    "make_film": ".pipeline.film", "Frame": ".vector.frame", "Cosine": ".model.islands",
    "Island": ".model.islands", "Paraboloid": ".model.islands", "Scene": ".model.scene",
    "default_scene": ".model.scene", "render": ".pipeline.frame", "solve_stokes": ".model.stokes_exact",
    "Sun": ".model.sun", "Sea": ".model.waves", "WaveTrain": ".model.waves", "scene_names": ".model.scene",
    "picture": ".pictures", "stokes_series": ".model.series", "explore": ".explorer",
}


def __getattr__(name: str):
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'sunset' has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))


__all__ = [
    "Camera", "Cosine", "Frame", "Island", "Paraboloid", "Scene", "Sea", "Sun",
    "SunsetError", "WaveTrain", "default_scene", "encode", "explore", "expose", "make_film", "picture", "render",
    "scene_names", "solve_stokes", "stokes_series", "__version__",
]
