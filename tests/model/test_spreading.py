"""Directional spreading (sunset/model/spreading.py): normalised, its moments by quadrature, and its shapes."""

import math

import numpy as np
import pytest
from scipy.special import gamma as gamma_fn

from sunset.errors import SunsetError
from sunset.model.spectrum import WindSpectrum
from sunset.model.spreading import SPREADINGS, density, elfouhaily_delta, mean_cos2, mitsuyasu_s, slope_variances
from sunset.model.wind import Wind

PHI = np.linspace(-math.pi, math.pi, 200001)
SEA = WindSpectrum(Wind(9.0), 60e3)


@pytest.mark.parametrize("name", SPREADINGS)
@pytest.mark.parametrize("ratio", [0.6, 1.0, 1.5, 4.0, 100.0])
def test_each_spreading_is_a_density_with_its_stated_cos2_moment(name, ratio):
    k = ratio * SEA.peak_wavenumber
    d = density(name, SEA, k, PHI)
    assert np.all(d >= 0)
    assert np.trapezoid(d, PHI) == pytest.approx(1.0, abs=1e-5)       # cos^2s(φ/2) with s ≪ 1 drops steeply at ±π
    assert np.trapezoid(d * np.cos(2 * PHI), PHI) == pytest.approx(float(mean_cos2(name, SEA, k)), abs=1e-5)


def test_cos_2s_against_its_normalisation_and_mitsuyasus_s():
    kp = SEA.peak_wavenumber
    sp = 11.5 * SEA.inverse_wave_age ** -2.5
    assert float(mitsuyasu_s(SEA, kp)) == pytest.approx(sp)
    assert float(mitsuyasu_s(SEA, 4 * kp)) == pytest.approx(sp * 2.0 ** -2.5)      # ω = 2ω_p
    assert float(mitsuyasu_s(SEA, 0.25 * kp)) == pytest.approx(sp * 0.5 ** 5)
    s = float(mitsuyasu_s(SEA, kp))
    g = 2 ** (2 * s - 1) * gamma_fn(s + 1) ** 2 / (math.pi * gamma_fn(2 * s + 1))
    assert float(density("mitsuyasu", SEA, kp, 0.3)) == pytest.approx(g * math.cos(0.15) ** (2 * s), rel=1e-10)


def test_elfouhaily_spreading_is_folded_downwind():
    k = 3 * SEA.peak_wavenumber
    delta = float(elfouhaily_delta(SEA, k))
    assert 0 < delta < 1
    assert float(density("elfouhaily", SEA, k, 0.4)) == pytest.approx((1 + delta * math.cos(0.8)) / math.pi)
    assert float(density("elfouhaily", SEA, k, math.pi - 0.4)) == 0.0
    # the snapshot's statistics are those of the unfolded (1 + Δ cos 2φ)/2π: ⟨cos 2φ⟩ = Δ/2
    assert float(mean_cos2("elfouhaily", SEA, k)) == pytest.approx(delta / 2)


@pytest.mark.parametrize("name", SPREADINGS)
def test_slope_variances_split_the_total(name):
    up, cross = slope_variances(name, SEA)
    assert up + cross == pytest.approx(SEA.mean_square_slope, rel=1e-12)
    assert up > cross > 0
    lo, hi = slope_variances(name, SEA, k_hi=1.0), slope_variances(name, SEA, k_lo=1.0)
    assert lo[0] + hi[0] == pytest.approx(up, rel=1e-3)


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_shapes(shape):
    k = np.full(shape, 0.2)
    for name in SPREADINGS:
        assert np.shape(density(name, SEA, k, 0.1)) == shape
        assert np.shape(mean_cos2(name, SEA, k)) == shape


def test_unknown_spreading():
    with pytest.raises(SunsetError, match="^spreading must be one of 'mitsuyasu', 'elfouhaily', got 'cos2'"):
        density("cos2", SEA, 0.1, 0.0)
