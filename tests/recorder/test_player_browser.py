"""The colour-table player in headless Chromium (Debian's ``chromium``, driven by Playwright).

The pixels the player draws are those of ``sunset.expose`` (exactly, and within
1/255 on the sun's anti-aliased rim), its PNG decoder reads every PNG row filter,
playing moves the picture and the sun, and nothing is loaded from outside the
file; a file written by ``sunset player`` works opened from disk, and
``make bench-player`` times its draws. ``make book-check`` asks the same of the
player in the built book (tests/recorder/player_browser.py holds the checks).

Without a Chromium these tests are skipped, except where the environment
variable ``CI`` is set: there they fail (``.ci/run`` installs Debian's
``chromium`` before ``make test``).
"""

import base64
import io
import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sunset.pipeline.film import player_data, render_cycle
from sunset.recorder.player import hours_grid, player_html, read_player_data
from tests.recorder.player_browser import (PLAYER_ID, ROOT, check_player, compare_dumps, decoded_png,
                                           dump_cases, filtered_png, open_player, play)
from tests.recorder.test_player import sun_scene

from chromium import BrowserError, PageLog, chromium, find_chromium  # noqa: E402  (book/, on the path)


@pytest.fixture(scope="module")
def browser():
    try:
        import playwright  # noqa: F401
        missing = None if find_chromium() else "chromium not found (apt-get install -y chromium)"
    except ImportError:
        missing = "playwright is not installed"
    if missing:
        if os.environ.get("CI"):
            pytest.fail(f"{missing}: CI runs the player's browser tests")
        pytest.skip(missing)
    with chromium() as b:
        yield b


@pytest.fixture
def page(browser):
    p = browser.new_page()
    log = PageLog(p)
    yield p, log
    p.close()


@pytest.fixture(scope="module")
def player(tmp_path_factory):
    """A small player whose sun sets inside the picture (its rim on sky pixels), as a file: (url, data)."""
    scene = sun_scene((48, 40))
    # (sun_scene's window edges are NumPy floats, which Scene.to_toml writes as np.float64(...))
    cam = scene.camera
    scene = replace(scene, camera=replace(cam, s_min=float(cam.s_min), s_max=float(cam.s_max)))
    tape = render_cycle(scene, 3, reflections=2, seed=5, progress=False, workers=1)
    data = player_data(tape, hours_grid(0.3, -0.1, 0.05), start_hours=0.12)
    path = tmp_path_factory.mktemp("player") / "player.html"
    path.write_text(player_html(data), encoding="utf-8")
    return path.as_uri(), data


def test_the_drawn_pixels_are_those_of_expose(page, player):
    p, log = page
    url, data = player
    cases = dump_cases(data)
    assert len(cases) >= 4
    problems, lines = compare_dumps(p, log, url, url, data, cases, need_rim=True)
    assert problems == []
    assert len(lines) == len(cases)                 # (need_rim: some compared pixels were on the sun's rim)


def test_a_wrong_table_is_found(page, player, tmp_path):
    """The comparison fails when the player draws with tables one step off."""
    p, log = page
    _, data = player
    tables = bytes(b ^ 1 for b in base64.b64decode(data["tables"]))
    bad = {**data, "tables": base64.b64encode(tables).decode("ascii")}
    path = tmp_path / "bad.html"
    path.write_text(player_html(bad), encoding="utf-8")
    problems, _ = compare_dumps(p, log, path.as_uri(), path.as_uri(), data, dump_cases(data)[:1], need_rim=False)
    assert problems and "differ from sunset.expose" in problems[0]


def test_the_png_decoder_reads_all_five_row_filters(page, player):
    p, _ = page
    url, data = player
    open_player(p, url)
    codes = np.random.default_rng(3).integers(0, 256, (data["height"], data["width"]), dtype=np.uint8)
    codes[:, :20] //= 16                             # smooth and noisy parts: every filter matters
    png = filtered_png(codes)
    with Image.open(io.BytesIO(png)) as img:                      # the test PNG itself, read by Pillow
        assert np.array_equal(np.asarray(img), codes)
    assert np.array_equal(decoded_png(p, png).reshape(codes.shape), codes)


def test_every_check_of_the_player_passes(page, player):
    """What make book-check asks of the book's player: the dumps, the PNG decoder, and play (the canvas
    changes and the sun sets), with nothing loaded from outside the file."""
    p, log = page
    url, data = player
    problems, lines = check_player(p, log, url, url, data)
    assert problems == []
    assert any("canvas changed: True" in line for line in lines)


