"""The 8-bit test: palettes, CIEDE2000 against colour-science's reference data, the code-group table."""

import warnings

import numpy as np
import pytest

from sunset.light.palette import QuantisationResult, code_group_palette, delta_e_2000, median_cut_kmeans


def test_delta_e_2000_of_identical_images_is_zero():
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (5, 6, 3), dtype=np.uint8)
    np.testing.assert_allclose(delta_e_2000(img, img), 0.0, atol=1e-9)


#: Sharma, Wu & Dalal (2005), Table 1: pairs of CIE L*a*b* and their ΔE₀₀, four decimals (pairs 1–4, 7, 8,
#: 17–20, 25, 26, 34: the hue's wrap, greys, large differences and a dark pair).
SHARMA = [((50, 2.6772, -79.7751), (50, 0, -82.7485), 2.0425), ((50, 3.1571, -77.2803), (50, 0, -82.7485), 2.8615),
          ((50, 2.8361, -74.0200), (50, 0, -82.7485), 3.4412), ((50, -1.3802, -84.2814), (50, 0, -82.7485), 1.0000),
          ((50, 0, 0), (50, -1, 2), 2.3669), ((50, -1, 2), (50, 0, 0), 2.3669),
          ((50, 2.5, 0), (73, 25, -18), 27.1492), ((50, 2.5, 0), (61, -5, 29), 22.8977),
          ((50, 2.5, 0), (56, -27, -3), 31.9030), ((50, 2.5, 0), (58, 24, 15), 19.4535),
          ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
          ((63.0109, -31.0961, -5.8663), (62.8187, -29.7946, -4.0864), 1.2630),
          ((2.0776, 0.0795, -1.1350), (0.9033, -0.0636, -0.5514), 0.9082)]


def test_delta_e_2000_is_sharmas():
    """The ΔE₀₀ the 8-bit test takes (colour-science's) against Sharma's published pairs; black against white
    through the sRGB path is 100 (L* 0 against 100, no chroma)."""
    import colour

    a = np.array([p[0] for p in SHARMA], float)
    b = np.array([p[1] for p in SHARMA], float)
    np.testing.assert_allclose(colour.delta_E(a, b, method="CIE 2000"), [p[2] for p in SHARMA], atol=5e-5)
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


def _frame_like(seed=8, shape=(120, 90)):
    """An image that repeats its colours as a frame does: smooth gradients, quantised to bytes, plus noise."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:shape[0], 0:shape[1]]
    img = np.stack([x * 255 / shape[1], y * 255 / shape[0], (x + y) % 97 * 2.0], axis=-1)
    img[rng.random(shape) < 0.05] = rng.integers(0, 256, 3)
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


@pytest.mark.parametrize("colours", [16, 64])
def test_kmeans_is_scipys_kmeans2_bit_for_bit(colours):
    from PIL import Image
    from scipy.cluster.vq import kmeans2

    from sunset.light.palette import kmeans

    img = _frame_like()
    q = Image.fromarray(img).quantize(colors=colours, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    seed = np.asarray(q.getpalette()[: 3 * colours], dtype=float).reshape(-1, 3)
    fit = img.reshape(-1, 3).astype(float)[::3]
    with warnings.catch_warnings(record=True) as theirs:          # empty clusters: warned both ways
        warnings.simplefilter("always")
        want, _ = kmeans2(fit, seed, iter=10, minit="matrix", missing="warn")
    with warnings.catch_warnings(record=True) as ours:
        warnings.simplefilter("always")
        got = kmeans(fit, seed, 10)
    assert got.tobytes() == want.tobytes()
    assert [str(w.message) for w in ours] == [str(w.message) for w in theirs]


def test_kmeans_keeps_an_empty_centre_as_kmeans2_does():
    from scipy.cluster.vq import kmeans2

    from sunset.light.palette import kmeans

    fit = np.repeat(np.array([[0.0, 0, 0], [10, 10, 10], [200, 0, 0], [210, 5, 0]]), [5, 3, 4, 2], axis=0)
    seed = np.array([[0.0, 0, 0], [205, 0, 0], [0, 255, 255]])           # nothing near the third
    with pytest.warns(UserWarning, match="clusters is empty"):
        want, _ = kmeans2(fit, seed, iter=4, minit="matrix", missing="warn")
    with pytest.warns(UserWarning, match="clusters is empty"):
        got = kmeans(fit, seed, 4)
    assert got.tobytes() == want.tobytes()


def test_quantisation_by_codes_is_the_bytes_of_the_mean_image():
    """quantisation_test turns each code's mean colour into bytes once: the bytes of to_uint8 of the whole image."""
    from sunset.light.output import to_uint8
    from sunset.light.palette import quantisation_test

    rng = np.random.default_rng(9)
    lin = rng.random((30, 40, 3)) ** 2
    codes = rng.integers(0, 256, (30, 40))
    sun = rng.random((30, 40)) < 0.1
    q = quantisation_test(lin, codes, sun)
    _, mean_image = code_group_palette(lin, np.where(sun, 256, codes))
    assert q.codes_image.tobytes() == to_uint8(mean_image).tobytes()
    assert q.best_image.dtype == np.uint8 and q.best_image.shape == lin.shape
