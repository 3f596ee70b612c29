"""Colour-table animation: one wave cycle, rendered once, filmed while the sun sets.

The paper's longest sequence was made from one cycle of the periodic wave
motion, written to tape once and rendered onto film again and again, "so that
the repeated frames were differently illuminated each time through the cycle"
(paper, *Color Table Animation*). Here:

1. :func:`render_cycle` renders the N frames t_i = i T/N, i = 0 … N − 1, of one
   period T of the sea (:attr:`sunset.model.waves.Sea.period`, from the dispersion
   relation), and codes them into a :class:`~sunset.tape.tapefile.Tape`. Frame N would
   be t = T, which is frame 0 again, so the cycle loops without a seam.
2. :func:`write_film` replays the tape ``cycles`` times while the hours before
   sunset run linearly from ``from_hours`` to ``to_hours``: film frame j
   shows tape frame j mod N through the tables for its own hour. It writes an
   MP4 (H.264, yuv420p, constant frame rate) and a small looping preview (GIF or WebP).

Only the film recorder runs in step 2: no frame is traced again.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from ..constants import (FILM_FPS, FILM_FROM_HOURS, FILM_TO_HOURS, MAX_CYCLE_FRAMES, MAX_FILM_CYCLES, MAX_FPS,
                         MAX_TAPE_BYTES, MAX_TIME)
from ..errors import SunsetError, real_number, require_bool, require_int_range
from ..io import all_or_nothing
from ..tape.tapefile import Tape, write_tape

from ..model.scene import SceneLike
from ..model.sun import require_hours

__all__ = ["cycle_times", "render_cycle", "film_hours", "film_frames", "write_film", "write_video", "make_film",
           "FILM_CYCLES", "PREVIEW_WIDTH", "PREVIEW_FRAMES"]

#: Default number of times the cycle is replayed in the film.
FILM_CYCLES = 6

#: Width of the looping preview, pixels, and the most frames it keeps.
PREVIEW_WIDTH = 240
PREVIEW_FRAMES = 96

#: x264 settings: a fixed thread count and bit-exact flags keep the MP4 the same
#: from run to run (ffmpeg writes no creation time unless asked). The ``ultrafast``
#: preset at the same constant quality (CRF 18) spends a fraction of ``medium``'s
#: time and gives frames at least as close to the exposed pictures (the benchmark
#: measures both in the same run: the PSNR of the decoded film against the
#: frames sent); it gives them in a larger file.
_X264_PARAMS = ["-preset", "ultrafast", "-crf", "18", "-threads", "2", "-x264-params", "threads=2",
                "-fflags", "+bitexact", "-flags:v", "+bitexact", "-map_metadata", "-1"]

#: How many film frames are exposed ahead of the encoder, and on how many threads.
FILM_AHEAD = 4
FILM_EXPOSERS = 2

#: The film's colours: sRGB frames converted to Y'CbCr with the BT.709 matrix
#: (video range) and tagged BT.709 (primaries, transfer, matrix), so that a
#: player decodes them with the matrix they were encoded with (untagged, many
#: assume BT.601 and shift the colours); the index (moov) goes first
#: (+faststart), so the film plays while it downloads.
_BT709 = ["-vf", "scale=out_color_matrix=bt709:out_range=tv,"
                 "setparams=color_primaries=bt709:color_trc=bt709:colorspace=bt709:range=tv",
          "-color_primaries", "bt709", "-color_trc", "bt709", "-colorspace", "bt709", "-color_range", "tv",
          "-movflags", "+faststart"]


def _film_params() -> list[str]:
    """ffmpeg's output options for the film: x264, BT.709, +faststart, and the provenance as its comment."""
    from ..provenance import provenance_json

    return _X264_PARAMS + _BT709 + ["-metadata", f"comment={provenance_json()}"]


def _mp4_writer(path, size: tuple[int, int], fps: int):
    """An started ffmpeg writer of (H, W, 3) uint8 sRGB frames to an MP4 (see :data:`_BT709`); ``.close()`` it."""
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(str(path), size, fps=fps, codec="libx264", pix_fmt_in="rgb24",
                                         pix_fmt_out="yuv420p", quality=None, macro_block_size=1,
                                         ffmpeg_log_level="quiet", output_params=_film_params())
    writer.send(None)
    return writer


