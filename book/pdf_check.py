#!/usr/bin/env python3
"""Check the book's PDF against the one-page HTML book it was printed from, and the HTML book.

Usage::

    python book/pdf_check.py [PDF] [--html book/_build/html] [--single book/_build/singlehtml]

``book/pdf.py`` (``make pdf``) runs these checks on the PDF it writes; this
script runs them again on any PDF it wrote. What the book should contain is
read from the HTML that Sphinx wrote (the parts from ``book/_toc.yml``, the
chapters' and sections' headings, the figures and formulas, the numbers of
the captions); where each thing landed is read from the PDF alone, with
pypdf: its named destinations (Chromium writes one for every target of a
link: book/pdf.py links the contents to every heading, and a hidden list to a
mark at the start and at the end of every figure and display formula), its
outline, its images' placement and its text with positions.

It checks that

* the **outline** (bookmarks) holds the book's title with the contents and
  the introduction's sections, then each part with its chapters and their
  sections, in the book's order, each pointing at the page of its heading;
* every heading of the contents is really on the page its destination names
  (its words are in that page's text), and the **contents' page numbers**,
  read off the contents pages (the numbers in their right-hand column, top to
  bottom), are those pages;
* every page but the title page carries its **number** at its foot, and
  every page of a chapter its chapter's title as its **running header**
  (the introduction's pages the book's title, a part's title page none);
* **figures and formulas are numbered as in the HTML book**: the captions'
  numbers (Figure 4.2, Table 3.1, Exercise 1.2) and the equations' numbers
  of the one-page book are those of the HTML pages in the order of the
  table of contents, and each caption's number is in the PDF's text;
* **no figure or display formula is cut by a page break**: the mark at its
  start and the mark at its end are on the same page, for as many figures
  and formulas as the one-page book holds; and no image is drawn past the
  page's text area (Chromium never slices an image across pages: one taller
  than the page would be cut off at its foot).

Exit status 1 if a check fails, 2 if a file is missing.
"""

from __future__ import annotations

import argparse
import html as htmlmod
import re
import sys
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path

BOOK = Path(__file__).resolve().parent
#: The part of a page above its text area and below it, in points (book/pdf.css: 18 mm margins).
MARGIN_PT = 18 / 25.4 * 72
#: Page numbers of the contents stand in the right-hand column: right of this fraction of the width.
NUMBER_COLUMN = 0.8
#: Marks of book/pdf.py: start and end of the n-th figure or display formula.
KEEP = re.compile(r"^sunset-keep-(\d+)(-end)?$")


# --------------------------------------------------------------------------- what the book holds
@dataclass
class Entry:
    """A heading of the contents: its id in the printed page, level, kind and words (between formulas)."""

    id: str
    level: int
    kind: str
    words: tuple[str, ...]

    @property
    def title(self) -> str:
        return " … ".join(self.words)


def norm(text: str) -> str:
    """Text compared without ligatures, quotes' shapes or white space."""
    text = unicodedata.normalize("NFKC", text).replace("\u2019", "'").replace("\u2018", "'")
    return re.sub(r"\s+", "", text)


def heading_words(inner: str) -> tuple[str, ...]:
    """The words of a heading's HTML, split where a formula stands, without its link mark."""
    inner = re.sub(r'<a class="headerlink".*?</a>', "", inner, flags=re.S)
    pieces = re.split(r'<span class="math[^"]*">.*?</span>', inner, flags=re.S)
    words = [" ".join(htmlmod.unescape(re.sub(r"<[^>]+>", "", p)).split()) for p in pieces]
    return tuple(w.strip(" ,") for w in words if w.strip(" ,"))


def toc() -> tuple[str, list[dict]]:
    """The root page and the parts of book/_toc.yml."""
    import yaml

    data = yaml.safe_load((BOOK / "_toc.yml").read_text(encoding="utf-8"))
    return data["root"], [{"caption": p["caption"], "files": [c["file"] for c in p["chapters"]]}
                          for p in data["parts"]]


