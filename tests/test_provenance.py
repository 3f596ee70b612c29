"""Every output records what made it (sunset/provenance.py), one test per writer.

PNGs (rendered frames, matplotlib figures, the RGB back end's 8- and 16-bit
PNGs, any PNG made by sunset.io.png_bytes), the tape, the player's HTML and
the PNG frames inside it, the POV-Ray export, `sunset info`; the MP4 and its
previews are checked in tests/recorder/test_film_container.py. A last test
reads the package's source: every image it saves goes through one of these
writers.
"""

import json
import platform
from importlib import metadata

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from sunset.cli import main
from sunset.io import png_bytes, save_matplotlib, save_png
from sunset.model.scene import Scene
from sunset.provenance import DISTRIBUTION, environment, provenance, provenance_json, stamped
from sunset.tape.tapefile import Tape, parse_tape, read_tape, tape_bytes, write_tape


def test_provenance_reads_the_installed_versions():
    from sunset import kernels

    p = provenance()
    assert list(p) == ["sunset", "python", "numpy", "numba", "colour-science", "kernels"]
    assert p["kernels"] == kernels.path() == ("compiled" if kernels.enabled() else "numpy (SUNSET_COMPILED=0)")
    assert p["sunset"] == metadata.version(DISTRIBUTION)
    assert p["python"] == platform.python_version()
    for name in ("numpy", "numba", "colour-science"):
        assert p[name] == metadata.version(name)
    assert json.loads(provenance_json()) == p
    assert provenance_json() == provenance_json()          # nothing that changes between runs


def test_environment_adds_the_kernels_and_settings():
    from sunset import kernels

    env = environment()
    assert env["kernels"] == kernels.path()
    with kernels.use_compiled(False):
        assert environment()["kernels"] == provenance()["kernels"] == "numpy (switched off)"
    assert {"platform", "SUNSET_WORKERS", "SUNSET_COMPILED"} <= set(env)


def test_rendered_png_records_provenance(tmp_path):
    assert main(["render", "carlas-island", "--size", "24x16", "-o", str(tmp_path / "a.png"), "-q"]) == 0
    with Image.open(tmp_path / "a.png") as im:
        assert json.loads(im.text["sunset:provenance"]) == provenance()
        assert im.text["Software"] == f"sunset {provenance()['sunset']}"


def test_matplotlib_png_records_provenance_and_is_deterministic(tmp_path):
    def draw(path):
        fig = Figure(figsize=(2, 1))
        fig.add_subplot().plot([0, 1], [1, 0])
        return save_matplotlib(fig, path, dpi=50)

    a, b = draw(tmp_path / "a.png"), draw(tmp_path / "b.png")
    assert a.read_bytes() == b.read_bytes()
    with Image.open(a) as im:
        assert json.loads(im.text["sunset:provenance"]) == provenance()
        assert "matplotlib" not in im.text.get("Software", "")


def small_tape():
    scene = Scene.default().with_size(8, 6)
    return Tape(scene=scene, codes=np.zeros((1, 6, 8), np.uint8), times=np.zeros(1))


def test_tape_records_provenance_and_reads_it_back(tmp_path):
    tape = small_tape()
    assert tape.provenance == provenance()
    write_tape(tmp_path / "t.tape", tape)
    back = read_tape(tmp_path / "t.tape")
    assert back.provenance == provenance()
    assert back.same_as(tape)
    assert tape_bytes(back) == tape_bytes(tape)


def test_a_tape_without_provenance_still_reads():
    """Tapes written before provenance was recorded have no such key: they read, with an empty record."""
    data = tape_bytes(small_tape())
    import struct

    magic, version, hlen = struct.unpack_from("<8sIQ", data)
    head = json.loads(data[20:20 + hlen])
    del head["provenance"]
    new = json.dumps(head, sort_keys=True, separators=(",", ":")).encode()
    body = struct.pack("<8sIQ", magic, version, len(new)) + new + data[20 + hlen:-32]
    import hashlib

    old = body + hashlib.sha256(body).digest()          # the checksum covers the header (format 2)
    tape = parse_tape(old)
    assert tape.provenance == {}


def test_sunset_info_prints_every_version(capsys):
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    for name, version in provenance().items():
        assert any(line.split()[:2] == [name, version] for line in out.splitlines()), (name, out)
    assert "frame workers" in out and "kernels" in out


def png_text(data: bytes) -> dict[str, str]:
    """The text chunks (tEXt, iTXt, zTXt) of a PNG, as Pillow reads them."""
    import io

    with Image.open(io.BytesIO(data)) as im:
        im.load()
        return dict(im.text)


