"""The compiled sea slopes and sea normals (sunset.vector.slopes_numba) against the NumPy reference, bit for bit."""

import numpy as np
import pytest

from sunset import kernels
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain
from sunset.vector import direct
from sunset.vector import heightfield as hf
from sunset.vector import slopes_numba


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


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("name", list(seas()))
@pytest.mark.parametrize("t", [0.0, 1.7, 5000.25])
def test_slopes_are_numpys(name, t):
    sea = seas()[name]
    rng = np.random.default_rng(len(name))
    s, y = points(rng, 6001)               # more than one block, and a ragged last one
    want = hf.sea_gradient_on_scanlines.reference(sea, s, y, t)
    got = slopes_numba.sea_gradient_on_scanlines(sea, s, y, t)
    assert same_bits(got[0], want[0]) and same_bits(got[1], want[1])
    if sea.trains:
        assert np.count_nonzero(want[0]) > 5000          # the test sees slopes, not zeros
        # and phases beyond NumPy's polynomial range (|θ| > 71476), which go to the C library
        assert np.abs(np.float32(sea.trains[0].k) * y).max() > 71476.0625
    # a 2-D shape comes back as it went in
    fx2, fy2 = slopes_numba.sea_gradient_on_scanlines(sea, s[:6000].reshape(60, 100), y[:6000].reshape(60, 100), t)
    assert fx2.shape == (60, 100) and same_bits(fx2.reshape(-1), want[0][:6000])


def test_slopes_of_no_points():
    fx, fy = slopes_numba.sea_gradient_on_scanlines(Scene.default().sea, np.zeros(0), np.zeros(0), 0.0)
    assert fx.shape == fy.shape == (0,) and fx.dtype == np.float32


def test_one_changed_bit_is_seen():
    # the comparison can fail: one ulp in one slope is caught
    sea = seas()["order 2"]
    s, y = points(np.random.default_rng(0), 500)
    want = hf.sea_gradient_on_scanlines.reference(sea, s, y, 0.0)
    got = slopes_numba.sea_gradient_on_scanlines(sea, s, y, 0.0)
    got[0][123] = np.nextafter(got[0][123], np.float32(np.inf))
    assert not same_bits(got[0], want[0])


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default"])
@pytest.mark.parametrize("t", [0.0, 3.3])
def test_sea_normals_are_numpys(name, t):
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
    assert same_bits(got, want)
    assert np.isfinite(want.reshape(-1, 3)[idx]).all() and np.isnan(np.delete(want.reshape(-1, 3), idx, 0)).all()


@pytest.mark.parametrize("threads", [1, 2])
def test_the_direct_frame_is_the_same_on_both_paths(threads):
    for name in ("order 1", "order 2", "order 4"):
        base = Scene.default().with_size(120, 90)
        scene = Scene(camera=base.camera, sun=base.sun, sea=seas()[name], islands=base.islands)
        for t in (0.0, 2.9):
            with kernels.use_threads(threads):
                with kernels.use_compiled(False):
                    ref = direct.trace_direct(scene, t)
                got = direct.trace_direct(scene, t)
            for field in ("surface", "direction", "point", "distance", "normal", "part"):
                assert same_bits(getattr(got, field), getattr(ref, field)), (name, t, field)
