#!/usr/bin/env python3
"""Open every page of the built book in headless Chromium and check it.

Usage::

    python book/browser_check.py book/_build/html [--screenshot-dir DIR]

The built HTML is served by a local ``http.server`` on 127.0.0.1 (a free
port). Chromium runs headless with a fresh profile and no background
networking, and is driven through the DevTools protocol over
``--remote-debugging-pipe`` (file descriptors 3 and 4), so this script needs
nothing but the standard library and the ``chromium`` binary (Debian package
``chromium``; ``.ci/run`` installs it when absent).

For every page (every ``*.html`` except Sphinx's search and general-index
pages and redirects such as ``index.html``) it checks that

* nothing was requested from the network: every request goes to the local
  server (or is a ``data:``/``blob:`` URL), and none failed or got an HTTP
  error status;
* the page's source contains no ``http(s)://`` URL in a ``<script src>`` or a
  ``<link href>`` (no CDN);
* where the page has math (Sphinx's ``.math`` elements), MathJax finished
  and put an ``mjx-container`` into every one of them, with no ``mjx-merror``;
* no raw TeX is left in the rendered text outside code: no ``$$``, ``\\(``,
  ``\\)``, ``\\[``, ``\\]``, and no ``$...$`` holding a TeX command;
* every ``<img>`` loaded (``complete`` and ``naturalWidth > 0``);
* every image of the text is a figure with a caption, and in a numbered
  chapter the caption is numbered by chapter ("Figure 4.2");
* glued numbers are set in the text's normal weight, and no number in the
  prose is left in e-notation ("6.7e-06" instead of "6.7 × 10⁻⁶");
* nothing overflows the text column, at 1280 px and again at phone width
  (``PHONE`` px): an element that is wider than the column must sit inside
  something that scrolls sideways (a wide table, equation or code block
  scrolls; a figure scales down), and the page itself never scrolls
  sideways;
* a code block in the column at 1280 px holds at least ``CODE_COLUMNS``
  characters, the width that tests/test_book.py allows included code.

Then it checks the colour-table player (sunset/recorder/player.py), on the
one page that embeds it and in a small file written by ``sunset player`` and
opened from disk: through the test hook ``?frame=F&hours=H&dump=1`` the
pixels it draws for several frames and hours are those of ``sunset.expose``
(exactly, and within 1/255 on the sun's anti-aliased rim); playing changes
the canvas; nothing is loaded from outside. It times the player's per-frame
draw (a benchmark: the median is printed and written to
``book/_build/player-bench.json``, never asserted).

It saves a screenshot (PNG) of every page under ``--screenshot-dir``
(default: ``book/_build/screenshots``) and a full-page one of the camera
chapter as ``book/_build/screenshot-camera.png``. It prints one line per page
and exits 1 with the list of failures if any check fails, 2 if the browser
cannot be run.
"""

from __future__ import annotations

import argparse
import base64
import functools
import http.server
import json
import math
import os
import queue
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

BOOK = Path(__file__).resolve().parent
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: Pages that are Sphinx machinery rather than chapters.
SKIP_PAGES = {"search.html", "genindex.html", "py-modindex.html"}
#: The chapter whose full-page screenshot is kept as book/_build/screenshot-camera.png.
CAMERA_PAGE = "01-camera.html"
PAGE_TIMEOUT = 60.0  # seconds for one page to load and typeset
VIEWPORT = (1280, 1000)
#: The phone's viewport (CSS pixels) for the second layout check.
PHONE = (390, 844)
#: Characters a code block must hold at 1280 px (tests/test_book.py's MAX_CODE_WIDTH).
CODE_COLUMNS = 84
MAX_SHOT_HEIGHT = 12000

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-quic",
    "--no-first-run",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--disable-default-apps",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--mute-audio",
    "--no-default-browser-check",
    "--remote-debugging-pipe",
]