def test_stamped_adds_software_and_provenance_and_keeps_the_rest():
    version = provenance()["sunset"]
    assert stamped() == {"Software": f"sunset {version}", "sunset:provenance": provenance_json()}
    given = {"sunset:settings": "{}", "Title": "x"}
    out = stamped(given)
    assert list(out) == ["Software", "sunset:settings", "Title", "sunset:provenance"]
    assert given == {"sunset:settings": "{}", "Title": "x"}           # not changed in place
    own = {"Software": "me", "a": "1", "sunset:provenance": "{}"}
    assert list(stamped(own).items()) == list(own.items())


def test_every_png_of_png_bytes_records_provenance(tmp_path):
    """Also a PNG made with no metadata at all (the player's frames are such PNGs)."""
    grey = np.arange(12, dtype=np.uint8).reshape(3, 4)
    text = png_text(png_bytes(grey))
    assert json.loads(text["sunset:provenance"]) == provenance()
    assert text["Software"] == f"sunset {provenance()['sunset']}"
    path = save_png(tmp_path / "a.png", np.zeros((2, 3, 3), np.uint8), {"note": "x"})
    text = png_text(path.read_bytes())
    assert text["note"] == "x" and json.loads(text["sunset:provenance"]) == provenance()


@pytest.mark.parametrize("depth", [8, 16])
def test_rgb_back_end_pngs_record_provenance(tmp_path, depth):
    from sunset.light.output import save_rgb

    display = np.linspace(0, 1, 2 * 3 * 3).reshape(2, 3, 3)
    path = save_rgb(tmp_path / "a.png", display, depth=depth, metadata={"sunset:settings": "{}"})
    text = png_text(path.read_bytes())
    assert json.loads(text["sunset:provenance"]) == provenance()
    assert text["sunset:settings"] == "{}"


def test_the_player_page_and_its_frames_record_provenance(tmp_path):
    import base64

    from sunset.pipeline.film import write_player
    from sunset.recorder.player import read_player_data

    path = write_player(Scene.default(), tmp_path / "p.html", frames=2, size=(16, 12), from_hours=0.5,
                        to_hours=0.45, progress=False)
    page = path.read_text(encoding="utf-8")
    data = read_player_data(page)
    assert data["provenance"] == provenance()
    assert f'<meta name="generator" content="sunset {provenance()["sunset"]}">' in page
    assert len(data["codes"]) == 2
    for frame in data["codes"]:
        assert json.loads(png_text(base64.b64decode(frame))["sunset:provenance"]) == provenance()


def test_the_pov_export_records_provenance():
    from sunset.model.pov import pov_scene

    lines = pov_scene(Scene.default().with_size(8, 6)).splitlines()
    made = [ln for ln in lines if ln.startswith("// made by: ")]
    assert len(made) == 1
    assert json.loads(made[0].removeprefix("// made by: ")) == provenance()


def test_every_image_the_package_saves_goes_through_a_recording_writer():
    """Reads the source: Pillow's ``.save(``, matplotlib's ``savefig`` and hand-made PNG chunks appear only in
    the writers tested above, so a new writer cannot skip the provenance unnoticed. (NumPy's ``np.save``
    writes the RGB back end's .npy, a bare array format with no place for text.)"""
    import re
    from pathlib import Path

    package = Path(__file__).resolve().parents[1] / "sunset"
    allowed = {"io.py": {"save", "savefig"}, "recorder/film.py": {"save"}, "light/output.py": {"IHDR"}}
    found = {}
    for path in package.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        kinds = {k for k, pattern in (("save", r"(?<!np)\.save\("),
                                       ("savefig", r"\.savefig\("), ("IHDR", r'b"IHDR"'))
                 if re.search(pattern, text)}
        if kinds:
            found[path.relative_to(package).as_posix()] = kinds
    for name, kinds in found.items():
        assert name in allowed and kinds <= allowed[name], f"sunset/{name} saves an image itself: {kinds}"
    film = (package / "recorder" / "film.py").read_text(encoding="utf-8")
    assert film.count("exif=preview_exif()") == 1 and film.count("comment=provenance_json()") == 1


