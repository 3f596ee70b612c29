"""The public API (sunset/__init__.py): short, stable, and the pipeline its docstring shows works."""

import numpy as np

import sunset
from sunset.constants import SKY


def test_everything_exported_exists():
    for name in sunset.__all__:
        assert hasattr(sunset, name), name
    names = [n for n in sunset.__all__ if not n.startswith("__")]    # __version__ aside
    assert len(names) <= 20          # short: a reader can hold it in mind


def test_the_docstring_pipeline_runs_scene_to_rgb():
    scene = sunset.Scene.default().with_size(40, 32)
    frame = sunset.render(scene, t=0.0, reflections=2)
    codes = sunset.encode(scene, frame)
    rgb = sunset.expose(scene, codes, hours=0.5)
    assert codes.dtype == np.uint8 and codes.shape == (32, 40)
    assert rgb.dtype == np.uint8 and rgb.shape == (32, 40, 3)
    # the top row looks at the sky, the bottom row at the sea
    assert np.all(frame.surface[0] == SKY) and np.all(frame.surface[-1] == 0)
    # the vector stage and the film recorder are separate: other tables, same codes, other colours
    assert not np.array_equal(rgb, sunset.expose(scene, codes, hours=4.5))
