#!/usr/bin/env python3
"""Write the whole sunset book as one PDF, offline, through headless Chromium, and check it.

Usage::

    python book/pdf.py [--execute {cache,force,off}] [--out PATH] [--no-build]

1. ``book/build.py --builder singlehtml`` builds the book as one HTML page
   into ``book/_build/singlehtml`` (strict, like ``make book``; the chapters
   come from the same execution cache, so after ``make book`` nothing is run
   again). Its figures, tables, exercises and equations carry the numbers of
   the HTML book (Sphinx numbers both from the same table of contents).
2. Chromium (``book/chromium.py``: Playwright on Debian's ``chromium``) opens
   that page from a local server, waits until every image has loaded and
   MathJax has typeset every formula, and lays it out for print with
   ``book/pdf.css``: a title page; a contents page of the parts, chapters and
   sections, each linked to its heading; a page with each part's title; each
   chapter on a new page under a running header with its title (a CSS named
   page per chapter); page numbers at the foot; no figure, formula or caption
   broken across pages. The exercises' solutions, hidden in the HTML book,
   are printed open.
3. It prints twice. The first print says on which page each heading of the
   contents landed (Chromium writes a named destination for every link
   target); those numbers are written into the contents, which keep their
   layout (the numbers sit in a column of fixed width), and the book is
   printed again, tagged (a structure tree for screen readers). If a heading
   moved between the two prints, it prints once more, up to :data:`MAX_PRINTS`
   times. pypdf then adds the bookmark outline (the book's title with the
   contents and the introduction, then the parts, chapters and sections, each at
   its heading) as an incremental update. (Chromium's own document outline is
   not used: it doubles the title of a heading that a page break moved.)

The PDF goes to ``book/_build/pdf/sunset-book.pdf`` unless ``--out`` says
otherwise. Then ``book/pdf_check.py`` checks it (the outline, the contents'
page numbers, the running headers, the numbering against the HTML book, and
that no figure or formula is cut by a page break); the script exits 1 if the
build, the print or a check fails, 2 if the browser cannot be run.
"""

from __future__ import annotations

import argparse
import io
import sys
import time
from pathlib import Path

BOOK = Path(__file__).resolve().parent
sys.path.insert(0, str(BOOK))

import build  # noqa: E402  (book/build.py)
import pdf_check  # noqa: E402  (book/pdf_check.py)
from chromium import PAGE_TIMEOUT, BrowserError, chromium, serve  # noqa: E402

DEFAULT_OUT = BOOK / "_build" / "pdf" / "sunset-book.pdf"
PRINT_CSS = BOOK / "pdf.css"
#: Prints at most, until no heading moves between two prints.
MAX_PRINTS = 4
#: Chromium's print scale (the text's 16 px at 0.9 is about 10.8 pt on A4).
SCALE = 0.9

