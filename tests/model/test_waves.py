"""Tests for sunset.model.waves: wave trains, eq. 1, the periodic sea, gradient and normal.

Reference values come from independent computations: the surface written out
term by term in the test (cos nθ directly, no recurrence), central finite
differences of the surface, the phase speed measured by following a crest
over time, Fourier analysis of a sampled profile, and the period found by
searching for the time shift that brings the sea back.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from sunset.constants import GRAVITY
from sunset.errors import SunsetError
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain

SHAPES = [(), (6,), (2, 3), (2, 3, 1)]


def stokes_sea() -> Sea:
    """A periodic sea whose trains carry Stokes harmonics of every order 1..4."""
    return Sea.periodic(
        wavelength=30.0,
        amplitudes=[0.6, 0.15, 0.05, 0.02],
        directions=[80.0, 115.0, 250.0, 10.0],
        phases=[0.3, 1.0, 2.0, 4.0],
        stokes_orders=[4, 3, 2, 1],
    )


def reference_elevation(sea: Sea, x, y, t):
    """Σ_j Σ_n a_jn cos(n(ℓx + my − ωt + φ)), written out with cos nθ evaluated directly.

    a_jn are the paper's amplitudes (after eq. 2) typed in here from the paper:
    α, α²/2 + 17α⁴/24, 3α³/8, α⁴/3 over k, truncated at the train's order.
    ω = √(g k) is the deep-water dispersion relation.
    """
    x, y, t = (np.asarray(v, dtype=np.float64) for v in (x, y, t))
    total = 0.0
    for train in sea.trains:
        k = 2 * math.pi / train.wavelength
        d = math.radians(train.direction)
        al = k * train.amplitude
        p = train.stokes_order
        ka = [al, al**2 / 2 + (17 * al**4 / 24 if p >= 4 else 0.0), 3 * al**3 / 8, al**4 / 3][:p]
        theta = k * math.cos(d) * x + k * math.sin(d) * y - math.sqrt(GRAVITY * k) * t + train.phase
        total = total + sum(kan / k * np.cos(n * theta) for n, kan in enumerate(ka, start=1))
    return total


def test_elevation_matches_written_out_eq1():
    sea = stokes_sea()
    rng = np.random.default_rng(1)
    x, y, t = rng.uniform(-80, 80, 500), rng.uniform(1, 300, 500), rng.uniform(-10, 10, 500)
    np.testing.assert_allclose(sea.elevation(x, y, t), reference_elevation(sea, x, y, t), rtol=0, atol=1e-12)


def test_default_sea_matches_written_out_eq1():
    sea = Scene.default().sea
    rng = np.random.default_rng(2)
    x, y, t = rng.uniform(-50, 50, 300), rng.uniform(1, 500, 300), rng.uniform(0, 6, 300)
    np.testing.assert_allclose(sea.elevation(x, y, t), reference_elevation(sea, x, y, t), rtol=0, atol=1e-12)


# --------------------------------------------------------------------------- periodicity
@pytest.mark.parametrize("sea_factory", [stokes_sea, lambda: Scene.default().sea])
def test_periodic_in_time_to_round_off(sea_factory):
    sea = sea_factory()
    lam = max(t.wavelength for t in sea.trains)
    T = math.sqrt(2 * math.pi * lam / GRAVITY)  # one period of the longest train, from ω = √(gk)
    assert sea.period == pytest.approx(T, rel=1e-12)
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-100, 100, 400), rng.uniform(1, 400, 400)
    for t0 in (0.0, 1.234, 7.5):
        f0 = sea.elevation(x, y, t0)
        np.testing.assert_allclose(sea.elevation(x, y, t0 + sea.period), f0, rtol=0, atol=1e-11)
        np.testing.assert_allclose(sea.elevation(x, y, t0 + 3 * sea.period), f0, rtol=0, atol=1e-11)
        gx0, gy0 = sea.gradient(x, y, t0)
        gx1, gy1 = sea.gradient(x, y, t0 + sea.period)
        np.testing.assert_allclose(gx1, gx0, rtol=0, atol=1e-11)
        np.testing.assert_allclose(gy1, gy0, rtol=0, atol=1e-11)
        # ... and T is the shortest period: at a fraction of T the sea differs.
        for frac in (0.5, 1 / 3, 0.25, 0.999):
            assert np.max(np.abs(sea.elevation(x, y, t0 + frac * sea.period) - f0)) > 1e-3


def test_period_found_by_search():
    """The first time shift that brings the sea back (a brute-force scan) is sea.period."""
    sea = stokes_sea()
    rng = np.random.default_rng(4)
    x, y = rng.uniform(-50, 50, 200), rng.uniform(1, 200, 200)
    f0 = sea.elevation(x, y, 0.0)
    taus = np.linspace(0.05, 2.5 * sea.period, 5001)
    misfit = np.array([np.max(np.abs(sea.elevation(x, y, tau) - f0)) for tau in taus])
    below = misfit < 0.05
    start = int(np.argmax(below))                      # the first dip of the misfit ...
    stop = start + int(np.argmin(below[start:]))       # ... and where it ends
    first = taus[start + int(np.argmin(misfit[start:stop]))]
    step = taus[1] - taus[0]
    best = minimize_scalar(lambda tau: np.sum((sea.elevation(x, y, tau) - f0) ** 2),
                           bounds=(first - step, first + step), method="bounded",
                           options={"xatol": 1e-12})
    assert best.x == pytest.approx(sea.period, rel=1e-6)


def test_periodic_wavelengths_and_frequencies():
    lam = 40.0
    sea = Sea.periodic(lam, amplitudes=[0.5, 0.1, 0.05, 0.02, 0.01], directions=[90, 100, 110, 120, 130])
    np.testing.assert_allclose([t.wavelength for t in sea.trains], [lam, lam / 4, lam / 9, lam / 16, lam / 25],
                               rtol=1e-15)
    w1 = sea.trains[0].omega
    np.testing.assert_allclose([t.omega / w1 for t in sea.trains], [1, 2, 3, 4, 5], rtol=1e-14)
    assert sea.period == pytest.approx(2 * math.pi / math.sqrt(GRAVITY * 2 * math.pi / lam), rel=1e-14)
    # chosen harmonics: λ and λ/9
    sea = Sea.periodic(lam, amplitudes=[0.5, 0.1], directions=[90, 60], harmonics=[1, 3])
    np.testing.assert_allclose([t.wavelength for t in sea.trains], [lam, lam / 9], rtol=1e-15)
    # without the fundamental the sea still repeats after 2π/ω₁ (the lcm of 2π/2ω₁ and 2π/3ω₁)
    sea = Sea.periodic(lam, amplitudes=[0.5, 0.1], directions=[90, 60], harmonics=[2, 3])
    assert sea.period == pytest.approx(math.sqrt(2 * math.pi * lam / GRAVITY), rel=1e-12)
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-50, 50, 100), rng.uniform(1, 200, 100)
    np.testing.assert_allclose(sea.elevation(x, y, sea.period), sea.elevation(x, y, 0.0), atol=1e-12)


def test_period_of_special_seas():
    assert Sea().period == 0.0
    assert Sea((WaveTrain(0.0, 10.0),)).period == 0.0  # still water: every instant is the same
    # wavelengths in the ratio 2: frequencies in the ratio √2, which never repeats
    assert Sea((WaveTrain(0.1, 10.0), WaveTrain(0.1, 5.0))).period is None
    one = WaveTrain(0.3, 12.0, 45.0, stokes_order=3)
    assert Sea((one,)).period == pytest.approx(one.period)


# --------------------------------------------------------------------------- dispersion
@pytest.mark.parametrize("wavelength, direction, order", [(40.0, 90.0, 1), (10.0, 30.0, 2), (2.5, 250.0, 4)])
def test_phase_speed_by_tracking_a_crest(wavelength, direction, order):
    """Follow a crest along the direction of travel; its speed is √(gλ/2π) (deep water)."""
    train = WaveTrain(0.05 * wavelength / (2 * math.pi), wavelength, direction, 0.7, order)
    sea = Sea((train,))
    d = math.radians(direction)
    ex, ey = math.cos(d), math.sin(d)
    x0, y0 = 3.0, 50.0

    def crest(t, guess):
        res = minimize_scalar(lambda s: -float(sea.elevation(x0 + s * ex, y0 + s * ey, t)),
                              bounds=(guess - wavelength / 4, guess + wavelength / 4), method="bounded",
                              options={"xatol": 1e-10 * wavelength})
        return res.x

    # a first crest: the highest point in one wavelength from (x0, y0)
    s = np.linspace(0.0, wavelength, 1001)
    start = s[np.argmax(sea.elevation(x0 + s * ex, y0 + s * ey, 0.0))]
    s0 = crest(0.0, start)
    dt = 0.05 * train.period
    positions = [s0]
    for i in range(1, 6):
        positions.append(crest(i * dt, positions[-1] + train.speed * dt))
    speeds = np.diff(positions) / dt
    expected = math.sqrt(GRAVITY * wavelength / (2 * math.pi))
    np.testing.assert_allclose(speeds, expected, rtol=1e-6)
    # a point on the crest line, moved sideways along the crest, stays on a crest
    assert float(sea.elevation(x0 + s0 * ex - 7 * ey, y0 + s0 * ey + 7 * ex, 0.0)) == pytest.approx(
        train.max_elevation, rel=1e-12)


def test_period_at_a_fixed_point():
    """The time between successive crests passing a fixed point is √(2πλ/g)."""
    train = WaveTrain(0.2, 25.0, 100.0, 0.0, 2)
    sea = Sea((train,))
    t = np.linspace(0.0, 3 * train.period, 30001)
    z = sea.elevation(4.0, 11.0, t)
    peaks = np.nonzero((z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:]))[0] + 1
    assert len(peaks) == 3
    measured = np.diff(t[peaks])
    np.testing.assert_allclose(measured, math.sqrt(2 * math.pi * 25.0 / GRAVITY), rtol=2e-4)


def test_train_properties():
    tr = WaveTrain(0.5, 40.0, 30.0)
    k = 2 * math.pi / 40.0
    assert tr.k == pytest.approx(k)
    np.testing.assert_allclose(tr.wave_vector, (k * math.sqrt(3) / 2, k / 2), rtol=1e-14)
    assert math.hypot(*tr.wave_vector) == pytest.approx(k)
    assert tr.omega**2 == pytest.approx(GRAVITY * k)
    assert tr.speed == pytest.approx(math.sqrt(GRAVITY * 40.0 / (2 * math.pi)))
    assert tr.steepness == pytest.approx(k * 0.5)


# --------------------------------------------------------------------------- Stokes harmonics
@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_stokes_harmonics_by_fourier_analysis(order):
    """The FFT of the elevation along the direction of travel has the paper's amplitudes."""
    lam, a = 20.0, 0.8
    train = WaveTrain(a, lam, 0.0, 0.0, order)
    n_samples = 64
    x = lam * np.arange(n_samples) / n_samples
    z = Sea((train,)).elevation(x, 0.0, 0.0)
    spectrum = np.fft.rfft(z) * 2 / n_samples
    al = 2 * math.pi * a / lam
    expected = [al, al**2 / 2 + (17 * al**4 / 24 if order == 4 else 0.0), 3 * al**3 / 8, al**4 / 3][:order]
    expected = np.array(expected) * lam / (2 * math.pi)
    np.testing.assert_allclose(spectrum[1:order + 1].real, expected, rtol=1e-12)
    np.testing.assert_allclose(spectrum[order + 1:].real, 0.0, atol=1e-14)
    np.testing.assert_allclose(spectrum.imag, 0.0, atol=1e-14)
    assert abs(spectrum[0]) < 1e-14  # mean sea level
    np.testing.assert_allclose(train.harmonic_amplitudes(), expected, rtol=1e-14)
    assert train.max_elevation == pytest.approx(float(np.sum(expected)))
    if order >= 2:  # sharp crests, shallow troughs
        assert z.max() > -z.min()


