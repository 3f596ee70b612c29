"""book/pdf_check.py, the check of the book's PDF (make pdf), on small made-up books and PDFs.

The PDF is stood in for by what the check reads from one (named destinations,
text runs with positions, images' boxes, the outline), so that each check is
seen to pass on a right book and to fail on a book wrong in one way. make pdf
runs the same checks on the real PDF.
"""

import sys
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parents[1] / "book"
sys.path.insert(0, str(BOOK))

import pdf_check  # noqa: E402  (book/pdf_check.py)

A4 = (595.0, 842.0)
PARTS = [{"caption": "The pipeline", "files": ["01-a", "02-b"]}, {"caption": "Reference", "files": ["refs"]}]

#: A one-page book as Sphinx's singlehtml writes it: the root page's title and sections, then each document
#: after its <span id="document-..."> mark (a label's span may stand before a heading; a heading may hold math).
SINGLE = """<html><body><div id="jb-print-docs-body"><h2> Contents </h2></div>
<article class="bd-article">
<section id="book"><h1>The Book<a class="headerlink" href="#book">#</a></h1>
<figure class="intro-picture align-center" id="id1"><img src="x.png"></figure>
<section id="what"><h2>What it is<a class="headerlink" href="#what">#</a></h2><p>text</p></section>
<div class="toctree-wrapper compound">
<span id="document-01-a"></span><section class="tex2jax_ignore" id="the-a">
<h2><span class="section-number">1. </span>The A<a class="headerlink" href="#the-a">#</a></h2>
<section id="exercises"><h3><span class="section-number">1.1. </span>Exercises</h3>
<div class="math notranslate nohighlight">\\[ x \\]</div></section>
</section>
<span id="document-02-b"></span><section class="tex2jax_ignore" id="the-b">
<span id="label-b"></span><h2><span class="section-number">2. </span>The B</h2>
<section id="where"><h3><span class="section-number">2.1. </span>Where to sample:
<span class="math notranslate nohighlight">\\(\\sigma\\)</span> and more</h3>
<figure class="align-default" id="fig-b"><img src="b.png">
<figcaption><p><span class="caption-number">Figure 2.1 </span>B.</p></figcaption></figure>
</section>
<section id="exercises"><h3><span class="section-number">2.2. </span>Exercises</h3></section>
</section>
<span id="document-refs"></span><section class="tex2jax_ignore" id="refs"><h2>References</h2></section>
</div></section></article></body></html>
"""


@pytest.fixture(autouse=True)
def parts(monkeypatch):
    monkeypatch.setattr(pdf_check, "toc", lambda: ("intro", PARTS))


def entries():
    return pdf_check.expected_entries(SINGLE)


def test_the_contents_are_read_from_the_one_page_book():
    got = [(e.id, e.level, e.kind, e.words) for e in entries()]
    assert got == [
        ("what-h", 1, "section", ("What it is",)),
        ("sunset-part-1", 0, "part", ("The pipeline",)),
        ("01-a-h", 1, "chapter", ("1. The A",)),
        ("01-a--exercises-h", 2, "section", ("1.1. Exercises",)),
        ("02-b-h", 1, "chapter", ("2. The B",)),
        ("02-b--where-h", 2, "section", ("2.1. Where to sample:", "and more")),
        ("02-b--exercises-h", 2, "section", ("2.2. Exercises",)),
        ("sunset-part-2", 0, "part", ("Reference",)),
        ("refs-h", 1, "chapter", ("References",)),
    ]
    assert pdf_check.blocks(SINGLE) == (2, 1)          # Sphinx's figures and display formulas
    assert pdf_check.numbers(SINGLE) == ["Figure 2.1"]


#: Where the made-up book's headings are: page 1 title, 2 contents, 3 intro, 4 part, 5-6 chapter 1, ...
PAGES = {"what-h": 3, "sunset-part-1": 4, "01-a-h": 5, "01-a--exercises-h": 6, "02-b-h": 7,
         "02-b--where-h": 7, "02-b--exercises-h": 8, "sunset-part-2": 9, "refs-h": 10}
HEADERS = {3: "The Book", 5: "1. The A", 6: "1. The A", 7: "2. The B", 8: "2. The B", 10: "References"}


def printed(numbers=None, headers=None, dests=None, images=None):
    """A stand-in for pdf_check.Printed of a right PDF of the made-up book, but for what is passed."""
    pdf = object.__new__(pdf_check.Printed)
    pdf.pages = 10
    pdf.box = [A4] * pdf.pages
    heights = {e.id: 700.0 - 20 * k for k, e in enumerate(entries())}
    pdf.dests = {"sunset-contents": (2, 800.0), **{i: (p, 700.0) for i, p in PAGES.items()}}
    pdf.dests.update(dests or {})
    pdf.runs = [[(297.0, 22.0, str(p))] if p > 1 else [] for p in range(1, pdf.pages + 1)]
    for e in entries():                                  # each heading on its page, and in the contents
        pdf.runs[PAGES[e.id] - 1].append((60.0, 700.0, " ".join(e.words)))
        pdf.runs[1].append((60.0, heights[e.id], " ".join(e.words)))
        pdf.runs[1].append((540.0, heights[e.id], str((numbers or {}).get(e.id, PAGES[e.id]))))
    for p, h in {**HEADERS, **(headers or {})}.items():
        pdf.runs[p - 1].append((45.0, 815.0, h))
    pdf.images = [[] for _ in range(pdf.pages)]
    for p, box in images or []:
        pdf.images[p - 1].append(box)
    pdf.outline = [(0, "The Book", 1), (1, "Contents", 2)] + [(e.level, " … ".join(e.words), PAGES[e.id])
                                                              for e in entries()]
    return pdf


