"""sunset: Nelson Max's 1981 "Waves and Islands in the Sunset", reproduced.

The public API, in the order of the paper's pipeline::

    scene = sunset.Scene.default()            # or Scene.from_toml("my.toml")
    frame = sunset.render(scene, t=0.0, reflections=2)   # vector stage
    codes = sunset.encode(scene, frame)       # the 8-bit tape
    rgb = sunset.expose(scene, codes, hours=0.5)          # film recorder
    sunset.make_film(scene, "sunset.mp4")     # one wave cycle, filmed as the sun sets
    wave = sunset.solve_stokes(0.12)          # an exact Stokes wave, H/λ = 0.12
"""

from .model.camera import Camera
from .tape.codes import encode
from .recorder.dicomed import expose
from .errors import SunsetError
from .recorder.film import make_film
from .vector.frame import Frame
from .model.islands import Cosine, Island, Paraboloid
from .model.scene import Scene, default_scene
from .vector.render import render
from .model.stokes_exact import solve_stokes
from .model.sun import Sun
from .model.waves import Sea, WaveTrain

__version__ = "0.1.0"

__all__ = [
    "Camera", "Cosine", "Frame", "Island", "Paraboloid", "Scene", "Sea", "Sun",
    "SunsetError", "WaveTrain", "default_scene", "encode", "expose", "make_film", "render", "solve_stokes",
    "__version__",
]
