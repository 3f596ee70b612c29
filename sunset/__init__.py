"""sunset: Nelson Max's 1981 "Waves and Islands in the Sunset", reproduced.

The public API, in the order of the paper's pipeline::

    scene = sunset.Scene.default()            # or Scene.from_toml("my.toml")
    frame = sunset.render(scene, t=0.0, reflections=2)   # vector stage
    codes = sunset.encode(scene, frame)       # the 8-bit tape
    rgb = sunset.expose(scene, codes, hours=0.5)          # film recorder
    sunset.make_film(scene, "sunset.mp4")     # one wave cycle, filmed as the sun sets
    wave = sunset.solve_stokes(0.12)          # an exact Stokes wave, H/λ = 0.12

and everything at once, for a notebook (a packaged scene's name works
wherever a scene does; ``sunset.scene_names()`` lists them)::

    rgb = sunset.picture("storm-swell", t=0.0, hours=1.0, size=(400, 400))
"""

from importlib import metadata as _metadata

from .provenance import DISTRIBUTION as _DISTRIBUTION

try:
    #: The version, read from the installed distribution's metadata (pyproject.toml is its one source).
    __version__: str = _metadata.version(_DISTRIBUTION)
except _metadata.PackageNotFoundError:  # pragma: no cover - running from a source tree that was never installed
    __version__ = "0+unknown"

from .model.camera import Camera
from .tape.codes import encode
from .recorder.dicomed import expose
from .errors import SunsetError
from .recorder.film import make_film
from .vector.frame import Frame
from .model.islands import Cosine, Island, Paraboloid
from .model.scene import Scene, default_scene, scene_names
from .pictures import picture
from .vector.render import render
from .model.stokes_exact import solve_stokes
from .model.sun import Sun
from .model.waves import Sea, WaveTrain

__all__ = [
    "Camera", "Cosine", "Frame", "Island", "Paraboloid", "Scene", "Sea", "Sun",
    "SunsetError", "WaveTrain", "default_scene", "encode", "expose", "make_film", "picture", "render",
    "scene_names", "solve_stokes", "__version__",
]
