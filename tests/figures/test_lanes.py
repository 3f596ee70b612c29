"""The film made by a second process beside the other figures (sunset/figures/lanes.py): same bytes, all or nothing."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import sunset.recorder.film as film
from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.figures.lanes import _can_fork, split
from sunset.model.scene import Scene

SMALL = Scene.default().with_size(40, 32)

@pytest.fixture
def needs_fork():
    """Asked when the test runs (a thread started by an earlier test can make forking unsafe on Python 3.12+)."""
    if not _can_fork():
        pytest.skip("processes cannot be forked safely here")


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_split_puts_the_film_beside_the_rest_only_with_two_workers():
    """(With the ripples and the diagnostic, which share nothing either.)"""
    names = ["2", "6", "film", "ripples"]
    if _can_fork():
        assert split(names, 2) == (["2", "6"], ["film", "ripples"])
        assert split(["film", "ripples"], 2) == (["ripples"], ["film"])
    assert split(names, 1) == (names, [])                   # --jobs 1: one lane
    assert split(["film"], 2) == (["film"], [])             # nothing to put beside it
    assert split(["2", "6"], 2) == (["2", "6"], [])


def test_two_lanes_make_the_same_bytes_as_one(tmp_path, needs_fork):
    logs = {1: [], 2: []}
    for workers in (1, 2):
        made = make_figures(tmp_path / str(workers), only="2,film,6", scene=SMALL, progress=False,
                            log=logs[workers].append, film_frames=2, workers=workers)
        assert [p.name for p in made] == ["fig2.png", "fig6.png", "film.mp4", "film-preview.webp"]
    assert files(tmp_path / "1") == files(tmp_path / "2")
    assert len(logs[2]) == 3 and "film.mp4" in logs[2][-1]      # the film's line, after the second process ended
    assert not [p for p in (tmp_path / "2").iterdir() if p.name.startswith(".sunset-")]


def test_an_error_in_the_second_process_lands_nothing(tmp_path, monkeypatch, needs_fork):
    out = tmp_path / "figs"
    out.mkdir()
    (out / "fig2.png").write_bytes(b"an older figure 2")
    pid_file = tmp_path / "pid"

    def broken(*_, **__):
        pid_file.write_text(str(os.getpid()))
        raise SunsetError("the film failed on purpose")

    monkeypatch.setattr(film, "make_film", broken)
    with pytest.raises(SunsetError, match="the film failed on purpose"):
        make_figures(out, only="2,film", scene=SMALL, progress=False, log=lambda *_: None, workers=2)
    assert int(pid_file.read_text()) != os.getpid()              # it failed in the second process
    assert files(out) == {"fig2.png": b"an older figure 2"}


def test_a_bug_in_the_second_process_is_reported_with_its_trace(tmp_path, monkeypatch, needs_fork):
    def buggy(*_, **__):
        raise ValueError("a bug on purpose")

    monkeypatch.setattr(film, "make_film", buggy)
    with pytest.raises(RuntimeError, match="ValueError: a bug on purpose") as info:
        make_figures(tmp_path / "figs", only="2,film", scene=SMALL, progress=False, log=lambda *_: None, workers=2)
    assert "Traceback" in str(info.value)
    assert not (tmp_path / "figs").exists()


def test_an_error_here_stops_the_second_process(tmp_path, monkeypatch, needs_fork):
    """A figure of this lane fails while the film is being made: the film's process is ended, nothing lands."""
    import sunset.figures.fig2 as fig2

    def slow(*_, **__):
        import time

        time.sleep(60)
        raise AssertionError("not stopped")

    def broken(*_, **__):
        raise SunsetError("figure 2 failed on purpose")

    monkeypatch.setattr(film, "make_film", slow)
    monkeypatch.setattr(fig2, "figure2", broken)
    import time

    start = time.perf_counter()
    with pytest.raises(SunsetError, match="figure 2 failed on purpose"):
        make_figures(tmp_path / "figs", only="2,film", scene=SMALL, progress=False, log=lambda *_: None, workers=2)
    assert time.perf_counter() - start < 30
    assert not (tmp_path / "figs").exists()
