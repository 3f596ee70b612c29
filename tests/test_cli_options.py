"""Conventions of the command line: --quiet everywhere, --jobs, the environment variables, info, packaged scenes."""

import subprocess
import sys

import pytest

from sunset.cli import build_parser, main
from sunset.model.scene import Scene, scene_names


def subcommands():
    parser = build_parser()
    action = next(a for a in parser._actions if a.dest == "command")
    return action.choices


def test_every_subcommand_has_quiet():
    for name, sub in subcommands().items():
        flags = {s for a in sub._actions for s in a.option_strings}
        assert {"-q", "--quiet"} <= flags, name


def test_help_documents_the_environment_variables():
    text = build_parser().format_help()
    assert "SUNSET_WORKERS" in text and "SUNSET_COMPILED" in text
    for name in ("figures", "film", "render"):
        sub = subcommands()[name].format_help()
        assert "SUNSET_WORKERS" in sub and "SUNSET_COMPILED" in sub, name
    for name in ("figures", "film"):
        assert "--jobs" in subcommands()[name].format_help()


@pytest.mark.parametrize("value", ["0", "-2", "two"])
def test_bad_jobs_is_one_clear_error(value, capsys, tmp_path):
    assert main(["film", "carlas-island", "--jobs", value, "-o", str(tmp_path / "f.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--jobs" in err
    assert list(tmp_path.iterdir()) == []


def test_jobs_reaches_the_frame_workers(monkeypatch, tmp_path):
    seen = {}
    import sunset.pipeline.film as film

    real = film.render_cycle

    def spy(*args, **kwargs):
        seen["workers"] = kwargs.get("workers")
        return real(*args, **kwargs)

    monkeypatch.setattr(film, "render_cycle", spy)
    assert main(["film", "storm-swell", "--size", "16x12", "--frames", "2", "--jobs", "1", "-q",
                 "-o", str(tmp_path / "f.mp4")]) == 0
    assert seen["workers"] == 1


def test_quiet_figures_print_nothing(tmp_path, capsys):
    assert main(["figures", "--only", "2", "--out", str(tmp_path), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""
    assert main(["figures", "--only", "2", "--out", str(tmp_path)]) == 0
    assert "Figure 2" in capsys.readouterr().err


def test_no_progress_bars_in_a_log_file(tmp_path):
    """stderr to a file (not a terminal): the film's progress bars do not write their redraws into it."""
    log = tmp_path / "log.txt"
    with open(log, "w") as fh:
        proc = subprocess.run([sys.executable, "-m", "sunset", "film", "carlas-island", "--size", "16x12",
                               "--frames", "2", "-o", str(tmp_path / "f.mp4")], stderr=fh, stdout=fh)
    assert proc.returncode == 0
    text = log.read_text()
    assert "filming" not in text and "\r" not in text


def test_scene_prints_any_packaged_scene(capsys):
    assert main(["scene", "--list"]) == 0
    assert capsys.readouterr().out.split() == scene_names()
    for name in scene_names():
        assert main(["scene", name]) == 0
        assert Scene.from_toml(capsys.readouterr().out) == Scene.named(name)
    assert main(["scene"]) == 0
    assert Scene.from_toml(capsys.readouterr().out) == Scene.default()
    assert main(["scene", "atlantis"]) == 2
    assert "no scene named 'atlantis'" in capsys.readouterr().err


def test_render_takes_a_packaged_scene(tmp_path):
    assert main(["render", "archipelago-at-dusk", "--size", "16x12", "--hours", "-0.15", "-o",
                 str(tmp_path / "a.png"), "--quiet"]) == 0
    assert (tmp_path / "a.png").is_file()
