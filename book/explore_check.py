#!/usr/bin/env python3
"""``make explore-check``: ``make lab``'s JupyterLab and ``sunset.explore`` in a real browser, offline.

Usage::

    python book/explore_check.py [--chapter 01-camera.md] [--screenshot PATH]

1. A chapter (a cheap one, ``01-camera.md`` by default) read by jupytext and
   executed top to bottom by nbclient in the kernel ``make lab`` gives it
   (:func:`lab.lab_environment`: the build's ``PYTHONPATH`` and IPython
   profile, the chapter's folder as working directory), as the book's build
   runs it: no cell may raise or write to stderr.
2. A JupyterLab server started here as ``make lab`` starts it
   (:func:`lab.lab_command`), on a free port of 127.0.0.1 with a token made
   here and ``--no-browser``, on a temporary folder holding a notebook and a
   copy of the chapter, driven by headless Chromium through Playwright
   (Debian's ``chromium``, or ``$CHROMIUM``, with the flags of
   ``book/chromium.py``: Playwright's own browsers are never downloaded).
   The chapter must open as a notebook (jupytext's viewer,
   ``make lab``'s default for ``.md``); the notebook's first cell runs
   ``sunset.explore()``, and the picture the page shows must be
   ``sunset.picture`` of Carla's Island at 512 × 512, byte for byte. The
   sun's azimuth slider is then dragged with the mouse; the second cell
   saves the explorer's settings, and the picture the page shows now must
   differ from the first and equal what ``sunset`` draws from the saved
   scene file and the command in its comment. The pointer over the picture
   must show the readout of the code under it.
3. No request of the page may leave the server (the check fails on any
   other address), and the server and the browser are stopped whatever
   happens.

Exit status 0 when everything holds, 1 otherwise (also when Chromium or
Playwright is missing: this check is never skipped).
"""

from __future__ import annotations

import argparse
import base64
import json
import os
import re
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

BOOK = Path(__file__).resolve().parent
ROOT = BOOK.parent
sys.path.insert(0, str(BOOK))
sys.path.insert(0, str(ROOT))

import lab  # noqa: E402  (book/lab.py: make lab's server)
from chromium import CHROMIUM_FLAGS, INSTALL_HINT, find_chromium  # noqa: E402  (book/chromium.py)

SIZE = 512
TIMEOUT_MS = 240_000


class CheckFailed(Exception):
    """One line saying what did not hold."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_chapter(chapter: Path, workdir: Path) -> float:
    """Execute ``chapter`` as ``make lab``'s kernel runs it; its seconds. Raises CheckFailed on an error or stderr."""
    import jupytext
    import nbclient

    nb = jupytext.read(chapter)
    began = time.perf_counter()
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(chapter.parent)}})
    try:
        client.execute(env=lab.lab_environment(workdir))
    except nbclient.exceptions.CellExecutionError as exc:
        raise CheckFailed(f"{chapter.name}: a cell raised: {str(exc).splitlines()[0]}") from None
    for k, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                raise CheckFailed(f"{chapter.name}: cell {k} wrote to stderr: {out.get('text', '')[:200]!r}")
    return time.perf_counter() - began


NOTEBOOK_CELLS = [
    "import sunset\nex = sunset.explore()\nex",
    "ex.wait()\nex.save_scene('after.toml')\nprint('SERIAL', ex.serial, 'ERROR', repr(ex.error))",
]


def write_notebook(path: Path) -> None:
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(src) for src in NOTEBOOK_CELLS]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, str(path))


