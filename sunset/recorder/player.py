"""The Dicomed in the browser: one wave cycle of codes, the tables of an afternoon, a player.

Colour-table animation needs only three things: the codes of one wave cycle
(the tape), a colour table for every hour, and where the sun's disk falls on
the picture at that hour. This module computes all three in Python, packs
them into one JSON document and writes them, with a small plain-JavaScript
player (``player.js``, ``player.css`` and ``player.html`` beside this file),
into one HTML file that works from disk with no network. The JavaScript
computes no colour of its own: it decodes the PNG frames, looks entries up in
the tables Python made and composes them exactly as :func:`sunset.expose`
does (:func:`compose` is the same composition in NumPy, the export format's
reference).

What the player's data holds
----------------------------
``codes``
    Frame F of an N-frame cycle is the sea at t = F·T/N (T the sea's period,
    :func:`~sunset.recorder.film.cycle_times`), one lossless 8-bit greyscale PNG per
    frame, base64.
``hours``, ``tables``
    A grid of hours before sunset from ``from_hours`` to ``to_hours``, both
    ends included (:func:`hours_grid`), and for each grid hour the three
    256-entry tables of :func:`~sunset.recorder.colour_tables.tables`, M × 3 × 256 bytes,
    base64.
``sun``
    For each grid hour, the sun's disk on the picture: the smallest box of
    pixels it covers (above the horizon), and in it each pixel's coverage as
    a count k of the s × s sub-samples inside the disk (coverage = k/s², the
    value :func:`~sunset.recorder.dicomed.sun_coverage` computes), with the sun's
    colour in linear light (:func:`~sunset.recorder.colour_tables.sun_colour`); ``null``
    when no pixel is covered. ``elevation`` is the sun's height, degrees.
``decode``, ``encode``
    The sRGB byte → linear value table the sun-disk mix decodes with, and the
    255 linear values at which the encoded and rounded byte steps up
    (:func:`encode_thresholds`): byte(x) = the number of thresholds <= x,
    exactly what :func:`sunset.expose` rounds to, with no power function in
    JavaScript.
``provenance``
    What made the page: the versions of sunset, Python, NumPy, Numba and
    colour-science (:func:`sunset.provenance.provenance`), as every file the
    package writes records them; each frame's PNG carries them too (its
    ``sunset:provenance`` text chunk), and the page's ``generator`` meta tag
    names the version of sunset.
``groups``, ``meanings``
    The code map (name, first, last code and a label per group) and, for
    each of the 256 codes, what its number says (the code inspector).

The sun-disk rule, as :func:`sunset.expose` applies it: a pixel of the box
whose code is a sky code (sky, track or halo) and whose coverage w is not 0
is exposed in (1 − w)·table + w·sun, mixed in linear light and encoded back.
"""

from __future__ import annotations

import base64
import json
import math
import re
from importlib import resources

import numpy as np

from ..constants import FILM_FPS, SUN_SUPERSAMPLE
from ..errors import SunsetError, real_array, real_number, require_bool, require_instance, require_int_range, shown
from ..escape import html_text, script_json
from ..model.eye import DECODE_LUT, srgb_encode, to_uint8
from ..model.scene import as_scene
from ..model.sun import require_hours
from ..tape.codemap import (CODE_MAP, cloud_code_depths, code_map, island_code_rho, sky_code_z, sun_plane_angle,
                             track_code_elevations)
from .colour_tables import sun_colour, tables
from .playerdoc import check_data, compose, data_tables, decode_codes
from .dicomed import sun_coverage
from .film import FILM_CYCLES

__all__ = ["PLAYER_FRAMES", "PLAYER_LONG_SIDE", "PLAYER_MAX_BYTES", "PLAYER_HOURS_STEP", "PLAYER_FORMAT", "HTML_SUFFIXES",
           "hours_grid", "player_size", "encode_thresholds", "quantise", "sun_geometry", "code_meanings",
           "player_fragment", "player_html", "read_player_data", "decode_codes", "data_tables", "nearest_hour",
           "compose"]
#: (hour_row, check_player_data and player_document are the pipeline's pieces of sunset.pipeline.film.player_data,
#: which checks their arguments: not in __all__.)

#: Frames of the wave cycle in the player (as in the film of ``make figures``).
PLAYER_FRAMES = 32

#: The player's longer side in pixels, when no size is asked for (see the book's player page for why).
PLAYER_LONG_SIDE = 512

