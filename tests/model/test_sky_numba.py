"""The compiled single-scattering integral (sunset/model/sky_numba.py) against its NumPy reference, bit for bit.

The reference (:func:`sunset.model.sky.sky_radiance` in NumPy) is the
independent computation: whole arrays, ``einsum``, ``cumsum``, a BLAS matrix
product and NumPy's ``exp``. The twin must give its exact bits for every
view direction (zenith, horizon, below it, random), every sun (high, low,
setting, set, far below) and other sample counts; the colour tables built
from it must be the same bytes as the reference's for every hour the film uses.
"""

import math

import numpy as np
import pytest

numba = pytest.importorskip("numba")

import sunset  # noqa: E402
from sunset import kernels  # noqa: E402
from sunset.model import sky, sky_numba  # noqa: E402
from sunset.model.sky import sky_radiance  # noqa: E402


def bits(a):
    return np.ascontiguousarray(a).view(np.uint8)


def directions(seed=0, n=400):
    rng = np.random.default_rng(seed)
    d = rng.standard_normal((n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    e = np.radians([90.0, 45.0, 5.0, 1.0, 0.0, -0.5, -30.0])
    axis = np.stack([np.zeros_like(e), np.cos(e), np.sin(e)], axis=-1)
    return np.concatenate([axis, sky._sphere()[0], d])


def compiled(v, p, n_view=sky._N_VIEW, n_sun=sky._N_SUN):
    """The compiled kernel itself (the twin's wrapper would hand a failing probe's calls to the reference)."""
    return sky_numba._compiled(v, p, n_view, n_sun)


def test_the_probe_passes_here():
    """Where this fails the twin hands every call to the reference: correct, but the tables are slow again."""
    assert sky_numba.matches_numpy()


@pytest.mark.parametrize("sun_elevation", [1.2, 0.5, 0.08, 0.01, 0.0, -0.013, -0.05, -0.4])
def test_the_twin_gives_the_references_bits(sun_elevation):
    v = directions(seed=int(1000 * abs(sun_elevation)))
    p = np.array([0.3 * math.cos(sun_elevation), 0.954 * math.cos(sun_elevation), math.sin(sun_elevation)])
    p /= np.linalg.norm(p)
    want = sky_radiance.reference(v, p)
    got = compiled(v, p)
    assert got.shape == want.shape == (len(v), len(sky.spectral_data().wavelengths))
    assert np.all(np.isfinite(got)) and np.all(got >= 0.0)
    assert np.array_equal(bits(got), bits(want))


@pytest.mark.parametrize("n_view, n_sun", [(1, 1), (2, 1), (7, 3), (64, 40)])
def test_the_twin_follows_the_sample_counts(n_view, n_sun):
    v = directions(seed=n_view, n=60)
    p = np.array([0.0, math.cos(0.1), math.sin(0.1)])
    want = sky_radiance.reference(v, p, n_view, n_sun)
    got = sky_radiance.compiled()(v, p, n_view, n_sun)
    assert np.array_equal(bits(got), bits(want))
    if n_view >= 2:
        assert np.array_equal(bits(compiled(v, p, n_view, n_sun)), bits(want))
    # and the counts matter: a different count is a different integral
    assert not np.array_equal(got, sky_radiance.compiled()(v, p, n_view + 1, n_sun))


def test_sky_radiance_is_the_same_bytes_either_way():
    v = directions(seed=7, n=50)
    p = np.array([0.1, 0.99, 0.05])
    p /= np.linalg.norm(p)
    with kernels.use_compiled(False):
        want = sky_radiance(v, p)
    with kernels.use_compiled(True):
        got = sky_radiance(v, p)
    assert np.array_equal(bits(got), bits(want))


def test_a_columns_function_goes_to_the_reference():
    """Only the reference integrates a caller's columns (the RGB back end's tabulated ones)."""
    v = directions(seed=3, n=20)
    p = np.array([0.0, math.cos(0.2), math.sin(0.2)])
    calls = []

    def columns(h, mu):
        calls.append(h.shape)
        return sky.slant_columns(h, mu)

    got = sky_radiance(v, p, columns=columns)
    assert calls and np.array_equal(bits(got), bits(sky_radiance(v, p)))


def test_where_the_probe_fails_the_reference_runs(monkeypatch):
    v = directions(seed=5, n=10)
    p = np.array([0.0, math.cos(0.3), math.sin(0.3)])
    monkeypatch.setitem(sky_numba._verdict, "ok", False)
    monkeypatch.setattr(sky_numba, "_compiled", lambda *a: pytest.fail("the compiled kernel ran"))
    assert np.array_equal(bits(sky_numba.sky_radiance(v, p)), bits(sky_radiance.reference(v, p)))


def test_the_probe_catches_a_twin_one_ulp_off(monkeypatch):
    """A twin whose results differ from the reference's in the last bit only is caught by the probe."""
    original = sky_numba._compiled

    def off(v, p, n_view, n_sun):
        out = original(v, p, n_view, n_sun)
        return np.nextafter(out, np.inf)

    monkeypatch.setattr(sky_numba, "_compiled", off)
    monkeypatch.delitem(sky_numba._verdict, "ok", raising=False)
    try:
        assert not sky_numba.matches_numpy()
    finally:
        sky_numba._verdict.pop("ok", None)


@pytest.mark.parametrize("scene", ["carlas-island", "carlas-island-clouds", "post-in-the-swell", "still-lake-at-noon"])
def test_the_tables_are_the_same_bytes_for_every_film_hour(scene):
    from sunset.constants import FILM_FROM_HOURS, FILM_TO_HOURS
    from sunset.recorder import colour_tables as ct

    sc = sunset.Scene.named(scene)
    hours = np.concatenate([np.linspace(FILM_FROM_HOURS, FILM_TO_HOURS, 12), [3.0, -1.0, 6.0, -11.5]])
    for h in hours:
        with kernels.use_compiled(False):
            want, want_sun = ct._tables_linear(sc.sun, float(h), sc.clouds)
        with kernels.use_compiled(True):
            got, got_sun = ct._tables_linear(sc.sun, float(h), sc.clouds)
        assert np.array_equal(bits(got), bits(want)), h
        assert np.array_equal(bits(got_sun), bits(want_sun)), h


def test_the_kernel_takes_the_exp_numpy_takes(monkeypatch):
    """The twin's exp is the probe's choice, and the other exp would not give the reference's bits."""
    from sunset import exp_numba

    assert sky_numba._which() == exp_numba.choice() in (exp_numba.LIBM, exp_numba.SVML)
    v = directions(seed=11, n=40)
    p = np.array([0.0, math.cos(0.05), math.sin(0.05)])
    want = sky_radiance.reference(v, p, 16, 8)
    assert np.array_equal(bits(compiled(v, p, 16, 8)), bits(want))
    other = exp_numba.SVML if sky_numba._which() == exp_numba.LIBM else exp_numba.LIBM
    monkeypatch.setattr(sky_numba, "_which", lambda: other)
    assert not np.array_equal(bits(compiled(v, p, 16, 8)), bits(want))


def test_with_numpys_avx512_kernels_off_the_c_librarys_exp_is_chosen_and_the_twin_holds():
    """NumPy told to leave its AVX-512 code (NPY_DISABLE_CPU_FEATURES) calls the C library's exp: the
    other branch of the choice, checked on this machine in a fresh process (the same where there is no AVX-512)."""
    import os
    import subprocess
    import sys

    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    off = [f for f in __cpu_dispatch__ if ("512" in f or f == "X86_V4") and __cpu_features__.get(f)]
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=" ".join(off)) if off else dict(os.environ)
    code = ("from sunset import exp_numba; from sunset.model import sky_numba; "
            "print(exp_numba.choice(), sky_numba.matches_numpy())")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    from sunset import exp_numba

    assert out.stdout.split() == [str(exp_numba.LIBM), "True"]
