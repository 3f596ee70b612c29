#!/usr/bin/env python3
"""Build the sunset book with Jupyter Book 1, strictly and offline.

Usage::

    python book/build.py [--execute {cache,force,off}] [--builder {html,singlehtml}]
                         [--toc PATH] [--config PATH]

The build runs ``jupyter-book build book -W -n --keep-going --all``: every
page is re-read on every build (so a warning is never hidden by Sphinx's
incremental build), warnings are errors, and the build goes on to report all
of them before it exits non-zero. Chapters are jupytext MyST notebooks
executed by myst-nb: through the local jupyter-cache by default, or every one
of them with ``--execute force`` (CI). jupyter-cache knows a chapter only by
its code cells, so before a cached build this script drops every stored
chapter whose other inputs changed since it was executed: the ``sunset``
modules it imports, directly or through the package, the package data they
read, the files of ``book/`` it names, and the Python environment
(``book/chapter_deps.py`` finds them; it says which chapter re-executes and
why). A chapter re-executes when one of those or its own code cells changed,
and only then. A cell that raises, or writes to stderr, fails the build.

The exit status is jupyter-book's; a summary line says how long it took.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
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


def _chapter_deps():
    """``book/chapter_deps.py``, loaded from its file (this script is also imported by pdf.py)."""
    spec = importlib.util.spec_from_file_location("_sunset_chapter_deps", BOOK / "chapter_deps.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["_sunset_chapter_deps"] = module       # (dataclasses look their module up there)
    spec.loader.exec_module(module)
    return module


def toc_chapters(toc: Path) -> list[Path]:
    """The source file of every page of the table of contents (files are relative to the book's folder)."""
    names: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            names.extend(str(node[k]) for k in ("root", "file") if k in node)
            node = list(node.values())
        if isinstance(node, list):
            for item in node:
                walk(item)

    walk(yaml.safe_load(toc.read_text(encoding="utf-8")))
    found = []
    for name in names:
        candidates = [BOOK / name] if Path(name).suffix else [BOOK / f"{name}.md", BOOK / f"{name}.ipynb"]
        found += [c for c in candidates if c.is_file()][:1]
    return found


def cache_folder(config: Path) -> Path:
    """Where myst-nb keeps its execution cache: the config's ``execute.cache``, or ``_build/.jupyter_cache``."""
    data = yaml.safe_load(config.read_text(encoding="utf-8")) or {}
    path = (data.get("execute") or {}).get("cache") or ""
    return (BOOK / path).resolve() if path else BOOK / "_build" / ".jupyter_cache"


class ChapterCache:
    """The execution cache, keyed by each chapter's dependencies as well as by its code cells.

    jupyter-cache stores an executed chapter under the hash of its code cells;
    beside its database this keeps, for every stored chapter, the
    :class:`Fingerprint` of what it was executed with (``sunset-chapter-deps.json``).
    :meth:`invalidate` (before a build) drops every stored chapter whose
    fingerprint is not today's, or that has none; :meth:`record` (after it)
    writes the fingerprint of every chapter the build stored, if its inputs did
    not change while it ran.
    """

    FILE = "sunset-chapter-deps.json"

    def __init__(self, folder: Path, chapters: list[Path]):
        self.deps = _chapter_deps()
        self.folder = folder
        self.chapters = {c.resolve(): c for c in chapters}
        self.env = "\n".join(self.deps.environment())
        self.prints = {c: self.deps.fingerprint(c, self.env) for c in self.chapters}

    def _cache(self):
        if not (self.folder / "global.db").is_file():
            return None
        from jupyter_cache import get_cache

        return get_cache(str(self.folder))

    def _known(self) -> dict:
        try:
            return json.loads((self.folder / self.FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}

    def _chapter(self, record) -> Path | None:
        path = Path(record.uri).resolve()
        return path if path in self.chapters else None

    def _name(self, path: Path) -> str:
        return path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)

    @staticmethod
    def _drop(cache, record) -> None:
        try:
            cache.remove_cache(record.pk)
        except KeyError:                          # its stored notebook is gone already: drop the record
            from jupyter_cache.cache.db import NbCacheRecord

            NbCacheRecord.remove_records([record.pk], cache.db)

    def invalidate(self) -> list[Path]:
        """Drop the stored chapters executed with other inputs than today's; return those chapters."""
        cache = self._cache()
        if cache is None:
            return []
        known, dropped = self._known(), []
        for record in cache.list_cache_records():
            chapter = self._chapter(record)
            if chapter is None:
                if not Path(record.uri).is_file():    # a chapter renamed or removed: its cells may match another
                    self._drop(cache, record)
                continue
            now, then = self.prints[chapter], known.get(record.hashkey)
            if then is not None and then["key"] == now.key:
                continue
            if then is None:
                why = "no record of what it was executed with"
            else:
                why = ", ".join(now.changed(then["files"])) or "the Python environment"
                why += " changed"
            self._drop(cache, record)
            known.pop(record.hashkey, None)       # re-executed, it is stored under the same hashkey again
            if chapter not in dropped:
                print(f"build.py: {self._name(chapter)} re-executes: {why}", flush=True)
                dropped.append(chapter)
        self._write(known)
        return dropped

    def record(self) -> None:
        """Write the fingerprint of every stored chapter the build executed (and keep the others')."""
        cache = self._cache()
        if cache is None:
            return
        known, keep = self._known(), {}
        for record in cache.list_cache_records():
            chapter = self._chapter(record)
            if record.hashkey in known:
                keep[record.hashkey] = known[record.hashkey]
            elif chapter is not None:
                now = self.deps.fingerprint(chapter, self.env)
                if now.key == self.prints[chapter].key:   # unchanged while the build ran
                    keep[record.hashkey] = {"chapter": self._name(chapter), "key": now.key, "files": now.files}
        self._write(keep)

    def _write(self, known: dict) -> None:
        tmp = self.folder / f"{self.FILE}.tmp"
        tmp.write_text(json.dumps(known, indent=1, sort_keys=True), encoding="utf-8")
        tmp.replace(self.folder / self.FILE)


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
    chapters = None
    if args.execute == "cache":
        chapters = ChapterCache(cache_folder(args.config.resolve()), toc_chapters(args.toc.resolve()))
        chapters.invalidate()
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
    if chapters is not None:
        chapters.record()     # also after a failed build: the chapters it did execute are stored
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