def expected_entries(single: str) -> list[Entry]:
    """The contents that book/pdf.py should print, from the one-page book's HTML: the introduction's
    sections, then each part, its chapters and their sections (the ids are book/pdf.py's)."""
    _, parts = toc()
    heading = r'<section[^>]*\bid="([^"]+)"[^>]*>\s*(?:<span id="[^"]*"></span>\s*)*<h{n}>(.*?)</h{n}>'
    marks = [(m.start(), m.group(1)) for m in re.finditer(r'<span id="document-([^"]+)"></span>', single)]
    starts = {f: i for i, f in marks}
    ends = {f: (marks[k + 1][0] if k + 1 < len(marks) else len(single)) for k, (_, f) in enumerate(marks)}
    article = single[single.find('<article class="bd-article">'):]
    first = article.find('<span id="document-')
    out = [Entry(f"{m.group(1)}-h", 1, "section", heading_words(m.group(2)))
           for m in re.finditer(heading.format(n=2), article[:first], flags=re.S)]
    for p, part in enumerate(parts, 1):
        out.append(Entry(f"sunset-part-{p}", 0, "part", (part["caption"],)))
        for file in part["files"]:
            if file not in starts:
                out.append(Entry(f"{file}-h", 1, "chapter", (f"(missing: {file})",)))
                continue
            body = single[starts[file]:ends[file]]
            h2 = re.search(heading.format(n=2), body, flags=re.S)
            out.append(Entry(f"{file}-h", 1, "chapter", heading_words(h2.group(2)) if h2 else (file,)))
            for m in re.finditer(heading.format(n=3), body, flags=re.S):
                out.append(Entry(f"{file}--{m.group(1)}-h", 2, "section", heading_words(m.group(2))))
    return out


def numbers(page: str) -> list[str]:
    """The numbers of the captions (Figure 4.2, Table 3.1, Exercise 1.2 ...) and equations of an HTML page."""
    caps = re.findall(r'<span class="caption-number">([^<]+)</span>', page)
    eqs = re.findall(r'<span class="eqno">\(([^)<]+)\)', page)
    return [" ".join(c.split()) for c in caps] + [f"({e})" for e in eqs]


def blocks(single: str) -> tuple[int, int]:
    """Figures (Sphinx's, with their class) and display formulas in the one-page book's article."""
    article = single[single.find('<article class="bd-article">'):]
    return len(re.findall(r"<figure class=", article)), len(re.findall(r'<div class="math\b', article))


# --------------------------------------------------------------------------- what the PDF holds
class Printed:
    """The PDF as pypdf reads it: named destinations, outline, and per page its text runs and images."""

    def __init__(self, path: Path):
        from pypdf import PdfReader

        self.reader = PdfReader(path)
        self.pages = len(self.reader.pages)
        self.box = [(float(p.mediabox.width), float(p.mediabox.height)) for p in self.reader.pages]
        self.dests = destinations(self.reader)
        self.runs: list[list[tuple[float, float, str]]] = []
        self.images: list[list[tuple[float, float, float, float]]] = []
        for (w, h), page in zip(self.box, self.reader.pages):
            runs, images = read_page(page)
            # (text drawn off the page is not seen: the print of an element moved off screen)
            self.runs.append([r for r in runs if 0 <= r[0] <= w and 0 <= r[1] <= h])
            self.images.append(images)
        self.outline = flat_outline(self.reader)

    def text(self, page: int, top: float | None = None, bottom: float | None = None) -> str:
        """The text of page ``page`` (from 1), optionally only between heights ``bottom`` and ``top``."""
        runs = sorted(self.runs[page - 1], key=lambda r: (-round(r[1]), r[0]))
        return " ".join(t for x, y, t in runs if (top is None or y <= top) and (bottom is None or y >= bottom))


def reader(stream):
    from pypdf import PdfReader

    return PdfReader(stream)


def destinations(rd) -> dict[str, tuple[int, float]]:
    """Every named destination of a PDF: its page (from 1) and height on it."""
    out = {}
    for name, dest in rd.named_destinations.items():
        try:
            out[str(name).lstrip("/")] = (rd.get_destination_page_number(dest) + 1, float(dest.top or 0.0))
        except (KeyError, ValueError, TypeError):
            continue
    return out


