"""Tape files (sunset/tape/tapefile.py): exact round trip, byte identity, clear errors."""

import hashlib
import json
import os
import struct
from pathlib import Path

import numpy as np
import pytest

from sunset.model.camera import Camera
from sunset.constants import TAPE_FORMAT_VERSION
from sunset.errors import SunsetError
from sunset.model.scene import Scene
from sunset.tape.tapefile import MAGIC, Tape, parse_tape, read_tape, tape_bytes, write_tape


def small_tape(frames=3, seed=4, scene=None):
    scene = scene or Scene.default().with_size(7, 5)
    rng = np.random.default_rng(seed)
    codes = rng.integers(0, 256, size=(frames, 5, 7), dtype=np.uint8)
    times = np.arange(frames) * (1 / 3) + 0.1       # not exactly representable in decimal
    return Tape(scene=scene, codes=codes, times=times, reflections=1, seed=seed)


def test_round_trip_is_exact(tmp_path):
    tape = small_tape()
    path = write_tape(tmp_path / "a.tape", tape)
    back = read_tape(path)
    assert back.same_as(tape)
    assert back.scene == tape.scene
    assert back.codes.dtype == np.uint8 and back.codes.shape == (3, 5, 7)
    assert back.times.tobytes() == tape.times.tobytes()
    assert (back.reflections, back.seed, back.version) == (1, 4, tape.version)
    assert os.listdir(tmp_path) == ["a.tape"]               # no temporary file left behind


def test_same_tape_same_bytes(tmp_path):
    a, b = small_tape(), small_tape()
    write_tape(tmp_path / "a.tape", a)
    write_tape(tmp_path / "b.tape", b)
    assert (tmp_path / "a.tape").read_bytes() == (tmp_path / "b.tape").read_bytes()
    assert tape_bytes(small_tape(seed=5)) != tape_bytes(a)


def test_layout_is_as_documented():
    tape = small_tape()
    data = tape_bytes(tape)
    magic, version, hlen = struct.unpack_from("<8sIQ", data)
    assert magic == MAGIC and version == TAPE_FORMAT_VERSION
    head = json.loads(data[20:20 + hlen])
    assert head["frames"] == 3 and head["height"] == 5 and head["width"] == 7
    assert Scene.from_toml(head["scene"]) == tape.scene
    assert data[20 + hlen:-32] == tape.codes.tobytes()
    assert len(data) == 20 + hlen + 3 * 5 * 7 + 32
    assert data[-32:] == hashlib.sha256(data[:-32]).digest()        # the whole file, header included


def test_every_flipped_bit_is_found():
    """Issue 12: a flipped bit in the header (tilt 40 -> 50) must not expose another picture."""
    data = tape_bytes(small_tape())
    hlen = struct.unpack_from("<Q", data, 12)[0]
    head = data[20:20 + hlen]
    i = head.index(b"tilt = 40.0") + len(b"tilt = ")
    flipped = bytearray(data)
    flipped[20 + i] ^= ord("4") ^ ord("5")                       # one bit: "4" -> "5"
    assert b"tilt = 50.0" in bytes(flipped)
    with pytest.raises(SunsetError, match="checksum"):
        parse_tape(bytes(flipped), "t")
    rng = np.random.default_rng(0)
    for pos in rng.choice(len(data), 40, replace=False):
        bad = bytearray(data)
        bad[pos] ^= 1 << int(rng.integers(8))
        with pytest.raises(SunsetError) as exc:
            parse_tape(bytes(bad), "t")
        assert "\n" not in str(exc.value)


def forged(head: dict, codes: bytes = b"") -> bytes:
    """A tape with a valid checksum around an arbitrary header (what a hostile file can do)."""
    raw = json.dumps(head).encode()
    body = struct.pack("<8sIQ", MAGIC, TAPE_FORMAT_VERSION, len(raw)) + raw + codes
    return body + hashlib.sha256(body).digest()


def good_header(**change):
    head = json.loads(tape_bytes(small_tape())[20:-(3 * 5 * 7 + 32)])
    head.update(change)
    return head


@pytest.mark.parametrize("change, words", [
    ({"scene": "/etc/passwd"}, ["damaged tape"]),                  # text, never a path
    ({"frames": -1, "height": -5}, ["frames must be a positive integer"]),
    ({"frames": True}, ["frames"]),
    ({"frames": 10**6, "height": 10**6}, ["GiB"]),
    ({"times": "x"}, ["times"]),
    ({"times": [1e308, 0.0, 0.0]}, ["times[0] must be a time within"]),       # ω t would overflow
    ({"times": [0.0, 10**400, 0.0]}, ["times[1] must be a finite number", " ... "]),
    ({"times": [[0.0], [0.0], [0.0]]}, ["times[0] must be a finite number"]),
    ({"frames": 10**400}, ["frames of 7x5 is more than", " ... "]),      # a number past 1,000 digits, cut
    ({"reflections": 7}, ["reflections"]),
])
def test_forged_headers(change, words):
    with pytest.raises(SunsetError) as exc:
        parse_tape(forged(good_header(**change), bytes(3 * 5 * 7)), "f.tape")
    msg = str(exc.value)
    assert msg.startswith("f.tape: ") and "\n" not in msg
    assert "root:" not in msg
    for w in words:
        assert w in msg


