"""The brute-force reference caster (sunset/vector/bruteforce.py) against exact answers."""

import numpy as np
import pytest

from sunset.vector.bruteforce import compare, island_circle, island_hits, sea_hits, trace_direct_bruteforce
from sunset.model.camera import Camera
from sunset.constants import PART_BEACH, PART_HILL, SEA, SKY
from sunset.errors import SunsetError
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain


def test_still_water_is_the_plane():
    cam = Camera(eye_height=3.0, width=12, height=14)
    frame = trace_direct_bruteforce(Scene(camera=cam), 0.0)
    D = cam.directions()
    sea = D[..., 2] < 0
    np.testing.assert_array_equal(frame.surface, np.where(sea, SEA, SKY))
    np.testing.assert_allclose(frame.distance[sea], 3.0 / -D[..., 2][sea], rtol=1e-6)


def test_first_crossing_of_a_wave_train():
    sea = Sea((WaveTrain(0.4, 12.0, 260.0, 0.5, 2),))
    h, t = 1.5, 0.3
    s = np.array([-0.2, 0.0, 0.1, 0.3])
    zeta = np.array([-0.02, -0.05, -0.2, -0.01])
    y = sea_hits(sea, h, s, zeta, t)
    F = lambda yy, i: sea.elevation(s[i] * yy, yy, t) - h - zeta[i] * yy  # noqa: E731
    for i in range(s.size):
        assert abs(F(y[i], i)) < 1e-9
        # independently: a very fine grid finds no earlier crossing
        grid = np.linspace(1e-3, y[i], 200001)[:-1]
        assert np.all(F(grid, i) < 0)


def test_rays_above_the_horizon_miss_the_sea():
    sea = Sea((WaveTrain(0.4, 12.0),))
    y = sea_hits(sea, 2.0, np.zeros(3), np.array([0.0, 0.01, 0.3]))
    assert np.all(np.isinf(y))


def test_bare_paraboloid_matches_the_quadratic():
    isl = Island(x=-20.0, y=500.0, cliff=Paraboloid(50.0, 0.003, -0.001, 0.004), beach=Paraboloid(0.5, 0.01, 0.0, 0.01),
                 cliff_top=49.0, hill_factor=1.0)
    h = 2.0
    s = np.linspace(-0.12, 0.05, 9)
    zeta = np.full(9, 0.02)
    y = island_hits(isl, h, s, zeta, 0.0)
    par, X, Y = isl.cliff, isl.x, isl.y
    A = par.e * s**2 + par.f * s + par.g
    B = 2 * par.e * s * X + par.f * (X + s * Y) + 2 * par.g * Y
    C = par.e * X**2 + par.f * X * Y + par.g * Y**2 - par.height + h
    disc = (B - zeta) ** 2 - 4 * A * C
    exact = np.where(disc > 0, ((B - zeta) - np.sqrt(np.abs(disc))) / (2 * A), np.inf)
    assert np.isfinite(exact).sum() >= 5
    np.testing.assert_allclose(y, exact, rtol=1e-10)


def test_island_circle_bounds_the_island():
    isl = Island(x=0.0, y=800.0, cliff=Paraboloid(90.0, 0.004, 0.003, 0.002), beach=Paraboloid(3.0, 5e-5, 0, 4e-5),
                 cliff_top=40.0, hill_factor=0.3, cosines=(Cosine(4.0, 0.1, 0.05),))
    d = 0.6
    R = island_circle(isl, d)
    ang = np.linspace(0, 2 * np.pi, 721)
    for r in (R, 1.2 * R):
        assert np.all(isl.height(isl.x + r * np.cos(ang), isl.y + r * np.sin(ang)) <= -d + 1e-9)


def test_frame_of_the_default_scene_is_well_formed():
    scene = Scene.default().with_size(20, 16)
    frame = trace_direct_bruteforce(scene, 0.0)
    assert frame.shape == (16, 20)
    hit = frame.surface != SKY
    np.testing.assert_allclose(np.linalg.norm(frame.normal[hit], axis=-1), 1.0, rtol=1e-5)
    assert np.all(np.isnan(frame.point[~hit]))
    island = frame.surface > 0
    assert island.any()
    assert np.all((frame.part[island] >= PART_BEACH) & (frame.part[island] <= PART_HILL))
    np.testing.assert_allclose(frame.point[hit], frame.direction[hit] * frame.distance[hit][:, None], rtol=1e-5, atol=1e-4)


@pytest.mark.parametrize("kw, name", [({"t": float("nan")}, "t"), ({"sea_step": 0.0}, "sea_step"),
                                      ({"island_step": -1.0}, "island_step")])
def test_bad_arguments(kw, name):
    scene = Scene.default().with_size(4, 4)
    args = {"t": 0.0, **kw}
    with pytest.raises(SunsetError, match=f"^{name} "):
        trace_direct_bruteforce(scene, **args)


def test_compare_counts_agreement_and_errors():
    scene = Scene(camera=Camera(width=8, height=10))
    ref = trace_direct_bruteforce(scene, 0.0)
    same = compare(ref, ref)
    assert same["agree"] == 1.0 and same["agree_part"] == 1.0
    assert same["sea_median"] == 0.0 and same["n_island"] == 0 and np.isnan(same["island_max"])
    other = trace_direct_bruteforce(scene, 0.0)
    other.surface[0, :4] = SEA          # 4 of 80 pixels now disagree
    other.distance[-1, 0] *= 1.5        # one sea distance 50 % off
    res = compare(other, ref)
    assert res["agree"] == pytest.approx(76 / 80)
    assert res["n_sea"] == int((ref.surface == SEA).sum())
    assert res["sea_p99"] > 0 and res["sea_median"] == 0.0
    with pytest.raises(SunsetError, match="^frame "):
        compare(trace_direct_bruteforce(scene.with_size(4, 4), 0.0), ref)
