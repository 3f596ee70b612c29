"""`sunset figures` is all or nothing (issue 12, 15): a failed figure leaves the output folder as it was."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

import sunset.figures.fig3 as fig3
import sunset.figures.paper as paper
from sunset.cli import main
from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.model.scene import Scene

SMALL = Scene.default().with_size(40, 32)


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every entry of ``folder`` (hidden ones too) with its bytes; folders as None."""
    return {p.name: (p.read_bytes() if p.is_file() else None) for p in sorted(folder.iterdir())}


@pytest.fixture
def out(tmp_path):
    """An output folder from an earlier run: an old figure, a file of the user's."""
    folder = tmp_path / "figs"
    folder.mkdir()
    (folder / "fig2.png").write_bytes(b"an older figure 2")
    (folder / "notes.txt").write_text("mine")
    return folder


def test_a_late_failure_leaves_the_folder_unchanged(out, monkeypatch, capsys):
    """Figure 2 is made, then Figure 3 fails: nothing lands, the earlier figure 2 stays as it was."""
    before = snapshot(out)

    def broken(*_, **__):
        raise SunsetError("figure 3 failed on purpose")

    monkeypatch.setattr(fig3, "figure3", broken)
    with pytest.raises(SunsetError, match="on purpose"):
        make_figures(out, only="2,3", scene=SMALL, progress=False, log=lambda *_: None)
    assert snapshot(out) == before
    # the same through the command line: one line, exit 2, the folder byte-identical, no hidden leftovers
    assert main(["figures", "--only", "2,3,4", "--size", "40x32", "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == ["sunset: error: figure 3 failed on purpose"]
    assert snapshot(out) == before


def test_a_target_that_cannot_be_replaced_lands_nothing(out):
    """fig4.png is a folder in the output folder: refused when the figures land, before any other one lands."""
    (out / "fig4.png").mkdir()
    before = snapshot(out)
    with pytest.raises(SunsetError, match="fig4.png: is a directory"):
        make_figures(out, only="2,4", scene=SMALL, progress=False, log=lambda *_: None)
    assert snapshot(out) == before


def test_interrupt_lands_nothing(out, monkeypatch):
    """Ctrl-C in the middle of the run: no figure lands and no hidden folder stays."""
    before = snapshot(out)

    def interrupted(*_, **__):
        raise KeyboardInterrupt

    monkeypatch.setattr(fig3, "figure3", interrupted)
    with pytest.raises(KeyboardInterrupt):
        make_figures(out, only="2,3", scene=SMALL, progress=False, log=lambda *_: None)
    assert snapshot(out) == before


def test_figure7_reads_figure6s_tape_in_one_run_and_later(out, monkeypatch):
    """Figures 6 and 7 in one run: 7 exposes 6's staged tape; later, --only 7 reuses the landed tape."""
    calls = []
    real = paper.render_tape

    def counting(*args, **kw):
        calls.append(args[0].camera.width)
        return real(*args, **kw)

    monkeypatch.setattr(paper, "render_tape", counting)
    written = make_figures(out, only="6,7", scene=SMALL, progress=False, log=lambda *_: None)
    assert [p.name for p in written] == ["fig6.png", "fig7.png"]
    assert len(calls) == 1
    assert {"fig6.png", "fig6.tape", "fig7.png", "fig2.png", "notes.txt"} == set(snapshot(out))
    tape = (out / "fig6.tape").read_bytes()
    first7 = (out / "fig7.png").read_bytes()
    make_figures(out, only="7", scene=SMALL, progress=False, log=lambda *_: None)
    assert len(calls) == 1                          # nothing rendered again
    assert (out / "fig6.tape").read_bytes() == tape
    assert (out / "fig7.png").read_bytes() == first7
    assert (out / "fig2.png").read_bytes() == b"an older figure 2"
    assert not [p for p in out.iterdir() if p.name.startswith(".sunset-")]


def test_a_killed_runs_staging_folder_is_removed(out):
    """A staging folder left by a process that SIGKILL ended is removed by the next run."""
    stale = out / ".sunset-999999999-abc.part"
    stale.mkdir()
    (stale / "fig2.png").write_bytes(b"half")
    old = time.time() - 3600
    os.utime(stale, (old, old))
    make_figures(out, only="2", scene=SMALL, progress=False, log=lambda *_: None)
    assert not stale.exists()
    assert (out / "fig2.png").read_bytes().startswith(b"\x89PNG")


def test_a_failed_run_leaves_no_new_folder(tmp_path, monkeypatch):
    """--out names folders that do not exist yet: a failed run removes the ones it made."""
    def broken(*_, **__):
        raise SunsetError("figure 3 failed on purpose")

    monkeypatch.setattr(fig3, "figure3", broken)
    with pytest.raises(SunsetError, match="on purpose"):
        make_figures(tmp_path / "new" / "figs", only="2,3", scene=SMALL, progress=False, log=lambda *_: None)
    assert list(tmp_path.iterdir()) == []


def test_a_figure_over_budget_is_refused_before_any_figure(out, monkeypatch, capsys):
    """The RGB figure traces 2x2 samples a pixel: at 4000x4000 that is over budget, refused before Figure 2 is made."""
    import sunset.figures.fig2 as fig2

    def not_now(*_, **__):
        raise AssertionError("a figure was made before the budget was checked")

    monkeypatch.setattr(fig2, "figure2", not_now)
    before = snapshot(out)
    code = main(["figures", "--only", "2,rgb", "--size", "4000x4000", "--out", str(out), "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert err[0].startswith("sunset: error: figure rgb at 4000x4000: samples:"), err
    assert snapshot(out) == before
