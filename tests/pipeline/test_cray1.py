"""Tests for sunset.cray1: the loop counts come from the renderer, the machine model adds up.

Sizes are checked against independent calls (the sampling rule, a rendered
frame's masks); the timing model against hand arithmetic for one loop.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sunset import Scene
from sunset.pipeline.cray1 import CLOCK_S, VECTOR_LENGTH, CrayCosts, Loop, count_frame
from sunset.errors import SunsetError
from sunset.vector.heightfield import sampling
from sunset.pipeline.frame import render

SMALL = Scene.default().with_size(64, 60)


@pytest.fixture(scope="module")
def counted():
    return count_frame(SMALL)


def test_counts_come_from_the_renderer(counted):
    fr = render(SMALL, 0.0, 2)
    assert counted.samples == sampling(SMALL.camera, SMALL.sea.max_elevation).n
    assert counted.sea_pixels == int((fr.surface == 0).sum())
    assert counted.twice == int((fr.bounces == 2).sum())
    assert counted.trains == len(SMALL.sea.trains) and counted.islands == len(SMALL.islands)
    assert counted.pixels == 64 * 60
    by_name = {lp.name: lp for lp in counted.loops}
    assert by_name["sea profile g(y_i)"].elements == counted.samples * 64
    assert by_name["island quadratics"].elements == counted.sea_pixels * counted.islands * 2
    assert not by_name["scan conversion (scalar)"].vector


def test_strips_of_64_and_the_clock_arithmetic():
    costs = CrayCosts(trig=20, sqrt=10, divide=4, startup=8, scalar_iteration=5)
    lp = Loop("x", 130, adds=2, muls=3, divides=1, sqrts=1, trig=1, memory=2)
    assert lp.strips() == 3 == math.ceil(130 / VECTOR_LENGTH)
    ops = 2 + 3 + 4 + 10 + 20 + 2
    assert lp.operations(costs) == ops
    assert lp.clocks(costs, 1.0) == 130 * ops + 3 * ops * 8
    assert lp.clocks(costs, 2.0) == 130 * ops / 2 + 3 * ops * 8
    assert Loop("s", 7, vector=False).clocks(costs, 2.0) == 7 * 5


def test_estimates_are_ordered_and_respond_to_the_assumptions(counted):
    slow, fast = counted.seconds(), counted.seconds(results_per_clock=2.0)
    assert 0 < fast < slow
    cheap = counted.seconds(CrayCosts(trig=5, sqrt=5, divide=2, startup=0, scalar_iteration=1))
    assert cheap < slow
    total = sum(r[3] for r in counted.table())
    assert total == pytest.approx(slow)
    assert counted.per_pixel() * counted.pixels == pytest.approx(counted.operations())
    # the model's clock: 80 million clock periods a second
    assert 1.0 / CLOCK_S == pytest.approx(80e6)


@pytest.mark.parametrize("kwargs", [dict(trig=-1.0), dict(sqrt=float("nan")), dict(startup=float("inf"))])
def test_bad_costs(kwargs):
    with pytest.raises(SunsetError):
        CrayCosts(**kwargs)


def test_bad_rate(counted):
    with pytest.raises(SunsetError, match="results_per_clock"):
        counted.seconds(results_per_clock=0.0)
    assert np.isfinite(counted.seconds())