def start_server(root: Path, workdir: Path, port: int, token: str) -> subprocess.Popen:
    env = lab.lab_environment(workdir)
    for name in ("JUPYTER_CONFIG_DIR", "JUPYTER_RUNTIME_DIR", "JUPYTER_DATA_DIR"):
        (workdir / name.lower()).mkdir()
        env[name] = str(workdir / name.lower())        # nothing of the user's Jupyter setup, nothing left behind
    cmd = lab.lab_command(workdir, root, browser=False, port=port, token=token)
    log = open(workdir / "server.log", "wb")
    proc = subprocess.Popen(cmd, env=env, cwd=root, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise CheckFailed(f"the server exited ({proc.returncode}): see its log, "
                              f"{(workdir / 'server.log').read_text(errors='replace')[-600:]}")
        try:
            urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status?token={token}", timeout=2).read()
            return proc
        except OSError:
            time.sleep(0.5)
    raise CheckFailed("the server did not answer within 180 s")


def stop_server(proc: subprocess.Popen) -> None:
    """SIGTERM to the server's process group (the server and its kernels), SIGKILL if it lingers."""
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(30)
        except ProcessLookupError:
            pass


def shown_picture(page):
    """The pixels the page's explorer shows (its canvas, read back) as an RGB array, and its serial."""
    import numpy as np

    got = page.evaluate("""() => {
        const canvas = document.querySelector("canvas.sunset-explorer-picture");
        const bytes = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
        let s = "";
        for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
        return {rgba: btoa(s), serial: Number(canvas.dataset.serial), size: [canvas.width, canvas.height]};
    }""")
    w, h = got["size"]
    rgba = np.frombuffer(base64.b64decode(got["rgba"]), dtype=np.uint8).reshape(h, w, 4)
    if np.any(rgba[..., 3] != 255):
        raise CheckFailed("the canvas has pixels that are not opaque")
    return rgba[..., :3], got["serial"], got["size"]


def differences(got, want) -> str:
    """Where two pictures differ, in a few words."""
    import numpy as np

    if got.shape != want.shape:
        return f"shape {got.shape}, not {want.shape}"
    bad = np.any(got != want, axis=-1)
    rows, cols = np.nonzero(bad)
    worst = int(np.max(np.abs(got.astype(int) - want.astype(int))))
    return (f"{int(bad.sum())} pixels differ (rows {rows.min()}-{rows.max()}, columns {cols.min()}-{cols.max()}), "
            f"by up to {worst}")


def run_cell(page, index: int) -> None:
    """Run the notebook's cell ``index`` as a reader does (click it, Shift+Enter), once the kernel is idle.

    A key pressed while JupyterLab is still setting the notebook up can be
    lost: the cell is run again until its prompt shows it queued or run.
    """
    page.locator(".jp-StatusBar-TextItem", has_text="Idle").first.wait_for()
    cell = page.locator(".jp-NotebookPanel:visible .jp-Cell").nth(index)
    prompt = cell.locator(".jp-InputPrompt")
    for _ in range(20):
        cell.locator(".jp-InputArea-editor").click()
        page.keyboard.press("Shift+Enter")
        try:
            page.wait_for_function("(el) => /\\[[*0-9]+\\]/.test(el.textContent)", arg=prompt.element_handle(),
                                   timeout=3000)
            return
        except Exception:      # playwright's TimeoutError: not queued yet
            continue
    raise CheckFailed(f"cell {index} would not run")


def saved_settings(path: Path) -> dict:
    """t, hours, reflections and seed from the saved scene's command comment."""
    import shlex

    line = next(l for l in path.read_text(encoding="utf-8").splitlines() if l.startswith("#   sunset render "))
    words = shlex.split(line[4:])
    out = {"reflections": 2, "seed": 0}
    for i, word in enumerate(words):
        if word.startswith("--time="):
            out["t"] = float(word.split("=", 1)[1])
        elif word.startswith("--hours="):
            out["hours"] = float(word.split("=", 1)[1])
        elif word == "--reflections":
            out["reflections"] = int(words[i + 1])
        elif word == "--seed":
            out["seed"] = int(words[i + 1])
    return out


def check_browser(exe: str, root: Path, port: int, token: str, screenshot: Path | None) -> dict:
    import numpy as np
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import sync_playwright

    import sunset
    from sunset.explorer.picture import Renderer, readout
    from sunset.explorer.settings import Start

    base = f"http://127.0.0.1:{port}"
    outside: list[str] = []
    report: dict = {}

    def watch(url: str) -> None:
        if not (url.startswith(base + "/") or url.startswith(f"ws://127.0.0.1:{port}/") or url.startswith("blob:")
                or url.startswith("data:")):
            outside.append(url)

    with sync_playwright() as pw:
        try:
            browser = pw.chromium.launch(executable_path=exe, headless=True, args=CHROMIUM_FLAGS)
        except PlaywrightError as exc:
            raise CheckFailed(f"chromium ({exe}) did not start: {str(exc).splitlines()[0]}") from None
        try:
            page = browser.new_page(viewport={"width": 1600, "height": 1200})
            page.set_default_timeout(TIMEOUT_MS)
            page.on("request", lambda r: watch(r.url))
            page.on("websocket", lambda ws: watch(ws.url))

            page.goto(f"{base}/lab/tree/explore.ipynb?reset&token={token}")
            page.locator(".jp-NotebookPanel:visible .jp-Cell").nth(1).wait_for()
            began = time.perf_counter()
            run_cell(page, 0)
            page.wait_for_function("""() => {
                const canvas = document.querySelector("canvas.sunset-explorer-picture");
                return canvas && canvas.dataset.serial === "1" && canvas.width > 0;
            }""")
            report["first_picture_s"] = round(time.perf_counter() - began, 1)
            first, serial, natural = shown_picture(page)
            if natural != [SIZE, SIZE] or serial != 1:
                raise CheckFailed(f"the first picture is {natural} (serial {serial}), not {SIZE}x{SIZE} (serial 1)")
            reference = sunset.picture("carlas-island", t=0.0, hours=0.35, size=(SIZE, SIZE))
            if not np.array_equal(first, reference):
                raise CheckFailed("the first picture the page shows is not sunset.picture('carlas-island', 512x512): "
                                  + differences(first, reference))

            # drag the sun's azimuth slider with the mouse
            slider = page.locator(".widget-hslider", has=page.locator(".widget-label", has_text="sun's azimuth"))
            handle = slider.locator(".noUi-handle")
            box = handle.bounding_box()
            x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
            page.mouse.move(x, y)
            page.mouse.down()
            page.mouse.move(x - 60, y, steps=12)
            page.mouse.up()
            report["azimuth_after_drag"] = slider.locator(".widget-readout").inner_text()
            run_cell(page, 1)
            out = page.locator(".jp-NotebookPanel:visible .jp-Cell").nth(1).locator(".jp-OutputArea-output")
            out.filter(has_text="SERIAL").wait_for()
            words = out.inner_text().split()
            serial_now = int(words[words.index("SERIAL") + 1])
            if "ERROR" in words and words[words.index("ERROR") + 1] != "''":
                raise CheckFailed(f"the explorer refused the dragged setting: {out.inner_text()!r}")
            page.wait_for_function(f"""() => {{
                const canvas = document.querySelector("canvas.sunset-explorer-picture");
                return canvas.dataset.serial === "{serial_now}";
            }}""")
            after, serial, _ = shown_picture(page)
            report["renders_after_drag"] = serial_now - 1

            saved = root / "after.toml"
            settings = saved_settings(saved)
            scene = sunset.Scene.from_toml(saved)
            report["azimuth_saved"] = scene.sun.azimuth
            if scene.sun.azimuth == 1.1:
                raise CheckFailed("dragging the azimuth slider did not change the sun's azimuth")
            expected = sunset.picture(saved, t=settings["t"], hours=settings["hours"], size=None,
                                      reflections=settings["reflections"], seed=settings["seed"])
            if np.array_equal(after, first):
                raise CheckFailed("the picture did not change when the slider moved")
            if not np.array_equal(after, expected):
                raise CheckFailed("the picture after the drag is not sunset.picture of the saved settings: "
                                  + differences(after, expected))

            # the code under the pointer
            box = page.locator("canvas.sunset-explorer-picture").bounding_box()
            col, row = 100, 400
            page.mouse.move(box["x"] + (col + 0.5) * box["width"] / SIZE, box["y"] + (row + 0.5) * box["height"] / SIZE)
            readout_box = page.locator("pre.sunset-explorer-readout")
            readout_box.filter(has_text=f"pixel ({col}, {row})").wait_for()
            start = Start.of(scene, size=(SIZE, SIZE), hours=settings["hours"], t=settings["t"],
                             reflections=settings["reflections"], seed=settings["seed"])
            picture = Renderer(start)(start.view)
            if not np.array_equal(picture.rgb, expected):
                raise CheckFailed("the explorer's renderer and sunset.picture disagree on the saved scene")
            text = readout_box.inner_text().strip()
            if text != readout(picture, col, row):
                raise CheckFailed(f"the readout under the pointer is {text!r}, not {readout(picture, col, row)!r}")
            report["readout"] = text.splitlines()[0]
            if screenshot is not None:
                page.screenshot(path=str(screenshot))

            # make lab's default viewer: a chapter opens as a notebook (in a workspace of its own)
            import jupytext

            cells = len(jupytext.read(root / "chapter.md").cells)
            page.goto(f"{base}/lab/tree/chapter.md?reset&token={token}")
            page.locator(".jp-NotebookPanel:visible .jp-CodeCell").first.wait_for()
            # the status bar counts the notebook's cells: "Cell 1/17"
            page.locator(".jp-StatusBar-TextItem", has_text=re.compile(rf"^Cell \d+/{cells}$")).first.wait_for()
            report["chapter_cells"] = cells
        except PlaywrightError as exc:
            if screenshot is not None:
                page.screenshot(path=str(screenshot))
            raise CheckFailed(f"in the page: {str(exc).splitlines()[0]}") from None
        finally:
            browser.close()
    if outside:
        raise CheckFailed(f"the page asked for {len(outside)} address(es) outside the server, e.g. {outside[0]}")
    return report


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--chapter", default="01-camera.md", help="the chapter executed and opened (book/...)")
    parser.add_argument("--screenshot", type=Path, help="write the page as a PNG at the end")
    args = parser.parse_args(argv)
    exe = find_chromium()
    if exe is None or not Path(exe).is_file():
        print(f"explore_check: FAILED: chromium not found; {INSTALL_HINT}", file=sys.stderr)
        return 1
    chapter = BOOK / args.chapter
    with tempfile.TemporaryDirectory(prefix="sunset-explore-check-") as tmp:
        tmp = Path(tmp)
        root = tmp / "notebooks"
        root.mkdir()
        write_notebook(root / "explore.ipynb")
        shutil.copyfile(chapter, root / "chapter.md")
        proc = None
        try:
            seconds = run_chapter(chapter, tmp / "chapter-kernel")
            print(f"explore_check: {chapter.name} ran top to bottom in make lab's kernel in {seconds:.1f} s", flush=True)
            port, token = free_port(), secrets.token_hex(16)
            (tmp / "server").mkdir()
            proc = start_server(root, tmp / "server", port, token)
            report = check_browser(exe, root, port, token, args.screenshot)
        except ImportError as exc:
            print(f"explore_check: FAILED: {exc} (make explore-check installs the book's environment)", file=sys.stderr)
            return 1
        except CheckFailed as exc:
            print(f"explore_check: FAILED: {exc}", file=sys.stderr)
            log = tmp / "server" / "server.log"
            if log.is_file():
                print("explore_check: the server's log ends:\n" + log.read_text(errors="replace")[-2000:],
                      file=sys.stderr)
            return 1
        finally:
            if proc is not None:
                stop_server(proc)
        print("explore_check: " + json.dumps(report), flush=True)
        print("explore_check: ok: the chapter opens as a notebook; the explorer shows sunset.picture before and "
              "after a slider is dragged, and the code under the pointer; nothing left 127.0.0.1", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
