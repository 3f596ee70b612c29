"""A wind sea's second reflections (sunset/vector/windsea_crests.py and its Numba twin).

References: a fine fixed-step march written here (no slope bound, no safe
step: steps of a 64th of the march's least step, then bisection), rays that
fall straight down (the hit is the height under them, in closed form) and
rays that climb steeper than any slope of the grid (they never meet it).
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA
from sunset.errors import SunsetError
from sunset.model.scene import Scene
from sunset.model.waves import Sea
from sunset.model.windsea import WindSea
from sunset.pipeline.frame import code_frame, render, trace_direct
from sunset.vector import windsea_crests, windsea_crests_numba
from sunset.vector.pierce import reflect
from sunset.vector.windsea_crests import (MARCH_MAX_TILES, MARCH_MIN_STEP, march_constants, slope_bounds,
                                          wind_march)

#: Hit or miss the same on all but this share of the rays (a graze thinner than the least step, or a
#: crossing the fine march finds by a step's rounding; measured 0 on these frames).
HIT_DISAGREE_SHARE = 0.002
#: Where both hit: the distances within this, metres (the bisection's bracket is δ/2⁴⁰; the fine march's
#: is its step/2⁶⁰).
DISTANCE_ATOL = 1e-6


def wind_scene(width=64, height=48, **wind):
    ws = WindSea(**{**dict(speed=9.0, direction=260.0, fetch=math.inf, seed=2, tile_points=64, tile_size=160.0,
                           cycle=64.0), **wind})
    base = Scene.default().with_size(width, height)
    return replace(base, sea=Sea(wind=ws), camera=replace(base.camera, eye_height=3.0))


def first_rays(scene, t):
    """The sea pixels' first reflected rays of a direct frame: (Q, R) float64."""
    frame = trace_direct(scene, t)
    sea = frame.surface == SEA
    q = frame.point[sea].astype(np.float64)
    return q, reflect(frame.direction[sea].astype(np.float64), frame.normal[sea].astype(np.float64))


def fine_march(tile, t, h, q, r, per=64):
    """The first crossing after the march's start by fixed steps of δ/per, bisected: +inf where none."""
    top, _, _, delta, longest = march_constants(tile, t, h)
    step = delta / per
    out = np.full(len(q), np.inf)
    for j in range(len(q)):
        end = min((top - q[j, 2]) / r[j, 2] if r[j, 2] > 0 else np.inf, longest)
        if not end > delta:
            continue

        def gap(s):
            p = q[j] + np.multiply.outer(s, r[j])
            return (tile.heights(p[..., 0], p[..., 1], t) - h) - p[..., 2]

        if gap(np.array(delta)) >= 0:
            continue
        lo = delta
        while lo < end:
            s = np.minimum(lo + step * np.arange(1, 4097), end)
            under = np.flatnonzero(gap(s) >= 0)
            if under.size:
                a, b = (s[under[0] - 1] if under[0] else lo), s[under[0]]
                for _ in range(60):
                    m = 0.5 * (a + b)
                    a, b = (a, m) if gap(np.array(m)) >= 0 else (m, b)
                out[j] = b
                break
            lo = s[-1]
    return out


@pytest.fixture(scope="module")
def scene():
    return wind_scene()


def test_the_slope_bound_bounds_the_interpolants_slopes(scene):
    """|∂z/∂x| of the bilinear interpolant at random points never exceeds S_x (finite differences of heights)."""
    tile = scene.sea.wind.tile
    sx, sy = slope_bounds(tile.fields(3.0)["z"], tile.spacing)
    rng = np.random.default_rng(1)
    x, y = rng.uniform(0, tile.size, 20000), rng.uniform(0, tile.size, 20000)
    e = 1e-4 * tile.spacing
    dzx = (tile.heights(x + e, y, 3.0) - tile.heights(x - e, y, 3.0)) / (2 * e)
    dzy = (tile.heights(x, y + e, 3.0) - tile.heights(x, y - e, 3.0)) / (2 * e)
    assert np.max(np.abs(dzx)) <= sx * (1 + 1e-6) and np.max(np.abs(dzy)) <= sy * (1 + 1e-6)
    assert np.max(np.abs(dzx)) > 0.5 * sx         # and is not loose by much


@pytest.mark.parametrize("compiled", [False, True])
def test_straight_down_and_steep_up_rays_in_closed_form(scene, compiled):
    """A ray falling straight down meets the sea at the height under it; one climbing faster than S never does."""
    tile, h, t = scene.sea.wind.tile, scene.camera.eye_height, 7.0
    rng = np.random.default_rng(2)
    n = 500
    x, y = rng.uniform(-200, 200, n), rng.uniform(5, 400, n)
    z0 = rng.uniform(-h + tile.bound(t) + 0.1, -h + tile.bound(t) + 3.0, n)
    q = np.stack([x, y, z0], -1)
    down = np.broadcast_to([0.0, 0.0, -1.0], (n, 3))
    sx, sy = slope_bounds(tile.fields(t)["z"], tile.spacing)
    up = np.stack([np.full(n, 0.3), np.full(n, 0.4), np.full(n, 0.3 * sx + 0.4 * sy + 0.01)], -1)
    with kernels.use_compiled(compiled):
        s_down = windsea_crests.wind_march(tile, t, h, q, down)
        s_up = windsea_crests.wind_march(tile, t, h, q, up)
    want = z0 - (tile.heights(x, y, t) - h)
    np.testing.assert_allclose(s_down, want, rtol=0, atol=1e-9)
    assert np.all(np.isinf(s_up))


