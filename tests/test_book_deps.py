"""The book is never built from stale outputs: a chapter re-executes when what it imports changed, and only then.

``book/chapter_deps.py`` finds what each chapter's execution depends on;
``book/build.py`` drops a stored chapter from the execution cache when that
changed. Checked here in two ways:

* statically, against what actually runs: the package files whose functions
  execute while a snippet runs (traced in a fresh interpreter with
  ``sys.setprofile``) must all be among the files the scan names for it;
* end to end, on a fixture book of three small chapters built with
  ``book/build.py --execute cache`` against a copy of the package: after a
  module changes, exactly the chapters that use it execute again (each
  chapter writes a line to a log when it runs: an independent witness), and
  a number glued from the changed code shows the new value. Needs the
  ``book`` extra (jupyter-book); ``.ci/run`` runs it after ``make book``.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import sunset

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"

_spec = importlib.util.spec_from_file_location("chapter_deps_under_test", BOOK / "chapter_deps.py")
chapter_deps = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = chapter_deps
_spec.loader.exec_module(chapter_deps)


def api_module(name: str) -> str:
    """The module the lazy public API loads ``name`` from, as the running package resolves it."""
    return importlib.util.resolve_name(sunset._API[name], "sunset")


def files_of(modules: set[str]) -> set[str]:
    out = set()
    for m in modules:
        f = chapter_deps.deps.module_file(m)
        out.add(f.relative_to(ROOT).as_posix())
    return out


# ---------------------------------------------------------------- the static scan
def test_code_cells_are_read_without_their_options():
    text = textwrap.dedent("""\
        # A chapter

        ```{code-cell} ipython3
        :tags: [hide-input]
        from sunset.model.series import stokes_series
        ```

        ```python
        from sunset.pipeline.frame import render
        ```

        ````{code-cell} ipython3
        ---
        tags: [remove-cell]
        ---
        %matplotlib inline
        import sunset.constants
        ````
        """)
    cells = chapter_deps.code_cells(text)
    assert cells == ["from sunset.model.series import stokes_series", "%matplotlib inline\nimport sunset.constants"]
    found = set().union(*(chapter_deps.sunset_modules(c) for c in cells))
    assert found == {"sunset.model.series", "sunset.constants"}      # not the ```python block


@pytest.mark.parametrize("code, names", [
    ("import sunset\nframe = sunset.render(scene, 0.0, 2)", ["render"]),
    ("import sunset as s\ns.Scene.default().with_size(8, 8)", ["Scene"]),
    ("from sunset import encode, expose", ["encode", "expose"]),
])
def test_the_lazy_public_api_counts_the_modules_its_names_load(code, names):
    found = chapter_deps.sunset_modules(code)
    assert {api_module(n) for n in names} <= found
    others = {api_module(n) for n in sunset._API if api_module(n) not in {api_module(x) for x in names}}
    assert not others & found                              # only what the names used load


@pytest.mark.parametrize("code", ["import sunset\nprint(sorted(dir(sunset)))", "from sunset import *",
                                  "import sunset\nf = getattr(sunset, name)", "import sunset\nsunset.not_a_name"])
def test_the_package_used_as_a_whole_depends_on_the_whole_public_api(code):
    found = chapter_deps.sunset_modules(code)
    assert {api_module(n) for n in sunset._API} <= found


@pytest.mark.parametrize("code", [
    'subprocess.run([sys.executable, "-m", "sunset", "render", "x.toml"])',
    'subprocess.run([sys.executable, "-c", "import sunset; sunset.picture(1)"])',
    'os.system("python -m sunset figures")',
])
def test_running_the_package_as_a_program_depends_on_all_of_it(code):
    every = {p for p in (ROOT / "sunset").rglob("*.py")}
    found = {chapter_deps.deps.module_file(m) for m in chapter_deps.sunset_modules(code)}
    assert found == every


def test_a_dotted_import_reaches_the_module_named():
    found = chapter_deps.sunset_modules("import sunset.pipeline.cray1\nx = sunset.pipeline.cray1.CLOCK_S")
    assert "sunset.pipeline.cray1" in found and "sunset.pipeline.frame" not in found


def test_package_data_and_book_files_are_dependencies(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "numbers.json").write_text("{}")
    (tmp_path / "lone.txt").write_text("")
    cells = ['json.loads(Path("data/numbers.json").read_text())', 'open("lone.txt")', 'print("not a file")']
    assert chapter_deps.book_files(cells, tmp_path) == {tmp_path / "data" / "numbers.json", tmp_path / "lone.txt"}
    scenes = {p.name for p in chapter_deps.package_data("sunset.model.scene")}
    assert scenes == {p.name for p in (ROOT / "sunset" / "scenes").glob("*.toml")} and scenes
    player = {p.name for p in chapter_deps.package_data("sunset.recorder.player")}
    assert {"player.html", "player.js", "player.css"} <= player
    assert chapter_deps.package_data("sunset.model.series") == set()


TRACER = """
import sys
ran = set()
def profile(frame, event, arg):
    if event == "call" and frame.f_code.co_name != "<module>":
        ran.add(frame.f_code.co_filename)
