"""The packaged scenes: each loads, validates, renders, and is what its name says."""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

import sunset
from sunset.constants import STOKES_MAX_STEEPNESS
from sunset.errors import SunsetError
from sunset.gallery import GALLERY
from sunset.model.scene import scene_names
from sunset.model.scene import Scene, load_named_scene
from sunset.model.waves import Sea

NAMES = ["archipelago-at-dusk", "carlas-island", "carlas-island-clouds", "carlas-island-in-the-wind", "fresh-gale",
         "post-in-the-swell", "still-lake-at-noon", "storm-swell"]


def test_every_packaged_scene_is_in_the_gallery():
    assert scene_names() == NAMES
    assert sorted(s.name for s in GALLERY) == NAMES


@pytest.mark.parametrize("name", NAMES)
def test_packaged_scene_loads_validates_and_round_trips(name):
    text = (resources.files("sunset") / "scenes" / f"{name}.toml").read_text(encoding="utf-8")
    scene = Scene.from_toml(text)
    assert scene == load_named_scene(name)
    assert scene.title
    assert Scene.from_toml(scene.to_toml()) == scene
    # the loader validates these files like any other: one broken field is named
    broken = text.replace("sigma = 0.25", "sigma = -0.25")
    assert broken != text
    with pytest.raises(SunsetError, match="sigma"):
        Scene.from_toml(broken)


@pytest.mark.parametrize("showing", GALLERY, ids=lambda s: s.name)
def test_gallery_scene_renders(showing):
    rgb = sunset.picture(showing.name, t=showing.t, hours=showing.hours, size=(40, 32))
    assert rgb.shape == (32, 40, 3) and rgb.dtype == np.uint8
    assert rgb.std() > 1.0        # a picture, not a flat colour


def _crest_to_trough(train) -> float:
    """H of one train's profile (its Stokes series), sampled finely over one wavelength."""
    lone = Sea((train,))
    d = math.radians(train.direction)
    u = np.linspace(0.0, train.wavelength, 20001)
    z = lone.elevation(u * math.cos(d), u * math.sin(d), 0.0)
    return float(z.max() - z.min())


def test_storm_swell_is_near_the_stokes_limit():
    scene = load_named_scene("storm-swell")
    steepest = max(scene.sea.trains, key=lambda t: _crest_to_trough(t) / t.wavelength)
    ratio = _crest_to_trough(steepest) / steepest.wavelength
    assert 0.9 * STOKES_MAX_STEEPNESS <= ratio < STOKES_MAX_STEEPNESS
    assert steepest.stokes_order == 4
    # the exact wave of that steepness exists (the solver converges below the limit)
    wave = sunset.solve_stokes(ratio)
    assert wave.steepness == pytest.approx(ratio)
    assert scene.sea.period is not None   # periodic: it can be filmed


def test_still_lake_is_still_and_lit_at_noon():
    scene = load_named_scene("still-lake-at-noon")
    assert scene.sea.max_elevation == 0.0 and scene.sea.period == 0.0
    noon = next(s for s in GALLERY if s.name == "still-lake-at-noon")
    # 6 hours before sunset the sun is at the top of its great circle: elevation = tilt
    assert math.degrees(float(scene.sun.elevation(noon.hours))) == pytest.approx(scene.sun.tilt)
    rgb = sunset.picture(scene, hours=noon.hours, size=(40, 40))
    assert np.array_equal(rgb, sunset.picture("still-lake-at-noon", hours=noon.hours, size=(40, 40)))


def test_archipelago_is_an_archipelago_at_dusk():
    scene = load_named_scene("archipelago-at-dusk")
    assert len(scene.islands) >= 5
    dusk = next(s for s in GALLERY if s.name == "archipelago-at-dusk")
    assert dusk.hours < 0 and float(scene.sun.elevation(dusk.hours)) < 0   # the sun has set
    assert scene.sea.period is not None