#: Largest step of the hours grid: 1.5 minutes, 0.375° of the sun's course, half its (enlarged) radius.
PLAYER_HOURS_STEP = 0.025
#: Most hours in a grid: the whole day (±12 h) at a fiftieth of PLAYER_HOURS_STEP.
MAX_GRID_HOURS = 50_000

#: What the player's data may weigh in a page of the book, bytes (its JSON, PNG frames as base64).
PLAYER_MAX_BYTES = 8_000_000

#: Version tag of the player's data document.
PLAYER_FORMAT = "sunset-player/1"

#: Name endings of the player's HTML file.
HTML_SUFFIXES = (".html", ".htm")

_DATA_ID = "sunset-player-data"


# --------------------------------------------------------------------------- the grid of hours
def hours_grid(from_hours: float, to_hours: float, step: float = PLAYER_HOURS_STEP) -> np.ndarray:
    """Hours before sunset of the player's tables: evenly spaced, both ends included.

    The fewest points whose spacing is at most ``step``: ``from_hours`` first
    and ``to_hours`` last, exactly; one point when they are equal.
    """
    a, b = real_number("from_hours", from_hours), real_number("to_hours", to_hours)
    require_hours("from_hours", a)
    require_hours("to_hours", b)
    step = real_number("step", step)
    if not step > 0:
        raise SunsetError(f"step must be positive, got {step!r}")
    if a == b:
        return np.array([a])
    count = int(math.ceil(abs(b - a) / step - 1e-9)) + 1
    if count > MAX_GRID_HOURS:
        raise SunsetError(f"step: {step:g} h makes {count:,} tables from {a:g} to {b:g} h (at most {MAX_GRID_HOURS:,})")
    grid = np.linspace(a, b, count)
    grid[0], grid[-1] = a, b
    return grid


def nearest_hour(grid, hours: float) -> int:
    """Index of the grid hour nearest ``hours`` (the first of two equally near)."""
    g = _grid(grid)
    return int(np.argmin(np.abs(g - real_number("hours", hours))))


def player_size(scene, long_side: int = PLAYER_LONG_SIDE) -> tuple[int, int]:
    """The scene's picture scaled so that its longer side is ``long_side`` pixels: (width, height)."""
    scene = as_scene(scene)
    require_int_range("long_side", long_side, 1, 1 << 16)
    w, h = scene.camera.width, scene.camera.height
    k = long_side / max(w, h)
    return max(1, round(w * k)), max(1, round(h * k))


# --------------------------------------------------------------------------- exact rounding as lookups
def quantise(lin) -> np.ndarray:
    """Linear value → the sRGB byte :func:`sunset.expose` writes (encode, round, clip)."""
    lin = real_array("lin", lin)
    if not np.all(np.isfinite(lin)):
        raise SunsetError(f"lin must be finite, got {shown(lin)}")
    return to_uint8(srgb_encode(lin))


def encode_thresholds() -> np.ndarray:
    """For b = 1 … 255, the smallest float64 x >= 0 whose byte (:func:`quantise`) is at least b.

    Found by bisection on the bit patterns of float64 (positive floats order
    like their bits), so the thresholds are exact: for every x,
    ``quantise(x)`` equals the number of thresholds <= x.
    """
    b = np.arange(1, 256)
    lo = np.full(b.shape, np.float64(0.0).view(np.int64))     # quantise(lo) < b
    hi = np.full(b.shape, np.float64(1.0).view(np.int64))     # quantise(hi) >= b
    while np.any(hi - lo > 1):
        mid = lo + (hi - lo) // 2
        ok = quantise(mid.view(np.float64)) >= b
        hi = np.where(ok, mid, hi)
        lo = np.where(ok, lo, mid)
    return hi.view(np.float64)