#: Runs in the page before the first print (argument: the parts of the table of contents):
#: wait for images and MathJax, open the solutions, mark the title page, the chapters and
#: their running headers, insert the parts' titles and the contents; report what it did.
PREPARE = r"""
async ({parts, book}) => {
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

  // A heading's text (a formula in it as its MathML's text); its content without the link mark.
  const bare = (h) => {
    const c = h.cloneNode(true);
    c.querySelectorAll(".headerlink").forEach((e) => e.remove());
    return c;
  };
  const text = (h) => bare(h).textContent.replace(/\s+/g, " ").trim();
  // Every heading gets its text as its accessible name (the outline's titles).
  document.querySelectorAll("article h1, article h2, article h3, article h4, article h5, article h6")
      .forEach((h) => h.setAttribute("aria-label", text(h)));
  const quote = (s) => '"' + s.replace(/\\/g, "\\\\").replace(/"/g, '\\"') + '"';
  const article = document.querySelector("article.bd-article");
  const root = article.querySelector("section");          // the root page: the book's title and introduction
  const rules = [];
  const header = (name, title) => rules.push(
      `@page ${name} { @top-left { content: ${quote(title)}; font: italic 9pt/1 sans-serif; color: #555; } }`);

  // The title page: the root page's heading and what comes before its first section.
  const title = document.createElement("div");
  title.className = "sunset-title-page";
  const first = root.querySelector(":scope > section");
  while (root.firstChild && root.firstChild !== first) title.appendChild(root.firstChild);
  root.prepend(title);

  // The introduction's sections, the chapters (with their sections), the parts.
  const entries = [];
  const intro = Array.from(root.querySelectorAll(":scope > section"));
  intro.forEach((s) => { s.style.page = "intro"; });
  header("intro", book);
  // Every heading of the contents gets an id of its own (the same section title, such as
  // "Exercises", has the same id in every chapter of the one-page book).
  const entry = (h, id, level, kind) => {
    h.id = id;
    entries.push({id, title: text(h), level, kind});
  };
  for (const s of intro) {
    const h = s.querySelector(":scope > h2");
    if (h) entry(h, `${s.id}-h`, 1, "section");
  }
  const chapters = [];
  parts.forEach((part, p) => {
    part.files.forEach((file, k) => {
      const mark = document.getElementById(`document-${file}`);
      const sec = mark && mark.nextElementSibling;
      if (!sec || sec.tagName !== "SECTION") { chapters.push({file, missing: true}); return; }
      if (k === 0) {
        const h = document.createElement("h1");
        h.className = "sunset-part";
        h.id = `sunset-part-${p + 1}`;
        h.textContent = part.caption;
        h.style.page = "part";
        h.setAttribute("aria-label", part.caption);
        mark.before(h);
        entries.push({id: h.id, title: part.caption, level: 0, kind: "part"});
      }
      sec.prepend(mark);                   // the target of links to the chapter, inside its pages
      const h2 = sec.querySelector(":scope > h2");
      const name = `chapter-${chapters.length + 1}`;
      sec.classList.add("sunset-chapter");
      sec.style.page = name;
      header(name, text(h2));
      chapters.push({file, id: `${file}-h`, title: text(h2)});
      entry(h2, `${file}-h`, 1, "chapter");
      for (const s of sec.querySelectorAll(":scope > section")) {
        const h3 = s.querySelector(":scope > h3");
        if (h3) entry(h3, `${file}--${s.id}-h`, 2, "section");
      }
    });
  });
  rules.push("@page part { @top-left { content: none; } }");

  // The contents: one linked line an entry, its page number filled in after the first print.
  const nav = document.createElement("nav");
  nav.className = "sunset-contents";
  nav.innerHTML = "<h2 id='sunset-contents' aria-label='Contents'>Contents</h2><ol></ol>";
  const ol = nav.querySelector("ol");
  for (const e of entries) {
    const li = document.createElement("li");
    li.className = `sunset-level-${e.level}`;
    const a = document.createElement("a");
    a.href = "#" + e.id;
    a.innerHTML = "<span class='sunset-entry'></span><span class='sunset-leader'></span>"
        + "<span class='sunset-page'></span>";
    const h = document.getElementById(e.id);
    a.querySelector(".sunset-entry").append(...bare(h).childNodes);
    a.querySelector(".sunset-page").dataset.for = e.id;
    li.appendChild(a);
    ol.appendChild(li);
  }
  title.after(nav);

  // A mark at the start and one at the end of every figure and display formula, and hidden links
  // to them and to the contents (so that Chromium writes a named destination for each):
  // book/pdf_check.py finds a figure cut by a page break when its two marks are on two pages.
  const hidden = document.createElement("nav");
  hidden.className = "sunset-marks";
  hidden.style.display = "none";
  const link = (id) => { const a = document.createElement("a"); a.href = "#" + id; hidden.appendChild(a); };
  link("sunset-contents");
  let kept = 0;
  const unseen = [];
  article.querySelectorAll("figure, div.math").forEach((el) => {
    // In a box of its own, between its marks (a formula is a flex row: marks inside it would sit beside
    // it). Not the figures of a page's hidden parts (the player's panel of passes): they are not printed.
    if (!el.getClientRects().length) { unseen.push(el.outerHTML.slice(0, 60)); return; }
    kept += 1;
    const keep = document.createElement("div");
    const start = document.createElement("div");
    const end = document.createElement("div");
    keep.className = "sunset-keep";
    start.className = end.className = "sunset-mark";
    start.id = `sunset-keep-${kept}`;
    end.id = `${start.id}-end`;
    el.before(keep);
    keep.append(start, el, end);
    link(start.id);
    link(end.id);
  });
  document.body.appendChild(hidden);

  const style = document.createElement("style");
  style.textContent = rules.join("\n");
  document.head.appendChild(style);
  await sleep(200);
  const maths = document.querySelectorAll(".math").length;
  const typeset = Array.from(document.querySelectorAll(".math"))
      .filter((m) => m.querySelector("mjx-container")).length;
  return {
    entries, chapters, kept, unseen,
    images: imgs.length,
    broken: imgs.filter((i) => !(i.complete && i.naturalWidth > 0)).map((i) => i.getAttribute("src")),
    math: maths, typeset: typeset,
    merror: document.querySelectorAll("mjx-merror").length,
  };
}
"""

#: Writes the page numbers (argument: {id: page}) into the contents.
FILL = r"""
(pages) => {
  let n = 0;
  for (const span of document.querySelectorAll("nav.sunset-contents .sunset-page")) {
    const p = pages[span.dataset.for];
    span.textContent = p === undefined ? "" : String(p);
    n += p === undefined ? 0 : 1;
  }
  return n;
}
"""


