"""The book's sources keep their promises, checked without building the book.

* Every ``literalinclude`` resolves the way Sphinx will resolve it: the file
  exists, a ``:pyobject:`` names a function, class or method that exists (found
  here with :mod:`ast`, independently of Sphinx), ``:start-after:`` and
  ``:end-before:`` markers occur once each and in that order. Raw ``:lines:``
  ranges are not allowed: they go stale silently when the code changes.
* Every included fragment of code is short (at most ``MAX_FRAGMENT_LINES`` lines) and
  every included line fits the column (at most ``MAX_CODE_WIDTH`` characters,
  the width of a code block in the book's column at 1280 px, measured by
  ``book/browser_check.py``).
* Every numbered chapter has at least two exercises, each with a solution
  hidden by default, and a section "What the tests check" that names test
  files; every test file the book names exists.
* Every figure directive is captioned and named, and no chapter shows a bare
  plot (``plt.show()``) outside a numbered, captioned figure.
* The ×10ⁿ formatting helper of book/_ext.
"""

from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
MAX_FRAGMENT_LINES = 60
MAX_CODE_WIDTH = 84

_spec = importlib.util.spec_from_file_location("numbers_sci", BOOK / "_ext" / "numbers_sci.py")
numbers_sci = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(numbers_sci)


def toc_parts() -> list[tuple[bool, list[str]]]:
    """(numbered, [file, ...]) for each part of book/_toc.yml (a small line parser)."""
    parts: list[tuple[bool, list[str]]] = []
    for line in (BOOK / "_toc.yml").read_text(encoding="utf-8").splitlines():
        line = line.split("#", 1)[0].rstrip()
        if re.match(r"^\s*-\s*caption:", line):
            parts.append((False, []))
        elif re.match(r"^\s*numbered:\s*true", line, re.I) and parts:
            parts[-1] = (True, parts[-1][1])
        else:
            m = re.match(r"^\s*-\s*file:\s*(\S+)", line)
            if m:
                if not parts:
                    parts.append((False, []))
                parts[-1][1].append(m.group(1))
    return parts


def numbered_chapters() -> list[str]:
    return [f for numbered, files in toc_parts() if numbered for f in files]


def pages() -> list[Path]:
    files = ["intro"] + [f for _, fs in toc_parts() for f in fs]
    return [BOOK / f"{f}.md" for f in files]


def chapter_id(path: Path) -> str:
    return path.stem


def directives(text: str, name: str) -> list[tuple[str, dict[str, str], str]]:
    """(argument, options, body) of every ```{name} ... ``` (or :::{name}) block in ``text``."""
    out = []
    pattern = re.compile(r"^(?P<fence>`{3,}|:{3,})\{" + re.escape(name) + r"\}[ \t]*(?P<arg>[^\n]*)\n"
                         r"(?P<rest>.*?)^(?P=fence)[ \t]*$", re.S | re.M)
    for m in pattern.finditer(text):
        rest = m.group("rest")
        options = {}
        body_lines = []
        in_options = True
        lines = rest.splitlines()
        if lines and lines[0].strip() == "---":  # YAML options block
            end = lines.index("---", 1)
            for opt in lines[1:end]:
                k, _, v = opt.partition(":")
                options[k.strip()] = v.strip()
            lines = lines[end + 1:]
            in_options = False
        for line in lines:
            om = re.match(r"^:([\w-]+):\s*(.*)$", line) if in_options else None
            if om:
                options[om.group(1)] = om.group(2).strip()
            else:
                in_options = False
                body_lines.append(line)
        out.append((m.group("arg").strip(), options, "\n".join(body_lines).strip()))
    return out


def python_object_lines(source: str, dotted: str) -> tuple[int, int] | None:
    """1-based (first, last) line of a function, class or method named ``dotted``, decorators included."""
    node: ast.AST = ast.parse(source)
    for part in dotted.split("."):
        found = None
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and child.name == part:
                found = child
        if found is None:
            return None
        node = found
    first = min([node.lineno] + [d.lineno for d in node.decorator_list])
    return first, node.end_lineno