@pytest.mark.parametrize("t", [0.0, 11.5])
def test_the_march_and_its_twin_against_a_fine_fixed_step_march(scene, t):
    """Both kernels find the fine march's first crossing, hit or miss, on a small frame's reflected rays."""
    tile, h = scene.sea.wind.tile, scene.camera.eye_height
    q, r = first_rays(scene, t)
    ref = wind_march(tile, t, h, q, r)
    got = windsea_crests_numba.wind_march(tile, t, h, q, r)
    rng = np.random.default_rng(int(t))
    hits = np.flatnonzero(np.isfinite(ref))
    pick = np.union1d(rng.choice(hits, size=min(100, hits.size), replace=False),
                      rng.choice(len(q), size=min(300, len(q)), replace=False))
    brute = fine_march(tile, t, h, q[pick], r[pick])
    assert np.isfinite(brute).sum() >= 40, "too few second bounces to test"
    for name, s in (("reference", ref[pick]), ("compiled", got)):
        s = s[pick] if name == "compiled" else s
        differ = np.isfinite(s) != np.isfinite(brute)
        assert differ.sum() <= max(1, HIT_DISAGREE_SHARE * len(pick)), (name, differ.sum())
        both = np.isfinite(s) & np.isfinite(brute)
        np.testing.assert_allclose(s[both], brute[both], rtol=0, atol=DISTANCE_ATOL, err_msg=name)
    # the twins on every ray
    assert np.count_nonzero(np.isfinite(ref) != np.isfinite(got)) <= HIT_DISAGREE_SHARE * len(q)
    both = np.isfinite(ref) & np.isfinite(got)
    np.testing.assert_allclose(got[both], ref[both], rtol=0, atol=DISTANCE_ATOL)


def test_the_march_leaves_after_its_longest_travel(scene):
    """A level ray above every crest but below the leaving height's reach gives up after MARCH_MAX_TILES sides."""
    tile, h, t = scene.sea.wind.tile, scene.camera.eye_height, 0.0
    top, _, _, delta, longest = march_constants(tile, t, h)
    assert longest == MARCH_MAX_TILES * tile.size and delta == tile.spacing / MARCH_MIN_STEP
    q = np.array([[0.0, 10.0, top + 0.01]])
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            assert np.isinf(windsea_crests.wind_march(tile, t, h, q, np.array([[0.0, 1.0, 0.0]])))[0]


@pytest.mark.parametrize("compiled", [False, True])
def test_a_wind_sea_bounces_twice_and_the_codes_change_only_there(scene, compiled):
    """--reflections 2 on a wind sea: some rays bounce twice, and only those pixels' codes differ from one bounce."""
    with kernels.use_compiled(compiled):
        two = render(scene, 4.0, 2)
        one = render(scene, 4.0, 1)
        c2 = code_frame(scene, 4.0, 2)
        c1 = code_frame(scene, 4.0, 1)
    twice = two.bounces == 2
    assert twice.sum() > 0 and np.all(one.bounces[one.surface == SEA] == 1)
    changed = c1 != c2
    assert changed.any()
    assert not np.any(changed & ~twice)


def test_the_twins_frames_agree(scene):
    with kernels.use_compiled(False):
        ref = render(scene, 9.0, 2)
    with kernels.use_compiled(True):
        got = render(scene, 9.0, 2)
    differ = np.count_nonzero(ref.bounces != got.bounces)
    assert differ <= HIT_DISAGREE_SHARE * ref.bounces.size, differ


def test_a_choppy_wind_sea_refuses_two_reflections():
    choppy = wind_scene(24, 16, choppiness=0.5)
    for compiled in (False, True):
        with kernels.use_compiled(compiled), pytest.raises(SunsetError, match=r"^reflections: a choppy wind sea"):
            render(choppy, 0.0, 2)
    assert render(choppy, 0.0, 1).bounces.max() == 1


@pytest.mark.parametrize("compiled", [False, True])
def test_the_rgb_back_end_bounces_twice_on_a_wind_sea(compiled):
    """The RGB picture with two reflections differs from one bounce's on the pixels that bounce twice, only there."""
    from sunset.pipeline.rgb import render_rgb

    scene = wind_scene(48, 36)
    with kernels.use_compiled(compiled):
        twice = render(scene, 6.0, 2).bounces == 2
        two = render_rgb(scene, 6.0, 0.35, reflections=2)
        one = render_rgb(scene, 6.0, 0.35, reflections=1)
    changed = np.any(two != one, axis=-1)
    assert twice.sum() > 0 and changed.any()
    assert not np.any(changed & ~twice)


def test_the_command_line_refuses_a_choppy_seas_second_reflection_in_one_line(tmp_path, capsys):
    """`sunset render` of a choppy wind sea: exit 2, one line naming the field, no picture left behind."""
    from sunset.cli import main

    from ..model.test_windsea import WIND_SCENE

    path = tmp_path / "choppy.toml"
    path.write_text(WIND_SCENE.replace("cycle = 64.0", "cycle = 64.0\nchoppiness = 0.5"), encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["render", str(path), "-q", "--size", "16x12", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "reflections: a choppy wind sea" in err[0], err
    assert not out.exists()
    assert main(["render", str(path), "-q", "--size", "16x12", "--reflections", "1", "-o", str(out)]) == 0
    assert out.stat().st_size > 0