def test_max_elevation_bounds_the_sea():
    sea = stokes_sea()
    rng = np.random.default_rng(6)
    z = sea.elevation(rng.uniform(-100, 100, 20000), rng.uniform(0, 300, 20000), rng.uniform(0, 10, 20000))
    d = sea.max_elevation
    assert np.max(np.abs(z)) <= d
    assert d == pytest.approx(sum(float(np.sum(t.harmonic_amplitudes())) for t in sea.trains))


def test_harmonic_amplitudes_read_only():
    amps = WaveTrain(0.5, 10.0, stokes_order=3).harmonic_amplitudes()
    with pytest.raises(ValueError):
        amps[0] = 1.0


# --------------------------------------------------------------------------- gradient and normal
@pytest.mark.parametrize("sea_factory", [stokes_sea, lambda: Scene.default().sea])
def test_gradient_against_central_differences(sea_factory):
    sea = sea_factory()
    rng = np.random.default_rng(7)
    x, y, t = rng.uniform(-60, 60, 400), rng.uniform(1, 300, 400), rng.uniform(0, 10, 400)
    fx, fy = sea.gradient(x, y, t)
    h = 1e-4
    # fourth-order central differences: error ~ h⁴ f⁽⁵⁾, far below the tolerance
    dx = (8 * (sea.elevation(x + h, y, t) - sea.elevation(x - h, y, t))
          - (sea.elevation(x + 2 * h, y, t) - sea.elevation(x - 2 * h, y, t))) / (12 * h)
    dy = (8 * (sea.elevation(x, y + h, t) - sea.elevation(x, y - h, t))
          - (sea.elevation(x, y + 2 * h, t) - sea.elevation(x, y - 2 * h, t))) / (12 * h)
    np.testing.assert_allclose(fx, dx, rtol=0, atol=1e-9)
    np.testing.assert_allclose(fy, dy, rtol=0, atol=1e-9)
    assert np.max(np.abs(fx)) > 0.05 and np.max(np.abs(fy)) > 0.05  # a real test, not of zeros


