"""The direct-ray diagnostic maps (sunset/figures/diagnostic.py)."""

import numpy as np
import pytest
from PIL import Image

from sunset.constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from sunset.errors import SunsetError
from sunset.figures.diagnostic import CLASS_COLOURS, class_image, diagnostic, normal_image
from sunset.pipeline.frame import trace_direct
from sunset.model.scene import Scene


@pytest.fixture(scope="module")
def frame():
    return trace_direct(Scene.default().with_size(64, 48), 0.0)


def test_class_image_colours_each_class(frame):
    rgb = class_image(frame)
    assert rgb.shape == frame.shape + (3,)
    np.testing.assert_allclose(rgb[frame.surface == SKY], np.broadcast_to(CLASS_COLOURS["sky"], rgb[frame.surface == SKY].shape))
    np.testing.assert_allclose(rgb[frame.surface == SEA], np.broadcast_to(CLASS_COLOURS["sea"], rgb[frame.surface == SEA].shape))
    for part, name in ((PART_BEACH, "beach"), (PART_CLIFF, "cliff"), (PART_HILL, "hill")):
        where = (frame.surface == 1) & (frame.part == part)      # island 1 is drawn at full brightness
        np.testing.assert_allclose(rgb[where], np.broadcast_to(CLASS_COLOURS[name], rgb[where].shape))


def test_normal_image_encodes_unit_normals(frame):
    rgb = normal_image(frame)
    hit = frame.surface != SKY
    np.testing.assert_allclose(2 * rgb[hit] - 1, frame.normal[hit], atol=1e-6)
    assert np.all(rgb[~hit] == 0)


def test_diagnostic_writes_a_deterministic_png(tmp_path):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    assert diagnostic(a, size=(48, 40)) == a
    diagnostic(b, size=(48, 40))
    assert a.read_bytes() == b.read_bytes()
    with Image.open(a) as im:
        assert im.width > 0 and im.height > 0


@pytest.mark.parametrize("size", [(0, 40), (48, -1)])
def test_bad_size_is_an_error_and_writes_nothing(tmp_path, size):
    with pytest.raises(SunsetError, match="width|height"):
        diagnostic(tmp_path / "x.png", size=size)
    assert list(tmp_path.iterdir()) == []
