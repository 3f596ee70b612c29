"""Anti-aliasing: the error against a 64-sample reference falls as samples grow."""

import numpy as np
import pytest

from sunset.errors import SunsetError
from sunset.light.render import box_filter, check_samples
from sunset.pipeline.antialias import aa_errors
from sunset.pipeline.rgb import render_rgb
from sunset.model.scene import Scene


@pytest.fixture(scope="module")
def result():
    # a window around the sun and an island's edge, small enough to be quick
    cam = Scene.default().camera
    scene = Scene.default().with_size(56, 48)
    return aa_errors(scene, hours=0.35, samples=(1, 4, 9, 16))


def test_there_are_edges_and_a_rim(result):
    assert result.edge_pixels >= 20 and result.rim_pixels >= 8


def test_error_falls_with_samples(result):
    for errors in (result.edge, result.rim):
        e = [errors[s] for s in (1, 4, 9, 16)]
        assert e[0] > e[1] > e[3], e
        assert e[2] < e[0] and e[3] < 0.5 * e[0]
    assert result.everywhere[16] < result.everywhere[1]


def test_box_filter_is_the_block_mean():
    rng = np.random.default_rng(0)
    img = rng.random((6, 9, 3))
    out = box_filter(img, 3)
    assert out.shape == (2, 3, 3)
    np.testing.assert_allclose(out[1, 2], img[3:6, 6:9].mean(axis=(0, 1)))
    assert box_filter(img, 1) is img


@pytest.mark.parametrize("bad", [0, 2, 3, 8, 257, -4, 2.0, True])
def test_samples_must_be_a_square(bad):
    with pytest.raises(SunsetError):
        check_samples(bad)


def test_one_sample_per_pixel_is_deterministic():
    scene = Scene.default().with_size(24, 20)
    a = render_rgb(scene, 0.5, 0.4, samples=4)
    b = render_rgb(scene, 0.5, 0.4, samples=4)
    np.testing.assert_array_equal(a, b)


def test_bench_measures_the_rgb_back_end():
    from sunset import bench

    times = bench.rgb_bench.measure_rgb(24, 20, 1)
    assert set(times) == {"shade stored frame", "light of one hour", "4-sample frame", "4-sample vector",
                          "4-sample back end"}
    assert all(len(v) == 1 and v[0] > 0 for v in times.values())
