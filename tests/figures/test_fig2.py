"""Tests for sunset.figures.fig2: Figure 2 is written, decodes, and is byte-for-byte repeatable."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.figures.fig2 import ORDER_COLOURS, TERM_COLOURS, figure2


def test_figure2_written_decodes_and_is_deterministic(tmp_path):
    a = figure2(tmp_path / "a.png", dpi=60)
    b = figure2(tmp_path / "b.png", dpi=60)
    assert a == tmp_path / "a.png"
    assert a.read_bytes() == b.read_bytes()
    with Image.open(a) as im:
        im.load()
        assert im.format == "PNG"
        assert im.width > 2 * im.height > 0
        assert not any("date" in key.lower() or "time" in key.lower() for key in im.info)
        rgb = np.asarray(im.convert("RGB"))
    # the curves are drawn: black (sums, exact wave) and the terms' colours are present
    assert np.sum(np.all(rgb < 40, axis=-1)) > 500
    assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 50
    assert not list(tmp_path.glob(".*"))  # no temporary file left behind


def test_figure2_depends_on_its_parameters(tmp_path):
    a = figure2(tmp_path / "a.png", alpha=0.2, dpi=50)
    b = figure2(tmp_path / "b.png", alpha=0.35, dpi=50)
    c = figure2(tmp_path / "c.png", alpha=0.2, steepness=0.1, dpi=50)
    assert len({a.read_bytes(), b.read_bytes(), c.read_bytes()}) == 3


def test_figure2_from_the_registry(tmp_path):
    logged = []
    files = make_figures(tmp_path, only="2", log=logged.append)
    assert files == [tmp_path / "fig2.png"]
    assert files[0].stat().st_size > 0
    assert len(logged) == 1 and "fig2.png" in logged[0]


def test_colours_are_distinct():
    assert len(set(TERM_COLOURS)) == 4
    assert len(set(ORDER_COLOURS.values())) == len(ORDER_COLOURS)


@pytest.mark.parametrize("kwargs, message", [
    (dict(alpha=float("nan")), "alpha must be a finite number"),
    (dict(alpha=0.0), r"alpha must be in \(0, 0.5\]"),
    (dict(alpha=0.9), r"alpha must be in \(0, 0.5\]"),
    (dict(steepness=float("inf")), "steepness must be a finite number"),
    (dict(steepness=0.0), "steepness must be positive"),
    (dict(steepness=0.2), "steepness must be in 0..0.141063"),
])
def test_figure2_bad_input(tmp_path, kwargs, message):
    with pytest.raises(SunsetError, match=message):
        figure2(tmp_path / "f.png", **kwargs)
    assert not list(tmp_path.iterdir())


def test_figure2_unwritable(tmp_path):
    with pytest.raises(SunsetError, match="does not exist"):
        figure2(tmp_path / "missing" / "f.png")
