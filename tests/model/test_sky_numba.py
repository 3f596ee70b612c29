"""The compiled single-scattering integral (sunset/model/sky_numba.py) against its NumPy reference, within tolerance.

The reference (:func:`sunset.model.sky.sky_radiance` in NumPy) is the
independent computation: whole arrays, ``einsum``, ``cumsum``, a BLAS matrix
product and NumPy's ``exp``. The twin sums in its own order with the C
library's ``exp``; the two agree within :data:`sunset.model.sky_numba.RADIANCE_RTOL`
for every view direction (zenith, horizon, below it, random), every sun
(high, low, setting, set, far below) and other sample counts, and the colour
tables built from either have the same 8-bit entries but for
:data:`sunset.model.sky_numba.TABLE_STEPS` steps on at most
:data:`sunset.model.sky_numba.TABLE_SHARE` of them. Each path gives the same
bytes on every call.
"""

import math

import numpy as np
import pytest

numba = pytest.importorskip("numba")

import sunset  # noqa: E402
from sunset import kernels  # noqa: E402
from sunset.model import sky, sky_numba  # noqa: E402
from sunset.model.sky import sky_radiance  # noqa: E402
from sunset.model.sky_numba import RADIANCE_FLOOR, RADIANCE_RTOL, TABLE_SHARE, TABLE_STEPS  # noqa: E402


def directions(seed=0, n=400):
    rng = np.random.default_rng(seed)
    d = rng.standard_normal((n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    e = np.radians([90.0, 45.0, 5.0, 1.0, 0.0, -0.5, -30.0])
    axis = np.stack([np.zeros_like(e), np.cos(e), np.sin(e)], axis=-1)
    return np.concatenate([axis, sky._sphere()[0], d])


def sun(elevation, azimuth=0.3):
    p = np.array([math.sin(azimuth) * math.cos(elevation), math.cos(azimuth) * math.cos(elevation),
                  math.sin(elevation)])
    return p / np.linalg.norm(p)


def relative(got, want):
    """|got − want| / max(want, RADIANCE_FLOOR)."""
    return np.abs(got - want) / np.maximum(np.abs(want), RADIANCE_FLOOR)


def within(got, want):
    return relative(got, want) <= RADIANCE_RTOL


@pytest.mark.parametrize("sun_elevation", [1.2, 0.5, 0.08, 0.01, 0.0, -0.013, -0.05, -0.1025, -0.4])
def test_the_twin_is_the_reference_within_the_tolerance(sun_elevation):
    v = directions(seed=int(1000 * abs(sun_elevation)))
    p = sun(sun_elevation)
    want = sky_radiance.reference(v, p)
    got = sky_radiance.compiled()(v, p)
    assert got.shape == want.shape == (len(v), len(sky.spectral_data().wavelengths))
    assert np.all(np.isfinite(got)) and np.all(got >= 0.0)
    assert np.all(within(got, want))
    # the tolerance is not slack: a twin off by ten times it is caught
    if want.max() > 0:
        assert not np.all(within(got * (1 + 10 * RADIANCE_RTOL), want))


def test_the_tolerance_is_needed_and_not_ten_times_wider_than_needed():
    """The largest relative difference over suns setting and set lies between a tenth of RADIANCE_RTOL and
    RADIANCE_RTOL: the two paths do differ, and by about what the tolerance allows."""
    v = directions(seed=1, n=300)
    worst = 0.0
    for e in np.linspace(-0.12, 0.02, 15):
        worst = max(worst, float(relative(sky_radiance.compiled()(v, sun(e, 1.0)), sky_radiance.reference(v, sun(e, 1.0))).max()))
    assert RADIANCE_RTOL / 10 < worst <= RADIANCE_RTOL


@pytest.mark.parametrize("n_view, n_sun", [(1, 1), (2, 1), (7, 3), (64, 40)])
def test_the_twin_follows_the_sample_counts(n_view, n_sun):
    v = directions(seed=n_view, n=60)
    p = sun(0.1, 0.0)
    want = sky_radiance.reference(v, p, n_view, n_sun)
    got = sky_radiance.compiled()(v, p, n_view, n_sun)
    assert np.all(within(got, want))
    # and the counts matter: a different count is a different integral
    assert not np.all(within(sky_radiance.compiled()(v, p, n_view + 1, n_sun), want))


def test_each_path_gives_the_same_bytes_every_time():
    v = directions(seed=7, n=50)
    p = sun(0.05, 0.1)
    for flag in (False, True):
        with kernels.use_compiled(flag):
            first = sky_radiance(v, p)
            assert first.tobytes() == sky_radiance(v, p).tobytes()
    # the compiled integral of one ray does not depend on its neighbours (the colour tables integrate each
    # distinct direction once)
    got = sky_radiance.compiled()(np.ascontiguousarray(v[::-1]), p)[::-1]
    assert got.tobytes() == sky_radiance.compiled()(v, p).tobytes()


def test_a_columns_function_goes_to_the_reference():
    """Only the reference integrates a caller's columns (the RGB back end's tabulated ones)."""
    v = directions(seed=3, n=20)
    p = sun(0.2, 0.0)
    calls = []

    def columns(h, mu):
        calls.append(h.shape)
        return sky.slant_columns(h, mu)

    got = sky_numba.sky_radiance(v, p, columns=columns)
    assert calls and got.tobytes() == sky_radiance.reference(v, p).tobytes()


SCENES = ["carlas-island", "carlas-island-clouds", "post-in-the-swell", "still-lake-at-noon", "archipelago-at-dusk",
          "storm-swell"]


def table_differences(scene, hours):
    """(entries, entries that differ, largest difference in steps) of the 8-bit tables of both paths."""
    from sunset.model.eye import srgb_encode, to_uint8
    from sunset.recorder import colour_tables as ct

    sc = sunset.Scene.named(scene)
    n = differ = worst = 0
    for h in hours:
        with kernels.use_compiled(False):
            want, want_sun = ct._tables_linear(sc.sun, float(h), sc.clouds)
        with kernels.use_compiled(True):
            got, got_sun = ct._tables_linear(sc.sun, float(h), sc.clouds)
        a = to_uint8(srgb_encode(np.concatenate([want, want_sun[None]]))).astype(int)
        b = to_uint8(srgb_encode(np.concatenate([got, got_sun[None]]))).astype(int)
        n, differ, worst = n + a.size, differ + int(np.sum(a != b)), max(worst, int(np.abs(a - b).max()))
    return n, differ, worst


@pytest.mark.parametrize("scene", SCENES)
def test_the_tables_8_bit_entries_agree_for_every_film_hour(scene):
    from sunset.constants import FILM_FROM_HOURS, FILM_TO_HOURS

    hours = np.concatenate([np.linspace(FILM_FROM_HOURS, FILM_TO_HOURS, 12), [3.0, -1.0, 6.0, -11.5]])
    n, differ, worst = table_differences(scene, hours)
    assert n == len(hours) * 257 * 3
    assert worst <= TABLE_STEPS and differ <= TABLE_SHARE * n


def test_the_table_check_sees_a_wrong_sky(monkeypatch):
    """The same check fails when the compiled sky is one part in a thousand too bright."""
    original = sky_numba.sky_radiance
    monkeypatch.setattr(sky_numba, "sky_radiance", lambda *a, **k: original(*a, **k) * 1.001)
    sky._upper_sky_cached.cache_clear()
    try:
        n, differ, worst = table_differences("carlas-island", [0.5, 0.1])
    finally:
        sky._upper_sky_cached.cache_clear()
    assert differ > TABLE_SHARE * n