def test_normal_is_unit_upward_and_perpendicular():
    sea = stokes_sea()
    rng = np.random.default_rng(8)
    x, y = rng.uniform(-60, 60, (20, 30)), rng.uniform(1, 300, (20, 30))
    n = sea.normal(x, y, 1.5)
    assert n.shape == (20, 30, 3)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, rtol=1e-14)
    assert np.all(n[..., 2] > 0)
    # perpendicular to the surface's tangents, built by finite differences
    h = 1e-5
    z = lambda xx, yy: sea.elevation(xx, yy, 1.5)  # noqa: E731
    tx = np.stack([np.full_like(x, 2 * h), np.zeros_like(x), z(x + h, y) - z(x - h, y)], axis=-1)
    ty = np.stack([np.zeros_like(x), np.full_like(x, 2 * h), z(x, y + h) - z(x, y - h)], axis=-1)
    assert np.max(np.abs(np.sum(n * tx, axis=-1))) / (2 * h) < 1e-8
    assert np.max(np.abs(np.sum(n * ty, axis=-1))) / (2 * h) < 1e-8


def test_still_water():
    sea = Sea()
    x = np.linspace(0, 1, 6)
    assert np.all(sea.elevation(x, 2.0) == 0)
    fx, fy = sea.gradient(x, 2.0)
    assert np.all(fx == 0) and np.all(fy == 0)
    np.testing.assert_array_equal(sea.normal(x, 2.0), np.broadcast_to([0.0, 0.0, 1.0], (6, 3)))
    assert sea.max_elevation == 0.0


