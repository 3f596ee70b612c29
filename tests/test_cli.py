"""The sunset command (sunset/cli.py): every user error is one line and exit 2."""

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from sunset.cli import main
from sunset.model.scene import Scene

SMALL = "48x40"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def assert_user_error(code, err, *words):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("sunset: error:")
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(Scene.default().to_toml())
    return path


def edit(path, old, new):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    return path


def test_scene_prints_default_toml(capsys):
    code, out, _ = run(capsys, "scene")
    assert code == 0
    assert Scene.from_toml(out) == Scene.default()


@pytest.mark.parametrize("mutate, words", [
    (lambda p: p.write_text("[camera\n"), ["malformed TOML"]),
    (lambda p: edit(p, "[camera]\n", "[camera]\nzoom = 2\n"), ["unknown key", "camera.zoom"]),
    (lambda p: edit(p, "eye_height = 2.0\n", ""), ["missing field", "camera.eye_height"]),
    (lambda p: edit(p, "eye_height = 2.0", "eye_height = -2.0"), ["camera.eye_height"]),
    (lambda p: edit(p, "eye_height = 2.0", "eye_height = nan"), ["camera.eye_height", "finite"]),
    (lambda p: edit(p, "width = 1020", "width = 0"), ["camera.width"]),
    (lambda p: edit(p, "amplitude = ", "amplitude = -"), ["sea.trains[0].amplitude"]),
    (lambda p: p.write_text(""), ["missing field", "camera"]),
    (lambda p: edit(p, "width = 1020", "width = 1000000000"), ["camera.width", "at most"]),
    (lambda p: edit(p, "sigma = 0.25", "sigma = 1e-9"), ["camera.sigma"]),
    (lambda p: edit(p, "eye_height = 2.0", "eye_height = 1e300"), ["camera.eye_height", "at most"]),
    (lambda p: edit(p, "wavelength = ", "wavelength = 1e-30 #"), ["sea.trains[0].wavelength", "capillary"]),
    (lambda p: edit(edit(p, "x = -300.0", "x = 0.0"), "y = 850.0", "y = 20.0"), ["islands[0]", "eye inside"]),
    (lambda p: p.write_text('islands = "x"\n' + Scene.default().to_toml().split("[[islands]]")[0]),
     ["islands", "array of tables"]),
])
def test_bad_scene_files(capsys, tmp_path, scene_file, mutate, words):
    mutate(scene_file)
    out = tmp_path / "o.png"
    code, _, err = run(capsys, "render", str(scene_file), "--size", SMALL, "-o", str(out))
    assert_user_error(code, err, *words)
    assert not out.exists()


@pytest.mark.parametrize("argv, words", [
    (["figures", "--only", "8"], ["unknown figure", "'8'"]),
    (["render", "carlas-island", "--size", "0x10", "-o", "x.png"], ["size"]),
    (["render", "carlas-island", "--size", "-4x10", "-o", "x.png"], ["size"]),
    (["render", "carlas-island", "--time", "nan", "-o", "x.png"], ["--time", "finite"]),
    (["render", "carlas-island", "--reflections", "3", "-o", "x.png"], ["--reflections"]),
    (["render", "no-such-scene.toml", "-o", "x.png"], ["no-such-scene.toml"]),
    (["film", "carlas-island", "--frames", "0", "-o", "x.mp4"], ["--frames"]),
    (["expose", "missing.tape", "--hours", "1", "-o", "x.png"], ["missing.tape"]),
    (["bogus"], ["bogus"]),
    (["figures", "--only", ""], ["--only"]),
    (["render", "carlas-island", "--size", "10x10x10", "-o", "x.png"], ["WIDTHxHEIGHT"]),
    (["render", "carlas-island", "--size", "9000x9000", "-o", "x.png"], ["too large"]),
    (["render", "carlas-island", "-o", "x.jpg"], ["'x.jpg'", ".png"]),
    (["render", "carlas-island", "-o", ""], ["output path is empty"]),
    (["expose", "t.tape", "--hours", "1", "-o", "x.gif"], [".png"]),
    (["film", "carlas-island", "--frames", "2", "-o", "x.txt"], ["'x.txt'", ".mp4"]),
    (["film", "carlas-island", "--frames", "2", "--preview", "p.png", "-o", "x.mp4"], ["'p.png'", ".webp"]),
    (["film", "carlas-island", "--frames", "2", "--fps", "100000", "-o", "x.mp4"], ["--fps", "at most"]),
    (["film", "carlas-island", "--frames", "100000", "--size", "64x64", "-o", "x.mp4"], ["--frames", "at most 1000"]),
    (["film", "carlas-island", "--frames", "1000", "--size", "2000x2000", "-o", "x.mp4"], ["frames", "GiB"]),
    (["render", ".", "-o", "x.png"], ["directory"]),
    (["expose", "/dev/zero", "--hours", "1", "-o", "x.png"], ["/dev/zero", "not a regular file"]),
    (["render", "/dev/zero", "-o", "x.png"], ["/dev/zero", "not a regular file"]),
])
def test_bad_arguments(capsys, tmp_path, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv)
    assert_user_error(code, err, *words)
    assert os.listdir(tmp_path) == []


