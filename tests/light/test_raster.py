"""Triangles of light onto a texture (sunset/light/raster.py): the exact area each texel covers, against an
independent integration; the flux conserved; degenerate triangles; the compiled twin within its tolerance."""

import numpy as np
import pytest

from sunset import kernels
from sunset.light.raster import clip_area, rasterise, triangle_area


def _column_integral(u, v, i, j, n=4001):
    """Area of triangle (u, v) inside [i, i+1] × [j, j+1] by the trapezoid rule across u of the length of the
    triangle's vertical chord clipped to the square (exact for a piecewise-linear integrand but at its kinks)."""
    x = np.linspace(i, i + 1, n)
    lo, hi = np.full(n, np.inf), np.full(n, -np.inf)
    for k in range(3):
        u0, v0, u1, v1 = u[k], v[k], u[(k + 1) % 3], v[(k + 1) % 3]
        if u0 == u1:
            continue
        f = (x - u0) / (u1 - u0)
        inside = (f >= 0) & (f <= 1)
        y = v0 + f * (v1 - v0)
        lo = np.where(inside, np.minimum(lo, y), lo)
        hi = np.where(inside, np.maximum(hi, y), hi)
    length = np.clip(np.minimum(hi, j + 1) - np.maximum(lo, j), 0.0, None)
    length[~np.isfinite(length)] = 0.0
    return float(np.sum(0.5 * (length[1:] + length[:-1]) * np.diff(x)))


def test_each_texels_share_is_the_area_of_the_triangle_inside_it():
    rng = np.random.default_rng(0)
    for _ in range(60):
        c = rng.uniform([1, 1], [4, 4])
        u, v = c[0] + rng.normal(size=3) * 0.9, c[1] + rng.normal(size=3) * 0.9
        i, j = int(np.floor(c[0])), int(np.floor(c[1]))
        got = clip_area(u[None, :], v[None, :], np.array([i]), np.array([j]))[0]
        assert got == pytest.approx(_column_integral(u, v, i, j), abs=2e-6)
    # the squares tile the plane: the areas add up to the triangle's
    u, v = np.array([[0.3, 5.7, 2.2]]), np.array([[0.1, 1.9, 4.6]])
    ii, jj = np.meshgrid(np.arange(-1, 7), np.arange(-1, 6))
    total = sum(clip_area(u, v, np.array([a]), np.array([b]))[0] for a, b in zip(ii.ravel(), jj.ravel()))
    assert total == pytest.approx(triangle_area(u, v)[0], rel=1e-14)


def _triangles(rng, n, n_u, n_v):
    c = rng.uniform([0, -2], [n_u, n_v + 2], (n, 2))
    size = np.exp(rng.uniform(-9, 1.2, n))
    u = c[:, :1] + size[:, None] * rng.normal(size=(n, 3))
    v = c[:, 1:] + size[:, None] * rng.normal(size=(n, 3))
    u[:5], v[:5] = u[:5, :1], v[:5, :1]                         # points
    u[5:10, 2], v[5:10, 2] = 0.5 * (u[5:10, 0] + u[5:10, 1]), 0.5 * (v[5:10, 0] + v[5:10, 1])   # segments
    return u, v, rng.random((n, 2))


@pytest.mark.parametrize("compiled", [False, True])
def test_the_flux_is_conserved_and_split_at_the_rows_as_the_areas_say(compiled):
    rng = np.random.default_rng(1)
    n_u, n_v = 17, 9
    u, v, flux = _triangles(rng, 3000, n_u, n_v)
    with kernels.use_compiled(compiled):
        tex, kept = rasterise(u, v, flux, n_u, n_v)
    assert tex.shape == (n_v, n_u, 2) and kept.shape == (3000,)
    np.testing.assert_allclose(tex.sum(axis=(0, 1)), (flux * kept[:, None]).sum(axis=0), rtol=1e-12)
    inside = (v.min(axis=1) >= 0) & (v.max(axis=1) <= n_v)
    assert np.all(kept[inside] == 1.0)
    # a clipped triangle keeps the share of its area between the rows (by the independent integral)
    for t in np.flatnonzero(~inside & (triangle_area(u, v) > 1e-2))[:20]:
        i0, i1 = int(np.floor(u[t].min())), int(np.floor(u[t].max()))
        area = sum(_column_integral(u[t], v[t], i, j) for i in range(i0, i1 + 1) for j in range(n_v))
        assert kept[t] == pytest.approx(area / triangle_area(u[t:t + 1], v[t:t + 1])[0], abs=1e-5)


def test_a_triangle_across_the_seam_wraps_round_and_a_point_lands_in_its_texel():
    n_u, n_v = 8, 4
    u = np.array([[7.5, 8.5, 8.0], [3.25, 3.25, 3.25]])
    v = np.array([[1.0, 1.0, 2.0], [2.5, 2.5, 2.5]])
    tex, kept = rasterise(u, v, np.array([[1.0], [2.0]]), n_u, n_v)
    assert tex[1, 7, 0] == pytest.approx(0.5) and tex[1, 0, 0] == pytest.approx(0.5)
    assert tex[2, 3, 0] == 2.0 and np.all(kept == 1.0)


@pytest.mark.skipif(not kernels.AVAILABLE, reason="Numba is not installed")
def test_the_compiled_rasteriser_agrees_within_its_tolerance():
    from sunset.light.raster_numba import RASTER_RTOL

    rng = np.random.default_rng(2)
    u, v, flux = _triangles(rng, 20000, 36, 20)
    ref_tex, ref_kept = rasterise.reference(u, v, flux, 36, 20)
    got_tex, got_kept = rasterise.compiled()(u, v, flux, 36, 20)
    np.testing.assert_allclose(got_tex, ref_tex, rtol=0, atol=RASTER_RTOL * ref_tex.max())
    np.testing.assert_allclose(got_kept, ref_kept, rtol=0, atol=RASTER_RTOL)


def test_the_reference_clips_a_bounded_number_of_pairs_at_a_time(monkeypatch):
    """The NumPy rasteriser in groups of at most PAIRS (triangle, texel) pairs (a group of one triangle where one
    alone covers more): the same texture to round-off, and its traced peak bounded by the groups, not the input."""
    import tracemalloc

    from sunset.light import raster

    rng = np.random.default_rng(3)
    u, v, flux = _triangles(rng, 4000, 40, 30)
    u[10:60] = u[10:60, :1] + rng.uniform(-15, 15, (50, 3))        # large triangles: hundreds of texels each
    v[10:60] = v[10:60, :1] + rng.uniform(-12, 12, (50, 3))
    whole_tex, whole_kept = rasterise.reference(u, v, flux, 40, 30)
    pairs = int(np.sum((np.floor(u.max(axis=1)) - np.floor(u.min(axis=1)) + 1) * 30))
    assert pairs > 20 * 1000
    monkeypatch.setattr(raster, "PAIRS", 1000)
    tracemalloc.start()
    tex, kept = rasterise.reference(u, v, flux, 40, 30)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    np.testing.assert_allclose(tex, whole_tex, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(kept, whole_kept)
    # the per-triangle arrays and a group's pairs (some 2 MB here), not every pair at once (24 MB here)
    assert peak < 8 * 2**20
