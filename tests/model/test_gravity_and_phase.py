"""Scene fields beyond the paper: the sea's gravity and a phase for island cosine hills.

Checked against independent computation (ω² = g k, dimensional scaling of the
sea's motion, eq. 4 written out with NumPy, finite differences), their
validation, and that their defaults leave every earlier scene unchanged.
"""

import math

import numpy as np
import pytest

from sunset.constants import GRAVITY
from sunset.errors import SunsetError
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain

MARS = 3.72076


def carla_text() -> str:
    return Scene.default().to_toml()


# ----------------------------------------------------------------------------- gravity
def test_dispersion_uses_the_seas_gravity():
    sea = Sea((WaveTrain(0.5, 40.0, 260.0), WaveTrain(0.1, 10.0, 235.0)), gravity=MARS)
    for train in sea.trains:
        assert train.gravity == MARS
        k = 2 * math.pi / train.wavelength
        assert train.omega**2 == pytest.approx(MARS * k, rel=1e-15)
        assert train.speed == pytest.approx(math.sqrt(MARS / k), rel=1e-15)


@pytest.mark.parametrize("g", [1.62, MARS, 24.79])
def test_motion_scales_with_the_square_root_of_gravity(g):
    """Under gravity g the sea at time t is the standard-gravity sea at t·√(g/g₀) (ω ∝ √g)."""
    earth = Scene.default().sea
    other = Sea(earth.trains, gravity=g)
    x, y = np.meshgrid(np.linspace(-50, 50, 7), np.linspace(5, 300, 9))
    for t in (0.0, 1.3, 7.0):
        np.testing.assert_allclose(other.elevation(x, y, t), earth.elevation(x, y, t * math.sqrt(g / GRAVITY)),
                                   rtol=0, atol=1e-9)
    assert other.period == pytest.approx(earth.period * math.sqrt(GRAVITY / g), rel=1e-12)


def test_gravity_in_a_scene_file_round_trips():
    text = carla_text().replace("[sea]\n", f"[sea]\ngravity = {MARS}\n")
    scene = Scene.from_toml(text)
    assert scene.sea.gravity == MARS and all(t.gravity == MARS for t in scene.sea.trains)
    assert Scene.from_toml(scene.to_toml()) == scene
    assert f"gravity = {MARS}" in scene.to_toml()


@pytest.mark.parametrize("value, words", [("0.0", r"must be in \[0.1, 300\] m/s²"), ("-9.8", "must be in"),
                                          ("5e-324", "must be in"), ("0.099", "must be in"), ("300.5", "must be in"),
                                          ("1e308", "must be in"),   # issue 33: ω t or the cycle left float64
                                          ("nan", "finite"), ("inf", "finite"), ('"9.8"', "must be a number"),
                                          ("true", "must be a number")])
def test_bad_gravity_is_named(value, words):
    text = carla_text().replace("[sea]\n", f"[sea]\ngravity = {value}\n")
    with pytest.raises(SunsetError, match=rf"sea\.gravity.*{words}|sea\.gravity {words}"):
        Scene.from_toml(text)


def test_a_train_has_no_gravity_of_its_own_in_a_file():
    text = carla_text().replace("stokes_order = 2\n", "stokes_order = 2\ngravity = 3.7\n", 1)
    with pytest.raises(SunsetError, match="unknown key 'sea.trains\\[0\\].gravity'"):
        Scene.from_toml(text)


def test_a_train_with_another_gravity_than_its_sea_is_an_error():
    with pytest.raises(SunsetError, match="set gravity on the sea"):
        Sea((WaveTrain(0.5, 40.0, gravity=MARS),))
    assert Sea((WaveTrain(0.5, 40.0, gravity=MARS),), gravity=MARS).gravity == MARS


def test_periodic_sea_takes_gravity():
    sea = Sea.periodic(40.0, [0.5, 0.1], [260.0, 235.0], gravity=MARS)
    assert sea.period == pytest.approx(math.sqrt(2 * math.pi * 40.0 / MARS), rel=1e-12)


# ----------------------------------------------------------------------------- cosine phase
def island(phase: float) -> Island:
    return Island(x=10.0, y=400.0, cliff_top=30.0, hill_factor=0.4,
                  cliff=Paraboloid(60.0, 0.004, 0.001, 0.003), beach=Paraboloid(4.0, 0.0001, 0.0, 0.0001),
                  cosines=(Cosine(5.0, 0.08, 0.05, phase), Cosine(2.0, -0.1, 0.17)))