def _option_text(value: str) -> str:
    """A directive option's text, with YAML-style quotes and escapes resolved."""
    value = value.strip()
    if len(value) >= 2 and value[0] == value[-1] and value[0] in "'\"":
        return ast.literal_eval(value)
    return value


def included_lines(md: Path, arg: str, options: dict[str, str]) -> list[str]:
    """The lines a literalinclude shows, or raise AssertionError saying why it does not resolve."""
    path = (md.parent / arg).resolve()
    assert path.is_file(), f"{md.name}: literalinclude of {arg}: no such file"
    assert "lines" not in options, (f"{md.name}: literalinclude of {arg} uses :lines: "
                                    "(use :pyobject: or :start-after:/:end-before: markers)")
    source = path.read_text(encoding="utf-8")
    lines = source.splitlines()
    if "pyobject" in options:
        span = python_object_lines(source, options["pyobject"])
        assert span is not None, f"{md.name}: {arg} has no object {options['pyobject']!r}"
        lines = lines[span[0] - 1:span[1]]
    # Start markers must be unambiguous (exactly one line holds them); an end
    # marker ends the fragment at its first line after the start, as in Sphinx.
    # Sphinx keeps the line endings, so a marker may end with a newline.
    for key, keep in (("start-after", 1), ("start-at", 0)):
        if key in options:
            marker = _option_text(options[key])
            hits = [i for i, line in enumerate(lines) if marker in line + "\n"]
            assert len(hits) == 1, f"{md.name}: marker {marker!r} occurs {len(hits)} times in {arg}"
            lines = lines[hits[0] + keep:]
    for key, keep in (("end-before", 0), ("end-at", 1)):
        if key in options:
            marker = _option_text(options[key])
            hits = [i for i, line in enumerate(lines) if marker in line + "\n"]
            assert hits, f"{md.name}: end marker {marker!r} does not occur after the start in {arg}"
            lines = lines[:hits[0] + keep]
    assert lines, f"{md.name}: literalinclude of {arg} {options} is empty"
    if "dedent" in options:
        n = int(options["dedent"]) if options["dedent"] else min(
            len(x) - len(x.lstrip()) for x in lines if x.strip())
        lines = [x[n:] for x in lines]
    return lines


INCLUDES = [(md, arg, opts) for md in pages() if md.exists()
            for arg, opts, _ in directives(md.read_text(encoding="utf-8"), "literalinclude")]


def test_the_book_has_literalincludes():
    assert len(INCLUDES) > 20


@pytest.mark.parametrize("md, arg, options", INCLUDES,
                         ids=[f"{m.stem}:{o.get('pyobject') or o.get('start-after') or a}" for m, a, o in INCLUDES])
def test_literalinclude_resolves_and_fits_the_column(md, arg, options):
    lines = included_lines(md, arg, options)
    code = arg.endswith(".py") or "pyobject" in options  # a data file may be shown whole
    assert not code or len(lines) <= MAX_FRAGMENT_LINES, (
        f"{md.name}: {options} shows {len(lines)} lines (at most {MAX_FRAGMENT_LINES}: "
        "show the part the prose explains, between markers)")
    wide = [(len(x.rstrip()), x.strip()[:50]) for x in lines if len(x.rstrip()) > MAX_CODE_WIDTH]
    assert not wide, f"{md.name}: {arg} {options}: lines wider than {MAX_CODE_WIDTH}: {wide}"


