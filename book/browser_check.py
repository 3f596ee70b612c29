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
* every ``<img>`` loaded (``complete`` and ``naturalWidth > 0``).

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

    # The network: only our server, no failures, no HTTP errors.
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("html", type=Path, nargs="?", default=BOOK / "_build" / "html",
                        help="the built book (default: book/_build/html)")
    parser.add_argument("--screenshot-dir", type=Path, default=None,
                        help="where to save page screenshots (default: <html>/../screenshots)")
    args = parser.parse_args(argv)

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
