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
