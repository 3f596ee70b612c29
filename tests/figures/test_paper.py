"""Figures 4–7 (sunset/figures/paper.py): one pipeline, and Figure 7 is Figure 6's tape re-exposed."""

import hashlib

import numpy as np
import pytest
from PIL import Image

from sunset.pipeline.frame import expose
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


# --------------------------------------------------------------------------- the two kernel paths' figures
def _figures(scene, names, compiled, out):
    from sunset import kernels
    from sunset.figures.rgb import rgb_figure6

    (out / "again").mkdir(parents=True)
    with kernels.use_compiled(compiled):
        files = [paper.paper_figure(n, out, scene) if n != "rgb6" else rgb_figure6(out / "rgb6.png", scene)
                 for n in names]
        again = [paper.paper_figure(n, out / "again", scene) if n != "rgb6" else
                 rgb_figure6(out / "again" / "rgb6.png", scene) for n in names[:1]]
    assert _sha(again[0]) == _sha(files[0])                      # each path: the same bytes every time
    return [np.asarray(Image.open(f).convert("RGB")) for f in files]


@pytest.mark.parametrize("name, figures", [
    ("carlas-island", ("4", "5", "6", "7", "rgb6")), ("carlas-island-clouds", ("6", "rgb6")),
    ("archipelago-at-dusk", ("6",)), ("post-in-the-swell", ("6",)), ("still-lake-at-noon", ("6",)),
    ("storm-swell", ("6",))])
def test_the_figures_of_both_paths_agree_within_the_stated_tolerance(name, figures, tmp_path):
    """The compiled path's figures against the NumPy path's (the reference): at most FIGURE_DIFFER_SHARE of the
    pixels differ, none by more than FIGURE_MAX_DE00 (CIEDE2000); not the same bytes, which only one path promises."""
    from sunset.light.palette import FIGURE_DIFFER_SHARE, FIGURE_MAX_DE00, picture_agreement

    scene = Scene.named(name).with_size(128, 128)
    want_got = zip(_figures(scene, figures, False, tmp_path / "numpy"), _figures(scene, figures, True, tmp_path / "nb"))
    for fig, (want, got) in zip(figures, want_got):
        agree = picture_agreement(got, want)
        assert agree["differ"] <= FIGURE_DIFFER_SHARE and agree["max_de00"] <= FIGURE_MAX_DE00, (fig, agree)


def test_the_figures_tolerance_sees_a_visible_change():
    """picture_agreement on a picture and itself with one pixel a little off, and with a colour cast."""
    from sunset.light.palette import FIGURE_DIFFER_SHARE, FIGURE_MAX_DE00, picture_agreement

    rng = np.random.default_rng(4)
    a = rng.integers(0, 256, (100, 100, 3), dtype=np.uint8)
    assert picture_agreement(a, a) == {"pixels": 10_000, "differ": 0.0, "visible": 0.0, "max_de00": 0.0}
    b = a.copy()
    b[7, 9] = (0, 0, 0) if a[7, 9].sum() > 300 else (255, 255, 255)
    agree = picture_agreement(a, b)
    assert agree["differ"] == 1e-4 <= FIGURE_DIFFER_SHARE and agree["max_de00"] > FIGURE_MAX_DE00
    cast = np.clip(a.astype(int) + [6, 0, 0], 0, 255).astype(np.uint8)
    agree = picture_agreement(a, cast)
    assert agree["differ"] > FIGURE_DIFFER_SHARE and agree["visible"] > 0.5
    with pytest.raises(ValueError, match="one shape"):
        picture_agreement(a, a[:-1])