def _bar(total: int, desc: str, progress: bool):
    """A progress bar on stderr, drawn only when stderr is a terminal (a log file gets none)."""
    from tqdm import tqdm

    shown = progress and sys.stderr is not None and sys.stderr.isatty()
    return tqdm(total=total, desc=desc, unit="frame", file=sys.stderr, disable=not shown, leave=False)


def cycle_times(scene, frames: int) -> np.ndarray:
    """t_i = i T/N for i = 0 … N − 1, seconds (all zero on still water).

    Raises :class:`SunsetError` when the sea never repeats.
    """
    require_int_range("frames", frames, 1)
    period = scene.sea.period
    if period is None:
        raise SunsetError("sea.trains: the sea never repeats (frequencies must be rational multiples of the "
                          "lowest, e.g. wavelengths λ, λ/4, λ/9, …), so it has no cycle to film")
    if period > MAX_TIME:                     # rational frequencies with large denominators: centuries
        raise SunsetError(f"sea.trains: the sea repeats only after {period:.3g} s, past the {MAX_TIME:g} s a "
                          "frame's time may reach (frequencies in ratios of smaller denominators repeat sooner)")
    return np.arange(frames, dtype=np.float64) * (float(period) / frames)


def render_cycle(scene, frames: int, reflections: int = 2, seed: int = 0, progress: bool = True,
                 workers: int | None = None) -> Tape:
    """Render and code one wave cycle: the vector stage, once per frame.

    The frames are independent, so they are rendered by ``workers``
    processes at once (:func:`sunset.tape.cycle.code_frames`); the tape is
    byte-identical to the one a single process makes.

    Parameters
    ----------
    scene : Scene
    frames : int
        N, frames per cycle.
    reflections : {0, 1, 2}
        Reflection mode (see :mod:`sunset.vector.render`).
    seed : int
        Dither seed, reset for every frame.
    progress : bool
        Show a progress bar on stderr (when it is a terminal).
    workers : int, optional
        Processes to use; default ``$SUNSET_WORKERS`` or every CPU this process may use.

    Returns
    -------
    Tape
        N frames of codes at t_i = i T/N.
    """
    from ..tape.cycle import code_frames

    require_int_range("reflections", reflections, 0, 2)
    require_int_range("seed", seed, 0, 2**32 - 1)
    times = cycle_times(scene, frames)
    cam = scene.camera
    if frames * cam.width * cam.height > MAX_TAPE_BYTES:
        raise SunsetError(f"frames: {frames} frames at {cam.width}x{cam.height} would need a tape of "
                          f"{frames * cam.width * cam.height / 2**30:.1f} GiB (at most "
                          f"{MAX_TAPE_BYTES / 2**30:g} GiB): use fewer frames or a smaller picture")
    with _bar(frames, "rendering the wave cycle", progress) as bar:
        codes = code_frames(scene, times, reflections, seed, workers=workers, on_frame=lambda i, c: bar.update(1))
    return Tape(scene=scene, codes=codes, times=times, reflections=reflections, seed=seed)


def film_hours(from_hours: float, to_hours: float, count: int) -> np.ndarray:
    """Hours before sunset of each film frame: linear from ``from_hours`` to ``to_hours`` inclusive."""
    require_hours("from_hours", from_hours)
    require_hours("to_hours", to_hours)
    require_int_range("count", count, 1)
    if count == 1:
        return np.array([float(from_hours)])
    return np.linspace(float(from_hours), float(to_hours), count)


def film_frames(tape: Tape, from_hours: float = FILM_FROM_HOURS,
                to_hours: float = FILM_TO_HOURS,
                cycles: int = FILM_CYCLES):
    """Yield ``(hours, rgb)`` for every film frame.

    Film frame j shows tape frame j mod N through the tables for its hour.
    """
    from .dicomed import expose

    require_int_range("cycles", cycles, 1)
    n = len(tape)
    for j, hours in enumerate(film_hours(from_hours, to_hours, cycles * n)):
        yield float(hours), expose(tape.scene, tape.codes[j % n], float(hours))


