#!/usr/bin/env python3
"""Write the whole sunset book as one PDF, offline, through headless Chromium.

Usage::

    python book/pdf.py [--execute {cache,force,off}] [--out PATH] [--no-build]

Two steps, nothing but the book's own environment and the ``chromium``
binary (the one ``make book-check`` uses):

1. ``book/build.py --builder singlehtml`` builds the book as one HTML page
   into ``book/_build/singlehtml`` (strict, like ``make book``; the chapters
   come from the same execution cache, so after ``make book`` nothing is run
   again).
2. Chromium opens that page from a local server, waits until every image has
   loaded and MathJax has typeset every formula, opens the exercises'
   solutions (hidden in the HTML book, printed in the PDF), and prints the
   page with ``Page.printToPDF`` (A4, page numbers in the footer).

The PDF goes to ``book/_build/pdf/sunset-book.pdf`` unless ``--out`` says
otherwise. The script checks what it wrote (a PDF with at least one page per
chapter, every chapter's title in the printed page, every image loaded and
every formula typeset) and exits 1 if the build
or a check fails, 2 if the browser cannot be run.
"""

from __future__ import annotations

import argparse
import base64
import re
import sys
import tempfile
import time
from pathlib import Path

BOOK = Path(__file__).resolve().parent
sys.path.insert(0, str(BOOK))

import build  # noqa: E402  (book/build.py)
from browser_check import PAGE_TIMEOUT, BrowserError, DevTools, find_chromium, serve  # noqa: E402

DEFAULT_OUT = BOOK / "_build" / "pdf" / "sunset-book.pdf"

#: Runs in the page before printing: wait for images and MathJax, open every
#: solution and hidden cell toggle that holds an exercise's solution, and
#: report the chapter titles and what might not be ready.
PREPARE = r"""
(async () => {
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  const imgs = Array.from(document.images);
  const t0 = Date.now();
  while (imgs.some((i) => !i.complete) && Date.now() - t0 < 30000) await sleep(50);
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
    if (MathJax.typesetPromise) await MathJax.typesetPromise();
  }
  // Solutions are dropdowns (sphinx-togglebutton) in the HTML book; print them open.
  document.querySelectorAll(".solution.dropdown, .solution").forEach((el) => {
    el.classList.remove("toggle-hidden");
    el.querySelectorAll(".toggle-hidden").forEach((c) => c.classList.remove("toggle-hidden"));
  });
  document.querySelectorAll("details.solution, .solution details").forEach((d) => { d.open = true; });
  // In the one-page book every chapter is a section of the root page: start each on a new page.
  const style = document.createElement("style");
  style.textContent = "@media print { article.bd-article > section > section:has(> h2 > .section-number), "
      + "section#symbols, section#bibliography { break-before: page; } }";
  document.head.appendChild(style);
  await sleep(200);
  const maths = document.querySelectorAll(".math").length;
  const typeset = Array.from(document.querySelectorAll(".math"))
      .filter((m) => m.querySelector("mjx-container")).length;
  return {
    images: imgs.length,
    broken: imgs.filter((i) => !(i.complete && i.naturalWidth > 0)).map((i) => i.getAttribute("src")),
    math: maths, typeset: typeset,
    merror: document.querySelectorAll("mjx-merror").length,
    titles: Array.from(document.querySelectorAll("article h1, article h2"))
        .map((h) => h.textContent.replace(/#$/, "").trim()),
    text: document.body.innerText.length,
  };
})()
"""

PRINT_OPTIONS = {
    "landscape": False,
    "printBackground": True,
    "preferCSSPageSize": False,
    "paperWidth": 8.27,   # A4, inches
    "paperHeight": 11.69,
    "marginTop": 0.6,
    "marginBottom": 0.7,
    "marginLeft": 0.6,
    "marginRight": 0.6,
    "scale": 0.9,
    "displayHeaderFooter": True,
    "headerTemplate": "<span></span>",
    "footerTemplate": ('<div style="font-size:8px;width:100%;text-align:center;color:#555">'
                       'Waves and Islands in the Sunset &mdash; '
                       '<span class="pageNumber"></span> / <span class="totalPages"></span></div>'),
    "transferMode": "ReturnAsStream",
}


def read_stream(dt: DevTools, handle: str, session: str) -> bytes:
    """The whole of a DevTools IO stream of the page's session."""
    out = bytearray()
    while True:
        chunk = dt.call("IO.read", {"handle": handle, "size": 1 << 20}, session, timeout=PAGE_TIMEOUT)
        data = chunk.get("data", "")
        out += base64.b64decode(data) if chunk.get("base64Encoded") else data.encode("latin-1")
        if chunk.get("eof"):
            break
    dt.call("IO.close", {"handle": handle}, session)
    return bytes(out)


