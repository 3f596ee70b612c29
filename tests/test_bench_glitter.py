"""The glitter measured on a rendered RGB picture against Cox and Munk's prediction (sunset/bench/glitter.py).

References: a Gaussian profile's middle 90 % (±1.6449σ, the normal quantile), and Cox and Munk's closed form for the
same pixels, which shares with the picture only the Fresnel factor and the sun.
"""

import math

import numpy as np
import pytest

from sunset.bench.glitter import extent, measure_glitter
from sunset.errors import SunsetError
from sunset.model.scene import Scene


def test_the_extent_of_a_gaussian_is_its_middle_ninety_per_cent():
    x = np.linspace(-10, 10, 2001)
    lo, hi = extent(np.exp(-0.5 * ((x - 1.0) / 2.0) ** 2), x)
    assert lo == pytest.approx(1.0 - 1.6449 * 2.0, abs=0.01) and hi == pytest.approx(1.0 + 1.6449 * 2.0, abs=0.01)
    assert all(math.isnan(v) for v in extent(np.zeros(5), np.arange(5.0)))


@pytest.fixture(scope="module")
def measured():
    scene = Scene.named("carlas-island-in-the-wind").with_size(128, 128)
    return [measure_glitter(scene, t, 0.35) for t in (0.0, 32.0)]


def test_the_pictures_glitter_is_cox_and_munks(measured):
    """One sea differs from the mean of all seas: a frame's total within 40 %, two frames' mean within 25 %."""
    for name in ("cox_munk", "model"):
        ratios = [m["total"]["image"] / m["total"][name] for m in measured]
        assert all(0.6 < r < 1.4 for r in ratios) and 0.75 < np.mean(ratios) < 1.25, (name, ratios)
        for m in measured:
            for side in ("vertical", "horizontal"):
                (a, b), (c, d) = m[side]["image"], m[side][name]
                assert abs((b - a) / (d - c) - 1) < 0.3, (side, m[side])
    for m in measured:
        assert m["image"].shape == (128, 128) and m["image"].min() >= -1e-3 * m["image"].max()
        # at the horizon the flat sea's formula is far above the picture's, which hides what grazing rays miss
        assert m["horizon"]["image"] < 0.5 * m["horizon"]["model"]


def test_only_a_wind_sea_and_a_risen_sun_are_measured():
    with pytest.raises(SunsetError, match="^scene: the glitter is measured on a sea given by its wind"):
        measure_glitter(Scene.default().with_size(16, 16))
    for kw, field in ((dict(below=-1.0), "below"), (dict(below=math.nan), "below"), (dict(hours=math.inf), "hours"),
                      (dict(t=math.nan), "t")):
        with pytest.raises(SunsetError, match=f"^{field}"):
            measure_glitter(Scene.named("carlas-island-in-the-wind").with_size(16, 16), **kw)
    with pytest.raises(SunsetError, match="^hours: the sun is below the horizon"):
        measure_glitter(Scene.named("carlas-island-in-the-wind").with_size(16, 16), 0.0, -1.0)
