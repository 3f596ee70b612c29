"""Every output records what made it (sunset/provenance.py): PNGs, matplotlib figures, the tape, `sunset info`."""

import json
import platform
from importlib import metadata

import numpy as np
from matplotlib.figure import Figure
from PIL import Image

from sunset.cli import main
from sunset.io import save_matplotlib
from sunset.model.scene import Scene
from sunset.provenance import DISTRIBUTION, environment, provenance, provenance_json
from sunset.tape.tapefile import Tape, parse_tape, read_tape, tape_bytes, write_tape


def test_provenance_reads_the_installed_versions():
    p = provenance()
    assert list(p) == ["sunset", "python", "numpy", "numba", "colour-science"]
    assert p["sunset"] == metadata.version(DISTRIBUTION)
    assert p["python"] == platform.python_version()
    for name in ("numpy", "numba", "colour-science"):
        assert p[name] == metadata.version(name)
    assert json.loads(provenance_json()) == p
    assert provenance_json() == provenance_json()          # nothing that changes between runs


def test_environment_adds_the_kernels_and_settings():
    env = environment()
    assert env["kernels"] in ("numba", "numpy")
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
