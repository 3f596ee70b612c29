"""POV-Ray beside the scan line (sunset.figures.povray): reading pictures back, and one tiny render."""

import numpy as np
import pytest

from sunset.figures.povray import compare, frame_classes, pov_classes, povray_path, render_pov
from sunset.model.scene import Scene
from sunset.pipeline.frame import render


def test_the_flat_colours_read_back_as_destinations():
    rgb = np.array([[[0, 0, 255], [255, 0, 0], [0, 255, 255], [255, 255, 0], [0, 255, 0]]], np.uint8)
    direct, final = pov_classes(rgb)
    assert direct.tolist() == [[-1, 1, 0, 0, 0]]
    assert final.tolist() == [[-1, 1, -1, 1, 2]]


def test_compare_counts_agreement():
    scene = Scene.default().with_size(40, 30)
    frame = render(scene, 0.0, 2)
    direct, final = frame_classes(frame)
    # the frame's own classes painted in POV-Ray's colours agree everywhere
    rgb = np.zeros(direct.shape + (3,), np.uint8)
    rgb[direct == -1] = (0, 0, 255)
    rgb[direct == 1] = (255, 0, 0)
    sea = direct == 0
    rgb[sea & (final == -1)] = (0, 255, 255)
    rgb[sea & (final == 1)] = (255, 255, 0)
    res = compare(frame, rgb)
    assert res["direct_agree"] == 1.0 and res["final_agree"] == 1.0 and res["sea_again"] == 0.0
    # one sea pixel turned to sky: one pixel in W·H disagrees
    k = np.flatnonzero(sea)[0]
    rgb.reshape(-1, 3)[k] = (0, 0, 255)
    assert compare(frame, rgb)["direct_agree"] == pytest.approx(1 - 1 / direct.size)


@pytest.mark.skipif(povray_path() is None, reason="povray is not installed (apt-get install povray)")
def test_povray_sees_what_the_scan_line_sees():
    scene = Scene.default().with_size(48, 40)
    rgb, seconds = render_pov(scene, 0.6, threads=1)
    assert rgb.shape == (40, 48, 3) and seconds > 0
    res = compare(render(scene, 0.6, 2), rgb)
    assert res["counts_pov"]["island"] > 0 and res["counts_pov"]["sea"] > 0 and res["counts_pov"]["sky"] > 0
    assert res["direct_agree"] > 0.98
    assert res["final_agree"] > 0.8