# --------------------------------------------------------------------------- the sun on the picture
def sun_geometry(scene, hours: float, supersample: int = SUN_SUPERSAMPLE) -> dict | None:
    """The sun's disk on the picture ``hours`` before sunset, as the player needs it.

    Returns
    -------
    dict or None
        ``r0``, ``c0`` (first row and column), ``h``, ``w`` (size of the
        smallest box holding every pixel the disk covers), ``cover`` (h·w
        counts k, row by row: the pixel's coverage is k/s², s =
        ``supersample``) and ``colour`` (the sun's colour, linear, 3 floats);
        None when the disk covers no pixel.
    """
    scene = as_scene(scene)
    hours = real_number("hours", hours)
    require_hours("hours", hours)
    require_int_range("supersample", supersample, 1, 64)
    rows, cols, cov = sun_coverage(scene.camera, scene.sun, hours, supersample)
    if not cov.size or not np.any(cov > 0):
        return None
    n2 = supersample * supersample
    k = np.rint(cov * n2).astype(np.int64)
    if not np.array_equal(k / n2, cov):     # coverage is a mean of s² samples, so k/s² is exact
        raise AssertionError("sun coverage is not a whole number of sub-samples")
    rr, cc = np.nonzero(k)
    k = k[rr.min():rr.max() + 1, cc.min():cc.max() + 1]
    return {"r0": int(rows.start + rr.min()), "c0": int(cols.start + cc.min()), "h": int(k.shape[0]),
            "w": int(k.shape[1]), "cover": [int(v) for v in k.ravel()],
            "colour": [float(v) for v in sun_colour(scene.sun, hours, scene.clouds)]}


# --------------------------------------------------------------------------- what the codes say
#: A label for each group of the code map, for the inspector.
GROUP_LABELS = {"hill": "green island hill", "cliff": "brown island cliff", "beach": "tan beach",
                "sky": "sky", "track": "sun track (glitter)", "halo": "halo beside the track",
                "cloud": "cloud (by depth below the mean level)"}


def code_meanings(sun, cmap=CODE_MAP, clouds=None) -> list[str]:
    """For each of the 256 codes, what its number says about the pixel (one line each).

    ``cmap`` is the scene's code map (:func:`~sunset.tape.codemap.code_map`) and
    ``clouds`` its cloud layer, if any.
    """
    from ..model.clouds import Clouds
    from ..model.sun import Sun
    from ..tape.codemap import CodeMap

    require_instance("sun", sun, Sun)
    require_instance("cmap", cmap, CodeMap)
    if clouds is not None:
        require_instance("clouds", clouds, Clouds)
    out = [""] * 256
    if cmap.cloud is not None and clouds is not None:
        d = cloud_code_depths(cmap.cloud.size, clouds.max_top, clouds.max_bottom)
        for k in range(cmap.cloud.size):
            out[cmap.cloud.start + k] = (f"cloud depth band {k} of {cmap.cloud.size}: {d[k]:+.0f} m below the mean "
                                         f"cloud level ({clouds.level:g} m)")
    for rng in cmap.islands:
        rh = island_code_rho(rng.size)
        psi = np.degrees(sun_plane_angle(rh))
        for k in range(rng.size):
            out[rng.start + k] = (f"ρ̂(N) band {k} of {rng.size}: ρ̂ ≈ {rh[k]:+.2f}, the normal's sun-plane angle "
                                  f"ψ ≈ {psi[k]:.0f}°; lit when cos(θ − ψ) > 0")
    z = sky_code_z(cmap.sky.size)
    for k in range(cmap.sky.size):
        out[cmap.sky.start + k] = (f"R_z band {k} of {cmap.sky.size} (√R_z coded): R_z ≈ {z[k]:.4f}, "
                                   f"{math.degrees(math.asin(z[k])):.2f}° above the horizon")
    for rng, where in ((cmap.track, "within δ of the sun's plane"), (cmap.halo, "within 3δ of the sun's plane")):
        e = np.degrees(track_code_elevations(rng.size, sun))
        for k in range(rng.size):
            out[rng.start + k] = (f"R_z band {k} of {rng.size}: a reflected ray {e[k]:.2f}° up, {where}; "
                                  f"sun-coloured when the sun stands {e[k]:.2f}° high")
    return out


# --------------------------------------------------------------------------- the data document
def _grid(grid) -> np.ndarray:
    """The hours of a grid: a non-empty 1-D array of finite hours before sunset."""
    g = real_array("grid", grid)
    if g.ndim != 1 or g.size == 0 or g.size > MAX_GRID_HOURS:
        raise SunsetError(f"grid must be a list of 1 to {MAX_GRID_HOURS:,} hours, got {shown(grid)}")
    require_hours("grid", g)
    return g


def _b64(data: bytes) -> str:
    return base64.b64encode(data).decode("ascii")


def _png(codes: np.ndarray) -> bytes:
    from ..io import png_bytes

    return png_bytes(codes)


def hour_row(scene, hours: float) -> tuple[np.ndarray, dict | None]:
    """One grid hour of the player: the colour tables (3, 256) and the sun's geometry (:func:`sun_geometry`)."""
    return tables(scene.sun, hours, scene.clouds), sun_geometry(scene, hours)


