"""The colour-table player (sunset/recorder/player.js) in headless Chromium: what its browser tests and
``make book-check`` ask of it, and the timing of its draws (``make bench-player``).

Chromium is Debian's, driven by Playwright (``book/chromium.py``). The player's
test hook ``?frame=F&hours=H&dump=1`` draws frame F with the table of the grid
hour nearest H and writes the canvas as a PNG data URL into ``#sunset-dump``;
``window.sunsetPlayer`` offers ``ready``, ``draw``, ``play``, ``pause``,
``state``, ``decodePng`` and ``bench``.

Usage (``make bench-player``)::

    python -m tests.recorder.player_browser PLAYER.html [--out JSON]

times the draws of a player file written by ``sunset player`` and prints (and
writes) the result: a measurement, never asserted.
"""

from __future__ import annotations

import argparse
import base64
import io
import os
import statistics
import struct
import sys
import time
import zlib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "book"))

from chromium import CHROMIUM_FLAGS, BrowserError, PageLog, chromium  # noqa: E402  (book/chromium.py)

#: Element id of the player (sunset/recorder/player.html).
PLAYER_ID = "sunset-player"
#: Blocks of ten draws per benchmark run, and runs (after one warm-up run).
PLAYER_BENCH_BLOCKS = 20
PLAYER_BENCH_RUNS = 5
#: Seconds of play after which the canvas and the hour must have moved.
PLAY_SECONDS = 1.5

PLAYER_READY = """
(async () => {
  const t0 = Date.now();
  while (!window.sunsetPlayer && Date.now() - t0 < 20000) await new Promise((r) => setTimeout(r, 20));
  await window.sunsetPlayer.ready;
  return document.getElementById("sunset-player").dataset.state;
})()
"""


def evaluate(page, expression: str):
    """The value of a JavaScript expression in the page (awaited); :class:`BrowserError` if it throws."""
    from playwright.sync_api import Error

    try:
        return page.evaluate(expression)
    except Error as exc:
        raise BrowserError(f"in the page: {str(exc).splitlines()[0]}") from None


def open_player(page, url: str) -> None:
    """Open a player page and wait until it has drawn."""
    page.goto(url, wait_until="load")
    state = evaluate(page, PLAYER_READY)
    if state != "ready":
        raise BrowserError(f"the player at {url} did not start (state {state!r})")
    time.sleep(0.1)


def canvas(page) -> str:
    """The player's canvas as a PNG data URL."""
    return evaluate(page, "document.querySelector('#sunset-player canvas').toDataURL('image/png')")


def rim_mask(data: dict, codes: np.ndarray, hour: int) -> np.ndarray:
    """Sky-coded pixels that the sun's disk covers only in part at grid hour ``hour`` (its anti-aliased rim)."""
    rim = np.zeros(codes.shape, bool)
    s = data["sun"][hour]
    if s is not None:
        k = np.asarray(s["cover"]).reshape(s["h"], s["w"])
        box = (slice(s["r0"], s["r0"] + s["h"]), slice(s["c0"], s["c0"] + s["w"]))
        rim[box] = (k > 0) & (k < data["supersample"] ** 2) & (codes[box] >= data["sky_start"])
    return rim