#: Runs in the page once it has loaded; resolves to a report of what it found.
PAGE_PROBE = r"""
(async () => {
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  const report = {mathjax: false, math: 0, typeset: 0, merror: 0, untypeset: [],
                  rawtex: [], images: [], nimages: 0, title: document.title};
  // Images: wait until every <img> has finished (loaded or failed).
  const imgs = Array.from(document.images);
  const t0 = Date.now();
  while (imgs.some((i) => !i.complete) && Date.now() - t0 < 20000) await sleep(50);
  report.nimages = imgs.length;
  for (const i of imgs) {
    if (!(i.complete && i.naturalWidth > 0)) report.images.push(i.getAttribute("src"));
  }
  // Math: Sphinx marks every math node with class "math".
  const maths = Array.from(document.querySelectorAll(".math"));
  report.math = maths.length;
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    report.mathjax = true;
    await MathJax.startup.promise;
    if (MathJax.typesetPromise) await MathJax.typesetPromise();
  }
  for (const m of maths) {
    if (m.querySelector("mjx-container")) report.typeset += 1;
    else report.untypeset.push(m.textContent.slice(0, 80));
  }
  report.merror = document.querySelectorAll("mjx-merror").length;
  // Raw TeX in the rendered text, outside code, scripts and MathJax output.
  const body = document.body.cloneNode(true);
  body.querySelectorAll("pre, code, script, style, mjx-container, .highlight, textarea")
      .forEach((e) => e.remove());
  const text = body.innerText || body.textContent || "";
  const patterns = [/\$\$/, /\\\(/, /\\\)/, /\\\[/, /\\\]/, /\$[^$\n]*\\[A-Za-z]+[^$\n]*\$/];
  for (const p of patterns) {
    const m = text.match(p);
    if (m) {
      const k = m.index;
      report.rawtex.push(text.slice(Math.max(0, k - 40), k + 40).replace(/\s+/g, " "));
    }
  }
  return report;
})()
"""

#: Runs in the page (after PAGE_PROBE) at the current viewport: what overflows
#: the text column, glued numbers' weight, e-notation, captions, code width.
LAYOUT_PROBE = r"""
(() => {
  const out = {overflow: [], pagewide: 0, bold: [], enote: [], uncaptioned: [], unnumbered: [],
               code_columns: null};
  const article = document.querySelector("article.bd-article") || document.querySelector("main")
      || document.body;
  const box = article.getBoundingClientRect();
  const inside = (r) => r.right <= box.right + 1 && r.left >= box.left - 1;
  const scrolls = (el) => ["auto", "scroll", "hidden", "clip"].includes(getComputedStyle(el).overflowX);
  out.pagewide = Math.max(0, document.documentElement.scrollWidth - window.innerWidth);
  const reported = [];
  for (const el of article.querySelectorAll("*")) {
    if (reported.some((r) => r.contains(el))) continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0 || inside(r)) continue;
    if (getComputedStyle(el).visibility === "hidden" || getComputedStyle(el).position === "fixed") continue;
    let p = el.parentElement, contained = false;
    while (p && p !== article) {
      if (scrolls(p) && inside(p.getBoundingClientRect())) { contained = true; break; }
      p = p.parentElement;
    }
    if (contained) continue;
    reported.push(el);
    const what = el.tagName.toLowerCase() + (el.className && typeof el.className === "string"
        ? "." + el.className.trim().split(/\s+/).slice(0, 2).join(".") : "");
    out.overflow.push(`${what} is ${Math.round(r.width)} px wide, the column ${Math.round(box.width)} px ` +
                      `(${(el.textContent || el.getAttribute("src") || "").trim().slice(0, 50)})`);
  }
  for (const el of article.querySelectorAll(".pasted-text, .pasted-inline")) {
    const w = parseInt(getComputedStyle(el).fontWeight, 10);
    if (w > 400) { out.bold.push(el.textContent.slice(0, 30)); }
  }
  const body = article.cloneNode(true);
  body.querySelectorAll("pre, code, script, style, mjx-container, .highlight, textarea, .math")
      .forEach((e) => e.remove());
  const text = body.innerText || body.textContent || "";
  const re = /(?<![\w.])[+\-]?\d+(?:\.\d+)?[eE][+\-]\d+(?![\w.])/g;
  let m;
  while ((m = re.exec(text)) && out.enote.length < 5) {
    out.enote.push(text.slice(Math.max(0, m.index - 30), m.index + 20).replace(/\s+/g, " "));
  }
  for (const img of article.querySelectorAll("img")) {
    const fig = img.closest("figure");
    if (!fig || !fig.querySelector("figcaption")) { out.uncaptioned.push(img.getAttribute("src")); continue; }
    const num = fig.querySelector("figcaption .caption-number");
    out.unnumbered.push(num ? num.textContent.trim() : "");
  }
  const pre = article.querySelector("div.highlight pre");
  if (pre) {
    const span = document.createElement("span");
    span.textContent = "0".repeat(100);
    pre.appendChild(span);
    const cs = getComputedStyle(pre);
    const inner = pre.clientWidth - parseFloat(cs.paddingLeft) - parseFloat(cs.paddingRight);
    out.code_columns = Math.floor(inner / (span.getBoundingClientRect().width / 100));
    span.remove();
  }
  return out;
})()
"""


class BrowserError(RuntimeError):
    """The browser could not be started or stopped answering."""


