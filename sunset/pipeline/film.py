"""A film and the player through the pipeline: one wave cycle coded once, then exposed hour by hour.

The paper's longest sequence was made from one cycle of the periodic wave
motion, written to tape once and rendered onto film again and again (paper,
*Color Table Animation*; :mod:`sunset.recorder.film`). Here the pipeline
chains the two stages: :func:`render_cycle` codes the cycle's frames over
worker processes (:func:`sunset.pipeline.cycle.code_frames`) into a
:class:`~sunset.tape.tapefile.Tape`; :func:`write_film` exposes the tape's
frames through the tables of each film frame's hour, a few ahead on threads
while the encoder works, and hands them to the film recorder's encoder
(:func:`sunset.recorder.film.write_video`); :func:`make_film` does both, as
``sunset film`` does. The player (:mod:`sunset.recorder.player`) gets its
cycle the same way and its tables of every hour over worker processes
(:func:`player_data`, :func:`write_player`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..constants import FILM_FROM_HOURS, FILM_TO_HOURS, MAX_CYCLE_FRAMES, MAX_TAPE_BYTES, FILM_FPS
from ..errors import SunsetError, require_bool, require_int_range, require_size
from ..io import all_or_nothing
from ..model.scene import SceneLike, as_scene
from ..model.sun import require_hours
from ..recorder.dicomed import expose_frame
from ..recorder.film import (FILM_AHEAD, FILM_CYCLES, FILM_EXPOSERS, PREVIEW_WIDTH, _bar, _check_film, cycle_times,
                             film_hours, write_video)
from ..recorder.player import (HTML_SUFFIXES, PLAYER_FRAMES, check_player_data, hour_row, hours_grid, player_document,
                               player_html, player_size)
from ..tape.tapefile import Tape, write_tape
from .cycle import code_frames, frame_workers
from .workers import process_map

__all__ = ["render_cycle", "write_film", "make_film", "player_data", "write_player"]


def render_cycle(scene, frames: int, reflections: int = 2, seed: int = 0, progress: bool = True,
                 workers: int | None = None) -> Tape:
    """Render and code one wave cycle: the vector stage, once per frame.

    The frames are independent, so they are rendered by ``workers``
    processes at once (:func:`sunset.pipeline.cycle.code_frames`); the tape is
    byte-identical to the one a single process makes.

    Parameters
    ----------
    scene : Scene
    frames : int
        N, frames per cycle.
    reflections : {0, 1, 2}
        Reflection mode (see :mod:`sunset.vector.reflect`).
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


def _frames_ahead(tape: Tape, from_hours: float, to_hours: float, cycles: int):
    """The pictures of :func:`film_frames`, exposed ahead on threads while the encoder works.

    Yields each film frame's RGB picture, in film order. Each frame is exposed by the
    same code as :func:`sunset.recorder.film.film_frames`; up to :data:`FILM_AHEAD` of them are
    in hand at once, on :data:`FILM_EXPOSERS` threads (the colour tables of
    each hour are most of the work, and NumPy releases the GIL for them).
    """
    from collections import deque
    from concurrent.futures import ThreadPoolExecutor

    n = len(tape)
    hours = film_hours(from_hours, to_hours, cycles * n)

    def job(j: int):
        return expose_frame(tape.scene, tape.codes[j % n], float(hours[j]))

    with ThreadPoolExecutor(max_workers=FILM_EXPOSERS, thread_name_prefix="film") as pool:
        pending = deque(pool.submit(job, j) for j in range(min(FILM_AHEAD, len(hours))))
        nxt = len(pending)
        while pending:
            frame = pending.popleft().result()
            if nxt < len(hours):
                pending.append(pool.submit(job, nxt))
                nxt += 1
            yield frame


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
    from ..io import check_distinct, check_writable

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


def _hour_task(args) -> tuple[np.ndarray, dict | None]:
    scene, hours = args
    return hour_row(scene, hours)


def player_data(tape, grid, start_hours: float | None = None, progress: bool = False,
                workers: int | None = None) -> dict:
    """Everything the player needs, as one JSON-ready dict (:mod:`sunset.recorder.player`'s docstring).

    Parameters
    ----------
    tape : Tape
        One wave cycle of codes (:func:`render_cycle`).
    grid : array_like (M,)
        Hours before sunset of the tables (:func:`sunset.recorder.player.hours_grid`).
    start_hours : float, optional
        The hour the player opens at (the grid hour nearest it); default the first.
    progress : bool
        Show a progress bar on stderr while the tables are computed.
    workers : int, optional
        Processes computing the tables (each hour's by :func:`sunset.recorder.player.hour_row`); default as for
        the frames (:func:`sunset.pipeline.cycle.frame_workers`). The data does not depend on it.
    """
    grid, start = check_player_data(tape, grid, start_hours, progress)
    tasks = [(tape.scene, float(h)) for h in grid]
    tabs, suns = [], []
    with _bar(grid.size, "colour tables", progress) as bar:
        for tab, sun_row in process_map(_hour_task, tasks, frame_workers(workers, len(tasks))):
            tabs.append(tab)
            suns.append(sun_row)
            bar.update(1)
    return player_document(tape, grid, start, tabs, suns)


def write_player(scene, path: str | os.PathLike, frames: int = PLAYER_FRAMES, size: tuple[int, int] | None = None,
                 from_hours: float = FILM_FROM_HOURS, to_hours: float = FILM_TO_HOURS, reflections: int = 2,
                 seed: int = 0, progress: bool = True) -> Path:
    """Render one wave cycle and write the player as one self-contained HTML file (``sunset player``).

    Every argument is checked before any work; the file is written
    atomically, so an error or an interrupt leaves no partial file.

    Parameters
    ----------
    scene : Scene
    path : path
        Output file, ``.html`` or ``.htm``.
    frames : int
        N, frames of the wave cycle.
    size : (int, int), optional
        (width, height) in pixels; default the scene's picture with its longer
        side :data:`PLAYER_LONG_SIDE`.
    from_hours, to_hours : float
        The range of the hours slider (hours before sunset).
    reflections, seed : int
        As for :func:`render_cycle`.
    progress : bool
        Progress bars on stderr.

    Returns
    -------
    Path
    """
    from ..io import check_writable, write_bytes

    path = check_writable(path, HTML_SUFFIXES)
    scene = as_scene(scene)
    require_bool("progress", progress)
    require_int_range("frames", frames, 1, MAX_CYCLE_FRAMES)
    require_int_range("reflections", reflections, 0, 2)
    require_int_range("seed", seed, 0, 2**32 - 1)
    grid = hours_grid(from_hours, to_hours)
    require_hours("from_hours", from_hours)
    require_hours("to_hours", to_hours)
    cycle_times(scene, frames)                       # a sea that never repeats fails here, before the work
    scene = scene.with_size(*(player_size(scene) if size is None else require_size("size", size)))
    tape = render_cycle(scene, frames, reflections=reflections, seed=seed, progress=progress)
    data = player_data(tape, grid, progress=progress)
    write_bytes(path, player_html(data).encode("utf-8"))
    return path
