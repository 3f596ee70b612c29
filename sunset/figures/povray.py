"""POV-Ray beside the scan line: render the exported scene, read its picture back, compare destinations.

:func:`render_pov` runs POV-Ray 3.7 (``povray``, when installed) on the
scene :func:`sunset.model.pov.pov_scene` writes, at the scene's size, and
times it; :func:`pov_classes` reads the flat colours of its picture back into
where each ray went; :func:`compare` holds them against this package's frame
of the same scene and time: the share of pixels whose direct ray meets the
same thing (sky, sea or an island), and, among the pixels both see as sea,
the share whose reflected ray ends on the same thing (sky or an island).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from ..constants import SEA, SKY
from ..errors import SunsetError

__all__ = ["povray_path", "render_pov", "pov_classes", "frame_classes", "compare", "CLASS_NAMES"]

#: Class numbers of :func:`pov_classes` and :func:`frame_classes`.
CLASS_NAMES = {-1: "sky", 0: "sea", 1: "island", 2: "sea again"}


def povray_path() -> str | None:
    """Where the ``povray`` program is (``$POVRAY`` or the PATH), or None."""
    env = os.environ.get("POVRAY")
    if env:
        return env if Path(env).exists() else None
    return shutil.which("povray")


def render_pov(scene, t: float = 0.0, out_png: str | os.PathLike | None = None, threads: int | None = None,
               timeout: float = 3600.0) -> tuple[np.ndarray, float]:
    """Render ``scene`` at time ``t`` with POV-Ray at the camera's size; (RGB uint8 (H, W, 3), seconds).

    The seconds are the wall-clock time of the ``povray`` process (parsing
    and tracing), on ``threads`` threads (default and at most: the usable CPUs); no
    anti-aliasing, one ray per pixel centre.
    """
    from PIL import Image

    from ..guard import usable_cpus
    from ..model.pov import pov_scene

    exe = povray_path()
    if exe is None:
        raise SunsetError("povray is not installed (Debian: apt-get install povray)")
    cam = scene.camera
    n = min(threads or usable_cpus(), usable_cpus())       # never more threads than the CPUs we may use
    with tempfile.TemporaryDirectory(prefix="sunset-pov-") as tmp:
        pov = Path(tmp) / "scene.pov"
        png = Path(tmp) / "scene.png"
        pov.write_text(pov_scene(scene, t), encoding="utf-8")
        cmd = [exe, f"+I{pov}", f"+O{png}", f"+W{cam.width}", f"+H{cam.height}", "-A", "+FN", "-D", "-V",
               f"+WT{n}", "-GA", "-GW", "-GR", "-GS", "+GF"]
        start = time.perf_counter()
        run = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=tmp,
                             env={**os.environ, "HOME": tmp})
        seconds = time.perf_counter() - start
        if run.returncode != 0 or not png.exists():
            last = (run.stderr.strip().splitlines() or ["no output"])[-1]
            raise SunsetError(f"povray failed (exit {run.returncode}): {last}")
        rgb = np.asarray(Image.open(png).convert("RGB"))
        if out_png is not None:
            shutil.copyfile(png, out_png)
    return rgb, seconds


def pov_classes(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where each ray of a POV-Ray picture of an exported scene went (the colours of :mod:`sunset.model.pov`).

    Returns
    -------
    direct : ndarray (H, W) int8
        What the direct ray met: −1 sky (blue), 0 sea (green), 1 island (red alone).
    final : ndarray (H, W) int8
        Where the sea's reflected rays ended: −1 sky (+ blue), 1 island
        (+ red), 2 the sea again after two reflections (green alone); the
        direct class elsewhere.
    """
    rgb = np.asarray(rgb)
    r, g, b = (rgb[..., k] >= 128 for k in range(3))
    direct = np.where(g, 0, np.where(r, 1, -1)).astype(np.int8)
    final = np.where(g, np.where(r, 1, np.where(b, -1, 2)), direct).astype(np.int8)
    return direct, final


def frame_classes(frame) -> tuple[np.ndarray, np.ndarray]:
    """The same classes for this package's frame: direct (−1 sky, 0 sea, 1 island) and final (−1 sky, 1 island)."""
    direct = np.where(frame.surface == SKY, -1, np.where(frame.surface == SEA, 0, 1)).astype(np.int8)
    final = np.where(frame.final_surface == SKY, -1, np.where(frame.final_surface == SEA, 0, 1)).astype(np.int8)
    return direct, final


def compare(frame, rgb: np.ndarray) -> dict:
    """Agreement of this package's ``frame`` with a POV-Ray picture ``rgb`` of the same scene, time and size.

    Returns ``direct_agree`` (share of all pixels whose direct ray meets the
    same class), ``final_agree`` (share, among pixels both see as sea, whose
    reflected ray ends on the same class; POV-Ray's rays that meet the sea a
    third time count as disagreeing), ``sea_again`` (share of those that
    POV-Ray sends into the sea a third time), and the per-class pixel
    counts of both.
    """
    d_ours, f_ours = frame_classes(frame)
    d_pov, f_pov = pov_classes(rgb)
    if d_ours.shape != d_pov.shape:
        raise SunsetError(f"the POV-Ray picture is {d_pov.shape}, the frame {d_ours.shape}")
    both_sea = (d_ours == 0) & (d_pov == 0)
    n_sea = int(both_sea.sum())
    return {
        "direct_agree": float(np.mean(d_ours == d_pov)),
        "final_agree": float(np.mean(f_ours[both_sea] == f_pov[both_sea])) if n_sea else float("nan"),
        "sea_again": float(np.mean(f_pov[both_sea] == 2)) if n_sea else float("nan"),
        "counts_ours": {CLASS_NAMES[k]: int(np.sum(d_ours == k)) for k in (-1, 0, 1)},
        "counts_pov": {CLASS_NAMES[k]: int(np.sum(d_pov == k)) for k in (-1, 0, 1)},
    }