def _even(rgb: np.ndarray) -> np.ndarray:
    """Pad an image to even width and height by repeating its last row/column (yuv420p needs both even)."""
    h, w = rgb.shape[:2]
    if not (h % 2 or w % 2):
        return np.ascontiguousarray(rgb)
    out = np.empty((h + h % 2, w + w % 2) + rgb.shape[2:], rgb.dtype)
    out[:h, :w] = rgb
    if h % 2:
        out[h, :w] = rgb[h - 1]
    if w % 2:
        out[:, w] = out[:, w - 1]
    return out


def _even_parts(rgb: np.ndarray) -> tuple[np.ndarray, ...]:
    """The bytes of :func:`_even` of ``rgb``, in one or two contiguous pieces for the encoder's pipe.

    An odd height needs only its last row once more (the film's 1020 × 1023 frames: no copy of
    3 MB per frame); an odd width needs a new picture.
    """
    h, w = rgb.shape[:2]
    if w % 2 or not rgb.flags.c_contiguous:
        return (_even(rgb),)
    return (rgb, rgb[h - 1:]) if h % 2 else (rgb,)


def _frames_ahead(tape: Tape, from_hours: float, to_hours: float, cycles: int):
    """The pictures of :func:`film_frames`, exposed ahead on threads while the encoder works.

    Yields each film frame's RGB picture, in film order. Each frame is exposed by the
    same code as :func:`film_frames`; up to :data:`FILM_AHEAD` of them are
    in hand at once, on :data:`FILM_EXPOSERS` threads (the colour tables of
    each hour are most of the work, and NumPy releases the GIL for them).
    """
    from collections import deque
    from concurrent.futures import ThreadPoolExecutor

    from .dicomed import expose

    n = len(tape)
    hours = film_hours(from_hours, to_hours, cycles * n)

    def job(j: int):
        return expose(tape.scene, tape.codes[j % n], float(hours[j]))

    with ThreadPoolExecutor(max_workers=FILM_EXPOSERS, thread_name_prefix="film") as pool:
        pending = deque(pool.submit(job, j) for j in range(min(FILM_AHEAD, len(hours))))
        nxt = len(pending)
        while pending:
            frame = pending.popleft().result()
            if nxt < len(hours):
                pending.append(pool.submit(job, nxt))
                nxt += 1
            yield frame


#: The preview's shrinking: Lanczos, from a picture first halved by 2 × 2 box averages wherever it is
#: more than twice as wide as the preview (Pillow's ``reducing_gap``). For the film's 1020-pixel frames
#: made 240 wide, that is a third of the CPU time of Lanczos from the full picture, and the frames
#: differ from the full picture's by a PSNR of 48 dB, far less than the WebP's own loss at quality 80
#: (36 dB; 2026-12-02, the film's 96 preview frames).
PREVIEW_REDUCING_GAP = 2.0


def _preview_image(rgb: np.ndarray, width: int):
    from PIL import Image

    img = Image.fromarray(rgb)
    if img.width > width:
        height = max(1, round(img.height * width / img.width))
        img = img.resize((width, height), Image.Resampling.LANCZOS, reducing_gap=PREVIEW_REDUCING_GAP)
    return img


def preview_exif() -> bytes:
    """The WebP preview's EXIF: ``Software`` (sunset's version) and, as its ``ImageDescription``, the provenance.

    The GIF preview carries the same JSON (:func:`sunset.provenance.provenance_json`) as its comment.
    """
    from PIL import Image

    from ..provenance import stamped

    text = stamped()
    exif = Image.Exif()
    exif[0x0131] = text["Software"]                 # Software
    exif[0x010E] = text["sunset:provenance"]        # ImageDescription
    return exif.tobytes()


#: Name endings of the film and of its preview.
FILM_SUFFIXES = (".mp4",)
PREVIEW_SUFFIXES = (".gif", ".webp")


def _check_film(path_mp4, path_preview, from_hours: float, to_hours: float, cycles: int, fps: int,
                preview_width: int = PREVIEW_WIDTH) -> tuple[Path, Path | None]:
    """Every check of :func:`write_film`'s arguments, made before any work; the checked paths."""
    from ..io import check_writable

    require_hours("from_hours", real_number("from_hours", from_hours))
    require_hours("to_hours", real_number("to_hours", to_hours))
    require_int_range("cycles", cycles, 1, MAX_FILM_CYCLES)
    require_int_range("fps", fps, 1, MAX_FPS)
    require_int_range("preview_width", preview_width, 8)
    path_mp4 = check_writable(path_mp4, FILM_SUFFIXES)
    if path_preview is not None:
        path_preview = check_writable(path_preview, PREVIEW_SUFFIXES)
    return path_mp4, path_preview