def test_unwritable_output(capsys, tmp_path):
    code, _, err = run(capsys, "render", "carlas-island", "--size", SMALL, "-o", str(tmp_path / "no" / "x.png"))
    assert_user_error(code, err, "does not exist")
    assert list(tmp_path.iterdir()) == []


def test_render_expose_and_damaged_tapes(capsys, tmp_path):
    png, tape = tmp_path / "f.png", tmp_path / "f.tape"
    code, _, err = run(capsys, "render", "carlas-island", "--size", SMALL, "--hours", "0.5", "-o", str(png),
                       "--tape", str(tape))
    assert code == 0, err
    img = Image.open(png)
    assert img.size == (48, 40)
    assert "sunset:scene" in img.text and "sunset:settings" in img.text and "Software" in img.text
    # the film-recorder stage alone reproduces the same picture from the tape
    again = tmp_path / "g.png"
    assert run(capsys, "expose", str(tape), "--hours", "0.5", "-o", str(again))[0] == 0
    np.testing.assert_array_equal(np.asarray(Image.open(again)), np.asarray(img))
    # truncated tape
    data = tape.read_bytes()
    cut = tmp_path / "cut.tape"
    cut.write_bytes(data[: len(data) // 2])
    out = tmp_path / "h.png"
    code, _, err = run(capsys, "expose", str(cut), "--hours", "1", "-o", str(out))
    assert_user_error(code, err, "cut.tape")
    assert not out.exists()
    # a file that is not a tape at all
    junk = tmp_path / "junk.tape"
    junk.write_bytes(b"not a tape at all" * 10)
    code, _, err = run(capsys, "expose", str(junk), "--hours", "1", "-o", str(out))
    assert_user_error(code, err, "junk.tape")


def test_same_command_gives_identical_bytes(capsys, tmp_path):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    for p in (a, b):
        assert run(capsys, "render", "carlas-island", "--size", SMALL, "--seed", "7", "-o", str(p))[0] == 0
    assert a.read_bytes() == b.read_bytes()


def test_python_dash_m_has_no_traceback(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "sunset", "render", str(tmp_path / "nope.toml"), "-o",
                           str(tmp_path / "x.png")], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


def test_every_subcommand_has_help_with_examples(capsys):
    for cmd in ("figures", "render", "expose", "film", "scene"):
        with pytest.raises(SystemExit) as exc:
            main([cmd, "--help"])
        assert exc.value.code == 0
        assert "examples:" in capsys.readouterr().out


def test_tape_of_another_version(capsys, tmp_path):
    import struct

    tape = tmp_path / "f.tape"
    assert run(capsys, "render", "carlas-island", "--size", SMALL, "-o", str(tmp_path / "f.png"),
               "--tape", str(tape))[0] == 0
    data = bytearray(tape.read_bytes())
    struct.pack_into("<I", data, 8, 99)                 # the format version field after the magic
    other = tmp_path / "other.tape"
    other.write_bytes(bytes(data))
    out = tmp_path / "o.png"
    code, _, err = run(capsys, "expose", str(other), "--hours", "1", "-o", str(out))
    assert_user_error(code, err, "other.tape", "version 99")
    assert not out.exists()


@pytest.mark.parametrize("argv", [
    ["figures", "--only", "6", "--size", SMALL, "--quiet", "--out", "{blocker}"],
    ["film", "carlas-island", "--size", "32x24", "--frames", "2", "--quiet", "-o", "{blocker}/f.mp4"],
    ["render", "carlas-island", "--size", SMALL, "-o", "{blocker}/f.png"],
])
def test_output_under_a_file_is_a_clear_error(capsys, tmp_path, argv):
    blocker = tmp_path / "plain-file"
    blocker.write_text("I am a file, not a folder")
    argv = [a.replace("{blocker}", str(blocker)) for a in argv]
    code, _, err = run(capsys, *argv)
    assert_user_error(code, err, "plain-file")
    assert sorted(os.listdir(tmp_path)) == ["plain-file"]


def test_negative_values_reach_their_checks(capsys, tmp_path):
    # "--hours -0.5" (after sunset) is a valid request, not an unknown option
    out = tmp_path / "after.png"
    code, _, err = run(capsys, "render", "carlas-island", "--size", SMALL, "--hours", "-0.5", "-o", str(out))
    assert code == 0, err
    assert out.exists()
    code, _, err = run(capsys, "render", "carlas-island", "--size", SMALL, "--seed", "-3", "-o", str(out))
    assert_user_error(code, err, "--seed")