def dump_cases(data: dict) -> list[tuple[int, float]]:
    """Frames and hours to compare: the ends of the grid, the hour the player opens at, and the two hours
    whose sun has most sky pixels on its rim; every other one a quarter step off the grid (to test "the
    grid hour nearest H")."""
    from sunset.recorder.player import decode_codes

    codes = decode_codes(data)
    n, m = data["frames"], len(data["hours"])
    rim = np.array([int(rim_mask(data, codes[0], h).sum()) for h in range(m)])
    best = [int(i) for i in np.argsort(-rim, kind="stable")[:2] if rim[i] > 0]
    start = int(np.argmin(np.abs(np.asarray(data["hours"]) - data["start_hours"])))
    hours = [0, m - 1, start] + best
    frames = [0, n // 2, n - 1, (n // 3) % n]
    step = (data["hours"][1] - data["hours"][0]) if m > 1 else 0.0
    return [(frames[i % len(frames)], data["hours"][h] + (0.25 * step if i % 2 else 0.0))
            for i, h in enumerate(dict.fromkeys(hours))]


def compare_dumps(page, log: PageLog, url: str, allowed: str, data: dict, cases,
                  need_rim: bool = True) -> tuple[list[str], list[str]]:
    """Open ``url?frame=F&hours=H&dump=1`` for each case and compare the dump with ``sunset.expose``:
    equal, except on the sun's rim, where it may differ by 1/255; opaque. Requests outside ``allowed``
    (a URL prefix) are problems; so is, when ``need_rim``, a set of cases with no sky pixel on the rim.
    Returns (problems, one line a case)."""
    from PIL import Image

    from sunset import Scene, expose
    from sunset.recorder.player import decode_codes, nearest_hour

    scene = Scene.from_toml(data["scene"])
    codes = decode_codes(data)
    problems, lines = [], []
    rim_total = 0
    for frame, hours in cases:
        log.clear()
        open_player(page, f"{url}?frame={frame}&hours={hours!r}&dump=1")
        problems += log.problems(allowed)
        dump = evaluate(page, "document.getElementById('sunset-dump').textContent")
        if not dump.startswith("data:image/png;base64,"):
            problems.append(f"frame {frame}, hours {hours}: #sunset-dump holds no PNG data URL")
            continue
        with Image.open(io.BytesIO(base64.b64decode(dump.split(",", 1)[1]))) as img:
            got = np.asarray(img.convert("RGBA"))
        h = nearest_hour(data["hours"], hours)
        want = expose(scene, codes[frame], data["hours"][h])
        if got.shape[:2] != want.shape[:2]:
            problems.append(f"frame {frame}, hours {hours}: canvas {got.shape[:2]} is not the picture "
                            f"{want.shape[:2]}")
            continue
        diff = np.abs(got[..., :3].astype(int) - want.astype(int)).max(axis=-1)
        rim = rim_mask(data, codes[frame], h)
        rim_total += int(rim.sum())
        bad_table = int(np.count_nonzero(diff[~rim]))
        bad_rim = int(np.count_nonzero(diff[rim] > 1))
        if bad_table or bad_rim or np.any(got[..., 3] != 255):
            problems.append(f"frame {frame}, hours {hours} (grid {data['hours'][h]:.4f}): {bad_table} pixels "
                            f"differ from sunset.expose, {bad_rim} rim pixels by more than 1/255")
        lines.append(f"frame {frame}, {data['hours'][h]:+.3f} h: {diff.size} pixels, "
                     f"{int(rim.sum())} on the sun's rim, largest difference {int(diff.max())}/255")
    if need_rim and rim_total == 0:
        problems.append("no compared frame had the sun's anti-aliased rim on a sky pixel")
    return problems, lines


def filtered_png(codes) -> bytes:
    """An 8-bit greyscale PNG of ``codes`` whose rows use the five PNG filters in turn (row y: y mod 5).

    Written here from the PNG specification (section 9, filter types None,
    Sub, Up, Average, Paeth), so that the player's decoder meets every filter,
    whichever ones Pillow happened to choose for the frames.
    """
    x = np.asarray(codes, dtype=np.int64)
    h, w = x.shape
    rows = []
    for y in range(h):
        cur = x[y]
        up = x[y - 1] if y else np.zeros(w, np.int64)
        a = np.concatenate([[0], cur[:-1]])
        c = np.concatenate([[0], up[:-1]])
        f = y % 5
        if f == 0:
            pred = np.zeros(w, np.int64)
        elif f == 1:
            pred = a
        elif f == 2:
            pred = up
        elif f == 3:
            pred = (a + up) // 2
        else:
            p = a + up - c
            pa, pb, pc = np.abs(p - a), np.abs(p - up), np.abs(p - c)
            pred = np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, up, c))
        rows.append(bytes([f]) + ((cur - pred) % 256).astype(np.uint8).tobytes())

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"".join(rows))) + chunk(b"IEND", b""))


def decoded_png(page, png: bytes) -> np.ndarray:
    """What the open player's PNG decoder makes of ``png`` (a flat array of codes)."""
    b64 = base64.b64encode(png).decode("ascii")
    return np.asarray(evaluate(page, f"window.sunsetPlayer.decodePng('{b64}')"), dtype=np.int64)


