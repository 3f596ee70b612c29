"""Figures 4–7 (sunset/figures/paper.py): one pipeline, and Figure 7 is Figure 6's tape re-exposed."""

import hashlib

import numpy as np
from PIL import Image

from sunset.recorder.dicomed import expose
from sunset.figures import paper
from sunset.model.scene import Scene
from sunset.tape.tapefile import read_tape

SIZE = (48, 48)


def _sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_figure7_reuses_figure6s_tape(tmp_path, monkeypatch):
    scene = Scene.default().with_size(*SIZE)
    calls = []
    real = paper.render_tape

    def counting(*args, **kwargs):
        calls.append(args[2])
        return real(*args, **kwargs)

    monkeypatch.setattr(paper, "render_tape", counting)
    f6 = paper.paper_figure("6", tmp_path, scene)
    f7 = paper.paper_figure("7", tmp_path, scene)
    assert calls == [2]                                  # the vector stage ran once, for Figure 6
    tape = read_tape(tmp_path / "fig6.tape")
    rgb7 = np.asarray(Image.open(f7).convert("RGB"))
    rgb6 = np.asarray(Image.open(f6).convert("RGB"))
    np.testing.assert_array_equal(rgb7, expose(scene, tape.codes[0], paper.AFTERNOON_HOURS))
    np.testing.assert_array_equal(rgb6, expose(scene, tape.codes[0], paper.SUNSET_HOURS))
    assert not np.array_equal(rgb6, rgb7)


def test_a_stale_tape_is_not_reused(tmp_path, monkeypatch):
    scene = Scene.default().with_size(*SIZE)
    paper.paper_figure("6", tmp_path, scene, seed=1)
    calls = []
    real = paper.render_tape
    monkeypatch.setattr(paper, "render_tape", lambda *a, **k: calls.append(a) or real(*a, **k))
    paper.paper_figure("7", tmp_path, scene, seed=2)     # another seed: Figure 6's tape does not apply
    assert len(calls) == 1


def test_figures_are_byte_identical_across_runs(tmp_path):
    scene = Scene.default().with_size(*SIZE)
    runs = []
    for k in range(2):
        out = tmp_path / str(k)
        out.mkdir()
        files = [paper.paper_figure(n, out, scene) for n in ("4", "5", "6", "7")] + [out / "fig6.tape"]
        runs.append([_sha(f) for f in files])
    assert runs[0] == runs[1]
