"""Atomic, deterministic writing (sunset/io.py)."""

import io
import os

import numpy as np
import pytest
from PIL import Image

from sunset.errors import SunsetError
from sunset.io import atomic_write, check_writable, png_bytes, save_png, write_bytes


def test_write_bytes_replaces_atomically(tmp_path):
    target = tmp_path / "a.bin"
    write_bytes(target, b"one")
    write_bytes(target, b"two")
    assert target.read_bytes() == b"two"
    assert sorted(os.listdir(tmp_path)) == ["a.bin"]


def test_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "a.bin"
    with pytest.raises(RuntimeError):
        with atomic_write(target) as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("interrupted")
    assert os.listdir(tmp_path) == []


def test_failed_write_keeps_old_file(tmp_path):
    target = tmp_path / "a.bin"
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with atomic_write(target) as tmp:
            tmp.write_bytes(b"new but broken")
            raise RuntimeError
    assert target.read_bytes() == b"old"


@pytest.mark.parametrize("make_path", [
    lambda d: d / "missing" / "x.png",
    lambda d: d,
])
def test_unwritable_paths_are_user_errors(tmp_path, make_path):
    with pytest.raises(SunsetError):
        check_writable(make_path(tmp_path))


def test_png_roundtrip_with_metadata_is_deterministic(tmp_path):
    rng = np.random.default_rng(1)
    rgb = rng.integers(0, 256, (7, 5, 3), dtype=np.uint8)
    meta = {"sunset:scene": "title = \"x\"\n", "Software": "sunset"}
    a, b = png_bytes(rgb, meta), png_bytes(rgb.copy(), dict(meta))
    assert a == b
    img = Image.open(io.BytesIO(a))
    np.testing.assert_array_equal(np.asarray(img), rgb)
    assert img.text["sunset:scene"] == meta["sunset:scene"]
    save_png(tmp_path / "x.png", rgb, meta)
    assert (tmp_path / "x.png").read_bytes() == a


def test_png_rejects_non_uint8():
    with pytest.raises(TypeError):
        png_bytes(np.zeros((2, 2, 3)))