class _quiet_ffmpeg_log:
    """Drop imageio-ffmpeg's "No frames have been written" warning: an interrupted film is removed anyway."""

    def __enter__(self):
        import logging

        self.logger = logging.getLogger("imageio_ffmpeg")
        self.logger.addFilter(self.filter)
        return self

    @staticmethod
    def filter(record) -> bool:
        return "No frames have been written" not in record.getMessage()

    def __exit__(self, *exc):
        self.logger.removeFilter(self.filter)
        return False


def count_video_frames(path: str | os.PathLike) -> int | None:
    """The number of video frames in a film file, read from its packets (not decoded); None if unreadable."""
    import subprocess

    import imageio_ffmpeg

    cmd = [imageio_ffmpeg.get_ffmpeg_exe(), "-v", "error", "-nostdin", "-i", str(path), "-map", "0:v:0",
           "-c", "copy", "-f", "framecrc", "-"]
    try:
        proc = subprocess.run(cmd, capture_output=True, timeout=600)
    except (OSError, subprocess.SubprocessError):
        return None
    if proc.returncode != 0 or proc.stderr.strip():
        return None
    return sum(1 for line in proc.stdout.splitlines() if line and not line.startswith(b"#"))


def _check_encoded(tmp, path_mp4, total: int) -> None:
    """Raise :class:`SunsetError` unless the encoder's file holds all ``total`` frames.

    ffmpeg's exit status is not reported by the pipe writer, and a full disk
    can leave a file without its index; so the file itself is read back
    (packets only, no decoding) before it may replace anything.
    """
    got = count_video_frames(tmp)
    if got != total:
        found = "an unreadable file" if got is None else f"{got} of {total} frames"
        raise SunsetError(f"{path_mp4}: cannot write the film (the encoder wrote {found}; is the disk full?)")


@all_or_nothing()
def write_film(tape: Tape, path_mp4: str | os.PathLike, path_preview: str | os.PathLike | None = None,
               from_hours: float = FILM_FROM_HOURS, to_hours: float = FILM_TO_HOURS, cycles: int = FILM_CYCLES,
               fps: int = FILM_FPS, progress: bool = True, preview_width: int = PREVIEW_WIDTH) -> list[Path]:
    """Film a tape: replay its cycle ``cycles`` times while the sun moves; MP4 and preview.

    Parameters
    ----------
    tape : Tape
        One wave cycle of codes (from :func:`render_cycle`).
    path_mp4 : path
        The film: H.264 in MP4, yuv420p, ``fps`` frames per second (an odd
        picture size is padded by one row or column to make it even),
        converted to and tagged BT.709, its index first (+faststart), with
        :func:`sunset.provenance.provenance` as its ``comment``.
    path_preview : path, optional
        A small looping preview, WebP if the name ends in ``.webp`` and GIF
        otherwise: every k-th film frame (at most
        :data:`PREVIEW_FRAMES`), ``preview_width`` pixels wide. A WebP is
        RGB: every frame is a key frame (WebP's animation encoder otherwise
        stores the changes between frames with an alpha channel), on an
        opaque background. It records the provenance too: a WebP in its
        EXIF (``Software``, and the versions as ``ImageDescription``,
        :func:`preview_exif`), a GIF as its comment.
    from_hours, to_hours : float
        Hours before sunset at the first and the last film frame.
    cycles : int
        How many times the cycle is replayed.
    fps : int
        Frames per second.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    list of Path
        The files written. Both are written atomically and land together:
        if the preview fails, the film is not written either.
    """
    path_mp4, path_preview = _check_film(path_mp4, path_preview, from_hours, to_hours, cycles, fps, preview_width)
    cam = tape.scene.camera
    frames = _frames_ahead(tape, from_hours, to_hours, cycles)
    return write_video(frames, cycles * len(tape), (cam.width, cam.height), path_mp4, path_preview, fps=fps,
                       progress=progress, preview_width=preview_width)


