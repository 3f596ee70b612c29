"""The film made by a second process beside the other figures (sunset/figures/lanes.py): same bytes, all or nothing."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import sunset.pipeline.film as film
from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.figures.lanes import Queue, _can_fork, plan
from sunset.model.scene import Scene

SMALL = Scene.default().with_size(40, 32)

@pytest.fixture
def needs_fork():
    """Asked when the test runs (a thread started by an earlier test can make forking unsafe on Python 3.12+)."""
    if not _can_fork():
        pytest.skip("processes cannot be forked safely here")


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_every_figure_is_in_exactly_one_unit():
    from sunset.figures import FIGURES
    from sunset.figures.lanes import UNITS

    names = [n for unit in UNITS for n in unit]
    assert sorted(names) == sorted(FIGURES) and len(names) == len(set(names))
    assert UNITS[0] == ("film",)                                # the longest, started first
    assert {"6", "7", "rgb", "quantisation", "clouds"} == set(next(u for u in UNITS if "6" in u))   # one process


def test_plan_keeps_the_asked_figures_in_units_and_two_lanes_only_with_two_workers():
    names = ["2", "6", "film", "ripples", "quantisation"]
    units, two = plan(names, 2)
    assert units == [["film"], ["6", "quantisation"], ["ripples"], ["2"]]
    assert two == _can_fork()
    assert plan(names, 1) == (units, False)                  # --jobs 1: one lane
    assert plan(["film"], 2) == ([["film"]], False)          # nothing to put beside it
    assert plan(["6", "rgb"], 2) == ([["6", "rgb"]], False)  # one unit: one frame, one process


def test_the_queue_gives_each_unit_to_one_process(needs_fork):
    """The two processes take from one counter: every unit after the first two once, none twice."""
    import multiprocessing

    queue = Queue(400)
    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)

    def take_all():
        got = []
        while (k := queue.take()) is not None:
            got.append(k)
        child.send(got)

    proc = ctx.Process(target=take_all)
    proc.start()
    mine = []
    while (k := queue.take()) is not None:
        mine.append(k)
    theirs = parent.recv()
    proc.join()
    assert sorted(mine + theirs) == list(range(2, 400))
    assert mine == sorted(mine) and theirs == sorted(theirs)
    assert Queue(1).take() is None and Queue(2).take() is None


def test_two_lanes_make_the_same_bytes_as_one(tmp_path, needs_fork):
    logs = {1: [], 2: []}
    for workers in (1, 2):
        made = make_figures(tmp_path / str(workers), only="1,2,film,6,7,reflections", scene=SMALL, progress=False,
                            log=logs[workers].append, film_frames=2, workers=workers)
        assert [p.name for p in made] == ["fig1.png", "fig2.png", "fig6.png", "fig7.png", "reflections.png",
                                          "film.mp4", "film-preview.webp"]
    assert files(tmp_path / "1") == files(tmp_path / "2")
    said = {w: sorted(line.split(": /")[0] for line in logs[w]) for w in logs}      # a line for each figure
    assert len(logs[2]) == 6 and said[1] == said[2]
    assert not [p for p in (tmp_path / "2").iterdir() if p.name.startswith(".sunset-")]


def test_the_second_process_takes_units_from_the_queue(tmp_path, monkeypatch, needs_fork):
    """The film is quick here: the second process goes on to take other figures, and says which."""
    import sunset.figures as figures

    made_by = tmp_path / "made-by"
    made_by.mkdir()
    real = figures.make_figure

    def make(name, *args, **kw):
        (made_by / name).write_text(str(os.getpid()))
        return real(name, *args, **kw)

    monkeypatch.setattr(figures, "make_figure", make)
    slow = __import__("sunset.figures.fig3", fromlist=["figure3"])
    real3 = slow.figure3

    def figure3(*args, **kw):                # this process is held on Figure 3 until the others are begun
        import time

        for _ in range(1200):
            if all((made_by / n).exists() for n in ("diagnostic", "1", "2", "5")):
                break
            time.sleep(0.05)
        return real3(*args, **kw)

    monkeypatch.setattr(slow, "figure3", figure3)
    make_figures(tmp_path / "figs", only="film,3,diagnostic,1,2,5", scene=SMALL, progress=False,
                 log=lambda *_: None, film_frames=2, workers=2)
    pids = {p.name: int(p.read_text()) for p in made_by.iterdir()}
    assert pids["3"] == os.getpid() and pids["film"] != os.getpid()
    assert {pids[n] for n in ("diagnostic", "1", "2", "5")} == {pids["film"]}    # taken while 3 was being made
    assert sorted(p.name for p in (tmp_path / "figs").iterdir()) == [
        "diagnostic.png", "fig1.png", "fig2.png", "fig3.png", "fig5.png", "film-preview.webp", "film.mp4"]


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


def test_an_error_in_the_second_process_stops_this_one_taking_more(tmp_path, monkeypatch, needs_fork):
    """The film fails while this process makes Figure 3: it takes no further figure, and nothing lands."""
    import sunset.figures.fig1 as fig1
    import sunset.figures.fig3 as fig3

    failed = tmp_path / "failed"

    def broken(*_, **__):
        failed.write_text("")
        raise SunsetError("the film failed on purpose")

    def figure3(path, **_):
        import time

        for _ in range(200):
            if failed.exists():
                break
            time.sleep(0.05)
        time.sleep(0.5)                                          # its word is in the pipe
        Path(path).write_bytes(b"3")
        return Path(path)

    called = []
    monkeypatch.setattr(film, "make_film", broken)
    monkeypatch.setattr(fig3, "figure3", figure3)
    monkeypatch.setattr(fig1, "figure1", lambda *a, **k: called.append(1))
    with pytest.raises(SunsetError, match="the film failed on purpose"):
        make_figures(tmp_path / "figs", only="film,3,1", scene=SMALL, progress=False, log=lambda *_: None, workers=2)
    assert failed.exists() and called == []
    assert not (tmp_path / "figs").exists()