def check_player_data(tape, grid, start_hours: float | None, progress: bool) -> tuple[np.ndarray, float]:
    """Every check of :func:`sunset.pipeline.film.player_data`'s arguments: (the grid's hours, the start hour)."""
    from ..tape.tapefile import Tape

    require_instance("tape", tape, Tape)
    require_bool("progress", progress)
    grid = _grid(grid)
    start = float(grid[0]) if start_hours is None else real_number("start_hours", start_hours)
    return grid, start


def player_document(tape, grid, start: float, tabs, suns) -> dict:
    """The player's data document (see the module's docstring) from the tape, the grid, the start hour, and each
    grid hour's tables and sun (:func:`hour_row`)."""
    from ..provenance import provenance

    scene = tape.scene
    sun = scene.sun
    cmap = code_map(scene)
    period = scene.sea.period
    return {
        "format": PLAYER_FORMAT,
        "sunset_version": tape.version,
        "provenance": provenance(),
        "title": scene.title or "sunset",
        "width": int(scene.camera.width),
        "height": int(scene.camera.height),
        "frames": len(tape),
        "period": None if period is None else float(period),
        "times": [float(t) for t in tape.times],
        "reflections": int(tape.reflections),
        "seed": int(tape.seed),
        "fps": FILM_FPS,
        "cycles": FILM_CYCLES,
        "codes": [_b64(_png(c)) for c in tape.codes],
        "hours": [float(h) for h in grid],
        "start_hours": start,
        "elevation": [float(np.degrees(sun.elevation(float(h)))) for h in grid],
        "tables": _b64(np.ascontiguousarray(np.stack(tabs)).tobytes()),
        "sun": suns,
        "supersample": SUN_SUPERSAMPLE,
        "decode": [float(v) for v in DECODE_LUT],
        "encode": [float(v) for v in encode_thresholds()],
        "sky_start": cmap.sky.start,
        "groups": [{"name": r.name, "first": r.start, "last": r.stop - 1, "label": GROUP_LABELS[r.name]}
                   for r in cmap.ranges],
        "meanings": code_meanings(sun, cmap, scene.clouds),
        "scene": scene.to_toml(),
    }


def _data_json(data: dict) -> str:
    return script_json(data)                 # no "</script>", no "<!--<script>": the element ends where it should


def _asset(name: str) -> str:
    return (resources.files(__package__) / name).read_text(encoding="utf-8")


def player_fragment(data: dict) -> str:
    """The player as an HTML fragment (markup, style, data and script) to embed in a page."""
    check_data(data, "title")
    markup = _asset("player.html").replace("{{TITLE}}", html_text(data["title"]))
    return (f"<style>\n{_asset('player.css')}</style>\n{markup}"
            f'<script type="application/json" id="{_DATA_ID}">{_data_json(data)}</script>\n'
            f"<script>\n{_asset('player.js')}</script>\n")


def player_html(data: dict) -> str:
    """The player as one self-contained HTML document: nothing is loaded from anywhere."""
    check_data(data, "title")
    title = html_text(f"{data['title']}: the colour-table player")
    made_by = html_text(f"sunset {data.get('sunset_version', '')}".strip())
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<meta name=\"generator\" content=\"{made_by}\">\n"
            f"<title>{title}</title>\n</head>\n<body>\n{player_fragment(data)}</body>\n</html>\n")


def read_player_data(text: str) -> dict:
    """The data document embedded in a player page (its HTML text)."""
    if not isinstance(text, str):
        raise SunsetError(f"text must be a page's HTML text, got {shown(text)}")
    m = re.search(rf'<script type="application/json" id="{_DATA_ID}">(.*?)</script>', text, flags=re.S)
    if m is None:
        raise SunsetError("no sunset player data in this page")
    try:
        data = json.loads(m.group(1))
    except (ValueError, RecursionError) as exc:       # a damaged page: its JSON, or an integer past 4300 digits
        raise SunsetError(f"the page's player data is not JSON ({shown(str(exc))})") from None
    if not isinstance(data, dict):
        raise SunsetError(f"the page's player data must be a JSON object, got {type(data).__name__}")
    if data.get("format") != PLAYER_FORMAT:
        raise SunsetError(f"player data format {data.get('format')!r} is not {PLAYER_FORMAT!r}")
    return data


# --------------------------------------------------------------------------- the file