sys.setprofile(profile)
exec(compile(sys.argv[1], "<snippet>", "exec"), {})
sys.setprofile(None)
print("\\n".join(sorted(ran)))
"""


@pytest.mark.parametrize("code", [
    "from sunset.model.series import stokes_series\nstokes_series(6).pade(\"height\", 0.1)",
    "import sunset\nsunset.Scene.default().with_size(16, 12)",
    "from sunset.pipeline.cray1 import CrayCosts\nCrayCosts()",
])
def test_every_package_file_whose_code_runs_is_a_dependency(code):
    """The independent reference: the package files whose functions ran (traced), never missing from the scan."""
    out = subprocess.run([sys.executable, "-c", TRACER, code], capture_output=True, text=True, check=True,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}).stdout
    package = (ROOT / "sunset").resolve()
    ran = {Path(f).resolve() for f in out.split("\n") if f}
    ran = {f.relative_to(ROOT).as_posix() for f in ran if f.is_relative_to(package)}
    assert ran                                             # the trace sees the package at all
    static = set()
    for m in chapter_deps.sunset_modules(code):
        static |= files_of(chapter_deps.deps.closure(m))
    assert ran <= static, sorted(ran - static)


def test_the_books_chapters_depend_on_what_they_say():
    stokes = {f.relative_to(ROOT).as_posix() for f in chapter_deps.chapter_files(BOOK / "03-stokes.md")}
    assert "sunset/model/series.py" in stokes and "sunset/model/stokes_exact.py" in stokes
    assert "sunset/recorder/dicomed.py" not in stokes and "sunset/pipeline/frame.py" not in stokes
    speed = {f.relative_to(ROOT).as_posix() for f in chapter_deps.chapter_files(BOOK / "10-speed.md")}
    assert "book/data/bench.json" in speed                 # it reads the snapshot of `make bench`
    cli = {f.relative_to(ROOT).as_posix() for f in chapter_deps.chapter_files(BOOK / "11-command-line.md")}
    assert "sunset/cli.py" in cli and "sunset/recorder/film.py" in cli       # it runs `python -m sunset`
    assert chapter_deps.chapter_files(BOOK / "symbols.md") == []             # no code cells


def test_a_fingerprint_compares_contents_not_times(tmp_path):
    md = tmp_path / "c.md"
    md.write_text("```{code-cell} ipython3\nfrom sunset.errors import SunsetError\n```\n")
    first = chapter_deps.fingerprint(md, env="e")
    assert {"sunset/__init__.py", "sunset/errors.py"} <= set(first.files)
    assert "sunset/pipeline/frame.py" not in first.files                  # the errors need no renderer
    assert chapter_deps.fingerprint(md, env="e").key == first.key
    assert chapter_deps.fingerprint(md, env="other").key != first.key    # another environment
    changed = dict(first.files, **{"sunset/errors.py": "0" * 64})
    assert first.changed(changed) == ["sunset/errors.py"]


# ---------------------------------------------------------------- the build, end to end
CONFIG = """\
title: fixture
only_build_toc_files: true
execute:
  execute_notebooks: cache
  stderr_output: warn
  allow_errors: false
sphinx:
  config:
    extensions: [sphinx_togglebutton, sphinx_copybutton, sphinx_comments, myst_nb, jupyter_book,
                 sphinx_external_toc, sphinx_design, sphinx_book_theme]
"""

TOC = """\
format: jb-book
root: intro
chapters:
  - file: series
  - file: scenes
  - file: plain
"""

HEADER = ("---\njupytext:\n  text_representation:\n    extension: .md\n    format_name: myst\n"
          "kernelspec:\n  display_name: Python 3\n  language: python\n  name: python3\n---\n")

LOG = """\
import os, pathlib
with open(os.environ["SUNSET_TEST_LOG"], "a") as log:
    log.write(f"{NAME} {pathlib.Path(__import__('sunset').__file__).parent}\\n")