def page_count(pdf: bytes) -> int:
    """Pages of a PDF, counted from its page objects."""
    return len(re.findall(rb"/Type\s*/Page(?![s\w])", pdf))


def print_page(html: Path, out: Path) -> tuple[int, dict]:
    """Print the one-page book in ``html`` to ``out``; return (pages, what the page reported)."""
    exe = find_chromium()
    if exe is None:
        raise BrowserError("chromium not found; install it with `apt-get install -y chromium` "
                           "(or set CHROMIUM=/path)")
    with tempfile.TemporaryDirectory(prefix="sunset-pdf-") as tmp:
        tmp = Path(tmp)
        dt = DevTools(exe, tmp / "profile", tmp / "chromium.log")
        server, base = serve(html)
        try:
            target = dt.call("Target.createTarget", {"url": "about:blank"})["targetId"]
            session = dt.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
            dt.call("Page.enable", {}, session)
            dt.call("Runtime.enable", {}, session)
            dt.call("Emulation.setEmulatedMedia", {"media": "print"}, session)
            dt.events()
            dt.call("Page.navigate", {"url": base + f"{root_document()}.html"}, session)
            dt.wait_event("Page.loadEventFired", session, 4 * PAGE_TIMEOUT)
            result = dt.call("Runtime.evaluate", {"expression": PREPARE, "awaitPromise": True,
                                                  "returnByValue": True}, session,
                             timeout=4 * PAGE_TIMEOUT)
            if "exceptionDetails" in result:
                raise BrowserError(f"page script failed: {result['exceptionDetails'].get('text')}")
            report = result["result"]["value"]
            printed = dt.call("Page.printToPDF", PRINT_OPTIONS, session, timeout=8 * PAGE_TIMEOUT)
            pdf = read_stream(dt, printed["stream"], session)
        finally:
            dt.close()
            server.shutdown()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(pdf)
    return page_count(pdf), report


def root_document() -> str:
    """The book's root page (the one-page build writes the whole book into it)."""
    found = re.search(r"^root:\s*(\S+)", (BOOK / "_toc.yml").read_text(encoding="utf-8"), re.M)
    return found.group(1) if found else "index"


def chapters() -> list[str]:
    """The files of the book's table of contents, in order."""
    return re.findall(r"^\s*-\s*file:\s*(\S+)", (BOOK / "_toc.yml").read_text(encoding="utf-8"), re.M)


def title_of(name: str) -> str:
    """The first level-one heading of a page's source."""
    text = (BOOK / f"{name}.md").read_text(encoding="utf-8")
    found = re.search(r"^# (.+)$", text, re.M)
    return found.group(1).strip() if found else name


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--execute", choices=build.MODES, default="cache",
                        help="notebook execution mode of the single-page build (default: cache)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"the PDF (default: {DEFAULT_OUT})")
    parser.add_argument("--no-build", action="store_true",
                        help="print book/_build/singlehtml as it is, without building it")
    args = parser.parse_args(argv)

    start = time.perf_counter()
    if not args.no_build:
        rc = build.main(["--builder", "singlehtml", "--execute", args.execute])
        if rc != 0:
            return rc
    html = BOOK / "_build" / "singlehtml"
    if not (html / f"{root_document()}.html").is_file():
        print(f"pdf.py: {html}/{root_document()}.html not found: build it first", file=sys.stderr)
        return 1
    try:
        pages, report = print_page(html, args.out.resolve())
    except BrowserError as exc:
        print(f"pdf.py: {exc}", file=sys.stderr)
        return 2

    problems = []
    if not args.out.read_bytes().startswith(b"%PDF-"):
        problems.append("the output is not a PDF")
    n_docs = len(chapters()) + 1  # the chapters and the intro
    if pages < n_docs:
        problems.append(f"only {pages} pages for {n_docs} documents")
    if report["broken"]:
        problems.append(f"images that did not load: {report['broken'][:3]}")
    if report["typeset"] < report["math"] or report["merror"]:
        problems.append(f"{report['math'] - report['typeset']} of {report['math']} formulas not typeset, "
                        f"{report['merror']} MathJax errors")
    printed = " | ".join(report["titles"]).replace("\u2019", "'")  # Sphinx's smart quotes
    missing = [title_of(c) for c in [root_document(), *chapters()] if title_of(c) not in printed]
    if missing:
        problems.append(f"chapters missing from the printed page: {missing}")
    size = args.out.stat().st_size
    print(f"pdf.py: {args.out} ({pages} pages, {size / 1e6:.1f} MB, {report['images']} images, "
          f"{report['math']} formulas) in {time.perf_counter() - start:.1f} s", flush=True)
    for p in problems:
        print(f"pdf.py: FAIL: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
