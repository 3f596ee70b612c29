#!/usr/bin/env python3
"""Open every page of the built book in headless Chromium and check it.

Usage::

    python book/browser_check.py book/_build/html [--screenshot-dir DIR]

The built HTML is served by a local ``http.server`` on 127.0.0.1 (a free
port). Chromium (Debian's ``chromium``; ``.ci/run`` installs it when absent)
runs headless with a fresh profile and no background networking, driven by
Playwright for Python (``book/chromium.py``; Playwright's own browsers are
never downloaded).

For every page (every ``*.html`` except Sphinx's search and general-index
pages and redirects such as ``index.html``) it checks that

* nothing was requested from the network: every request goes to the local
  server (or is a ``data:``/``blob:`` URL), none failed or got an HTTP
  error status, and no JavaScript exception was thrown;
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
  (``PHONE`` px, a mobile viewport): an element that is wider than the
  column must sit inside something that scrolls sideways (a wide table,
  equation or code block scrolls; a figure scales down), and the page itself
  never scrolls sideways;
* a code block in the column at 1280 px holds at least ``CODE_COLUMNS``
  characters, the width that tests/test_book.py allows included code.

Then it checks the colour-table player on the one page that embeds it, with
the checks of its own browser tests (tests/recorder/player_browser.py, run by
``make test``): through the test hook ``?frame=F&hours=H&dump=1`` the pixels it
draws for several frames and hours are those of ``sunset.expose`` (exactly,
and within 1/255 on the sun's anti-aliased rim); its PNG decoder reads every
row filter; playing changes the canvas and moves the sun; nothing is loaded
from outside. It times the player's per-frame draw (a benchmark: the median
is printed and written to ``book/_build/player-bench.json``, never asserted).

It saves a screenshot (PNG) of every page under ``--screenshot-dir``
(default: ``book/_build/screenshots``) and a full-page one of the camera
chapter as ``book/_build/screenshot-camera.png``. It prints one line per page
and exits 1 with the list of failures if any check fails, 2 if the browser
cannot be run.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
from pathlib import Path

BOOK = Path(__file__).resolve().parent
sys.path.insert(0, str(BOOK))
sys.path.insert(0, str(BOOK.parent))

from chromium import INSTALL_HINT, BrowserError, PageLog, chromium, find_chromium, serve  # noqa: E402

#: Pages that are Sphinx machinery rather than chapters.
SKIP_PAGES = {"search.html", "genindex.html", "py-modindex.html"}
#: The chapter whose full-page screenshot is kept as book/_build/screenshot-camera.png.
CAMERA_PAGE = "01-camera.html"
VIEWPORT = (1280, 1000)
#: The phone's viewport (CSS pixels) for the second layout check.
PHONE = (390, 844)
#: Characters a code block must hold at 1280 px (tests/test_book.py's MAX_CODE_WIDTH).
CODE_COLUMNS = 84
MAX_SHOT_HEIGHT = 12000

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


def probe(page, script: str) -> tuple[dict, str | None]:
    """Run a probe in the page: (its report, or {} and the error's first line)."""
    from playwright.sync_api import Error

    try:
        return page.evaluate(script) or {}, None
    except Error as exc:
        return {}, str(exc).splitlines()[0]


def page_problems(report: dict) -> list[str]:
    """What :data:`PAGE_PROBE` found wrong: math, raw TeX, images."""
    problems = []
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
    return problems


def layout_problems(layout: dict, label: str, chapter: bool, desktop: bool) -> list[str]:
    """What :data:`LAYOUT_PROBE` found wrong at one width; captions, numbers and code only at the desktop's."""
    problems = [f"overflows its column at {label}: {o}" for o in layout["overflow"][:5]]
    if layout["pagewide"] > 1:
        problems.append(f"the page scrolls sideways by {layout['pagewide']} px at {label}")
    if not desktop:
        return problems
    problems += [f"a glued number is bold: {b!r}" for b in layout["bold"][:3]]
    problems += [f"a number in e-notation: ...{e}..." for e in layout["enote"]]
    problems += [f"an image without a captioned figure: {src}" for src in layout["uncaptioned"]]
    if chapter:
        problems += [f"a figure not numbered by chapter: {num!r}" for num in layout["unnumbered"]
                     if not re.match(r"Figure \d+\.\d+", num)]
    if layout["code_columns"] is not None and layout["code_columns"] < CODE_COLUMNS:
        problems.append(f"a code block holds {layout['code_columns']} characters at {label}, "
                        f"fewer than the {CODE_COLUMNS} that included code may use")
    return problems


def check_page(desk, desk_log: PageLog, phone, phone_log: PageLog, base: str, root: Path, page: Path,
               shot_dir: Path) -> tuple[list[str], dict]:
    """Every check of one page, at the desktop's width and the phone's; its screenshots."""
    rel = page.relative_to(root).as_posix()
    url = base + rel
    problems = [f"loads {cdn} from the network (script/link)"
                for cdn in static_cdn_urls(page.read_text(encoding="utf-8", errors="replace"))]
    chapter = bool(re.match(r"(\d\d)-", rel))
    report: dict = {}
    for tab, log, (w, h), desktop in ((desk, desk_log, VIEWPORT, True), (phone, phone_log, PHONE, False)):
        label = f"{w} px"
        log.clear()
        tab.goto(url, wait_until="load")
        got, error = probe(tab, PAGE_PROBE)
        if error:
            problems.append(f"page probe failed at {label}: {error}")
        elif desktop:
            report = got
            problems += page_problems(got)
        time.sleep(0.2)
        problems += [f"{p} (at {label})" if not desktop else p for p in log.problems(base)]
        layout, error = probe(tab, LAYOUT_PROBE)
        if error:
            problems.append(f"layout probe failed at {label}: {error}")
            continue
        problems += layout_problems(layout, label, chapter, desktop)
        if desktop:
            report["code_columns"] = layout["code_columns"]

    # Screenshots: the viewport of every page; the whole of the camera chapter.
    desk.screenshot(path=shot_dir / (rel.replace("/", "_")[:-5] + ".png"))
    if page.name == CAMERA_PAGE:
        # A full-page shot: make the viewport as tall as the page (a capture
        # "beyond the viewport" would lay the page out again at another size).
        height = desk.evaluate("document.documentElement.scrollHeight")
        desk.set_viewport_size({"width": VIEWPORT[0], "height": min(MAX_SHOT_HEIGHT, int(math.ceil(height)))})
        time.sleep(0.5)
        desk.screenshot(path=root.parent / "screenshot-camera.png")
        desk.set_viewport_size({"width": VIEWPORT[0], "height": VIEWPORT[1]})
    return problems, report


def check_player(browser, base: str, root: Path, pages: list[Path], bench_out: Path) -> tuple[list[str], list[str]]:
    """The colour-table player of the built book: the checks of tests/recorder/player_browser.py on the
    one page that embeds it (served by the book's server: nothing may come from elsewhere), and the
    timing of its draws, written to ``bench_out`` (never asserted)."""
    from sunset.recorder.player import read_player_data
    from tests.recorder import player_browser as pb

    found = [p for p in pages if f'id="{pb.PLAYER_ID}"' in p.read_text(encoding="utf-8", errors="replace")]
    if len(found) != 1:
        return [f"expected one page with the player (id {pb.PLAYER_ID}), found {len(found)}"], []
    rel = found[0].relative_to(root).as_posix()
    data = read_player_data(found[0].read_text(encoding="utf-8"))
    page = browser.new_page(viewport={"width": VIEWPORT[0], "height": VIEWPORT[1]})
    log = PageLog(page)
    problems, lines = pb.check_player(page, log, base + rel, base, data)
    bench = pb.bench(page, data, browser.version)
    bench_out.write_text(json.dumps(bench, indent=1) + "\n", encoding="utf-8")
    lines.append(f"{pb.bench_line(bench)} -> {bench_out}")
    page.close()
    return [f"{rel}: {x}" for x in problems], [f"{rel}: {x}" for x in lines]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("html", type=Path, nargs="?", default=BOOK / "_build" / "html",
                        help="the built book (default: book/_build/html)")
    parser.add_argument("--screenshot-dir", type=Path, default=None,
                        help="where to save page screenshots (default: <html>/../screenshots)")
    args = parser.parse_args(argv)

    root = args.html.resolve()
    if not (root / "index.html").is_file():
        print(f"browser_check: {root}/index.html not found: build the book first (make book)", file=sys.stderr)
        return 2
    if find_chromium() is None:
        print(f"browser_check: chromium not found; {INSTALL_HINT}", file=sys.stderr)
        return 2
    shot_dir = (args.screenshot_dir or root.parent / "screenshots").resolve()
    shot_dir.mkdir(parents=True, exist_ok=True)
    pages = pages_of(root)
    if not pages:
        print(f"browser_check: no pages under {root}", file=sys.stderr)
        return 2

    start = time.perf_counter()
    failures: dict[str, list[str]] = {}
    try:
        with chromium() as browser, serve(root) as base:
            desk = browser.new_page(viewport={"width": VIEWPORT[0], "height": VIEWPORT[1]}, device_scale_factor=1)
            phone_context = browser.new_context(viewport={"width": PHONE[0], "height": PHONE[1]},
                                                device_scale_factor=1, is_mobile=True, has_touch=True)
            phone = phone_context.new_page()
            desk_log, phone_log = PageLog(desk), PageLog(phone)
            for page in pages:
                rel = page.relative_to(root).as_posix()
                problems, report = check_page(desk, desk_log, phone, phone_log, base, root, page, shot_dir)
                status = "ok" if not problems else "FAIL"
                print(f"browser_check: {status:4} {rel}: {report.get('math', '?')} math "
                      f"({report.get('typeset', '?')} typeset), {report.get('nimages', '?')} images", flush=True)
                if problems:
                    failures[rel] = problems
            problems, lines = check_player(browser, base, root, pages, root.parent / "player-bench.json")
            for line in lines:
                print(f"browser_check: player: {line}", flush=True)
            print(f"browser_check: {'ok' if not problems else 'FAIL':4} the colour-table player", flush=True)
            if problems:
                failures["player"] = problems
    except BrowserError as exc:
        print(f"browser_check: {exc}", file=sys.stderr)
        return 2
    elapsed = time.perf_counter() - start

    if failures:
        print(f"browser_check: FAILED on {len(failures)} of {len(pages)} pages:", file=sys.stderr)
        for rel, problems in failures.items():
            for p in problems:
                print(f"  {rel}: {p}", file=sys.stderr)
        return 1
    print(f"browser_check: all {len(pages)} pages passed in {elapsed:.1f} s; screenshots in {shot_dir}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