# --------------------------------------------------------------------------- shapes and dtypes
@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shapes_and_dtypes(shape, dtype):
    sea = stokes_sea()
    rng = np.random.default_rng(9)
    x = rng.uniform(-50, 50, shape).astype(dtype)
    y = rng.uniform(1, 200, shape).astype(dtype)
    z = sea.elevation(x, y, 0.7)
    fx, fy = sea.gradient(x, y, 0.7)
    n = sea.normal(x, y, 0.7)
    assert z.shape == fx.shape == fy.shape == shape
    assert n.shape == shape + (3,)
    assert z.dtype == fx.dtype == fy.dtype == n.dtype == dtype
    # element by element, from Python floats (the float32 inputs' exact values)
    flat = [float(reference_elevation(sea, float(a), float(b), 0.7)) for a, b in zip(x.ravel(), y.ravel())]
    tol = 1e-12 if dtype == np.float64 else 2e-7
    np.testing.assert_allclose(np.asarray(z, float).ravel(), flat, rtol=0, atol=tol)


def test_broadcasting_between_inputs():
    sea = stokes_sea()
    x = np.linspace(-10, 10, 6)                        # (6,)
    y = np.linspace(5, 50, 3).reshape(3, 1)            # (3, 1)
    t = np.array([0.0, 0.5]).reshape(2, 1, 1)          # (2, 1, 1)
    z = sea.elevation(x, y, t)
    assert z.shape == (2, 3, 6)
    X, Y, T = np.broadcast_arrays(x, y, t)
    np.testing.assert_allclose(z, reference_elevation(sea, X, Y, T), atol=1e-12)
    fx, fy = sea.gradient(x, y, t)
    gx, gy = sea.gradient(X.copy(), Y.copy(), T.copy())
    np.testing.assert_array_equal(fx, gx)
    np.testing.assert_array_equal(fy, gy)
    assert sea.normal(x, y, t).shape == (2, 3, 6, 3)
    # (2, 3, 1) against (6,) broadcasts to (2, 3, 6)
    assert sea.elevation(np.zeros((2, 3, 1)), np.ones(6)).shape == (2, 3, 6)
    # Python scalars and integers give float64
    assert sea.elevation(1, 2, 3).dtype == np.float64


