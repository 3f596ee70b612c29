"""The work budget where the pipeline keeps it (sunset/pipeline/budget.py): checked once per RGB frame or film.

The checks are counted by wrapping the vector stage's prediction
(:func:`sunset.vector.budget.predict_work`), which every check of a frame's
work makes once.
"""

import pytest

import sunset.vector.budget as vbudget
from sunset.model.scene import Scene
from sunset.pipeline.budget import check_rgb_work, rgb_work
from sunset.pipeline.rgb import render_rgb, trace_cycle, trace_geometry
from tests.test_hostile_input import one_line_error, run


@pytest.fixture
def checks(monkeypatch):
    """The (width, height) of every frame whose work is checked, in order."""
    seen = []
    real = vbudget.predict_work

    def counting(scene):
        seen.append((scene.camera.width, scene.camera.height))
        return real(scene)

    monkeypatch.setattr(vbudget, "predict_work", counting)
    return seen


SCENE = Scene.default().with_size(24, 20)


def test_an_rgb_frame_checks_the_budget_once(checks):
    trace_geometry(SCENE, 0.3, 2)
    assert checks == [(24, 20)]
    checks.clear()
    trace_geometry(SCENE, 0.3, 2, 4)                # the supersampled frame's work, once
    assert checks == [(48, 40)]
    checks.clear()
    render_rgb(SCENE, 0.3, 0.5)
    assert checks == [(24, 20)]


def test_an_rgb_film_checks_the_budget_once_for_all_its_frames(checks):
    geometries = trace_cycle(SCENE, [0.0, 0.5, 1.0], 2, 1, progress=False)
    assert len(geometries) == 3 and checks == [(24, 20)]


def test_the_work_passed_down_is_the_checked_frames(checks):
    work = rgb_work(SCENE, 4)
    assert (work.width, work.height) == (48, 40) and checks == [(48, 40)]
    assert check_rgb_work(SCENE, 4) > check_rgb_work(SCENE, 1) > 0


def test_the_bound_still_refuses_an_rgb_frame_over_budget(capsys, tmp_path, monkeypatch, checks):
    monkeypatch.setattr(vbudget, "MAX_FRAME_SAMPLES", 1000)          # any frame's sea is over it
    out = tmp_path / "f.png"
    code, _, err = run(capsys, "render", "carlas-island", "--shading", "rgb", "--size", "64x48", "-o", out)
    one_line_error(code, err, "samples", "per frame")
    assert checks == [(64, 48)] and list(tmp_path.iterdir()) == []
