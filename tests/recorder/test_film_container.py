"""The film as a file (sunset/recorder/film.py): BT.709, +faststart, provenance, an RGB preview, quiet logs."""

import json
import struct
import subprocess
import sys

import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

from sunset.model.scene import Scene
from sunset.provenance import provenance, provenance_json
from sunset.pipeline.film import make_film, render_cycle, write_film
from sunset.recorder.film import _mp4_writer

SIZE = (120, 96)


@pytest.fixture(scope="module")
def tape():
    return render_cycle(Scene.default().with_size(*SIZE), 4, reflections=1, progress=False)


@pytest.fixture(scope="module")
def film(tape, tmp_path_factory):
    out = tmp_path_factory.mktemp("film")
    return write_film(tape, out / "f.mp4", out / "f.webp", from_hours=1.5, to_hours=-0.25, cycles=6, fps=12,
                      progress=False)


def atoms(data: bytes) -> list[str]:
    """The top-level MP4 boxes, in file order."""
    out, i = [], 0
    while i + 8 <= len(data):
        size, kind = struct.unpack(">I4s", data[i:i + 8])
        if size == 1:
            size = struct.unpack(">Q", data[i + 8:i + 16])[0]
        out.append(kind.decode("latin-1"))
        i += size if size else len(data)
    return out


def probe(path) -> str:
    """What ffmpeg says about a file (its stderr for `ffmpeg -i`)."""
    exe = imageio_ffmpeg.get_ffmpeg_exe()
    return subprocess.run([exe, "-hide_banner", "-i", str(path)], capture_output=True, text=True).stderr


def decode_first(path, matrix: str) -> np.ndarray:
    """The first frame decoded to RGB with the given Y'CbCr matrix (bt709 or bt601), whatever the tags say."""
    exe = imageio_ffmpeg.get_ffmpeg_exe()
    out = subprocess.run([exe, "-v", "error", "-i", str(path), "-frames:v", "1", "-vf",
                          f"scale=in_color_matrix={matrix}:in_range=tv", "-f", "rawvideo", "-pix_fmt", "rgb24",
                          "-"], capture_output=True, check=True).stdout
    return np.frombuffer(out, np.uint8).reshape(SIZE[1], SIZE[0], 3)


def test_mp4_index_comes_first(film):
    boxes = atoms(film[0].read_bytes())
    assert "moov" in boxes and "mdat" in boxes
    assert boxes.index("moov") < boxes.index("mdat")      # +faststart: plays while it downloads


def test_mp4_is_tagged_bt709(film):
    info = probe(film[0])
    assert "yuv420p(tv, bt709, progressive)" in info, info


def test_mp4_is_converted_with_the_bt709_matrix(tmp_path):
    """Saturated patches, encoded by the film's writer, come back with BT.709 decoding, not with BT.601."""
    rgb = np.zeros((SIZE[1], SIZE[0], 3), np.uint8)
    rgb[:, : SIZE[0] // 2] = (200, 60, 30)
    rgb[:, SIZE[0] // 2:] = (30, 150, 220)
    writer = _mp4_writer(tmp_path / "p.mp4", SIZE, 12)
    for _ in range(3):
        writer.send(rgb)
    writer.close()
    inner = np.s_[4:-4, 4:SIZE[0] // 2 - 4]          # away from the edge between the patches
    err709 = np.abs(decode_first(tmp_path / "p.mp4", "bt709")[inner].astype(int) - rgb[inner]).max()
    err601 = np.abs(decode_first(tmp_path / "p.mp4", "bt601")[inner].astype(int) - rgb[inner]).max()
    assert err709 <= 3
    assert err601 >= 10                 # the wrong matrix shifts the colours: the encoder used BT.709


def test_mp4_carries_its_provenance(film):
    info = probe(film[0])
    line = next(ln for ln in info.splitlines() if ln.strip().startswith("comment"))
    assert json.loads(line.split(":", 1)[1].strip()) == provenance()
    assert provenance_json().encode() in film[0].read_bytes()


def test_previews_carry_their_provenance(film, tape, tmp_path):
    """The WebP preview in its EXIF (Software, ImageDescription), a GIF preview as its comment."""
    with Image.open(film[1]) as im:
        exif = im.getexif()
        assert json.loads(exif[0x010E]) == provenance()
        assert exif[0x0131] == f"sunset {provenance()['sunset']}"
    gif = write_film(tape, tmp_path / "g.mp4", tmp_path / "g.gif", from_hours=1.0, to_hours=0.9, cycles=1, fps=12,
                     progress=False)[1]
    with Image.open(gif) as im:
        assert json.loads(im.info["comment"]) == provenance()


def test_webp_preview_is_rgb_with_an_opaque_background(film):
    data = film[1].read_bytes()
    assert data[:4] == b"RIFF" and data[8:16] == b"WEBPVP8X"
    flags = data[20]
    assert not flags & 0x10, "the VP8X header says the preview has alpha"
    assert b"ALPH" not in data
    anim = data.index(b"ANIM")
    assert data[anim + 8 + 3] == 255           # background colour's alpha (BGRA): opaque
    with Image.open(film[1]) as im:
        assert im.mode == "RGB" and im.n_frames == 24


def test_progress_only_on_a_terminal(tmp_path, tape, capsys, monkeypatch):
    write_film(tape, tmp_path / "a.mp4", None, cycles=1, progress=True)
    assert capsys.readouterr().err == ""            # stderr is not a terminal: no bar in a log
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    write_film(tape, tmp_path / "b.mp4", None, cycles=1, progress=True)
    assert "filming" in capsys.readouterr().err
    write_film(tape, tmp_path / "c.mp4", None, cycles=1, progress=False)   # --quiet
    assert capsys.readouterr().err == ""


def test_make_film_takes_a_packaged_scene_by_name(tmp_path):
    files = make_film("still-lake-at-noon", tmp_path / "lake.mp4", frames=1, cycles=1, progress=False,
                      tape_path=tmp_path / "lake.tape")
    assert [f.name for f in files] == ["lake.mp4", "lake.tape"]
    assert "bt709" in probe(files[0])
