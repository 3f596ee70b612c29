"""Colour-table animation: one wave cycle, rendered once, filmed while the sun sets.

The paper's longest sequence was made from one cycle of the periodic wave
motion, written to tape once and rendered onto film again and again, "so that
the repeated frames were differently illuminated each time through the cycle"
(paper, *Color Table Animation*). Here:

1. the pipeline renders the N frames t_i = i T/N, i = 0 … N − 1, of one
   period T of the sea (:func:`cycle_times`, :attr:`sunset.model.waves.Sea.period`,
   from the dispersion relation), and codes them into a
   :class:`~sunset.tape.tapefile.Tape` (:func:`sunset.pipeline.film.render_cycle`).
   Frame N would be t = T, which is frame 0 again, so the cycle loops without a seam.
2. the tape is replayed ``cycles`` times while the hours before sunset run
   linearly from ``from_hours`` to ``to_hours``: film frame j shows tape
   frame j mod N through the tables for its own hour (:func:`film_frames`).
   :func:`write_video` writes the frames as an MP4 (H.264, yuv420p, constant
   frame rate) and a small looping preview (GIF or WebP);
   :func:`sunset.pipeline.film.write_film` feeds it a tape's frames.

Only the film recorder runs in step 2: no frame is traced again.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from ..constants import FILM_FPS, FILM_FROM_HOURS, FILM_TO_HOURS, MAX_FILM_CYCLES, MAX_FPS, MAX_TIME
from ..errors import SunsetError, real_number, require_int_range
from ..io import all_or_nothing
from ..tape.tapefile import Tape

from ..model.sun import require_hours

__all__ = ["cycle_times", "film_hours", "film_frames", "write_video", "count_video_frames",
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
    from .dicomed import expose_frame

    require_int_range("cycles", cycles, 1)
    n = len(tape)
    for j, hours in enumerate(film_hours(from_hours, to_hours, cycles * n)):
        codes = tape.codes[j % n]
        yield float(hours), expose_frame(tape.scene, codes, float(hours))


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
    """Every check of :func:`sunset.pipeline.film.write_film`'s arguments, made before any work; the checked paths."""
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
def write_video(frames, total: int, size: tuple[int, int], path_mp4: str | os.PathLike,
                path_preview: str | os.PathLike | None = None, fps: int = FILM_FPS, progress: bool = True,
                preview_width: int = PREVIEW_WIDTH) -> list[Path]:
    """Encode ``total`` sRGB frames (H, W, 3) uint8 of ``size`` = (W, H) as an MP4 and an optional looping preview.

    The encoder behind :func:`sunset.pipeline.film.write_film`, and behind the RGB back end's film
    (``sunset film --shading rgb``); see :func:`~sunset.pipeline.film.write_film` for the formats.
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