def destination_pages(rd, ids) -> dict[str, int]:
    """The page (from 1) of each of ``ids`` that is a named destination of the PDF."""
    dests = destinations(rd)
    return {i: dests[i][0] for i in ids if i in dests}


def _mul(a, b):
    return [a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3], a[2] * b[0] + a[3] * b[2],
            a[2] * b[1] + a[3] * b[3], a[4] * b[0] + a[5] * b[2] + b[4], a[4] * b[1] + a[5] * b[3] + b[5]]


def _xobjects(resources) -> dict:
    """Every XObject of a resource dictionary and of the forms in it, by name."""
    out = {}
    todo = [resources]
    while todo:
        res = todo.pop()
        xo = (res.get_object() or {}).get("/XObject") if res is not None else None
        for name, ref in (xo.get_object().items() if xo is not None else []):
            obj = ref.get_object()
            if name not in out:
                out[name] = obj
                if obj.get("/Subtype") == "/Form" and "/Resources" in obj:
                    todo.append(obj["/Resources"])
    return out


def read_page(page) -> tuple[list, list]:
    """The text runs (x, y, text) of a page and the boxes (x0, y0, x1, y1) where it draws images."""
    runs: list[tuple[float, float, str]] = []
    images: list[tuple[float, float, float, float]] = []
    xobjects = _xobjects(page.get("/Resources"))

    def text(t, cm, tm, font, size):
        if t.strip():
            m = _mul(tm, cm)
            runs.append((m[4], m[5], t))

    def operand(op, args, cm, tm):
        if op == b"Do" and args:
            obj = xobjects.get(args[0])
            if obj is not None and obj.get("/Subtype") == "/Image":
                xs = [cm[4], cm[4] + cm[0], cm[4] + cm[2], cm[4] + cm[0] + cm[2]]
                ys = [cm[5], cm[5] + cm[1], cm[5] + cm[3], cm[5] + cm[1] + cm[3]]
                images.append((min(xs), min(ys), max(xs), max(ys)))

    page.extract_text(visitor_text=text, visitor_operand_before=operand)
    return runs, images


def flat_outline(rd) -> list[tuple[int, str, int]]:
    """The outline as (depth, title, page from 1), in order."""
    out: list[tuple[int, str, int]] = []

    def walk(items, depth):
        for item in items:
            if isinstance(item, list):
                walk(item, depth + 1)
            else:
                out.append((depth, str(item.title), rd.get_destination_page_number(item) + 1))

    walk(rd.outline, 0)
    return out


# --------------------------------------------------------------------------- the checks
@dataclass
class Result:
    pages: int = 0
    outline: int = 0
    problems: list[str] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)


def has_words(text: str, words) -> bool:
    """Whether ``text`` holds every one of ``words``, in order."""
    t, k = norm(text), 0
    for w in words:
        k = t.find(norm(w), k)
        if k < 0:
            return False
        k += len(norm(w))
    return True


def check_contents(pdf: Printed, entries: list[Entry], result: Result) -> dict[str, int]:
    """Each heading on the page of its destination; the contents' numbers those pages. Returns the pages."""
    pages = {}
    for e in entries:
        if e.id not in pdf.dests:
            result.problems.append(f"no destination for the heading {e.title!r} ({e.id})")
            continue
        p = pdf.dests[e.id][0]
        pages[e.id] = p
        if not has_words(pdf.text(p), e.words):
            result.problems.append(f"the heading {e.title!r} is not on page {p}, where its destination points")
    if len(pages) < len(entries):
        return pages
    contents = pdf.dests.get("sunset-contents", (2, 0.0))[0]
    last = min(pages.values()) - 1                      # the contents end before the first heading they list
    if last < contents:
        result.problems.append(f"no contents pages before page {last + 1}")
        return pages
    printed = []
    text = ""
    for p in range(contents, last + 1):
        w = pdf.box[p - 1][0]
        runs = sorted(pdf.runs[p - 1], key=lambda r: (-round(r[1]), r[0]))
        printed += [int(t) for x, y, t in runs if x > NUMBER_COLUMN * w and t.strip().isdigit()
                    and MARGIN_PT < y < pdf.box[p - 1][1] - MARGIN_PT]
        text += pdf.text(p) + " "
    want = [pages[e.id] for e in entries]
    if printed != want:
        diff = [(e.title, a, b) for e, a, b in zip(entries, printed, want) if a != b][:3]
        result.problems.append(f"the contents (pages {contents}-{last}) print {len(printed)} page numbers for "
                               f"{len(want)} headings; first differences (title, printed, real): {diff}")
    if not has_words(text, [w for e in entries for w in e.words]):
        result.problems.append("the contents do not list every heading in the book's order")
    result.lines.append(f"contents: pages {contents}-{last}, {len(want)} entries, each number the page of its "
                        f"heading: {printed == want}")
    return pages