def png_filter_problems(page, data: dict) -> list[str]:
    """The player's PNG decoder, on a PNG that uses all five row filters (checked first with Pillow)."""
    from PIL import Image

    codes = np.random.default_rng(14).integers(0, 256, (data["height"], data["width"]), dtype=np.uint8)
    codes[:, : data["width"] // 2] //= 8                   # smooth and noisy parts, so that every filter matters
    png = filtered_png(codes)
    with Image.open(io.BytesIO(png)) as img:
        if not np.array_equal(np.asarray(img), codes):
            return ["the test PNG with all five filters does not decode to its codes in Pillow"]
    if not np.array_equal(decoded_png(page, png).reshape(codes.shape), codes):
        return ["the player's PNG decoder gets a PNG with all five row filters wrong"]
    return []


def play(page, log: PageLog, allowed: str) -> tuple[list[str], dict]:
    """Draw frame 0 at the first hour, then tick 'the sun sets' and play for :data:`PLAY_SECONDS`, looking
    every 0.1 s: the canvas must change, more than one frame be shown and the hour move on, with nothing
    loaded from outside ``allowed``."""
    log.clear()
    evaluate(page, "window.sunsetPlayer.pause(), window.sunsetPlayer.draw(0, 0), true")
    before = canvas(page)
    evaluate(page, "document.querySelector('#sunset-player [data-role=follow]').click(), "
                   "window.sunsetPlayer.play(), true")
    frames, hours, changed = set(), set(), False
    end = time.monotonic() + PLAY_SECONDS
    while time.monotonic() < end:
        time.sleep(0.1)
        state = evaluate(page, "({frame: sunsetPlayer.state.frame, hour: sunsetPlayer.state.hour})")
        frames.add(state["frame"])
        hours.add(state["hour"])
        changed = changed or canvas(page) != before
    evaluate(page, "window.sunsetPlayer.pause(), true")
    problems = log.problems(allowed)
    if not changed:
        problems.append("playing did not change the canvas")
    if len(frames) < 2:
        problems.append(f"playing showed only the frames {sorted(frames)}")
    if hours <= {0}:
        problems.append("the sun did not move while the player played with 'the sun sets' on")
    return problems, {"frames": sorted(frames), "hours": sorted(hours), "changed": changed}


def check_player(page, log: PageLog, url: str, allowed: str, data: dict,
                 need_rim: bool = True) -> tuple[list[str], list[str]]:
    """Every check of the player at ``url`` (its data ``data``): the dumps of :func:`dump_cases` against
    ``sunset.expose``, the PNG decoder on all five filters, and play. Returns (problems, lines)."""
    problems, lines = compare_dumps(page, log, url, allowed, data, dump_cases(data), need_rim)
    log.clear()
    open_player(page, url)
    problems += log.problems(allowed)
    png = png_filter_problems(page, data)
    problems += png
    if not png:
        lines.append(f"the PNG decoder gets a {data['width']}x{data['height']} PNG using all five row filters "
                     f"exactly")
    p, state = play(page, log, allowed)
    problems += p
    lines.append(f"in {PLAY_SECONDS} s of play: frames {state['frames']}, grid hours {state['hours']}, "
                 f"canvas changed: {state['changed']}")
    return problems, lines


def bench(page, data: dict, version: str) -> dict:
    """Time the open player's draws (compose + putImageData) at its resolution: a JSON-ready report.

    One warm-up run, then :data:`PLAYER_BENCH_RUNS` runs of
    :data:`PLAYER_BENCH_BLOCKS` blocks of ten draws at varying frames and hours,
    timed by blocks because the page's clock ticks in 0.1 ms; the median and
    the 95th percentile of the milliseconds per draw over every block.
    """
    evaluate(page, "window.sunsetPlayer.pause(), window.sunsetPlayer.bench(5), true")
    runs = [evaluate(page, f"window.sunsetPlayer.bench({PLAYER_BENCH_BLOCKS})") for _ in range(PLAYER_BENCH_RUNS)]
    every = [t for r in runs for t in r]
    return {"width": data["width"], "height": data["height"], "draws_per_run": 10 * PLAYER_BENCH_BLOCKS,
            "runs": PLAYER_BENCH_RUNS, "median_ms": statistics.median(every),
            "run_medians_ms": [statistics.median(r) for r in runs],
            "p95_ms": sorted(every)[int(0.95 * (len(every) - 1))],
            "chromium": f"Chrome/{version}", "chromium_flags": CHROMIUM_FLAGS,
            "cpus": os.cpu_count(), "load_average": os.getloadavg()[0],
            "date": time.strftime("%Y-%m-%d", time.gmtime())}


def bench_line(result: dict) -> str:
    """One line saying what :func:`bench` measured."""
    runs = ", ".join(f"{m:.3f}" for m in result["run_medians_ms"])
    return (f"draw {result['width']}x{result['height']}: median {result['median_ms']:.3f} ms (run medians "
            f"{runs} ms; p95 {result['p95_ms']:.3f} ms; load average {result['load_average']:.1f})")


def main(argv: list[str] | None = None) -> int:
    """``make bench-player``: open a player file from disk, time its draws, print (and write) the result."""
    import json

    from sunset.recorder.player import read_player_data

    parser = argparse.ArgumentParser(description="Time the colour-table player's draws in headless Chromium.")
    parser.add_argument("html", type=Path, help="a player file written by `sunset player`")
    parser.add_argument("--out", type=Path, help="also write the measurement here (JSON)")
    args = parser.parse_args(argv)
    if not args.html.is_file():
        print(f"player_browser: {args.html}: no such file", file=sys.stderr)
        return 2
    data = read_player_data(args.html.read_text(encoding="utf-8"))
    try:
        with chromium() as browser:
            page = browser.new_page()
            open_player(page, args.html.resolve().as_uri())
            result = bench(page, data, browser.version)
    except BrowserError as exc:
        print(f"player_browser: {exc}", file=sys.stderr)
        return 2
    result["file"] = str(args.html)
    print(f"player_browser: {bench_line(result)}", flush=True)
    if args.out is not None:
        args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