class DevTools:
    """A minimal DevTools-protocol client over Chromium's --remote-debugging-pipe."""

    def __init__(self, exe: str, profile: Path, log: Path):
        to_r, to_w = os.pipe()      # we write commands -> Chromium reads on fd 3
        from_r, from_w = os.pipe()  # Chromium writes on fd 4 -> we read

        def child_fds():  # runs in the child before exec
            a, b = os.dup(to_r), os.dup(from_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self._log = open(log, "wb")
        args = [exe, *CHROMIUM_FLAGS, f"--user-data-dir={profile}",
                f"--window-size={VIEWPORT[0]},{VIEWPORT[1]}", "about:blank"]
        self.proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=self._log,
                                     stderr=subprocess.STDOUT, pass_fds=(3, 4),
                                     preexec_fn=child_fds)
        os.close(to_r)
        os.close(from_w)
        self._w = to_w
        self._r = from_r
        self._next = 0
        self._responses: dict[int, dict] = {}
        self._events: queue.Queue = queue.Queue()
        self._cv = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        buf = b""
        while True:
            try:
                chunk = os.read(self._r, 1 << 20)
            except OSError:
                chunk = b""
            if not chunk:
                with self._cv:
                    self._responses[-1] = {"closed": True}
                    self._cv.notify_all()
                return
            buf += chunk
            while b"\0" in buf:
                raw, buf = buf.split(b"\0", 1)
                msg = json.loads(raw)
                if "id" in msg:
                    with self._cv:
                        self._responses[msg["id"]] = msg
                        self._cv.notify_all()
                else:
                    self._events.put(msg)

    def call(self, method: str, params: dict | None = None, session: str | None = None,
             timeout: float = PAGE_TIMEOUT) -> dict:
        """Send one command and wait for its result."""
        self._next += 1
        mid = self._next
        msg = {"id": mid, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        data = json.dumps(msg).encode() + b"\0"
        try:
            os.write(self._w, data)
        except OSError as exc:
            raise BrowserError(f"chromium closed its pipe ({exc})") from None
        deadline = time.monotonic() + timeout
        with self._cv:
            while mid not in self._responses:
                if -1 in self._responses:
                    raise BrowserError("chromium exited")
                left = deadline - time.monotonic()
                if left <= 0:
                    raise BrowserError(f"no answer to {method} within {timeout:.0f} s")
                self._cv.wait(left)
            reply = self._responses.pop(mid)
        if "error" in reply:
            raise BrowserError(f"{method}: {reply['error'].get('message')}")
        return reply.get("result", {})

    def events(self) -> list[dict]:
        """Every event received since the last call."""
        out = []
        while True:
            try:
                out.append(self._events.get_nowait())
            except queue.Empty:
                return out

    def wait_event(self, method: str, session: str, timeout: float) -> list[dict]:
        """Collect events until ``method`` arrives for ``session``; return all collected."""
        seen = []
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise BrowserError(f"no {method} within {timeout:.0f} s")
            try:
                ev = self._events.get(timeout=left)
            except queue.Empty:
                continue
            seen.append(ev)
            if ev.get("method") == method and ev.get("sessionId") == session:
                return seen

    def close(self) -> None:
        try:
            self.call("Browser.close", timeout=5)
        except BrowserError:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self._w, self._r):
            try:
                os.close(fd)
            except OSError:
                pass
        self._log.close()


def find_chromium() -> str | None:
    env = os.environ.get("CHROMIUM")
    if env:
        return env
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 - signature from the base class
        pass


def serve(root: Path) -> tuple[http.server.ThreadingHTTPServer, str]:
    handler = functools.partial(QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_address[1]}/"


def static_cdn_urls(html: str) -> list[str]:
    """http(s) URLs in <script src> and <link href> of a page's source."""
    urls = []
    for tag in re.findall(r"<(?:script|link)\b[^>]*>", html, flags=re.I):
        for attr in re.findall(r"""\b(?:src|href)\s*=\s*["']([^"']*)["']""", tag, flags=re.I):
            if re.match(r"(?:https?:)?//", attr, flags=re.I):
                urls.append(attr)
    return urls


def pages_of(root: Path) -> list[Path]:
    pages = []
    for p in sorted(root.rglob("*.html")):
        rel = p.relative_to(root)
        if rel.parts[0].startswith("_") or rel.name in SKIP_PAGES:
            continue
        if re.search(r"<meta[^>]+http-equiv=[\"']?refresh", p.read_text(errors="replace"), re.I):
            continue  # a redirect (the index.html that points at the root page)
        pages.append(p)
    return pages


