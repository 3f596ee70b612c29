"""The Makefile's housekeeping, run for real in a scratch copy: `make clean` removes what make wrote.

(`make figures` and `make all` themselves are exercised by CI and measured in
the README; tests/figures/test_deps.py checks the figure rules they include.)
"""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="GNU make is not installed")

#: What make, the build and the tests write, relative to the repository.
WRITTEN = [".venv/bin/python", ".venv-lock/bin/uv", "book/_build/html/index.html", "book/_build/pdf/sunset-book.pdf",
           "book/.jupyter_cache/global.db", "build/lib/x.py", "dist/sunset_waves-0.1.0.tar.gz",
           "sunset_waves.egg-info/PKG-INFO", ".pytest_cache/README.md", ".hypothesis/examples/x",
           "sunset/__pycache__/cli.cpython-311.pyc", "tests/model/__pycache__/x.pyc",
           "figures/fig6.png", "figures/fig6.tape", "figures/film.mp4", "figures/film-preview.webp",
           "figures/bench.json", "figures/player.html", "figures/.deps.mk"]
#: Sources that must survive.
KEPT = ["figures/.gitkeep", "sunset/cli.py", "tests/test_makefile.py", "book/intro.md", "pyproject.toml"]


def test_make_clean_removes_everything_make_wrote_and_keeps_the_sources(tmp_path):
    shutil.copy(ROOT / "Makefile", tmp_path / "Makefile")
    for rel in WRITTEN + KEPT:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text("x", encoding="utf-8")
    out = subprocess.run(["make", "-C", str(tmp_path), "clean"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    left = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file())
    assert left == sorted(KEPT + ["Makefile"]), left


def test_make_help_lists_every_documented_target():
    out = subprocess.run(["make", "-s", "-C", str(ROOT), "help"], capture_output=True, text=True, timeout=60,
                         check=True).stdout
    for target in ("all", "figures", "test", "book", "book-check", "lab", "explore-check", "pdf", "bench",
                   "bench-player", "lock", "clean"):
        assert f"make {target} " in out, target


def _figure_project(tmp_path) -> Path:
    """A scratch copy of the Makefile with three figure rules of the generated kind and an up-to-date environment."""
    import os
    import time

    shutil.copy(ROOT / "Makefile", tmp_path / "Makefile")
    for rel in ("pyproject.toml", "requirements/test.lock", "src/a.txt", "src/b.txt", "src/c.txt",
                ".venv/bin/python", ".venv/.stamp-test"):
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text("x", encoding="utf-8")
    (tmp_path / "figures").mkdir()
    (tmp_path / "sunset").mkdir()
    rules = ["FIGURE_FILES := figures/a.png figures/b.png figures/b.tape figures/c.png", ""]
    for name, deps in (("a", "src/a.txt"), ("b", "src/b.txt"), ("c", "src/c.txt figures/b.tape")):
        target = "figures/b.png figures/b.tape &:" if name == "b" else f"figures/{name}.png:"
        recipe = "$(call figure,b,c)" if name == "b" else f"$(call figure,{name})"      # c reads b's tape
        rules += [f"{target} {deps} $(FIGURE_ENV)", f"\t{recipe}", ""]
    (tmp_path / "figures/.deps.mk").write_text("\n".join(rules), encoding="utf-8")
    past = time.time() - 100
    for rel in ("pyproject.toml", "requirements/test.lock", "src/a.txt", "src/b.txt", "src/c.txt", ".venv/bin/python"):
        os.utime(tmp_path / rel, (past, past))
    return tmp_path


def _make(folder: Path, *goals: str) -> list[str]:
    """The sunset commands `make` runs (SUNSET echoes them), one per line."""
    out = subprocess.run(["make", "-s", "-C", str(folder), "SUNSET=echo RUN", *goals], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return [line for line in out.stdout.splitlines() if line.startswith("RUN")]


def _write(folder: Path, *names: str) -> None:
    for name in names:
        (folder / "figures" / name).write_text("made", encoding="utf-8")


def test_make_figures_makes_every_stale_figure_in_one_process(tmp_path):
    """`make figures` runs ONE `sunset figures --only ...` with just the stale figures; none when all are fresh."""
    import os
    import time

    folder = _figure_project(tmp_path)
    assert _make(folder, "figures") == ["RUN figures --only a,b,c --out figures"]
    _write(folder, "a.png", "b.png", "b.tape", "c.png")
    assert _make(folder, "figures") == []                                        # nothing to do: no process

    def older(*names):                                # the figure made before its source changed
        old = time.time() - 200
        for name in names:
            os.utime(folder / "figures" / name, (old, old))

    older("a.png")
    assert _make(folder, "figures") == ["RUN figures --only a --out figures"]
    _write(folder, "a.png")
    older("b.png", "b.tape")
    assert _make(folder, "figures") == ["RUN figures --only b,c --out figures"]  # c re-exposes b's tape
    _write(folder, "b.png", "b.tape", "c.png")
    # a file asked for by itself is made by its own process
    (folder / "figures/a.png").unlink()
    assert _make(folder, "figures/a.png") == ["RUN figures --only a --out figures"]


def test_make_figures_without_the_figures_folder_makes_them_all(tmp_path):
    """`rm -rf figures` then `make figures`: the rules are written again (into a new folder), not skipped."""
    folder = _figure_project(tmp_path)
    rules = (folder / "figures/.deps.mk").read_text(encoding="utf-8")
    # the generator of the rules, as sunset/figures/deps.py: it prints them
    (folder / "sunset/figures").mkdir(parents=True)
    (folder / "sunset/figures/deps.py").write_text(f"print({rules!r}, end='')\n", encoding="utf-8")
    shutil.rmtree(folder / "figures")
    assert _make(folder, "figures") == ["RUN figures --only a,b,c --out figures"]
    assert (folder / "figures/.deps.mk").read_text(encoding="utf-8") == rules