def test_included_lines_finds_what_sphinx_would(tmp_path):
    src = tmp_path / "m.py"
    src.write_text("class A:\n    @staticmethod\n    def f(x):\n        return x\n\n\n"
                   "def g():\n    # [start]\n    y = 1\n    # [end]\n    return y\n", encoding="utf-8")
    md = tmp_path / "c.md"
    assert included_lines(md, "m.py", {"pyobject": "A.f"}) == [
        "    @staticmethod", "    def f(x):", "        return x"]
    assert included_lines(md, "m.py", {"pyobject": "A.f", "dedent": "4"})[1] == "def f(x):"
    assert included_lines(md, "m.py", {"start-after": "[start]", "end-before": "[end]"}) == ["    y = 1"]
    assert included_lines(md, "m.py", {"start-at": "def g", "end-at": '"y = 1\\n"'}) == [
        "def g():", "    # [start]", "    y = 1"]
    for bad in ({"pyobject": "A.h"}, {"pyobject": "B"}, {"start-after": "[nowhere]"},
                {"lines": "1-3"}, {"start-after": "return"}):
        with pytest.raises(AssertionError):
            included_lines(md, "m.py", bad)
    with pytest.raises(AssertionError):
        included_lines(md, "missing.py", {})


@pytest.mark.parametrize("chapter", numbered_chapters())
def test_chapter_has_exercises_with_hidden_solutions(chapter):
    text = (BOOK / f"{chapter}.md").read_text(encoding="utf-8")
    exercises = directives(text, "exercise")
    assert len(exercises) >= 2, f"{chapter}: {len(exercises)} exercises (at least 2)"
    labels = [opts.get("label") for _, opts, _ in exercises]
    assert all(labels), f"{chapter}: every exercise needs a :label:"
    solved = {}
    for arg, opts, _ in directives(text, "solution") + directives(text, "solution-start"):
        solved[arg] = opts.get("class", "")
    for label in labels:
        assert label in solved, f"{chapter}: exercise {label} has no solution"
        assert "dropdown" in solved[label].split(), f"{chapter}: the solution of {label} is not hidden"
    assert text.count("{solution-start}") == text.count("{solution-end}")


def test_exercise_labels_are_unique():
    labels = [opts.get("label") for md in pages() if md.exists()
              for _, opts, _ in directives(md.read_text(encoding="utf-8"), "exercise")]
    assert len(labels) == len(set(labels))


TEST_PATH = re.compile(r"tests/[\w/]+\.py")


@pytest.mark.parametrize("chapter", numbered_chapters())
def test_chapter_says_what_the_tests_check(chapter):
    text = (BOOK / f"{chapter}.md").read_text(encoding="utf-8")
    m = re.search(r"^## What the tests check\s*$(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert m, f"{chapter}: no section '## What the tests check'"
    named = TEST_PATH.findall(m.group(1))
    assert named, f"{chapter}: 'What the tests check' names no test file (tests/...py)"


@pytest.mark.parametrize("page", pages(), ids=lambda p: p.stem)
def test_every_test_file_the_book_names_exists(page):
    text = page.read_text(encoding="utf-8")
    missing = sorted({p for p in TEST_PATH.findall(text) if not (ROOT / p).is_file()})
    assert not missing, f"{page.name} names test files that do not exist: {missing}"


def test_the_intro_table_names_test_files_that_exist():
    text = (BOOK / "intro.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| ") and "{doc}" in line]
    assert rows
    for row in rows:
        tests = row.rstrip(" |").rsplit("|", 1)[1]
        for name in re.findall(r"`([\w/]+\.py)`", tests):
            assert (ROOT / "tests" / name).is_file(), f"intro: tests/{name} does not exist"


FIGURE_DIRECTIVES = ("figure", "glue:figure")


@pytest.mark.parametrize("page", pages(), ids=lambda p: p.stem)
def test_every_figure_is_captioned_and_numbered_in_chapters(page):
    """Captions everywhere; in a numbered chapter a :name:, which gives the number (Figure 4.2)."""
    text = page.read_text(encoding="utf-8")
    numbered = page.stem in numbered_chapters()
    for name in FIGURE_DIRECTIVES:
        for arg, opts, body in directives(text, name):
            assert len(body.split()) >= 5, f"{page.name}: {name} {arg} has no caption"
            if numbered:
                assert opts.get("name"), f"{page.name}: {name} {arg} has no :name: (so no number)"


