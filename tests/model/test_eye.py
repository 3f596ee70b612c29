"""Exposure and the eye (sunset/model/eye.py)."""

import math

import numpy as np



def test_eye_response():
    from sunset.constants import EYE_RESPONSE_EXPONENT as n, EYE_SEMI_SATURATION as sigma
    from sunset.model.eye import eye_response

    assert math.isclose(float(eye_response(sigma)), 0.5)
    x = np.logspace(-4, 3, 50)
    y = eye_response(x)
    assert np.all(np.diff(y) > 0) and np.all((y >= 0) & (y < 1))
    # far below σ it is the power law (x/σ)^n: a luminance ratio r becomes r^n
    small = eye_response(np.array([1e-12, 3e-12]))
    assert math.isclose(small[1] / small[0], 3.0**n, rel_tol=1e-4)
    assert eye_response(np.zeros((2, 3, 1))).shape == (2, 3, 1)


def test_xyz_to_linear_srgb_is_cat02_then_the_srgb_matrix():
    """colour-science's XYZ → sRGB against the transform written here from its sources: von Kries scaling in the
    CAT02 space (CIECAM02) from the film's white to D65 (x, y = 0.3127, 0.3290), then IEC 61966-2-1's matrix."""
    from sunset.model.eye import film_white, reference_white, xyz_to_linear_srgb

    cat02 = np.array([[0.7328, 0.4296, -0.1624], [-0.7036, 1.6975, 0.0061], [0.0030, 0.0136, 0.9834]])
    srgb = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])

    def xyz(xy):
        return np.array([xy[0] / xy[1], 1.0, (1 - xy[0] - xy[1]) / xy[1]])

    gain = (cat02 @ xyz((0.3127, 0.3290))) / (cat02 @ xyz(film_white()))
    m = srgb @ np.linalg.inv(cat02) @ np.diag(gain) @ cat02
    sample = np.random.default_rng(3).random((2, 5, 3))
    np.testing.assert_allclose(xyz_to_linear_srgb(sample), sample @ m.T, rtol=1e-12, atol=1e-15)
    # the film's white card comes out grey
    rgb = xyz_to_linear_srgb(reference_white())
    np.testing.assert_allclose(rgb / rgb.mean(), 1.0, atol=2e-4)    # sRGB's D65 is 4 digits: (0.3127, 0.3290)
