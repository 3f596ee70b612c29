"""Output: 16-bit PNG, float .npy, and the command line's one-line errors."""

import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from sunset.cli import main
from sunset.errors import SunsetError
from sunset.light.output import check_rgb_output, png16_bytes, save_rgb, to_uint16, to_uint8


def decode_png16(data: bytes) -> np.ndarray:
    """A minimal reader of what png16_bytes writes (filter 0 rows), parsing the chunks by the specification."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n = struct.unpack(">I", data[pos:pos + 4])[0]
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        assert struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])[0] == zlib.crc32(kind + body)
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, colour = hdr[:4]
    assert (depth, colour) == (16, 2)
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + 6 * w)
    assert np.all(raw[:, 0] == 0)
    return raw[:, 1:].copy().view(">u2").reshape(h, w, 3).astype(np.uint16)


def test_png16_round_trip_and_pillow_reads_it(tmp_path):
    rng = np.random.default_rng(1)
    lin = rng.random((7, 5, 3))
    path = save_rgb(tmp_path / "a.png", lin, depth=16, metadata={"k": "v"})
    data = path.read_bytes()
    got = decode_png16(data)
    np.testing.assert_array_equal(got, to_uint16(lin))
    with Image.open(path) as im:              # an independent reader opens it, at its size
        assert im.size == (5, 7)
    # the high byte is the 8-bit encoding to within one step
    assert np.max(np.abs(got.astype(int) // 257 - to_uint8(lin).astype(int))) <= 1


def test_npy_is_float32_scene_linear(tmp_path):
    arr = np.array([[[0.5, 2.0, 30.0]]], np.float32)
    path = save_rgb(tmp_path / "a.npy", None, arr)
    back = np.load(path)
    assert back.dtype == np.float32 and back.max() == 30.0


@pytest.mark.parametrize("path,depth", [("a.jpg", 8), ("a.npy", 16), ("a.png", 12)])
def test_bad_outputs(tmp_path, path, depth):
    with pytest.raises(SunsetError):
        check_rgb_output(tmp_path / path, depth)


@pytest.mark.parametrize("argv,message", [
    (["--samples", "4"], "--samples needs --shading rgb"),
    (["--shading", "rgb", "--samples", "3"], "square"),
    (["--shading", "rgb", "--samples", "0"], "positive"),
    (["--shading", "rgb", "--samples", "x"], "whole number"),
    (["--shading", "rgb", "--samples", "1024"], "at most"),
    (["--shading", "rgb", "--tape", "t.tape"], "--tape needs --shading codes"),
    (["--shading", "paint"], "invalid choice"),
    (["--depth", "16"], "--depth needs --shading rgb"),
])
def test_cli_errors_are_one_line(tmp_path, capsys, argv, message):
    out = tmp_path / "x.png"
    assert main(["render", "carlas-island", "--size", "8x8", "-o", str(out)] + argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and message in err and not out.exists()


def test_cli_renders_rgb(tmp_path):
    for name, extra in (("a.png", ["--samples", "4"]), ("b.png", ["--depth", "16"]), ("c.npy", [])):
        assert main(["render", "carlas-island", "--size", "16x12", "--shading", "rgb", "-o",
                     str(tmp_path / name)] + extra) == 0
    with Image.open(tmp_path / "a.png") as im:
        assert im.size == (16, 12) and im.mode == "RGB"
    assert np.load(tmp_path / "c.npy").shape == (12, 16, 3)


def test_cli_rgb_film(tmp_path):
    assert main(["film", "carlas-island", "--shading", "rgb", "--frames", "2", "--size", "16x12", "--quiet",
                 "-o", str(tmp_path / "f.mp4"), "--preview", str(tmp_path / "f.gif")]) == 0
    assert (tmp_path / "f.mp4").stat().st_size > 0 and (tmp_path / "f.gif").stat().st_size > 0
    assert main(["film", "carlas-island", "--shading", "rgb", "--tape", str(tmp_path / "t"), "-o",
                 str(tmp_path / "g.mp4")]) == 2


def test_cli_rgb_film_takes_jobs(tmp_path):
    outs = []
    for jobs in ("1", "2"):
        out = tmp_path / f"f{jobs}.mp4"
        assert main(["film", "carlas-island", "--shading", "rgb", "--frames", "2", "--size", "16x12", "--quiet",
                     "--jobs", jobs, "-o", str(out)]) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    assert main(["film", "carlas-island", "--shading", "rgb", "--jobs", "0", "-o", str(tmp_path / "g.mp4")]) == 2