def toc_parts() -> tuple[str, list[dict]]:
    """The root page and the parts of ``book/_toc.yml``: ``[{"caption": ..., "files": [...]}, ...]``."""
    import yaml

    toc = yaml.safe_load((BOOK / "_toc.yml").read_text(encoding="utf-8"))
    parts = [{"caption": p["caption"], "files": [c["file"] for c in p["chapters"]]} for p in toc["parts"]]
    return toc["root"], parts


def book_title() -> str:
    import yaml

    return yaml.safe_load((BOOK / "_config.yml").read_text(encoding="utf-8"))["title"]


def book_author() -> str:
    import yaml

    return yaml.safe_load((BOOK / "_config.yml").read_text(encoding="utf-8"))["author"]


def print_book(html: Path) -> tuple[bytes, int, dict]:
    """Print the one-page book in ``html``: (the PDF, prints made, what the page reported with the pages)."""
    root, parts = toc_parts()
    with chromium() as browser, serve(html) as base:
        page = browser.new_page(viewport={"width": 1100, "height": 1400})
        page.set_default_timeout(8 * PAGE_TIMEOUT * 1000)
        page.emulate_media(media="print")
        page.goto(base + f"{root}.html", wait_until="load")
        page.add_style_tag(path=str(PRINT_CSS))
        report = page.evaluate(PREPARE, {"parts": parts, "book": book_title()})
        ids = [e["id"] for e in report["entries"]]
        pages: dict[str, int] = {}
        report["print_s"] = []
        for prints in range(1, MAX_PRINTS + 1):
            page.evaluate(FILL, pages)
            t0 = time.perf_counter()
            pdf = page.pdf(prefer_css_page_size=True, print_background=True, scale=SCALE, tagged=True)
            report["print_s"].append(time.perf_counter() - t0)
            found = pdf_check.destination_pages(pdf_check.reader(io.BytesIO(pdf)), ids)
            if found == pages:
                break
            pages = found
        else:
            raise BrowserError(f"the headings still moved after {MAX_PRINTS} prints")
    report["pages"] = pages
    return pdf, prints, report


def finish(pdf: bytes, report: dict, out: Path) -> int:
    """Write ``pdf`` to ``out`` with its outline (the book's title, the contents and the introduction, then
    the parts, chapters and sections, each at its heading) and its title; the number of bookmarks."""
    from pypdf import PdfWriter
    from pypdf.generic import Fit

    dests = pdf_check.destinations(pdf_check.reader(io.BytesIO(pdf)))
    writer = PdfWriter(io.BytesIO(pdf), incremental=True)

    def mark(title: str, target: str | None, parent=None):
        page, top = dests.get(target, (1, float(writer.pages[0].mediabox.height)))
        return writer.add_outline_item(title=title, page_number=page - 1, parent=parent, fit=Fit.xyz(0, top))

    book = mark(book_title(), None)
    mark("Contents", "sunset-contents", book)
    part = chapter = book
    made = 2
    for e in report["entries"]:
        if e["kind"] == "part":
            part = chapter = mark(e["title"], e["id"])
        elif e["kind"] == "chapter":
            chapter = mark(e["title"], e["id"], part)
        else:
            mark(e["title"], e["id"], chapter)
        made += 1
    writer.page_mode = "/UseOutlines"
    writer.add_metadata({"/Title": book_title(), "/Author": book_author()})
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "wb") as f:
        writer.write(f)
    return made


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
    root, _ = toc_parts()
    if not (html / f"{root}.html").is_file():
        print(f"pdf.py: {html}/{root}.html not found: build it first", file=sys.stderr)
        return 1
    out = args.out.resolve()
    try:
        pdf, prints, report = print_book(html)
    except BrowserError as exc:
        print(f"pdf.py: {exc}", file=sys.stderr)
        return 2
    bookmarks = finish(pdf, report, out)
    printed = time.perf_counter() - start

    problems = []
    if report["broken"]:
        problems.append(f"images that did not load: {report['broken'][:3]}")
    if report["typeset"] < report["math"] or report["merror"]:
        problems.append(f"{report['math'] - report['typeset']} of {report['math']} formulas not typeset, "
                        f"{report['merror']} MathJax errors")
    missing = [c["file"] for c in report["chapters"] if c.get("missing")]
    if missing:
        problems.append(f"chapters missing from the one-page book: {missing}")
    result = pdf_check.check(out, BOOK / "_build" / "html", html / f"{root}.html")
    problems += result.problems
    print(f"pdf.py: {out} ({result.pages} pages, {out.stat().st_size / 1e6:.1f} MB, {report['images']} images, "
          f"{report['math']} formulas, {len(report['entries'])} headings in the contents, {bookmarks} bookmarks; "
          f"{prints} prints: {', '.join(f'{t:.0f}' for t in report['print_s'])} s) in {printed:.1f} s, "
          f"checked in {time.perf_counter() - start - printed:.1f} s", flush=True)
    for line in result.lines:
        print(f"pdf.py: {line}", flush=True)
    for p in problems:
        print(f"pdf.py: FAIL: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