def test_deeply_nested_header_is_one_error():
    raw = b"[" * 100_000 + b"]" * 100_000
    body = struct.pack("<8sIQ", MAGIC, TAPE_FORMAT_VERSION, len(raw)) + raw
    with pytest.raises(SunsetError, match="nested too deep|damaged tape header"):
        parse_tape(body + hashlib.sha256(body).digest(), "deep")


def test_huge_header_length_is_refused_before_reading(tmp_path):
    path = tmp_path / "big.tape"
    path.write_bytes(struct.pack("<8sIQ", MAGIC, TAPE_FORMAT_VERSION, 2**62))
    with pytest.raises(SunsetError, match="damaged tape header"):
        read_tape(path)


def test_tape_is_read_in_a_stream(tmp_path, monkeypatch):
    """The file is never read whole: the codes go straight into their array."""
    tape = small_tape()
    path = write_tape(tmp_path / "a.tape", tape)
    monkeypatch.setattr(Path, "read_bytes", lambda self: pytest.fail("read whole"))
    assert read_tape(path).same_as(tape)


@pytest.mark.parametrize("keep", [0, 5, 19, 25, -1, -50])
def test_truncated_tapes(tmp_path, keep):
    data = tape_bytes(small_tape())
    cut = tmp_path / "cut.tape"
    cut.write_bytes(data[:keep] if keep >= 0 else data[:len(data) + keep])
    with pytest.raises(SunsetError) as exc:
        read_tape(cut)
    msg = str(exc.value)
    assert msg.startswith(str(cut)) and "\n" not in msg
    assert "truncated" in msg or "damaged" in msg or "not a sunset tape" in msg


def test_truncated_codes_say_so(tmp_path):
    data = tape_bytes(small_tape())
    with pytest.raises(SunsetError, match="truncated tape"):
        parse_tape(data[:-1], "x.tape")


def test_other_version(tmp_path):
    data = bytearray(tape_bytes(small_tape()))
    struct.pack_into("<I", data, 8, TAPE_FORMAT_VERSION + 1)
    with pytest.raises(SunsetError, match=f"version {TAPE_FORMAT_VERSION + 1} is not supported"):
        parse_tape(bytes(data), "v.tape")


def test_not_a_tape_damaged_codes_and_trailing_bytes():
    data = tape_bytes(small_tape())
    with pytest.raises(SunsetError, match="not a sunset tape"):
        parse_tape(b"PNG" + data, "junk")
    flipped = bytearray(data)
    flipped[-1] ^= 0xFF
    with pytest.raises(SunsetError, match="checksum"):
        parse_tape(bytes(flipped), "f")
    flipped[-40] ^= 0x01                                 # a code
    with pytest.raises(SunsetError, match="checksum"):
        parse_tape(bytes(flipped), "f")
    with pytest.raises(SunsetError, match="after the codes"):
        parse_tape(data + b"\0", "t")
    head = bytearray(data)
    head[25] = ord("#")                                   # break the JSON (then also its checksum)
    with pytest.raises(SunsetError, match="damaged tape header|checksum"):
        parse_tape(bytes(head), "h")


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(SunsetError, match="no such tape file"):
        read_tape(tmp_path / "missing.tape")
    with pytest.raises(SunsetError, match="directory"):
        read_tape(tmp_path)


def test_tape_validation():
    scene = Scene(camera=Camera(width=4, height=3))
    with pytest.raises(SunsetError, match="uint8"):
        Tape(scene=scene, codes=np.zeros((1, 3, 4), np.int16), times=[0.0])
    with pytest.raises(SunsetError, match="camera"):
        Tape(scene=scene, codes=np.zeros((1, 4, 3), np.uint8), times=[0.0])
    with pytest.raises(SunsetError, match="times"):
        Tape(scene=scene, codes=np.zeros((2, 3, 4), np.uint8), times=[0.0])
    with pytest.raises(SunsetError, match="times"):
        Tape(scene=scene, codes=np.zeros((1, 3, 4), np.uint8), times=[float("nan")])
    with pytest.raises(SunsetError, match="reflections"):
        Tape(scene=scene, codes=np.zeros((1, 3, 4), np.uint8), times=[0.0], reflections=3)
    t = Tape(scene=scene, codes=np.zeros((2, 3, 4), np.uint8), times=[0.0, 1.0])
    assert len(t) == t.frames == 2


def test_failed_write_leaves_no_file(tmp_path):
    with pytest.raises(SunsetError, match="does not exist"):
        write_tape(tmp_path / "no" / "a.tape", small_tape())
    assert os.listdir(tmp_path) == []