def network_problems(events: list[dict], session: str, base: str) -> list[str]:
    """What went wrong on the network while a page loaded: requests outside ``base`` (other than
    ``data:``/``blob:``/``about:`` URLs), failed requests, HTTP errors and JavaScript exceptions."""
    problems: list[str] = []
    requests = {}
    for ev in events:
        if ev.get("sessionId") != session:
            continue
        p = ev.get("params", {})
        if ev.get("method") == "Network.requestWillBeSent":
            requests[p["requestId"]] = p["request"]["url"]
        elif ev.get("method") == "Network.loadingFailed":
            u = requests.get(p.get("requestId"), "?")
            if not p.get("canceled"):
                problems.append(f"request failed: {u} ({p.get('errorText')})")
        elif ev.get("method") == "Network.responseReceived":
            status = p["response"].get("status", 0)
            if status >= 400 and not p["response"].get("url", "").endswith("/favicon.ico"):
                problems.append(f"HTTP {status} for {p['response'].get('url')}")
        elif ev.get("method") == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            msg = (d.get("exception") or {}).get("description") or d.get("text")
            problems.append(f"JavaScript exception: {str(msg).splitlines()[0]}")
    for u in sorted(set(requests.values())):
        if not (u.startswith(base) or u.startswith(("data:", "blob:", "about:"))):
            problems.append(f"network request outside the book: {u}")
    return problems


def check_page(dt: DevTools, session: str, base: str, root: Path, page: Path,
               shot_dir: Path) -> tuple[list[str], dict]:
    rel = page.relative_to(root).as_posix()
    url = base + rel
    problems: list[str] = []
    for cdn in static_cdn_urls(page.read_text(encoding="utf-8", errors="replace")):
        problems.append(f"loads {cdn} from the network (script/link)")

    dt.events()  # drop what came before this page
    dt.call("Page.navigate", {"url": url}, session)
    events = dt.wait_event("Page.loadEventFired", session, PAGE_TIMEOUT)
    result = dt.call("Runtime.evaluate", {"expression": PAGE_PROBE, "awaitPromise": True,
                                          "returnByValue": True}, session)
    if "exceptionDetails" in result:
        problems.append(f"page probe failed: {result['exceptionDetails'].get('text')}")
        report = {}
    else:
        report = result["result"]["value"]
    time.sleep(0.2)
    events += dt.events()

    problems += network_problems(events, session, base)

    if report:
        if report["math"]:
            if not report["mathjax"]:
                problems.append(f"{report['math']} math elements but MathJax did not load")
            if report["typeset"] < report["math"]:
                problems.append(f"{report['math'] - report['typeset']} of {report['math']} math "
                                f"elements not typeset, e.g. {report['untypeset'][:2]}")
            if report["merror"]:
                problems.append(f"{report['merror']} MathJax errors (mjx-merror)")
        for snippet in report["rawtex"]:
            problems.append(f"raw TeX left in the page: ...{snippet}...")
        for src in report["images"]:
            problems.append(f"image did not load: {src}")

    # Layout, captions and numbers, at the desktop width and at the phone's.
    chapter = re.match(r"(\d\d)-", rel)
    for label, (w, h), mobile in (("1280 px", VIEWPORT, False), (f"{PHONE[0]} px", PHONE, True)):
        if mobile:
            dt.call("Emulation.setDeviceMetricsOverride",
                    {"width": w, "height": h, "deviceScaleFactor": 1, "mobile": True}, session)
            dt.call("Page.reload", {}, session)
            dt.wait_event("Page.loadEventFired", session, PAGE_TIMEOUT)
            dt.call("Runtime.evaluate", {"expression": PAGE_PROBE, "awaitPromise": True,
                                         "returnByValue": True}, session)
        got = dt.call("Runtime.evaluate", {"expression": LAYOUT_PROBE, "returnByValue": True}, session)
        layout = got.get("result", {}).get("value") or {}
        if "exceptionDetails" in got:
            problems.append(f"layout probe failed at {label}: {got['exceptionDetails'].get('text')}")
            continue
        for o in layout["overflow"][:5]:
            problems.append(f"overflows its column at {label}: {o}")
        if layout["pagewide"] > 1:
            problems.append(f"the page scrolls sideways by {layout['pagewide']} px at {label}")
        if mobile:
            dt.call("Emulation.setDeviceMetricsOverride",
                    {"width": VIEWPORT[0], "height": VIEWPORT[1], "deviceScaleFactor": 1, "mobile": False},
                    session)
            continue
        for b in layout["bold"][:3]:
            problems.append(f"a glued number is bold: {b!r}")
        for e in layout["enote"]:
            problems.append(f"a number in e-notation: ...{e}...")
        for src in layout["uncaptioned"]:
            problems.append(f"an image without a captioned figure: {src}")
        if chapter:
            for num in layout["unnumbered"]:
                if not re.match(r"Figure \d+\.\d+", num):
                    problems.append(f"a figure not numbered by chapter: {num!r}")
        if layout["code_columns"] is not None and layout["code_columns"] < CODE_COLUMNS:
            problems.append(f"a code block holds {layout['code_columns']} characters at {label}, "
                            f"fewer than the {CODE_COLUMNS} that included code may use")
        report["code_columns"] = layout["code_columns"]

    # Screenshots: the viewport of every page; the whole of the camera chapter.
    shot = dt.call("Page.captureScreenshot", {"format": "png"}, session)
    out = shot_dir / (rel.replace("/", "_")[:-5] + ".png")
    out.write_bytes(base64.b64decode(shot["data"]))
    if page.name == CAMERA_PAGE:
        # A full-page shot: make the viewport as tall as the page (a capture
        # "beyond the viewport" would lay the page out again at another size).
        metrics = dt.call("Page.getLayoutMetrics", {}, session)
        size = metrics.get("cssContentSize") or metrics["contentSize"]
        tall = min(MAX_SHOT_HEIGHT, int(math.ceil(size["height"])))
        dt.call("Emulation.setDeviceMetricsOverride",
                {"width": VIEWPORT[0], "height": tall, "deviceScaleFactor": 1, "mobile": False}, session)
        time.sleep(0.5)
        full = dt.call("Page.captureScreenshot", {"format": "png"}, session)
        (root.parent / "screenshot-camera.png").write_bytes(base64.b64decode(full["data"]))
        dt.call("Emulation.setDeviceMetricsOverride",
                {"width": VIEWPORT[0], "height": VIEWPORT[1], "deviceScaleFactor": 1, "mobile": False},
                session)
    return problems, report