def check_outline(pdf: Printed, entries: list[Entry], pages: dict[str, int], title: str, result: Result) -> None:
    """The outline: the book's title (contents and introduction under it), then the parts, chapters, sections."""
    got = pdf.outline
    result.outline = len(got)
    want = [(0, (title,), 1), (1, ("Contents",), pdf.dests.get("sunset-contents", (2, 0.0))[0])]
    want += [(e.level, e.words, pages.get(e.id)) for e in entries]
    if len(got) != len(want):
        result.problems.append(f"the outline has {len(got)} bookmarks, the book {len(want)} headings for it")
    bad = [(g, w) for g, w in zip(got, want)
           if g[0] != w[0] or g[2] != w[2] or not has_words(g[1], w[1])]
    for g, w in bad[:5]:
        result.problems.append(f"bookmark {g} is not {w[1]!r} at depth {w[0]} on page {w[2]}")
    parts = sum(1 for e in entries if e.kind == "part")
    chapters = sum(1 for e in entries if e.kind == "chapter")
    result.lines.append(f"outline: {len(got)} bookmarks ({parts} parts, {chapters} chapters, "
                        f"{len(got) - parts - chapters - 2} sections), each at its heading's page: {not bad}")


def check_running(pdf: Printed, entries: list[Entry], pages: dict[str, int], title: str, result: Result) -> None:
    """Page numbers at every page's foot but the title page's; the chapter's title at the head of its pages."""
    starts = sorted((pages[e.id], e) for e in entries if e.kind in ("part", "chapter") and e.id in pages)
    intro = min((pages[e.id] for e in entries if e.kind == "section" and e.id in pages), default=pdf.pages + 1)
    bad_numbers, bad_heads = [], []
    for p in range(1, pdf.pages + 1):
        h = pdf.box[p - 1][1]
        foot = pdf.text(p, top=MARGIN_PT).strip()
        head = pdf.text(p, bottom=h - MARGIN_PT).strip()
        if foot != ("" if p == 1 else str(p)):
            bad_numbers.append((p, foot[:20]))
        current = [e for s, e in starts if s <= p]
        if p < intro:
            want = None
        elif not current:
            want = (title,)
        elif current[-1].kind == "part":
            want = None if pages[current[-1].id] == p else (title,)
        else:
            want = current[-1].words
        if (want is None and head) or (want is not None and not has_words(head, want)):
            bad_heads.append((p, head[:40], want))
    if bad_numbers:
        result.problems.append(f"{len(bad_numbers)} pages without their number at the foot, e.g. {bad_numbers[:3]}")
    if bad_heads:
        result.problems.append(f"{len(bad_heads)} pages with a wrong running header, e.g. {bad_heads[:3]}")
    result.lines.append(f"page numbers and running headers on {pdf.pages} pages: "
                        f"{not bad_numbers and not bad_heads}")