@pytest.mark.parametrize("page", pages(), ids=lambda p: p.stem)
def test_no_bare_plots(page):
    """A chapter's plots are glued into captioned figures, never shown bare."""
    text = page.read_text(encoding="utf-8")
    cells = [body for _, _, body in directives(text, "code-cell")]
    for cell in cells:
        assert "plt.show(" not in cell, f"{page.name}: a cell shows a bare plot (plt.show)"
        if re.search(r"plt\.(subplots|figure)\(", cell):
            assert "plt.close(" in cell, f"{page.name}: a cell makes a figure and leaves it open"


def test_the_intro_has_a_picture():
    text = (BOOK / "intro.md").read_text(encoding="utf-8")
    figures = [opts for name in FIGURE_DIRECTIVES for _, opts, _ in directives(text, name)]
    assert figures, "the intro page has no figure"


@pytest.mark.parametrize("text, expected", [
    ("6.7e-06", "6.7 × 10⁻⁶"),
    ("1.234e+05", "1.234 × 10⁵"),
    ("3.2E+12", "3.2 × 10¹²"),
    ("1e+03", "10³"),
    ("1e-13", "10⁻¹³"),
    ("-1e-05", "-10⁻⁵"),
    ("-2.50e+00", "-2.50"),
    ("-4.5e-10", "-4.5 × 10⁻¹⁰"),
    ("an error of 2.0e-15 m, then 3.1e-07", "an error of 2.0 × 10⁻¹⁵ m, then 3.1 × 10⁻⁷"),
    ("4.0e-01%", "4.0 × 10⁻¹%"),
    ("0.000012", "0.000012"),
    ("fig6-510x512.png", "fig6-510x512.png"),
    ("x1e-3 and 1e5 and sample_2e-05", "x1e-3 and 1e5 and sample_2e-05"),
    ("version 1.2e-3.4", "version 1.2e-3.4"),
])
def test_scientific(text, expected):
    assert numbers_sci.scientific(text) == expected


def test_scientific_round_trips_through_float():
    """The rewritten number is the same number: read it back and compare."""
    table = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
    for value in (6.7e-06, 1.5e+22, -3.25e-300, 9.99e-10, 2.0e+7):
        for spec in (".1e", ".3e", ".6e"):
            text = numbers_sci.scientific(format(value, spec))
            mantissa, _, power = text.partition(" × 10")
            back = float(mantissa) * 10.0 ** int(power.translate(table))
            assert back == pytest.approx(float(format(value, spec)), rel=1e-12)


def test_the_symbols_page_resolves_the_overloaded_letters():
    """σ, f, g, H and c each have a row per meaning, with units and the chapter that defines it."""
    assert "symbols" in [f for _, files in toc_parts() for f in files]
    text = (BOOK / "symbols.md").read_text(encoding="utf-8")
    section = text.split("## Letters with more than one meaning", 1)[1].split("\n## ", 1)[0]
    rows = [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in section.splitlines() if line.startswith("| $")]
    assert rows and all(len(r) == 4 and all(r) for r in rows), "every row: symbol, meaning, units, chapter"
    for letter in (r"\sigma", "f", "g", "H", "c"):
        meanings = [r for r in rows if re.match(r"\$" + re.escape(letter) + r"(\$|_|\()", r[0])
                    or re.search(r"(^|\$|, )" + re.escape(letter) + r"(\$|,)", r[0])]
        assert len(meanings) >= 2, f"{letter}: {len(meanings)} meanings on the symbols page"
    for name in re.findall(r"\{doc\}`([^`]+)`", text):
        assert (BOOK / f"{name}.md").is_file(), f"symbols.md refers to a missing page {name}"


def test_the_browser_check_measures_the_width_these_tests_allow():
    """book/browser_check.py fails a page whose code column holds fewer than MAX_CODE_WIDTH characters."""
    source = (BOOK / "browser_check.py").read_text(encoding="utf-8")
    m = re.search(r"^CODE_COLUMNS = (\d+)", source, re.M)
    assert m and int(m.group(1)) == MAX_CODE_WIDTH
    css = (BOOK / "_static" / "sunset.css").read_text(encoding="utf-8")
    assert "div.highlight pre" in css and "overflow-x: auto" in css