def run(check, pdf, *args):
    result = pdf_check.Result()
    check(pdf, *args, result)
    return result


def test_the_contents_numbers_are_the_headings_pages():
    assert run(pdf_check.check_contents, printed(), entries()).problems == []
    wrong = run(pdf_check.check_contents, printed(numbers={"02-b--where-h": 8}), entries()).problems
    assert len(wrong) == 1 and "('2.1. Where to sample: … and more', 8, 7)" in wrong[0]


def test_a_destination_away_from_its_heading_is_found():
    pdf = printed(dests={"01-a--exercises-h": (5, 700.0)})
    problems = run(pdf_check.check_contents, pdf, entries()).problems
    assert "the heading '1.1. Exercises' is not on page 5, where its destination points" in problems


def test_the_outline_is_the_book():
    pages = PAGES
    assert run(pdf_check.check_outline, printed(), entries(), pages, "The Book").problems == []
    pdf = printed()
    pdf.outline = pdf.outline[:5] + pdf.outline[6:]                      # a section left out
    problems = run(pdf_check.check_outline, pdf, entries(), pages, "The Book").problems
    assert problems[0] == "the outline has 10 bookmarks, the book 11 headings for it"
    pdf = printed()
    pdf.outline[4] = (1, "1. The A", 6)                                  # a chapter on the wrong page
    assert run(pdf_check.check_outline, pdf, entries(), pages, "The Book").problems


def test_page_numbers_and_running_headers():
    assert run(pdf_check.check_running, printed(), entries(), PAGES, "The Book").problems == []
    problems = run(pdf_check.check_running, printed(headers={6: "2. The B"}), entries(), PAGES, "The Book").problems
    assert problems == ["1 pages with a wrong running header, e.g. [(6, '2. The B', ('1. The A',))]"]
    pdf = printed()
    pdf.runs[4] = [r for r in pdf.runs[4] if r[1] > 30]                 # page 5 loses its number
    problems = run(pdf_check.check_running, pdf, entries(), PAGES, "The Book").problems
    assert problems == ["1 pages without their number at the foot, e.g. [(5, '')]"]


def test_a_figure_or_formula_across_a_page_break_is_found():
    marks = {"sunset-keep-1": (3, 600.0), "sunset-keep-1-end": (3, 400.0),
             "sunset-keep-2": (6, 300.0), "sunset-keep-2-end": (6, 200.0),
             "sunset-keep-3": (7, 100.0), "sunset-keep-3-end": (7, 60.0)}
    assert run(pdf_check.check_breaks, printed(dests=marks), SINGLE).problems == []
    cut = {**marks, "sunset-keep-3-end": (8, 700.0)}
    problems = run(pdf_check.check_breaks, printed(dests=cut), SINGLE).problems
    assert problems == ["figure or formula 3 is cut by a page break: it starts on page 7, ends on 8"]
    few = {k: v for k, v in marks.items() if not k.startswith("sunset-keep-3")}
    problems = run(pdf_check.check_breaks, printed(dests=few), SINGLE).problems
    assert problems == ["marks for 2 figures and formulas, the book has 2 figures and 1 display formulas"]


def test_an_image_past_the_text_area_is_found():
    inside = [(7, (100.0, 300.0, 400.0, 700.0))]
    assert run(pdf_check.check_breaks, printed(images=inside, dests={}), SINGLE).problems[1:] == []
    below = [(7, (100.0, 10.0, 400.0, 500.0))]                         # runs into the foot: cut off
    problems = run(pdf_check.check_breaks, printed(images=below), SINGLE).problems
    assert any("1 images drawn past their page's text area (cut), e.g. [(7, 10, 500)]" in p for p in problems)


def test_words_are_compared_without_ligatures_quotes_or_spaces():
    assert pdf_check.has_words("Height \ufb01elds  along\nscan lines", ["Height fields along scan lines"])
    assert pdf_check.has_words("Stokes\u2019 expansion", ["Stokes' expansion"])
    assert not pdf_check.has_words("b a", ["a", "b"])                      # in order
    assert pdf_check.heading_words('<span class="section-number">4.2. </span>Where to sample: '
                                   '<span class="math notranslate nohighlight">\\(\\sigma\\)</span>'
                                   '<a class="headerlink" href="#x">#</a>') == ("4.2. Where to sample:",)
