"""The compiled sea slopes and sea normals (sunset.vector.slopes_numba) against the NumPy reference.

Float32 on both paths, with different cosines (NumPy's, and the compiled
kernels' own, sunset.vector.sincos_numba): the slopes agree to a few float32
roundings of the largest term, the unit normals within AGREE_NORMAL, and the
compiled direct frame with the reference's as tests/agree.py says.
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain
from sunset.vector import direct
from sunset.vector import heightfield as hf
from sunset.vector import slopes_numba
from sunset.pipeline.frame import trace_direct

from ..agree import assert_geometry_agrees

#: The slopes at the same points on both paths, absolute, as a share of the sea's largest slope Σ n k a_n: the
#: two paths' float32 cosines and sums differ by a rounding or two (measured 1.8e-7).
SLOPE_ATOL = 5e-7
#: The unit normals at the same points on both paths, absolute (measured 1.2e-7: a float32 rounding).
NORMAL_ATOL = 2.5e-7


def seas():
    """Seas of Stokes orders 1, 2 and 4, several trains, one of amplitude 0, and still water."""
    return {
        "order 1": Sea((WaveTrain(0.4, 30.0, direction=80.0, phase=0.3, stokes_order=1),)),
        "order 2": Sea((WaveTrain(0.5, 40.0, direction=95.0, phase=1.1, stokes_order=2),
                        WaveTrain(0.1, 9.0, direction=40.0, phase=2.0, stokes_order=1))),
        "order 4": Sea((WaveTrain(0.6, 35.0, direction=100.0, phase=0.0, stokes_order=4),
                        WaveTrain(0.0, 12.0, direction=10.0, phase=0.5, stokes_order=2),
                        WaveTrain(0.05, 3.0, direction=170.0, phase=4.0, stokes_order=4))),
        "default": Scene.default().sea,
        "still": Sea(()),
    }


def points(rng, n):
    s = rng.uniform(-0.7, 0.7, n)
    y = np.concatenate([rng.uniform(1.0, 300.0, n // 2), 10.0 ** rng.uniform(2.5, 6.0, n - n // 2)])
    return s, y


def steepest_slope(sea) -> float:
    """Σ over trains and harmonics of n k a_n: no slope of the sea is larger (1 for still water)."""
    return sum(tr.k * float(np.sum(np.arange(1, len(a) + 1) * np.abs(a)))
               for tr in sea.trains for a in [tr.harmonic_amplitudes()]) or 1.0


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("name", list(seas()))
@pytest.mark.parametrize("t", [0.0, 1.7, 5000.25])
def test_slopes_agree_with_numpys(name, t):
    sea = seas()[name]
    rng = np.random.default_rng(len(name))
    s, y = points(rng, 6001)               # more than one block, and a ragged last one
    want = hf.sea_gradient_on_scanlines.reference(sea, s, y, t)
    got = slopes_numba.sea_gradient_on_scanlines(sea, s, y, t)
    assert got[0].dtype == got[1].dtype == np.float32 and got[0].shape == want[0].shape
    steepest = steepest_slope(sea)
    for g, w in zip(got, want):
        assert np.abs(g.astype(float) - w).max() <= SLOPE_ATOL * steepest
    if sea.trains:
        assert np.count_nonzero(want[0]) > 5000          # the test sees slopes, not zeros
        # and phases beyond the compiled cosine's fast range, which go to the C library
        assert np.abs(np.float32(sea.trains[0].k) * y).max() > 131072
    # a 2-D shape comes back as it went in
    fx2, fy2 = slopes_numba.sea_gradient_on_scanlines(sea, s[:6000].reshape(60, 100), y[:6000].reshape(60, 100), t)
    assert fx2.shape == (60, 100) and same_bits(fx2.reshape(-1), got[0][:6000])


def test_slopes_of_no_points():
    fx, fy = slopes_numba.sea_gradient_on_scanlines(Scene.default().sea, np.zeros(0), np.zeros(0), 0.0)
    assert fx.shape == fy.shape == (0,) and fx.dtype == np.float32


def test_a_slope_off_by_twice_the_tolerance_is_seen():
    # the comparison can fail: one slope moved by twice the tolerance is seen
    sea = seas()["order 2"]
    s, y = points(np.random.default_rng(0), 500)
    want = hf.sea_gradient_on_scanlines.reference(sea, s, y, 0.0)
    got = slopes_numba.sea_gradient_on_scanlines(sea, s, y, 0.0)
    steepest = steepest_slope(sea)
    assert np.abs(got[0].astype(float) - want[0]).max() <= SLOPE_ATOL * steepest
    got[0][123] += np.float32(2 * SLOPE_ATOL * steepest)
    assert np.abs(got[0].astype(float) - want[0]).max() > SLOPE_ATOL * steepest


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default"])
@pytest.mark.parametrize("t", [0.0, 3.3])
def test_sea_normals_agree_with_numpys(name, t):
    sea = seas()[name]
    rng = np.random.default_rng(7)
    H, W = 40, 70
    idx = np.sort(rng.choice(H * W, 2000, replace=False))
    s, y = points(rng, 2000)
    want = np.full((H, W, 3), np.nan, np.float32)
    got = want.copy()
    with kernels.use_compiled(False):
        direct.put_sea_normals.reference(sea, t, want, idx, s, y)
    slopes_numba.put_sea_normals(sea, t, got, idx, s, y)
    err = np.linalg.norm(got.reshape(-1, 3) - want.reshape(-1, 3), axis=-1)[idx]
    assert err.max() <= NORMAL_ATOL
    assert np.isfinite(want.reshape(-1, 3)[idx]).all() and np.isnan(np.delete(want.reshape(-1, 3), idx, 0)).all()
    assert np.isnan(np.delete(got.reshape(-1, 3), idx, 0)).all()


def test_the_direct_frame_agrees_on_both_paths_and_not_with_the_threads():
    for name in ("order 1", "order 2", "order 4"):
        base = Scene.default().with_size(120, 90)
        scene = Scene(camera=base.camera, sun=base.sun, sea=seas()[name], islands=base.islands)
        for t in (0.0, 2.9):
            with kernels.use_compiled(False):
                ref = trace_direct(scene, t)
            runs = []
            for threads in (1, 2):
                with kernels.use_threads(threads):
                    runs.append(trace_direct(scene, t))
            for field in ("surface", "direction", "point", "distance", "normal", "part"):
                assert same_bits(getattr(runs[1], field), getattr(runs[0], field)), (name, t, field)
            assert_geometry_agrees(ref.finish_direct(False), runs[0].finish_direct(False), f"{name} t={t}")
