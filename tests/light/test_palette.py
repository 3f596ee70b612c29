"""The 8-bit test: palettes, CIEDE2000 against colour-science's reference data, the code-group table."""

import numpy as np
import pytest

from sunset.light.palette import QuantisationResult, code_group_palette, delta_e_2000, median_cut_kmeans


def test_delta_e_2000_of_identical_images_is_zero():
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (5, 6, 3), dtype=np.uint8)
    np.testing.assert_allclose(delta_e_2000(img, img), 0.0, atol=1e-9)


def test_delta_e_2000_matches_sharma_for_one_pair():
    """Sharma, Wu & Dalal (2005), pair 1: Lab (50, 2.6772, −79.7751) vs (50, 0, −82.7485): ΔE₀₀ = 2.0425."""
    import colour

    assert colour.delta_E([50, 2.6772, -79.7751], [50, 0, -82.7485], method="CIE 2000") == pytest.approx(2.0425,
                                                                                                          abs=1e-4)
    # and our sRGB path: black against white is about 100
    assert delta_e_2000(np.zeros((1, 1, 3), np.uint8), np.full((1, 1, 3), 255, np.uint8))[0, 0] == \
        pytest.approx(100.0, abs=0.1)


def test_median_cut_kmeans_is_exact_for_few_colours():
    rng = np.random.default_rng(4)
    colours = rng.integers(0, 256, (40, 3), dtype=np.uint8)
    img = colours[rng.integers(0, 40, (30, 30))]
    palette, out = median_cut_kmeans(img, colours=64)
    np.testing.assert_array_equal(out, img)            # 40 colours fit in 64
    _, out2 = median_cut_kmeans(img, colours=64)
    np.testing.assert_array_equal(out, out2)           # deterministic


def test_code_group_palette_is_the_mean_per_code():
    lin = np.array([[[0.1, 0.2, 0.3], [0.3, 0.2, 0.1]], [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]])
    codes = np.array([[7, 7], [9, 300]])
    palette, img = code_group_palette(lin, codes)
    np.testing.assert_allclose(img[0, 0], [0.2, 0.2, 0.2])
    np.testing.assert_allclose(img[1], lin[1])
    assert palette.shape == (301, 3)


def test_summary():
    s = QuantisationResult.summary(np.array([0.0, 0.5, 2.0, 4.0]))
    assert s["median"] == 1.25 and s["max"] == 4.0 and s["over1"] == 0.5 and s["over3"] == 0.25


def test_delta_e_per_distinct_pair_is_per_pixel():
    import colour

    rng = np.random.default_rng(6)
    a = rng.integers(0, 256, (40, 30, 3), dtype=np.uint8)
    a[::2] = a[1::2]                                            # repeated colours
    b = np.clip(a.astype(int) + rng.integers(-9, 10, a.shape), 0, 255).astype(np.uint8)
    d65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    want = colour.delta_E(colour.XYZ_to_Lab(colour.sRGB_to_XYZ(a / 255.0), d65),
                          colour.XYZ_to_Lab(colour.sRGB_to_XYZ(b / 255.0), d65), method="CIE 2000")
    np.testing.assert_allclose(delta_e_2000(a, b), want, rtol=1e-12, atol=1e-12)


def test_every_pixel_takes_its_nearest_palette_colour():
    rng = np.random.default_rng(7)
    img = rng.integers(0, 256, (50, 40, 3), dtype=np.uint8)
    palette, out = median_cut_kmeans(img, colours=16)
    d = ((img.reshape(-1, 1, 3).astype(int) - palette.astype(int)[None]) ** 2).sum(-1)
    best = d.min(axis=1)
    got = ((img.reshape(-1, 3).astype(int) - out.reshape(-1, 3).astype(int)) ** 2).sum(-1)
    np.testing.assert_array_equal(got, best)