"""

CHAPTERS = {
    # the probe reaches the real Stokes series (series.py, pade.py, ...), not the scenes
    "series": ("from myst_nb import glue\nfrom sunset.model.probe import glued\n"
               'NAME = "series"\n' + LOG + 'glue("probe", glued(), display=False)\n',
               "Probe value: {glue:text}`probe`."),
    # the lazy public API: sunset.scene_names is sunset/model/scene.py, and it reads the scenes
    "scenes": ("from myst_nb import glue\nimport sunset\n"
               'NAME = "scenes"\n' + LOG + 'glue("n_scenes", len(sunset.scene_names()), display=False)\n',
               "Scenes: {glue:text}`n_scenes`."),
    "plain": ('NAME = "plain"\n' + LOG.replace("__import__('sunset').__file__", "'x/y'"), "No package here."),
}

PROBE = '''"""A fixture's number for a chapter to glue, through the real Stokes series."""
from .series import stokes_series

FACTOR = {factor}


def glued():
    return FACTOR * len(stokes_series(2).height())
'''


def fixture_project(root: Path) -> None:
    shutil.copytree(ROOT / "sunset", root / "sunset", ignore=shutil.ignore_patterns("__pycache__"))
    (root / "sunset" / "model" / "probe.py").write_text(PROBE.format(factor=1))
    book = root / "book"
    book.mkdir()
    for name in ("build.py", "chapter_deps.py"):
        shutil.copy(BOOK / name, book / name)
    (book / "_config.yml").write_text(CONFIG)
    (book / "_toc.yml").write_text(TOC)
    (book / "intro.md").write_text("# Fixture\n\nA book of three chapters.\n")
    for name, (code, prose) in CHAPTERS.items():
        (book / f"{name}.md").write_text(f"{HEADER}\n# {name}\n\n```{{code-cell}} ipython3\n{code}```\n\n{prose}\n")


def build(root: Path, log: Path) -> tuple[set[str], str]:
    """Build the fixture book from the cache; the chapters that executed, and build.py's output."""
    log.write_text("")
    env = {**os.environ, "SUNSET_TEST_LOG": str(log)}
    proc = subprocess.run([sys.executable, str(root / "book" / "build.py"), "--execute", "cache"],
                          cwd=root, env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    ran = {}
    for line in log.read_text().splitlines():
        name, package = line.split(" ", 1)
        ran[name] = package
    for name, package in ran.items():                       # the kernels imported the copy, not this tree
        assert name == "plain" or Path(package) == root / "sunset", package
    return set(ran), proc.stdout


def page(root: Path, name: str) -> str:
    """The text of a built page, without its tags."""
    return re.sub(r"<[^>]+>", "", (root / "book" / "_build" / "html" / f"{name}.html").read_text(encoding="utf-8"))


def edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


def test_exactly_the_chapters_that_use_a_changed_module_re_execute(tmp_path):
    pytest.importorskip("jupyter_book", reason="the book extra (jupyter-book) builds the fixture book")
    pytest.importorskip("jupyter_cache", reason="the book extra (jupyter-cache) builds the fixture book")
    root = tmp_path / "project"
    fixture_project(root)
    log = tmp_path / "executed.log"
    pkg = root / "sunset"

    ran, _ = build(root, log)
    assert ran == {"series", "scenes", "plain"}            # a fresh cache executes every chapter
    height_terms = len(sunset.stokes_series(2).height())     # the probe's number, computed here
    assert f"Probe value: {height_terms}." in page(root, "series")
    stored = json.loads((root / "book" / "_build" / ".jupyter_cache" / "sunset-chapter-deps.json").read_text())
    assert sorted(e["chapter"] for e in stored.values()) == ["book/plain.md", "book/scenes.md", "book/series.md"]

    # a module only the series chapter reaches (series -> pade), changed; another one only touched
    (pkg / "model" / "pade.py").write_text((pkg / "model" / "pade.py").read_text() + "\n# changed\n")
    os.utime(pkg / "model" / "scene.py")
    ran, out = build(root, log)
    assert ran == {"series"}
    assert "book/series.md re-executes: sunset/model/pade.py changed\n" in out, out

    # package data only the scenes chapter reads (the lazy API's scene_names), and the code behind
    # the series chapter's glued number: each chapter for its own reason, and the page shows the new number
    toml = pkg / "scenes" / "storm-swell.toml"
    toml.write_text(toml.read_text() + "\n# changed\n")
    edit(pkg / "model" / "probe.py", "FACTOR = 1", "FACTOR = 1000")
    ran, out = build(root, log)
    assert ran == {"series", "scenes"}
    assert "book/scenes.md re-executes: sunset/scenes/storm-swell.toml changed\n" in out, out
    assert "book/series.md re-executes: sunset/model/probe.py changed\n" in out, out
    text = page(root, "series")
    assert f"Probe value: {1000 * height_terms}." in text and f"Probe value: {height_terms}." not in text