@all_or_nothing()
def write_video(frames, total: int, size: tuple[int, int], path_mp4: str | os.PathLike,
                path_preview: str | os.PathLike | None = None, fps: int = FILM_FPS, progress: bool = True,
                preview_width: int = PREVIEW_WIDTH) -> list[Path]:
    """Encode ``total`` sRGB frames (H, W, 3) uint8 of ``size`` = (W, H) as an MP4 and an optional looping preview.

    The encoder behind :func:`write_film`, and behind the RGB back end's film
    (``sunset film --shading rgb``); see :func:`write_film` for the formats.
    Both files are written atomically and land together (or neither does).
    """
    from concurrent.futures import ThreadPoolExecutor

    from ..io import atomic_write
    from ..provenance import provenance_json

    step = max(1, -(-total // PREVIEW_FRAMES))
    preview = []
    size = (size[0] + size[0] % 2, size[1] + size[1] % 2)

    with atomic_write(path_mp4) as tmp, _bar(total, "filming", progress) as bar, _quiet_ffmpeg_log(), \
            ThreadPoolExecutor(max_workers=1, thread_name_prefix="preview") as shrink:
        try:
            writer = _mp4_writer(tmp, size, fps)
            try:
                for j, rgb in enumerate(frames):
                    if path_preview is not None and j % step == 0:     # shrunk on a thread while the film is fed
                        preview.append(shrink.submit(_preview_image, rgb, preview_width))
                    for part in _even_parts(rgb):
                        writer.send(part)
                    bar.update(1)
            finally:
                writer.close()
        except OSError as exc:               # ffmpeg stopped reading: a full disk, a killed encoder
            raise SunsetError(f"{path_mp4}: cannot write the film (the encoder stopped: "
                              f"{str(exc).splitlines()[0] if str(exc).strip() else 'no reason given'})") from None
        _check_encoded(tmp, path_mp4, total)
        preview = [f.result() for f in preview]
    written = [Path(path_mp4)]
    if path_preview is not None:
        import io

        from ..io import write_bytes

        buf = io.BytesIO()
        if Path(path_preview).suffix.lower() == ".webp":
            preview[0].save(buf, format="WEBP", save_all=True, append_images=preview[1:], loop=0,
                            duration=round(1000 * step / fps), quality=80, method=4,
                            background=(0, 0, 0, 255), kmin=0, kmax=1, exif=preview_exif())
        else:
            preview[0].save(buf, format="GIF", save_all=True, append_images=preview[1:], loop=0,
                            duration=round(1000 * step / fps), optimize=False, comment=provenance_json())
        write_bytes(path_preview, buf.getvalue())
        written.append(Path(path_preview))
    return written


def make_film(scene: SceneLike, path_mp4: str | os.PathLike, path_preview: str | os.PathLike | None = None,
              frames: int = 32,
              from_hours: float = FILM_FROM_HOURS, to_hours: float = FILM_TO_HOURS, reflections: int = 2,
              seed: int = 0, fps: int = FILM_FPS, tape_path: str | os.PathLike | None = None,
              progress: bool = True, cycles: int = FILM_CYCLES, workers: int | None = None) -> list[Path]:
    """Render one cycle to a tape (optionally saved), then film it: what ``sunset film`` runs.

    ``scene`` may be a :class:`~sunset.Scene`, a packaged scene's name or a
    scene file. Returns the files written (MP4, then the preview and the tape
    if asked).
    """
    from ..io import all_or_nothing, check_distinct, check_writable
    from ..model.scene import as_scene

    scene = as_scene(scene)
    _check_film(path_mp4, path_preview, from_hours, to_hours, cycles, fps)
    require_bool("progress", progress)
    if tape_path is not None:
        check_writable(tape_path)
    check_distinct({"the film": path_mp4, "the preview": path_preview, "the tape": tape_path})
    require_int_range("frames", frames, 1, MAX_CYCLE_FRAMES)
    tape = render_cycle(scene, frames, reflections=reflections, seed=seed, progress=progress,
                        workers=workers)
    with all_or_nothing():                   # the film, its preview and the tape land together, or none
        written = write_film(tape, path_mp4, path_preview, from_hours=from_hours, to_hours=to_hours,
                             cycles=cycles, fps=fps, progress=progress)
        if tape_path is not None:
            written.append(write_tape(tape_path, tape))
    return written
