"""Cox and Munk's published laws and the Gaussian facet density (sunset/model/coxmunk.py)."""

import math

import numpy as np
import pytest

from sunset.errors import SunsetError
from sunset.model.coxmunk import cox_munk_clean, facet_density


def test_the_clean_surface_laws():
    law = cox_munk_clean(10.0)
    assert law["total"][0] == pytest.approx(0.0542) and law["total"][1] == 0.004
    assert law["upwind"][0] == pytest.approx(0.0316) and law["crosswind"][0] == pytest.approx(0.0222)
    # fitted one by one, the two components sum to the total within 0.0005 at 10 m/s
    assert law["upwind"][0] + law["crosswind"][0] == pytest.approx(law["total"][0], abs=5e-4)
    assert np.shape(cox_munk_clean(np.array([[2.0, 4.0, 6.0]]))["total"][0]) == (1, 3)


@pytest.mark.parametrize("u", [-1.0, 15.0, float("nan")])
def test_outside_cox_and_munks_range(u):
    with pytest.raises(SunsetError, match="^u12_5 must be in"):
        cox_munk_clean(u)


@pytest.mark.parametrize("direction", [0.0, 90.0, 30.0, 260.0])
def test_facet_density_is_a_gaussian_with_the_given_variances(direction):
    vu, vc = 0.03, 0.012
    s = np.linspace(-1.5, 1.5, 1201)
    zx, zy = np.meshgrid(s, s)
    p = facet_density(zx, zy, vu, vc, direction)
    ds = s[1] - s[0]
    assert p.sum() * ds * ds == pytest.approx(1.0, rel=1e-6)
    d = math.radians(direction)
    zu, zc = zx * math.cos(d) + zy * math.sin(d), -zx * math.sin(d) + zy * math.cos(d)
    assert (p * zu * zu).sum() * ds * ds == pytest.approx(vu, rel=1e-6)
    assert (p * zc * zc).sum() * ds * ds == pytest.approx(vc, rel=1e-6)
    assert abs((p * zu * zc).sum() * ds * ds) < 1e-9
    assert facet_density(0.0, 0.0, vu, vc) == pytest.approx(1 / (2 * math.pi * math.sqrt(vu * vc)))


@pytest.mark.parametrize("args, field", [((0.0, 0.01), "var_upwind"), ((0.01, -1.0), "var_crosswind"),
                                         ((float("nan"), 0.01), "var_upwind")])
def test_bad_variances(args, field):
    with pytest.raises(SunsetError, match=f"^{field} must"):
        facet_density(0.0, 0.0, *args)
