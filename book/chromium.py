"""Headless Chromium for the book's checks, its PDF and the player's browser tests, through Playwright.

Playwright for Python drives Debian's ``chromium`` (never a browser that
Playwright downloads: ``playwright install`` is not needed and not used), with
a fresh profile and the flags below, which keep it off the network: it
works offline. ``.ci/run`` installs the Debian package when it is absent; the
environment variable ``CHROMIUM`` names another binary.

Used by ``book/browser_check.py`` (``make book-check``), ``book/pdf.py``
(``make pdf``) and ``tests/recorder/player_browser.py`` (the colour-table
player's browser tests and ``make bench-player``).
"""

from __future__ import annotations

import contextlib
import functools
import http.server
import os
import shutil
import threading
from collections.abc import Iterator
from pathlib import Path

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

#: Chromium's command-line flags: headless, no sandbox (CI runs as root), and
#: nothing that talks to Google's hosts (background networking, component
#: updates, sync, QUIC): on a closed network those connections fail by the dozen.
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--disable-default-apps",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--mute-audio",
    "--no-default-browser-check",
]

#: Seconds for one page to load, typeset or print (Playwright's timeouts are in ms).
PAGE_TIMEOUT = 60.0

INSTALL_HINT = "install it with `apt-get update && apt-get install -y chromium` (or set CHROMIUM=/path)"


class BrowserError(RuntimeError):
    """The browser could not be started, or stopped answering."""


def find_chromium() -> str | None:
    """The Chromium binary: ``$CHROMIUM``, else the first of :data:`CHROMIUM_NAMES` on the PATH."""
    env = os.environ.get("CHROMIUM")
    if env:
        return env
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


@contextlib.contextmanager
def chromium() -> Iterator:
    """A Playwright ``Browser`` on the system's Chromium, closed on exit; :class:`BrowserError` if there is none."""
    exe = find_chromium()
    if exe is None:
        raise BrowserError(f"chromium not found; {INSTALL_HINT}")
    try:
        from playwright.sync_api import Error, sync_playwright
    except ImportError:
        raise BrowserError("playwright is not installed (pip install -e '.[book]')") from None
    with sync_playwright() as pw:
        try:
            browser = pw.chromium.launch(executable_path=exe, args=CHROMIUM_FLAGS, headless=True,
                                         timeout=PAGE_TIMEOUT * 1000)
        except Error as exc:
            raise BrowserError(f"{exe} did not start: {str(exc).splitlines()[0]}") from None
        try:
            yield browser
        finally:
            browser.close()


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 - signature from the base class
        pass


@contextlib.contextmanager
def serve(root: Path) -> Iterator[str]:
    """Serve the folder ``root`` on 127.0.0.1 (a free port) while the block runs; yields its base URL."""
    handler = functools.partial(_QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


class PageLog:
    """What a Playwright page asked of the network and what went wrong in it, since the last :meth:`clear`."""

    def __init__(self, page):
        self.clear()
        page.on("request", lambda r: self.requests.append(r.url))
        page.on("requestfailed", self._failed)
        page.on("response", self._response)
        page.on("pageerror", self._exception)

    def clear(self) -> None:
        self.requests: list[str] = []
        self.errors: list[str] = []

    def _exception(self, exc) -> None:
        name = getattr(exc, "name", None) or "Error"
        message = (getattr(exc, "message", None) or str(exc)).splitlines()[0]
        self.errors.append(f"JavaScript exception: {name}: {message}")

    def _failed(self, request) -> None:
        text = request.failure or "?"
        if "ERR_ABORTED" not in text:  # a request the page cancelled (it navigated on) is no failure
            self.errors.append(f"request failed: {request.url} ({text})")

    def _response(self, response) -> None:
        if response.status >= 400 and not response.url.endswith("/favicon.ico"):
            self.errors.append(f"HTTP {response.status} for {response.url}")

    def problems(self, base: str) -> list[str]:
        """Failed requests, HTTP errors, JavaScript exceptions, and requests outside ``base`` (a URL
        prefix) other than ``data:``, ``blob:`` and ``about:`` URLs."""
        out = list(self.errors)
        for url in sorted(set(self.requests)):
            if not (url.startswith(base) or url.startswith(("data:", "blob:", "about:"))):
                out.append(f"network request outside the book: {url}")
        return out