# --------------------------------------------------------------------------- the path that ran: nothing silent
def _run(tmp_path, env_extra, code=None, rgb=False, pythonpath=None, scene="carlas-island"):
    """A fresh ``sunset render`` (or ``code``) with ``env_extra``; returns (stderr lines, the PNG's provenance)."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "SUNSET_COMPILED"}
    env.update(env_extra)
    if pythonpath:
        env["PYTHONPATH"] = os.pathsep.join([str(pythonpath)] + [p for p in [env.get("PYTHONPATH")] if p])
    out = tmp_path / "a.png"
    argv = ["render", scene, "--size", "24x16", "-o", str(out), "-q"] + (["--shading", "rgb"] if rgb else [])
    prog = (code or "") + f"\nimport sys\nfrom sunset.cli import main\nsys.exit(main({argv!r}))\n"
    run = subprocess.run([sys.executable, "-c", prog], env=env, capture_output=True, text=True, timeout=600,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    with Image.open(out) as im:
        made = json.loads(im.text["sunset:provenance"])
    info = subprocess.run([sys.executable, "-c", (code or "") + "\nfrom sunset.cli import main\nmain(['info'])"],
                          env=env, capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert info.returncode == 0 and info.stderr == "", info.stderr
    kernels_line = [line for line in info.stdout.splitlines() if line.split()[:1] == ["kernels"]]
    return run.stderr.splitlines(), made["kernels"], kernels_line[0].split(None, 1)[1]


def test_sunset_compiled_0_is_recorded_and_not_said(tmp_path):
    """The user's own choice: nothing on stderr (a read-only install's run must stay quiet), in the record."""
    err, made, info = _run(tmp_path, {"SUNSET_COMPILED": "0"}, rgb=True)
    assert err == []
    assert made == info == "numpy (SUNSET_COMPILED=0)"


def test_numba_missing_is_said_once_and_recorded(tmp_path):
    """A ``numba`` on the path whose import fails, as where Numba is not installed."""
    fake = tmp_path / "fake"
    (fake / "numba").mkdir(parents=True)
    (fake / "numba" / "__init__.py").write_text("raise ImportError('no numba here')\n")
    err, made, info = _run(tmp_path, {}, rgb=True, pythonpath=fake)
    assert len(err) == 1 and err[0].startswith("sunset: Numba is not installed: the NumPy kernels run"), err
    assert made == info == "numpy (numba missing)"


def test_a_kernel_that_does_not_compile_is_said_once_and_recorded(tmp_path):
    """The RGB shader's island kernel replaced by one that Numba cannot type: its family falls back, the rest
    stay compiled; the picture is still made."""
    code = ("import numba\n"
            "import sunset.light.kernel_numba as kn\n"
            "@numba.njit\n"
            "def _bad(x):\n"
            "    return x.no_such_attribute\n"
            "kn.island_pixels = lambda normals, *rest: _bad(normals)\n")
    err, made, info = _run(tmp_path, {}, code=code, rgb=True)
    assert len(err) == 1, err
    assert err[0].startswith("sunset: the compiled kernels of light.kernel could not be compiled (TypingError")
    assert made == "mixed: compiled, numpy for light.kernel (compilation failed: TypingError)"
    assert info == "compiled"        # another process: nothing failed there (a failure is found when first used)


def test_a_wind_seas_own_kernel_that_does_not_compile_is_said_once_and_recorded(tmp_path):
    """A wind sea's reflected rays run its own kernels (sunset.pipeline.frame.sea_stage): their twin replaced by
    one that Numba cannot type, their family falls back, said and recorded as any kernel's."""
    code = ("import numba\n"
            "import sunset.vector.windsea_crests_numba as wn\n"
            "@numba.njit\n"
            "def _bad(x):\n"
            "    return x.no_such_attribute\n"
            "wn.wind_sea_rays = lambda scene, frame, reflections: _bad(frame.normal)\n")
    err, made, info = _run(tmp_path, {}, code=code, scene="carlas-island-in-the-wind")
    assert len(err) == 1, err
    assert err[0].startswith("sunset: the compiled kernels of vector.windsea_crests could not be compiled (TypingError")
    assert made == "mixed: compiled, numpy for vector.windsea_crests (compilation failed: TypingError)"


def test_a_kernels_own_error_is_raised_not_taken_for_a_compile_failure(monkeypatch):
    import sys
    import types

    from sunset import kernels

    fake = types.ModuleType("sunset_fake_twin")

    def k(x):
        raise ValueError(f"bad x: {x}")

    fake.k = k
    monkeypatch.setitem(sys.modules, "sunset_fake_twin", fake)

    @kernels.twin("sunset_fake_twin")
    def k(x):  # noqa: F811 - the reference of the fake twin
        return "the reference"

    with kernels.use_compiled(True), pytest.raises(ValueError, match="bad x: 3"):
        k(3)
    assert kernels.fallbacks() == {} and kernels.path() == "compiled"
    with kernels.use_compiled(False):
        assert k(3) == "the reference"
