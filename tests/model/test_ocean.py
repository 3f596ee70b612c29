"""The FFT tile on Max's lattice (sunset/model/ocean.py) against direct sums, closed forms and differences."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from sunset.constants import GRAVITY as G
from sunset.errors import SunsetError
from sunset.model.ocean import OceanTile, lattice, resolved_mask

L, T = 64.0, 20.0


def one_component(n=32, m=(3, 0), amp=0.2, phase=0.4, choppiness=0.0, oversample=1, size=L):
    """A tile holding one train: h₀ = (a/2) e^{iφ} at k = (2π/L) m, so z = a cos(k·x − ωt + φ)."""
    h0 = np.zeros((n, n), complex)
    h0[m[1] % n, m[0] % n] = 0.5 * amp * np.exp(1j * phase)
    return OceanTile(h0, size, T, choppiness=choppiness, oversample=oversample)


def random_tile(n=32, seed=0, choppiness=0.0, oversample=1):
    rng = np.random.default_rng(seed)
    kx, ky = lattice(n, L)
    k = np.hypot(kx, ky)
    amp = np.where(k > 0, 0.05 * np.exp(-k / 1.5) / np.maximum(k, 1e-9) ** 0.5, 0.0)
    return OceanTile(amp * (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))), L, T,
                     choppiness=choppiness, oversample=oversample)


def test_lattice_and_mask():
    kx, ky = lattice(8, 16.0)
    assert kx.shape == ky.shape == (8, 8)
    assert kx[0, 1] == pytest.approx(2 * math.pi / 16.0) and ky[1, 0] == pytest.approx(2 * math.pi / 16.0)
    mask = resolved_mask(8)
    assert not mask[0, 0] and not mask[4, :].any() and not mask[:, 4].any()
    assert mask.sum() == 7 * 7 - 1


def test_one_component_is_a_travelling_cosine():
    tile = one_component()
    k = 2 * math.pi * 3 / L
    w = tile.omega[0, 3]
    assert w == pytest.approx(round(math.sqrt(G * k) / tile.omega0) * tile.omega0)
    x = np.linspace(0, L, 7)[:, None]
    y = np.linspace(0, L, 5)[None, :]
    for t in (0.0, 3.3, 17.0):
        z, zx, zy = tile.exact(x, y, t)
        theta = k * x - w * t + 0.4 + 0 * y
        np.testing.assert_allclose(z, 0.2 * np.cos(theta), atol=1e-13)
        np.testing.assert_allclose(zx, -0.2 * k * np.sin(theta), atol=1e-13)
        np.testing.assert_allclose(zy, 0.0, atol=1e-13)
        f = tile.fields(t)
        xg = np.arange(32) * L / 32
        np.testing.assert_allclose(f["z"], np.broadcast_to(0.2 * np.cos(k * xg - w * t + 0.4), (32, 32)), atol=1e-13)


def test_the_fft_grid_is_the_direct_sum():
    tile = random_tile()
    xg = np.arange(32) * L / 32
    x, y = np.meshgrid(xg, xg)
    for t in (0.0, 7.25):
        f = tile.fields(t)
        z, zx, zy = tile.exact(x, y, t)
        for a, b in ((f["z"], z), (f["zx"], zx), (f["zy"], zy)):
            np.testing.assert_allclose(a, b, atol=1e-12 * np.abs(b).max())


def test_fft_gradient_against_finite_differences_of_the_series():
    tile = random_tile(seed=3)
    rng = np.random.default_rng(1)
    x, y = rng.uniform(0, L, 50), rng.uniform(0, L, 50)
    _, zx, zy = tile.exact(x, y, 2.0)
    h = 1e-4
    fdx = (tile.exact(x + h, y, 2.0)[0] - tile.exact(x - h, y, 2.0)[0]) / (2 * h)
    fdy = (tile.exact(x, y + h, 2.0)[0] - tile.exact(x, y - h, 2.0)[0]) / (2 * h)
    np.testing.assert_allclose(zx, fdx, atol=1e-7)
    np.testing.assert_allclose(zy, fdy, atol=1e-7)
    # and the FFT's slopes, interpolated, against the same differences
    sx, sy = tile.sample(x, y, 2.0)[1:]
    err = tile.interpolation_error()
    assert math.sqrt(np.mean((sx - fdx) ** 2)) < 3 * err["rms_zx"]


def test_the_sea_repeats_after_the_cycle():
    tile = random_tile()
    for t in (0.0, 1.7, 1234.5):
        a, b = tile.fields(t), tile.fields(t + T)
        b2 = tile.fields(t + 50 * T)
        for key in ("z", "zx", "zy"):
            scale = np.abs(a[key]).max()
            np.testing.assert_allclose(b[key], a[key], atol=1e-9 * scale)
            np.testing.assert_allclose(b2[key], a[key], atol=1e-9 * scale)
    # every frequency is a multiple of ω₀ = 2π/T, within ω₀/2 of √(g k) where that is at least ω₀/2
    assert np.all(tile.omega[tile.mask] == tile.harmonic[tile.mask] * tile.omega0)
    ok = tile.mask & (tile.true_omega >= tile.omega0 / 2)
    assert np.all(np.abs(tile.omega - tile.true_omega)[ok] <= tile.omega0 / 2 + 1e-12)
    # but not after less: half a cycle moves it
    assert np.abs(tile.fields(T / 2)["z"] - tile.fields(0.0)["z"]).max() > 0.01 * np.abs(tile.fields(0.0)["z"]).max()


def test_the_sea_repeats_across_the_tile():
    tile = random_tile(seed=5)
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-L, 2 * L, 200), rng.uniform(-L, 2 * L, 200)
    a = tile.sample(x, y, 3.0)
    for dx, dy in ((L, 0.0), (0.0, -L), (3 * L, 2 * L)):
        b = tile.sample(x + dx, y + dy, 3.0)
        for u, v in zip(a, b):
            np.testing.assert_allclose(u, v, atol=1e-9)


def test_parseval():
    tile = random_tile(seed=7)
    for t in (0.0, 4.0):
        f = tile.fields(t)
        assert f["z"].mean() == pytest.approx(0.0, abs=1e-15)
        assert np.mean(f["z"] ** 2) == pytest.approx(np.sum(np.abs(tile.amplitudes(t)) ** 2), rel=1e-12)
    # over the cycle the variance averages to Σ (|h₀(k)|² + |h₀(−k)|²)
    ts = np.arange(64) * T / 64
    mean = np.mean([np.mean(tile.fields(t)["z"] ** 2) for t in ts])
    assert mean == pytest.approx(tile.power.sum(), rel=0.02)


def test_oversampled_grids_hold_the_same_sea():
    a, b = random_tile(seed=4), random_tile(seed=4, oversample=2)
    fa, fb = a.fields(1.0), b.fields(1.0)
    assert fb["z"].shape == (64, 64)
    for key in ("z", "zx", "zy"):
        np.testing.assert_allclose(fb[key][::2, ::2], fa[key], atol=1e-12 * np.abs(fa[key]).max())


@pytest.mark.parametrize("oversample", [1, 2, 4])
def test_interpolation_error_is_what_the_tile_says(oversample):
    tile = random_tile(n=32, seed=11, oversample=oversample)
    err = tile.interpolation_error()
    rng = np.random.default_rng(4)
    x, y, t = rng.uniform(0, L, 4000), rng.uniform(0, L, 4000), rng.uniform(0, T, 4)
    dz, dzx = [], []
    for tt, xs, ys in zip(t, np.split(x, 4), np.split(y, 4)):
        z, zx, _ = tile.sample(xs, ys, tt)
        ez, ezx, _ = tile.exact(xs, ys, tt)
        dz.append(z - ez)
        dzx.append(zx - ezx)
    dz, dzx = np.concatenate(dz), np.concatenate(dzx)
    assert math.sqrt(np.mean(dz ** 2)) == pytest.approx(err["rms_z"], rel=0.15)
    assert math.sqrt(np.mean(dzx ** 2)) == pytest.approx(err["rms_zx"], rel=0.15)
    assert np.abs(dz).max() <= err["max_z"]


def test_the_bound_holds_for_the_interpolated_sea():
    tile = random_tile(seed=9, choppiness=0.3)
    rng = np.random.default_rng(8)
    x, y = rng.uniform(0, L, 5000), rng.uniform(0, L, 5000)
    for t in (0.0, 5.0):
        z, _, _ = tile.sample(x, y, t)
        assert np.abs(z).max() <= tile.bound(t)
        assert tile.bound(t) <= tile.bound_all_times


def test_choppy_is_gerstners_trochoid_for_one_component():
    a, m = 0.6, 2
    k = 2 * math.pi * m / L
    tile = one_component(n=64, m=(m, 0), amp=a, phase=0.0, choppiness=1.0, oversample=4)
    w = tile.omega[0, m]
    t = 1.3
    # J = 1 − λ a k cos θ (closed form), on the grid
    xg = np.arange(256) * L / 256
    np.testing.assert_allclose(tile.jacobian(t)[0], 1 - a * k * np.cos(k * xg - w * t), atol=1e-12)
    assert tile.folded_fraction(t) == 0.0
    # the Eulerian surface: X = x₀ − a sin θ₀, z = a cos θ₀ (θ₀ = k x₀ − ωt), solved point by point
    xs = np.linspace(0.0, L / m, 41)
    z, zx, zy = tile.sample(xs, 0.0 * xs, t)
    x0 = np.array([brentq(lambda s: s - a * math.sin(k * s - w * t) - X, X - 1, X + 1) for X in xs])
    th = k * x0 - w * t
    np.testing.assert_allclose(z, a * np.cos(th), atol=2e-4)
    slope = -a * k * np.sin(th) / (1 - a * k * np.cos(th))                   # dz/dX of the trochoid
    np.testing.assert_allclose(zx, slope, atol=2e-3)
    np.testing.assert_allclose(zy, 0.0, atol=1e-12)


def test_choppy_gives_stokes_second_harmonic_for_one_component():
    # to second order in ka the trochoid is a cos θ + ½ka² cos 2θ − ½ka²: Stokes' second harmonic,
    # with the Eulerian mean lowered by ½ka² (expand z(X) of the trochoid to second order)
    a, m = 0.2, 2
    k = 2 * math.pi * m / L                                                    # ka ≈ 0.04
    tile = one_component(n=64, m=(m, 0), amp=a, phase=0.0, choppiness=1.0, oversample=4)
    X = np.linspace(0.0, L / m, 101)
    z, _, _ = tile.sample(X, 0 * X, 0.0)
    stokes = a * np.cos(k * X) + 0.5 * k * a * a * (np.cos(2 * k * X) - 1)
    linear = a * np.cos(k * X)
    err = np.abs(z - stokes).max()
    assert err < 3 * (k * a) ** 2 * a                                          # third order
    assert err < 0.2 * np.abs(z - linear).max()                                # far closer than the cosine


def test_choppiness_zero_is_the_plain_height_field():
    plain, flat = random_tile(seed=2), random_tile(seed=2, choppiness=0.0)
    assert "dx" not in flat.fields(1.0)
    assert np.all(flat.jacobian(1.0) == 1.0) and flat.folded_fraction(1.0) == 0.0
    x = np.linspace(0, L, 33)
    for u, v in zip(plain.sample(x, 0.3 * x, 1.0), flat.sample(x, 0.3 * x, 1.0)):
        np.testing.assert_array_equal(u, v)


def test_a_steep_choppy_train_folds_where_the_trochoid_loops():
    a = 1.2 / (2 * math.pi * 2 / L)                                            # λ a k = 1.2
    tile = one_component(n=64, m=(2, 0), amp=a, phase=0.0, choppiness=1.0)
    assert tile.folded_fraction(0.0) == pytest.approx(math.acos(1 / 1.2) / math.pi, abs=2 / 64)


def test_dispersion_error_of_a_long_cycle_is_smaller():
    short, long = random_tile(), OceanTile(random_tile().h0, L, 8 * T)
    es, el = short.dispersion_error(), long.dispersion_error()
    assert el["rms"] < es["rms"] and el["max"] <= es["max"]
    assert es["max"] <= short.omega0 / (2 * math.sqrt(G * es["k_min"])) + 1e-12


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_shapes_and_nan(shape):
    tile = random_tile()
    x = np.full(shape, 1.5)
    for v in tile.sample(x, x, 0.0):
        assert np.shape(v) == shape
    z, zx, zy = tile.sample(np.array([np.nan, 1.0]), np.array([0.0, np.inf]), 0.0)
    assert np.isnan(z).all() and np.isnan(zx).all() and np.isnan(zy).all()


def test_the_same_amplitudes_give_the_same_bytes():
    a, b = random_tile(seed=6), random_tile(seed=6)
    assert a.fields(2.5)["z"].tobytes() == b.fields(2.5)["z"].tobytes()


@pytest.mark.parametrize("kwargs, match", [
    ({"h0": np.zeros((8, 8))}, "^h0 must be a square complex array"),
    ({"h0": np.zeros((8, 4), complex)}, "^h0 must be a square complex array"),
    ({"h0": np.zeros((12, 12), complex)}, "^points must be a power of two"),
    ({"h0": np.zeros((4, 4), complex)}, "^points must be in 8..1024"),
    ({"h0": np.full((8, 8), np.nan + 0j)}, "^h0 must be finite"),
    ({"size": -1.0}, "^size must be in"), ({"cycle": 0.0}, "^cycle must be in"),
    ({"choppiness": 1.5}, "^choppiness must be in"), ({"oversample": 3}, "^oversample must be one of"),
    ({"gravity": float("nan")}, "^gravity must be"),
])
def test_bad_tiles(kwargs, match):
    args = {"h0": np.zeros((8, 8), complex), "size": 10.0, "cycle": 5.0, **kwargs}
    with pytest.raises(SunsetError, match=match):
        OceanTile(**args)
    with pytest.raises(SunsetError, match="^t must be a finite time"):
        random_tile().fields(float("nan"))