def test_a_player_that_does_not_play_is_found(page, player):
    """play() reports a player whose play button does nothing."""
    p, log = page
    url, _ = player
    open_player(p, url)
    p.evaluate("window.sunsetPlayer.play = () => {}")
    problems, state = play(p, log, url)
    assert "playing did not change the canvas" in problems and state["frames"] == [0]


def test_a_request_outside_the_page_is_reported(page, tmp_path):
    """The network log that the checks read notices what a page asks of the network."""
    p, log = page
    html = tmp_path / "outside.html"
    html.write_text('<!doctype html><img src="http://127.0.0.1:9/x.png"><script>throw new Error("boom")</script>',
                    encoding="utf-8")
    p.goto(html.as_uri(), wait_until="load")
    p.wait_for_timeout(300)
    problems = log.problems(html.as_uri())
    assert any("network request outside the book: http://127.0.0.1:9/x.png" in x for x in problems)
    assert any("JavaScript exception: Error: boom" in x for x in problems)
    assert log.problems("http://127.0.0.1:9/") != []                 # the exception stays a problem


def test_a_file_written_by_the_command_opens_from_disk(page, tmp_path):
    p, log = page
    html = tmp_path / "player.html"
    run = subprocess.run([sys.executable, "-m", "sunset", "player", "carlas-island", "-o", str(html), "--frames",
                          "3", "--size", "64x64", "--from-hours", "0.6", "--to-hours", "0.2", "--quiet"],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    data = read_player_data(html.read_text(encoding="utf-8"))
    assert html.read_text(encoding="utf-8").count(f'id="{PLAYER_ID}"') == 1
    cases = [(0, data["hours"][0]), (data["frames"] - 1, data["hours"][-1])]
    problems, lines = compare_dumps(p, log, html.as_uri(), html.as_uri(), data, cases, need_rim=False)
    assert problems == [] and len(lines) == 2


def test_bench_player_writes_its_measurement(browser, player, tmp_path):
    """`make bench-player` (python -m tests.recorder.player_browser): a report of the draws' times."""
    url, data = player
    out = tmp_path / "bench.json"
    from urllib.parse import urlparse
    from urllib.request import url2pathname

    path = Path(url2pathname(urlparse(url).path))
    run = subprocess.run([sys.executable, "-m", "tests.recorder.player_browser", str(path), "--out", str(out)],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    report = json.loads(out.read_text(encoding="utf-8"))
    assert (report["width"], report["height"]) == (data["width"], data["height"])
    assert report["draws_per_run"] == 200 and len(report["run_medians_ms"]) == report["runs"] == 5
    assert 0 < report["median_ms"] <= report["p95_ms"]
    assert "median" in run.stdout


def test_a_missing_browser_is_one_clear_error(player, tmp_path):
    """No Chromium where $CHROMIUM points: one line, exit status 2, no traceback, no report written."""
    from urllib.parse import urlparse
    from urllib.request import url2pathname

    out = tmp_path / "bench.json"
    path = Path(url2pathname(urlparse(player[0]).path))
    env = {**os.environ, "CHROMIUM": str(tmp_path / "no-such-chromium")}
    run = subprocess.run([sys.executable, "-m", "tests.recorder.player_browser", str(path), "--out", str(out)],
                         capture_output=True, text=True, cwd=ROOT, env=env)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and "did not start" in run.stderr and "Traceback" not in run.stderr
    assert not out.exists()


@pytest.mark.parametrize("title", ["<!--<script>", "</script><script>throw new Error('ran')</script>"])
def test_a_hostile_title_neither_stops_the_player_nor_runs(page, tmp_path, title):
    """Issue 33: a scene titled ``<!--<script>`` kept the player from ever starting (the HTML tokenizer,
    inside the data's <script>, never found its end). Written by the command, the player now opens,
    plays, shows the title as text, and runs nothing from it."""
    from sunset.model.scene import load_named_scene

    p, log = page
    scene = tmp_path / "hostile.toml"
    scene.write_text(replace(load_named_scene("carlas-island"), title=title).to_toml(), encoding="utf-8")
    html = tmp_path / "player.html"
    run = subprocess.run([sys.executable, "-m", "sunset", "player", str(scene), "-o", str(html), "--frames", "2",
                          "--size", "48x48", "--from-hours", "0.6", "--to-hours", "0.2", "--quiet"],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    assert read_player_data(html.read_text(encoding="utf-8"))["title"] == title
    open_player(p, html.as_uri())
    problems, state = play(p, log, html.as_uri())
    assert problems == [] and len(state["frames"]) > 1, (problems, state)
    assert p.evaluate("document.title").count(title) == 1 and title in p.inner_text("body")
    assert p.evaluate("document.querySelectorAll('script').length") == 2