def check_numbers(pdf: Printed, html: Path, single: str, result: Result) -> None:
    """Captions and equations numbered as in the HTML book, and each caption's number in the PDF's text."""
    root, parts = toc()
    pages = [root] + [f for p in parts for f in p["files"]]
    missing = [f for f in pages if not (html / f"{f}.html").is_file()]
    if missing:
        result.problems.append(f"the HTML book lacks {missing}: build it (make book) before checking the PDF")
        return
    want = [n for f in pages for n in numbers((html / f"{f}.html").read_text(encoding="utf-8"))]
    got = numbers(single)
    if got != want:
        diff = next(((i, a, b) for i, (a, b) in enumerate(zip(got, want)) if a != b), (min(len(got), len(want)),))
        result.problems.append(f"the one-page book numbers {len(got)} captions and equations, the HTML book "
                               f"{len(want)}; first difference (index, one page, HTML): {diff}")
    text = norm(" ".join(pdf.text(p) for p in range(1, pdf.pages + 1)))
    k, lost = 0, []
    for n in got:
        j = text.find(norm(n), k)
        if j < 0:
            lost.append(n)
        else:
            k = j
    if lost:
        result.problems.append(f"{len(lost)} numbers of captions or equations not in the PDF's text, e.g. {lost[:3]}")
    result.lines.append(f"numbering: {len(got)} captions and equations as in the HTML book: {got == want and not lost}")


def check_breaks(pdf: Printed, single: str, result: Result) -> None:
    """No figure or display formula across a page break; no image past the text area of its page."""
    figures, formulas = blocks(single)
    marks: dict[int, dict[bool, int]] = {}
    for name, (page, _) in pdf.dests.items():
        m = KEEP.match(name)
        if m:
            marks.setdefault(int(m.group(1)), {})[bool(m.group(2))] = page
    pairs = {n: d for n, d in marks.items() if len(d) == 2}
    cut = sorted((n, d[False], d[True]) for n, d in pairs.items() if d[False] != d[True])
    if len(pairs) < figures + formulas:
        result.problems.append(f"marks for {len(pairs)} figures and formulas, the book has {figures} figures "
                               f"and {formulas} display formulas")
    for n, a, b in cut[:5]:
        result.problems.append(f"figure or formula {n} is cut by a page break: it starts on page {a}, ends on {b}")
    outside = []
    for p, boxes in enumerate(pdf.images, 1):
        w, h = pdf.box[p - 1]
        for x0, y0, x1, y1 in boxes:
            if x0 < -1 or x1 > w + 1 or y0 < MARGIN_PT - 1 or y1 > h - MARGIN_PT + 1:
                outside.append((p, round(y0), round(y1)))
    if outside:
        result.problems.append(f"{len(outside)} images drawn past their page's text area (cut), e.g. {outside[:3]}")
    n_images = sum(len(b) for b in pdf.images)
    result.lines.append(f"page breaks: {figures} figures and {formulas} display formulas, {len(cut)} cut; "
                        f"{n_images} images drawn, {len(outside)} past the text area")


def check(pdf_path: Path, html: Path, single_html: Path) -> Result:
    """Every check of this module on the PDF ``pdf_path`` printed from ``single_html``."""
    import yaml

    result = Result()
    single = single_html.read_text(encoding="utf-8")
    title = yaml.safe_load((BOOK / "_config.yml").read_text(encoding="utf-8"))["title"]
    pdf = Printed(pdf_path)
    result.pages = pdf.pages
    entries = expected_entries(single)
    pages = check_contents(pdf, entries, result)
    check_outline(pdf, entries, pages, title, result)
    check_running(pdf, entries, pages, title, result)
    check_numbers(pdf, html, single, result)
    check_breaks(pdf, single, result)
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("pdf", type=Path, nargs="?", default=BOOK / "_build" / "pdf" / "sunset-book.pdf")
    parser.add_argument("--html", type=Path, default=BOOK / "_build" / "html", help="the HTML book")
    parser.add_argument("--single", type=Path, default=BOOK / "_build" / "singlehtml",
                        help="the one-page book the PDF was printed from")
    args = parser.parse_args(argv)
    root, _ = toc()
    single = args.single / f"{root}.html"
    for path in (args.pdf, single, args.html):
        if not path.exists():
            print(f"pdf_check: {path} not found (make pdf)", file=sys.stderr)
            return 2
    result = check(args.pdf, args.html, single)
    for line in result.lines:
        print(f"pdf_check: {line}")
    for p in result.problems:
        print(f"pdf_check: FAIL: {p}", file=sys.stderr)
    print(f"pdf_check: {args.pdf}: {result.pages} pages, {result.outline} bookmarks, "
          f"{'FAILED' if result.problems else 'all checks passed'}")
    return 1 if result.problems else 0


if __name__ == "__main__":
    sys.exit(main())
