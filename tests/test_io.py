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


def _busy_figure(layout="constrained"):
    """A figure with what the package's figures hold: images, a colour bar, titles, a log axis, a legend."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5, 3), layout=layout)
    axes = fig.subplots(2, 2)
    img = np.linspace(0, 1, 40 * 30).reshape(30, 40)
    im = axes[0, 0].imshow(img, cmap="magma", interpolation="nearest")
    axes[0, 0].set_title("an image, nearest", fontsize=9)
    axes[0, 1].imshow(np.dstack([img, img[::-1], 1 - img]), interpolation="nearest")
    axes[0, 1].set_axis_off()
    fig.colorbar(im, ax=axes[0, 0], shrink=0.8, label="ΔE₀₀ (clipped)")
    axes[1, 0].hist(img.ravel(), bins=12, histtype="step", density=True, label="a: median 0.50")
    axes[1, 0].set_yscale("log")
    axes[1, 0].legend(fontsize=7)
    axes[1, 1].plot([0, 1, 2], [2, 0, 1])
    axes[1, 1].set_xlabel("x (m)")
    fig.suptitle("a busy figure")
    return fig


@pytest.mark.parametrize("layout", ["constrained", "tight", None])
def test_save_matplotlib_is_savefig_laid_out_once(tmp_path, layout):
    """save_matplotlib runs the layout once and draws once: the bytes of matplotlib's savefig (which draws twice),
    and the figure keeps its layout engine and dpi."""
    from sunset.io import save_matplotlib
    from sunset.provenance import stamped

    buf = io.BytesIO()
    _busy_figure(layout).savefig(buf, format="png", dpi=70, metadata=stamped())
    fig = _busy_figure(layout)
    engine, dpi = fig.get_layout_engine(), fig.dpi
    save_matplotlib(fig, tmp_path / "a.png", dpi=70)
    assert (tmp_path / "a.png").read_bytes() == buf.getvalue()
    assert fig.get_layout_engine() is engine and fig.dpi == dpi