def test_float32_keeps_the_phase():
    """40 km away a float32 phase would be off by ~1e-2 rad (~1e-3 m here); the result is not."""
    sea = stokes_sea()
    y32 = np.float32(np.linspace(40000.0, 40100.0, 50))
    z32 = sea.elevation(np.float32(3.25), y32, 0.4)
    assert z32.dtype == np.float32
    z64 = reference_elevation(sea, 3.25, y32.astype(np.float64), 0.4)
    np.testing.assert_allclose(z32, z64, rtol=0, atol=1e-6)


def test_nan_in_nan_out():
    sea = stokes_sea()
    z = sea.elevation(np.array([0.0, np.nan, 1.0]), 2.0)
    assert np.isnan(z[1]) and np.all(np.isfinite(z[[0, 2]]))


# --------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("kwargs, message", [
    (dict(amplitude=-0.1, wavelength=10.0), "amplitude must not be negative"),
    (dict(amplitude=float("nan"), wavelength=10.0), "amplitude must be a finite number"),
    (dict(amplitude=0.1, wavelength=0.0), "wavelength must be positive"),
    (dict(amplitude=0.1, wavelength=-5.0), "wavelength must be positive"),
    (dict(amplitude=0.1, wavelength=float("nan")), "wavelength must be a finite number"),
    (dict(amplitude=0.1, wavelength=float("inf")), "wavelength must be a finite number"),
    (dict(amplitude=0.1, wavelength=10.0, direction=float("nan")), "direction must be a finite number"),
    (dict(amplitude=0.1, wavelength=10.0, phase=float("inf")), "phase must be a finite number"),
    (dict(amplitude=0.1, wavelength=10.0, stokes_order=0), "stokes_order must be in 1..4"),
    (dict(amplitude=0.1, wavelength=10.0, stokes_order=5), "stokes_order must be in 1..4"),
    (dict(amplitude=0.1, wavelength=10.0, stokes_order=2.0), "stokes_order must be an integer"),
])
def test_train_bad_input(kwargs, message):
    with pytest.raises(SunsetError, match=message):
        WaveTrain(**kwargs)


@pytest.mark.parametrize("args, kwargs, message", [
    ((0.0, [0.1], [90.0]), {}, "wavelength must be positive"),
    ((float("nan"), [0.1], [90.0]), {}, "wavelength must be a finite number"),
    ((10.0, [0.1, 0.2], [90.0]), {}, "one entry per train"),
    ((10.0, [0.1], [90.0]), dict(harmonics=[0]), r"harmonics\[0\] must be >= 1"),
    ((10.0, [0.1], [90.0]), dict(harmonics=[1.5]), r"harmonics\[0\] must be an integer"),
    ((10.0, [-0.1], [90.0]), {}, "amplitude must not be negative"),
    ((10.0, [0.1], [90.0]), dict(stokes_orders=[7]), "stokes_order must be in 1..4"),
])
def test_periodic_bad_input(args, kwargs, message):
    with pytest.raises(SunsetError, match=message):
        Sea.periodic(*args, **kwargs)


def test_sea_bad_input():
    with pytest.raises(SunsetError, match=r"trains\[1\] must be a WaveTrain"):
        Sea((WaveTrain(0.1, 10.0), (0.1, 10.0)))
    with pytest.raises(SunsetError, match="x must be real numbers"):
        stokes_sea().elevation(np.array([1j]), 0.0)
    with pytest.raises(SunsetError, match="t must be real numbers"):
        stokes_sea().gradient(0.0, 0.0, "soon")


def test_capillary_ripples_are_refused():
    from sunset.constants import MIN_WAVELENGTH

    with pytest.raises(SunsetError, match=r"^wavelength must be at least"):
        WaveTrain(0.001, 0.5 * MIN_WAVELENGTH)
    WaveTrain(0.001, MIN_WAVELENGTH)
