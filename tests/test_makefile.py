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
    for target in ("all", "figures", "test", "book", "book-check", "pdf", "bench", "bench-player", "lock", "clean"):
        assert f"make {target} " in out, target