# --------------------------------------------------------------------------- the colour-table player
#: Element id of the player (sunset/recorder/player.html) and of its test hook's output.
PLAYER_ID = "sunset-player"
#: Blocks of ten draws per benchmark run, and runs (after one warm-up run).
PLAYER_BENCH_BLOCKS = 20
PLAYER_BENCH_RUNS = 5
#: The small self-contained player written with `sunset player` and opened from disk.
STANDALONE_ARGS = ["--frames", "3", "--size", "64x64", "--from-hours", "0.6", "--to-hours", "0.2", "--quiet"]

PLAYER_READY = """
(async () => {
  const t0 = Date.now();
  while (!window.sunsetPlayer && Date.now() - t0 < 20000) await new Promise((r) => setTimeout(r, 20));
  await window.sunsetPlayer.ready;
  return document.getElementById("sunset-player").dataset.state;
})()
"""


def _evaluate(dt: DevTools, session: str, expression: str):
    result = dt.call("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                          "returnByValue": True}, session)
    if "exceptionDetails" in result:
        d = result["exceptionDetails"]
        msg = (d.get("exception") or {}).get("description") or d.get("text")
        raise BrowserError(f"in the page: {str(msg).splitlines()[0]}")
    return result["result"].get("value")


def _open_player(dt: DevTools, session: str, url: str) -> list[dict]:
    """Navigate to a player page and wait until it has drawn; the events seen on the way."""
    dt.events()
    dt.call("Page.navigate", {"url": url}, session)
    events = dt.wait_event("Page.loadEventFired", session, PAGE_TIMEOUT)
    state = _evaluate(dt, session, PLAYER_READY)
    if state != "ready":
        raise BrowserError(f"the player at {url} did not start (state {state!r})")
    time.sleep(0.1)
    return events + dt.events()


def _canvas(dt: DevTools, session: str) -> str:
    return _evaluate(dt, session, "document.querySelector('#sunset-player canvas').toDataURL('image/png')")


def _compare_dumps(dt: DevTools, session: str, url: str, allowed: str, data: dict, cases,
                   need_rim: bool = True) -> tuple[list[str], list[str]]:
    """Open ``url?frame=F&hours=H&dump=1`` for each case and compare the dump with sunset.expose.

    Requests outside ``allowed`` (a URL prefix) are problems; so is, when
    ``need_rim``, a set of cases in which no sky pixel lies on the sun's rim.
    """
    import io

    import numpy as np
    from PIL import Image

    from sunset import Scene, expose
    from sunset.recorder.player import decode_codes, nearest_hour

    scene = Scene.from_toml(data["scene"])
    codes = decode_codes(data)
    n2 = data["supersample"] ** 2
    problems, lines = [], []
    rim_total = 0
    for frame, hours in cases:
        events = _open_player(dt, session, f"{url}?frame={frame}&hours={hours!r}&dump=1")
        problems += network_problems(events, session, allowed)
        dump = _evaluate(dt, session, "document.getElementById('sunset-dump').textContent")
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
        rim = np.zeros(diff.shape, bool)        # sky-coded pixels the disk covers only in part
        s = data["sun"][h]
        if s is not None:
            k = np.asarray(s["cover"]).reshape(s["h"], s["w"])
            box = (slice(s["r0"], s["r0"] + s["h"]), slice(s["c0"], s["c0"] + s["w"]))
            rim[box] = (k > 0) & (k < n2) & (codes[frame][box] >= data["sky_start"])
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
    import struct
    import zlib

    import numpy as np

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


def _check_png_filters(dt: DevTools, session: str, data: dict) -> list[str]:
    """The player's PNG decoder, on a PNG that uses all five row filters (checked first with Pillow)."""
    import io

    import numpy as np
    from PIL import Image

    codes = np.random.default_rng(14).integers(0, 256, (data["height"], data["width"]), dtype=np.uint8)
    codes[:, : data["width"] // 2] //= 8                   # smooth and noisy parts, so that every filter matters
    png = filtered_png(codes)
    with Image.open(io.BytesIO(png)) as img:
        if not np.array_equal(np.asarray(img), codes):
            return ["the test PNG with all five filters does not decode to its codes in Pillow"]
    b64 = base64.b64encode(png).decode("ascii")
    got = _evaluate(dt, session, f"window.sunsetPlayer.decodePng('{b64}')")
    if not np.array_equal(np.asarray(got, dtype=np.int64).reshape(codes.shape), codes):
        return ["the player's PNG decoder gets a PNG with all five row filters wrong"]
    return []


def _dump_cases(data: dict) -> list[tuple[int, float]]:
    """Frames and hours to compare: the ends of the grid, the hour the player opens at, and the hours where
    the rim has most sky pixels."""
    import numpy as np

    from sunset.recorder.player import decode_codes

    codes = decode_codes(data)
    n, m, n2 = data["frames"], len(data["hours"]), data["supersample"] ** 2
    rim = np.zeros(m, int)
    for h, s in enumerate(data["sun"]):
        if s is not None:
            k = np.asarray(s["cover"]).reshape(s["h"], s["w"])
            box = codes[0][s["r0"]:s["r0"] + s["h"], s["c0"]:s["c0"] + s["w"]]
            rim[h] = int(np.count_nonzero((k > 0) & (k < n2) & (box >= data["sky_start"])))
    best = [int(i) for i in np.argsort(-rim, kind="stable")[:2] if rim[i] > 0]
    start = int(np.argmin(np.abs(np.asarray(data["hours"]) - data["start_hours"])))
    hours = [0, m - 1, start] + best
    frames = [0, n // 2, n - 1, (n // 3) % n]
    step = (data["hours"][1] - data["hours"][0]) if m > 1 else 0.0
    # off-grid hours (a quarter step away) test "the grid hour nearest H"
    return [(frames[i % len(frames)], data["hours"][h] + (0.25 * step if i % 2 else 0.0))
            for i, h in enumerate(dict.fromkeys(hours))]


def bench_player(dt: DevTools, session: str, data: dict) -> dict:
    """Time the open player's draws (compose + putImageData) at its resolution: a JSON-ready report.

    One warm-up run, then :data:`PLAYER_BENCH_RUNS` runs of
    :data:`PLAYER_BENCH_BLOCKS` blocks of ten draws at varying frames and hours,
    timed by blocks because the page's clock ticks in 0.1 ms; the median and
    the 95th percentile of the milliseconds per draw over every block.
    """
    import statistics

    _evaluate(dt, session, "window.sunsetPlayer.pause(), window.sunsetPlayer.bench(5), true")
    runs = [_evaluate(dt, session, f"window.sunsetPlayer.bench({PLAYER_BENCH_BLOCKS})")
            for _ in range(PLAYER_BENCH_RUNS)]
    every = [t for r in runs for t in r]
    return {"width": data["width"], "height": data["height"], "draws_per_run": 10 * PLAYER_BENCH_BLOCKS,
            "runs": PLAYER_BENCH_RUNS, "median_ms": statistics.median(every),
            "run_medians_ms": [statistics.median(r) for r in runs],
            "p95_ms": sorted(every)[int(0.95 * (len(every) - 1))],
            "chromium": dt.call("Browser.getVersion").get("product", "?"), "chromium_flags": CHROMIUM_FLAGS,
            "cpus": os.cpu_count(), "load_average": os.getloadavg()[0],
            "date": time.strftime("%Y-%m-%d", time.gmtime())}


def bench_line(bench: dict) -> str:
    """One line saying what :func:`bench_player` measured."""
    runs = ", ".join(f"{m:.3f}" for m in bench["run_medians_ms"])
    return (f"draw {bench['width']}x{bench['height']}: median {bench['median_ms']:.3f} ms (run medians {runs} ms; "
            f"p95 {bench['p95_ms']:.3f} ms; load average {bench['load_average']:.1f})")


def check_player(dt: DevTools, session: str, base: str, root: Path, pages: list[Path],
                 bench_out: Path) -> tuple[list[str], list[str]]:
    """The colour-table player in the built book and as a file written by ``sunset player``.

    * The book has a page with the player; for several frames and hours the
      test hook's dump equals ``sunset.expose`` on the same codes exactly,
      except on the sun's anti-aliased rim, where it may differ by 1/255.
    * Playing changes the canvas (and so does the sun setting while it plays).
    * Nothing is loaded from outside (the book's server, or the file itself).
    * The per-frame draw time at the player's resolution (a benchmark: the
      median is reported and written to ``bench_out``, never asserted).
    """
    from sunset.recorder.player import read_player_data

    problems: list[str] = []
    lines: list[str] = []
    found = [p for p in pages if f'id="{PLAYER_ID}"' in p.read_text(encoding="utf-8", errors="replace")]
    if len(found) != 1:
        return [f"expected one page with the player (id {PLAYER_ID}), found {len(found)}"], lines
    page = found[0]
    rel = page.relative_to(root).as_posix()
    url = base + rel
    data = read_player_data(page.read_text(encoding="utf-8"))
    p, out = _compare_dumps(dt, session, url, base, data, _dump_cases(data))
    problems += [f"{rel}: {x}" for x in p]
    lines += [f"{rel}: {x}" for x in out]

    # Playing changes the canvas; with the sun setting, the hour moves on too.
    events = _open_player(dt, session, url)
    png_problems = _check_png_filters(dt, session, data)
    problems += [f"{rel}: {x}" for x in png_problems]
    if not png_problems:
        lines.append(f"{rel}: the PNG decoder gets a {data['width']}x{data['height']} PNG using all five row "
                     f"filters exactly")
    _evaluate(dt, session, "window.sunsetPlayer.pause(), window.sunsetPlayer.draw(0, 0), true")
    before = _canvas(dt, session)
    _evaluate(dt, session, "document.querySelector('#sunset-player [data-role=follow]').click(), "
                           "window.sunsetPlayer.play(), true")
    time.sleep(1.5)
    after = _canvas(dt, session)
    st = _evaluate(dt, session, "({frame: sunsetPlayer.state.frame, hour: sunsetPlayer.state.hour, "
                                "playing: sunsetPlayer.state.playing})")
    events += dt.events()
    problems += [f"{rel}: {x}" for x in network_problems(events, session, base)]
    if before == after:
        problems.append(f"{rel}: playing did not change the canvas")
    if st["hour"] == 0:
        problems.append(f"{rel}: the sun did not move while the player played with 'the sun sets' on")
    lines.append(f"{rel}: after 1.5 s of play: frame {st['frame']}, grid hour {st['hour']}, canvas changed: "
                 f"{before != after}")

    # The benchmark: draws at the player's resolution (a measurement, never asserted).
    bench = bench_player(dt, session, data)
    bench_out.write_text(json.dumps(bench, indent=1) + "\n", encoding="utf-8")
    lines.append(f"{rel}: {bench_line(bench)} -> {bench_out}")

    # A file written by `sunset player`, opened from disk: no server, no network.
    with tempfile.TemporaryDirectory(prefix="sunset-player-") as tmp:
        html = Path(tmp) / "player.html"
        run = subprocess.run([sys.executable, "-m", "sunset", "player", "carlas-island", "-o", str(html),
                              *STANDALONE_ARGS], capture_output=True, text=True, cwd=BOOK.parent)
        if run.returncode != 0 or not html.is_file():
            problems.append(f"sunset player failed (exit {run.returncode}): {run.stderr.strip()[-300:]}")
        else:
            file_url = html.as_uri()
            sdata = read_player_data(html.read_text(encoding="utf-8"))
            cases = [(0, sdata["hours"][0]), (sdata["frames"] - 1, sdata["hours"][-1])]
            p, out = _compare_dumps(dt, session, file_url, file_url, sdata, cases, need_rim=False)
            problems += [f"sunset player file: {x}" for x in p]
            lines += [f"sunset player file: {x}" for x in out]
    return problems, lines


def player_bench_main(html: Path, out: Path | None) -> int:
    """``--player-bench``: open a player file from disk, time its draws, print (and write) the result."""
    from sunset.recorder.player import read_player_data

    exe = find_chromium()
    if exe is None or not html.is_file():
        print(f"browser_check: {'chromium not found' if exe is None else f'{html}: no such file'}",
              file=sys.stderr)
        return 2
    data = read_player_data(html.read_text(encoding="utf-8"))
    with tempfile.TemporaryDirectory(prefix="sunset-chromium-") as tmp:
        dt = DevTools(exe, Path(tmp) / "profile", Path(tmp) / "chromium.log")
        try:
            target = dt.call("Target.createTarget", {"url": "about:blank"})["targetId"]
            session = dt.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
            for domain in ("Page", "Network", "Runtime"):
                dt.call(f"{domain}.enable", {}, session)
            _open_player(dt, session, html.resolve().as_uri())
            bench = bench_player(dt, session, data)
        except BrowserError as exc:
            print(f"browser_check: {exc}", file=sys.stderr)
            return 2
        finally:
            dt.close()
    bench["file"] = str(html)
    print(f"browser_check: player: {bench_line(bench)}", flush=True)
    if out is not None:
        out.write_text(json.dumps(bench, indent=1) + "\n", encoding="utf-8")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("html", type=Path, nargs="?", default=BOOK / "_build" / "html",
                        help="the built book (default: book/_build/html)")
    parser.add_argument("--screenshot-dir", type=Path, default=None,
                        help="where to save page screenshots (default: <html>/../screenshots)")
    parser.add_argument("--player-bench", type=Path, metavar="PLAYER.html",
                        help="only time the draws of a player file written by `sunset player` (make bench-player)")
    parser.add_argument("--out", type=Path, help="with --player-bench: also write the measurement here (JSON)")
    args = parser.parse_args(argv)
    if args.player_bench:
        return player_bench_main(args.player_bench, args.out)

    root = args.html.resolve()
    if not (root / "index.html").is_file():
        print(f"browser_check: {root}/index.html not found: build the book first (make book)",
              file=sys.stderr)
        return 2
    exe = find_chromium()
    if exe is None:
        print("browser_check: chromium not found; install it with "
              "`apt-get update && apt-get install -y chromium` (or set CHROMIUM=/path)",
              file=sys.stderr)
        return 2
    shot_dir = (args.screenshot_dir or root.parent / "screenshots").resolve()
    shot_dir.mkdir(parents=True, exist_ok=True)
    pages = pages_of(root)
    if not pages:
        print(f"browser_check: no pages under {root}", file=sys.stderr)
        return 2

    start = time.perf_counter()
    failures: dict[str, list[str]] = {}
    with tempfile.TemporaryDirectory(prefix="sunset-chromium-") as tmp:
        tmp = Path(tmp)
        log = tmp / "chromium.log"
        dt = DevTools(exe, tmp / "profile", log)  # before the server thread starts
        server, base = serve(root)
        try:
            dt.call("Target.setDiscoverTargets", {"discover": False})
            target = dt.call("Target.createTarget", {"url": "about:blank"})["targetId"]
            session = dt.call("Target.attachToTarget",
                              {"targetId": target, "flatten": True})["sessionId"]
            for domain in ("Page", "Network", "Runtime"):
                dt.call(f"{domain}.enable", {}, session)
            dt.call("Emulation.setDeviceMetricsOverride",
                    {"width": VIEWPORT[0], "height": VIEWPORT[1], "deviceScaleFactor": 1,
                     "mobile": False}, session)
            for page in pages:
                rel = page.relative_to(root).as_posix()
                problems, report = check_page(dt, session, base, root, page, shot_dir)
                status = "ok" if not problems else "FAIL"
                print(f"browser_check: {status:4} {rel}: {report.get('math', '?')} math "
                      f"({report.get('typeset', '?')} typeset), {report.get('nimages', '?')} images",
                      flush=True)
                if problems:
                    failures[rel] = problems
            problems, lines = check_player(dt, session, base, root, pages, root.parent / "player-bench.json")
            for line in lines:
                print(f"browser_check: player: {line}", flush=True)
            print(f"browser_check: {'ok' if not problems else 'FAIL':4} the colour-table player", flush=True)
            if problems:
                failures["player"] = problems
        except BrowserError as exc:
            tail = log.read_text(errors="replace")[-2000:] if log.exists() else ""
            print(f"browser_check: {exc}\n--- chromium log (tail) ---\n{tail}", file=sys.stderr)
            dt.close()
            server.shutdown()
            return 2
        dt.close()
        server.shutdown()
    elapsed = time.perf_counter() - start

    if failures:
        print(f"browser_check: FAILED on {len(failures)} of {len(pages)} pages:", file=sys.stderr)
        for rel, problems in failures.items():
            for p in problems:
                print(f"  {rel}: {p}", file=sys.stderr)
        return 1
    print(f"browser_check: all {len(pages)} pages passed in {elapsed:.1f} s; "
          f"screenshots in {shot_dir}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
