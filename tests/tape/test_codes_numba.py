"""The compiled coding (sunset/tape/codes_numba.py) against the NumPy reference.

The twin of ``encode_rows`` computes the dither inside its loop: its numbers
must be those of ``codes.dither`` exactly (64-bit integer arithmetic, which
both paths compute exactly), for any row offset. Given the same traced frame
the two paths' codes must agree as tests/agree.py says (they differ only
where a value lies within a rounding of a code boundary), for any cut into
strips and any number of threads, and each path's codes must be the same
bytes whatever the cut and the threads.
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import PART_CLIFF
from sunset.errors import SunsetError
from sunset.model.scene import as_scene
from sunset.tape import codes, codes_numba
from sunset.pipeline.frame import render
from sunset.pipeline.frame import encode

from ..agree import assert_codes_agree


@pytest.mark.parametrize("seed, start", [(0, 0), (1, 1), (9, 12345), (2**32 - 1, 10**12 + 7)])
def test_the_compiled_dither_is_the_numpy_one(seed, start):
    for which in (0, 1):
        got = np.empty(20011)
        codes_numba._dither_fill(seed, start, which, got)
        want = codes.dither(seed, start, got.shape, which)
        np.testing.assert_array_equal(got.view(np.uint64), want.view(np.uint64))
        # one pixel off is seen
        assert not np.array_equal(got, codes.dither(seed, start + 1, got.shape, which))


def code_rows(scene, frame, seed, cuts, rows_fn):
    H, W = frame.shape
    out = np.zeros((H, W), np.uint8)
    left = {}
    for r0, r1 in cuts:
        left[r0] = rows_fn(out[r0:r1], frame.rows(r0, r1), seed, r0, scene.sun, codes.code_map(scene))
    return out, left


@pytest.mark.parametrize("name", ["carlas-island", "post-in-the-swell", "carlas-island-clouds",
                                  "archipelago-at-dusk"])
def test_the_compiled_rows_agree_with_the_numpy_ones(name):
    scene = as_scene(name).with_size(173, 131)
    frame = render(scene, 0.8, 2)
    H, W = frame.shape
    rng = np.random.default_rng(3)
    for seed in (0, 77):
        want, want_u = code_rows(scene, frame, seed, [(0, H)], codes.encode_rows.reference)
        edges = np.unique(np.concatenate([[0, H], rng.integers(1, H, 5)])).tolist()
        cuts = list(zip(edges[:-1], edges[1:]))
        got, got_u = code_rows(scene, frame, seed, cuts, codes.encode_rows.compiled())
        # islands and sky coded alike; posts and clouds are left to encode, with the rows' u where there are any
        done = (frame.final_surface >= 1) | (frame.final_surface == -1)
        assert_codes_agree(scene, frame, frame, np.where(done, want, 0), np.where(done, got, 0), seed, name)
        for r0, r1 in cuts:
            rest = ~done[r0:r1]
            if rest.any():
                np.testing.assert_array_equal(got_u[r0], want_u[0][r0:r1])
            else:
                assert got_u[r0] is None
        # whole frames: each path the same bytes on any threads, and the two paths agreeing
        with kernels.use_compiled(False):
            ref = encode(scene, frame, seed=seed)
        with kernels.use_compiled(True), kernels.use_threads(1):
            one = encode(scene, frame, seed=seed)
        assert_codes_agree(scene, frame, frame, ref, one, seed, name)
        for n in (2, 3):
            with kernels.use_compiled(True), kernels.use_threads(n):
                np.testing.assert_array_equal(encode(scene, frame, seed=seed), one)


def test_an_unknown_island_part_is_refused_on_both_paths():
    scene = as_scene("carlas-island").with_size(60, 40)
    frame = render(scene, 0.0, 2)
    island = frame.final_surface >= 1
    assert island.any() and (frame.final_part[island] == PART_CLIFF).any()
    frame.final_part[island] = 7
    for compiled in (False, True):
        with kernels.use_compiled(compiled), pytest.raises(SunsetError, match="got 7"):
            encode(scene, frame)
