"""The compiled island normals of the direct frame (direct_numba.put_island_normals) against the NumPy reference.

The same float32 surface on both paths, with NumPy's cosines and sines on
one and the compiled kernels' own (sunset.vector.sincos_numba) on the
other: the parts the same, the unit normals within a float32 rounding or two.
"""

from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.model.scene import Scene
from sunset.vector import direct, direct_numba

from .test_slopes_numba import same_bits

#: The unit normals at the same points on both paths, absolute (measured 1.2e-7: a float32 rounding).
NORMAL_ATOL = 2.5e-7


def islands():
    """The default scene's islands, and the first one again with phases in its cosines."""
    isl = list(Scene.default().islands)
    isl.append(replace(isl[0], cosines=tuple(replace(c, phase=0.9 * (i + 1)) for i, c in enumerate(isl[0].cosines))))
    return isl


@pytest.mark.parametrize("k", range(4))
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_island_normals_agree_with_numpys(k, dtype):
    island = islands()[k]
    rng = np.random.default_rng(k)
    H, W, n = 60, 90, 5000
    idx = np.sort(rng.choice(H * W, n, replace=False))
    # points over the island and around it: beach, cliff and hill all present
    y = (island.y + rng.uniform(-500, 500, n)).astype(dtype)
    s = ((island.x + rng.uniform(-500, 500, n)) / y).astype(dtype)
    want_n = np.full((H, W, 3), np.nan, np.float32)
    want_p = np.zeros((H, W), np.int8)
    got_n, got_p = want_n.copy(), want_p.copy()
    with kernels.use_compiled(False):
        direct.put_island_normals.reference(island, want_n, want_p, idx, s, y)
    direct_numba.put_island_normals(island, got_n, got_p, idx, s, y)
    assert same_bits(got_p, want_p)
    assert set(np.unique(want_p.reshape(-1)[idx])) == {1, 2, 3}
    err = np.linalg.norm(got_n.reshape(-1, 3) - want_n.reshape(-1, 3), axis=-1)
    assert err[idx].max() <= NORMAL_ATOL
    assert np.isnan(np.delete(got_n.reshape(-1, 3), idx, 0)).all()
    # the comparison can fail: a normal off by twice the tolerance is caught
    got_n.reshape(-1, 3)[idx[7], 0] += np.float32(2 * NORMAL_ATOL)
    assert np.linalg.norm(got_n.reshape(-1, 3) - want_n.reshape(-1, 3), axis=-1)[idx].max() > NORMAL_ATOL


def test_the_phases_matter():
    a, b = islands()[0], islands()[-1]
    s, y = np.full(50, a.x / a.y), np.linspace(a.y - 100, a.y + 100, 50)
    out = [np.zeros((1, 50, 3), np.float32) for _ in range(2)]
    for isl, o in zip((a, b), out):
        direct_numba.put_island_normals(isl, o, np.zeros((1, 50), np.int8), np.arange(50), s, y)
    assert not np.array_equal(out[0], out[1])
