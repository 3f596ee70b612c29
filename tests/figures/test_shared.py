"""Figures of one run share frames, codes, exposures and lights (sunset/figures/shared.py): the same bytes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sunset.pipeline.frame as pipeline_frame
from sunset.figures import make_figures, shared
from sunset.model.scene import Scene
from sunset.pipeline.frame import code_frame

SMALL = Scene.default().with_size(40, 32)


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


@pytest.mark.filterwarnings("ignore:One of the clusters is empty")       # k-means on a 40 x 32 frame
def test_figures_made_together_are_the_bytes_of_figures_made_alone(tmp_path, monkeypatch):
    together = tmp_path / "together"
    renders = []
    real = pipeline_frame.depth_buffer

    def counted(*a, **k):                                     # every traced frame's depth buffer (render, code_frame)
        renders.append(a[1:2])
        return real(*a, **k)

    monkeypatch.setattr(pipeline_frame, "depth_buffer", counted)
    make_figures(together, only="6,rgb,quantisation,clouds", scene=SMALL, progress=False, log=lambda *_: None,
                 workers=1)                                   # one process: its renders are counted here
    # Figure 6's codes, the 2x2 RGB frame, the traced frame of the 8-bit test, the cloudy frame: 4 traced
    assert len(renders) == 4
    for name in ("6", "rgb", "quantisation", "clouds"):
        make_figures(tmp_path / "alone", only=name, scene=SMALL, progress=False, log=lambda *_: None)
    assert len(renders) == 4 + 5                              # alone, the RGB figure codes Figure 6 again
    assert files(together) == files(tmp_path / "alone")


def test_codes_are_the_code_frame_and_computed_afresh_outside_a_run():
    a = shared.codes(SMALL, 0.0, 2, 3)
    b = shared.codes(SMALL, 0.0, 2, 3)
    assert a is not b and np.array_equal(a, b)
    assert np.array_equal(a, code_frame(SMALL, 0.0, 2, 3))
    with shared.sharing():
        frame = shared.frame(SMALL, 0.0, 2)
        c = shared.codes(SMALL, 0.0, 2, 3)                    # from the whole frame: the same bytes
        assert shared.codes(SMALL, 0.0, 2, 3) is c
        assert shared.frame(SMALL, 0.0, 2) is frame
        assert shared.codes(SMALL, 0.0, 2, 4) is not c        # another seed is another key
        with pytest.raises(ValueError):
            c[0, 0] = 1                                       # handed out read-only
    assert np.array_equal(a, c)
    assert shared.codes(SMALL, 0.0, 2, 3) is not c            # the run's store is gone