@pytest.mark.parametrize("phase", [0.0, 0.7, math.pi, -2.0])
def test_cliff_equation_with_a_phase_is_eq4_with_the_phase(phase):
    x, y = np.meshgrid(np.linspace(-40, 60, 11), np.linspace(360, 440, 9))
    dx, dy = x - 10.0, y - 400.0
    expected = (60.0 - (0.004 * dx * dx + 0.001 * dx * dy + 0.003 * dy * dy)
                + 5.0 * np.cos(0.08 * x + 0.05 * y + phase) + 2.0 * np.cos(-0.1 * x + 0.17 * y))
    np.testing.assert_allclose(island(phase).cliff_equation(x, y), expected, rtol=0, atol=1e-12)


def test_phase_pi_turns_a_hill_into_a_hollow():
    x, y = np.meshgrid(np.linspace(-40, 60, 11), np.linspace(360, 440, 9))
    flat = island(0.0)
    hollow = island(math.pi)
    # Q(φ = π) = P + Σ_others − a cos(ℓx + my): the mirror of Q(φ = 0) about P + Σ_others
    base = flat.cliff_equation(x, y) - 5.0 * np.cos(0.08 * x + 0.05 * y)
    np.testing.assert_allclose(hollow.cliff_equation(x, y), base - 5.0 * np.cos(0.08 * x + 0.05 * y), atol=1e-9)


def test_gradient_with_a_phase_matches_finite_differences():
    isl = island(1.1)
    x, y = np.array([3.0, -17.0, 25.0]), np.array([390.0, 410.0, 402.0])
    h = 1e-5
    gx, gy = isl.cliff_equation_gradient(x, y)
    fx = (isl.cliff_equation(x + h, y) - isl.cliff_equation(x - h, y)) / (2 * h)
    fy = (isl.cliff_equation(x, y + h) - isl.cliff_equation(x, y - h)) / (2 * h)
    np.testing.assert_allclose(gx, fx, atol=1e-6)
    np.testing.assert_allclose(gy, fy, atol=1e-6)


def test_phase_in_a_scene_file_round_trips_and_is_validated():
    text = carla_text().replace("l = 0.08\nm = 0.05\n", "l = 0.08\nm = 0.05\nphase = 1.25\n")
    scene = Scene.from_toml(text)
    assert scene.islands[0].cosines[0].phase == 1.25
    assert Scene.from_toml(scene.to_toml()) == scene
    with pytest.raises(SunsetError, match=r"islands\[0\]\.cosines\[0\]\.phase must be a finite number"):
        Scene.from_toml(text.replace("phase = 1.25", "phase = nan"))


# ----------------------------------------------------------------------------- defaults change nothing
def test_defaults_leave_scenes_and_their_toml_unchanged():
    scene = Scene.default()
    assert scene.sea.gravity == GRAVITY
    assert all(c.phase == 0.0 for i in scene.islands for c in i.cosines)
    text = scene.to_toml()
    assert "gravity" not in text and "\nphase = 0.0\nstokes" in text and text.count("phase") == len(scene.sea.trains)
    explicit = text.replace("[sea]\n", f"[sea]\ngravity = {GRAVITY!r}\n").replace("l = 0.08\nm = 0.05\n",
                                                                                 "l = 0.08\nm = 0.05\nphase = 0.0\n")
    again = Scene.from_toml(explicit)
    assert again == scene and again.to_toml() == text


def test_defaults_render_bit_for_bit_as_before():
    """A zero phase adds nothing (not even +0.0) and standard gravity is the old constant: same codes."""
    from sunset.pipeline.frame import code_frame

    scene = Scene.default().with_size(48, 40)
    text = scene.to_toml().replace("[sea]\n", f"[sea]\ngravity = {GRAVITY!r}\n").replace(
        "l = 0.08\nm = 0.05\n", "l = 0.08\nm = 0.05\nphase = 0.0\n")
    assert np.array_equal(code_frame(scene, 1.0, 2), code_frame(Scene.from_toml(text), 1.0, 2))
    shifted = Scene.from_toml(scene.to_toml().replace("l = 0.08\nm = 0.05\n", "l = 0.08\nm = 0.05\nphase = 2.0\n"))
    assert not np.array_equal(code_frame(scene, 0.0, 0), code_frame(shifted, 0.0, 0))
