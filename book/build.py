#!/usr/bin/env python3
"""Build the sunset book with Jupyter Book 1, strictly and offline.

Usage::

    python book/build.py [--execute {cache,force,off}] [--builder {html,singlehtml}]
                         [--toc PATH] [--config PATH]

The build runs ``jupyter-book build book -W -n --keep-going --all``: every
page is re-read on every build (so a warning is never hidden by Sphinx's
incremental build), warnings are errors, and the build goes on to report all
of them before it exits non-zero. Chapters are jupytext MyST notebooks
executed by myst-nb: through the local jupyter-cache by default (a chapter is
re-run only when its code cells change), or every one of them with
``--execute force`` (CI: a change in ``sunset/`` does not invalidate the
cache). A cell that raises, or writes to stderr, fails the build.

The exit status is jupyter-book's; a summary line says how long it took.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

BOOK = Path(__file__).resolve().parent
ROOT = BOOK.parent
MODES = ("cache", "force", "off", "auto")
#: Sphinx builders: the HTML book, or the whole book as one page (book/pdf.py prints it).
BUILDERS = ("html", "singlehtml")


def jupyter_book() -> list[str]:
    """The command that runs jupyter-book from this interpreter's environment."""
    exe = Path(sys.executable).with_name("jupyter-book")
    if exe.exists():
        return [str(exe)]
    found = shutil.which("jupyter-book")
    if found is None:
        raise SystemExit("build.py: jupyter-book is not installed (pip install -e '.[book]')")
    return [found]


def config_for(mode: str, config: Path, workdir: Path) -> Path:
    """A copy of ``config`` whose execution mode is ``mode``."""
    data = yaml.safe_load(config.read_text(encoding="utf-8"))
    data.setdefault("execute", {})["execute_notebooks"] = mode
    # jupyter-book resolves local extensions' folders against the config file's
    # folder: the copy lives elsewhere, so they are made absolute here.
    local = data.get("sphinx", {}).get("local_extensions") or {}
    for name, folder in local.items():
        local[name] = str((config.parent / folder).resolve())
    out = workdir / "_config.yml"
    out.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return out


#: The chapters' kernels load this profile. ipykernel warns on every start that its
#: loopback TCP sockets are not encrypted; the kernels of a book build talk to no
#: one else, so that one message is dropped and every other kernel message stays.
KERNEL_CONFIG = """\
import logging


class _LoopbackTcpIsFine(logging.Filter):
    def filter(self, record):
        return "running over TCP without encryption" not in record.getMessage()


logging.getLogger("IPKernelApp").addFilter(_LoopbackTcpIsFine())
"""


def quiet_kernel_profile(workdir: Path) -> Path:
    """An IPython directory whose default profile holds :data:`KERNEL_CONFIG`."""
    root = workdir / "ipython"
    profile = root / "profile_default"
    profile.mkdir(parents=True)
    (profile / "ipython_kernel_config.py").write_text(KERNEL_CONFIG, encoding="utf-8")
    return root


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--execute", choices=MODES, default="cache",
                        help="notebook execution mode (default: cache; CI: force)")
    parser.add_argument("--toc", type=Path, default=BOOK / "_toc.yml",
                        help="table of contents (default: book/_toc.yml)")
    parser.add_argument("--config", type=Path, default=BOOK / "_config.yml",
                        help="book configuration (default: book/_config.yml)")
    parser.add_argument("--builder", choices=BUILDERS, default="html",
                        help="html (default) or singlehtml, the whole book as one page")
    args = parser.parse_args(argv)

    start = time.perf_counter()
    env = dict(os.environ)
    # The chapters' kernels import the package from this working tree (the
    # code the chapters literalinclude), whatever is installed in the venv.
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    # Build matplotlib's font cache now: on a fresh machine the first import
    # reports it on stderr, which a chapter would turn into a build warning.
    subprocess.run([sys.executable, "-c", "import matplotlib.pyplot"], env=env, check=False,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with tempfile.TemporaryDirectory(prefix="sunset-book-") as tmp:
        config = config_for(args.execute, args.config.resolve(), Path(tmp))
        env["IPYTHONDIR"] = str(quiet_kernel_profile(Path(tmp)))
        cmd = jupyter_book() + [
            "build", str(BOOK), "--builder", args.builder, "--all",
            "-W", "-n", "--keep-going",
            "--config", str(config), "--toc", str(args.toc.resolve()),
        ]
        print("build.py:", " ".join(cmd), flush=True)
        rc = subprocess.run(cmd, cwd=ROOT, env=env).returncode
    elapsed = time.perf_counter() - start
    index = BOOK / "_build" / args.builder / "index.html"
    if rc == 0 and not index.is_file():
        print(f"build.py: jupyter-book exited 0 but {index} is missing", file=sys.stderr)
        rc = 1
    verdict = "built" if rc == 0 else f"FAILED (exit {rc})"
    print(f"build.py: book {verdict} in {elapsed:.1f} s (execute={args.execute}) -> {index}", flush=True)
    return rc


if __name__ == "__main__":
    sys.exit(main())
