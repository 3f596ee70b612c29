"""What each chapter's execution depends on: the key of its entry in the book's execution cache.

jupyter-cache, through which ``book/build.py`` executes the chapters, matches
a chapter to its stored outputs by its code cells alone: a change in
``sunset/`` would leave the book showing the old code's numbers and figures.
``build.py`` therefore keys every stored chapter also by what this module
finds, and drops the entry (the chapter re-executes) when that changed:

* the ``sunset`` modules its code cells import, directly or through the
  package, found statically with the same import scan as the figures' rules
  (:mod:`sunset.figures.deps`: ``from sunset.model.scene import Scene`` is
  ``sunset/model/scene.py`` and every package module it imports, transitively);
* for the lazy public API (``import sunset`` then ``sunset.render(...)``, or
  ``from sunset import render``), the modules the names used load (the
  package's ``_API`` table); a chapter that uses the package object other than
  through an attribute depends on the whole public API, and one that runs the
  package as a program (``python -m sunset``) on every module of it;
* the package data those modules read (``importlib.resources``: the scenes, the
  player's page), the files of the book's own folder that its cells name
  (``data/bench.json``), and the Python environment (every installed
  distribution and its version).

Files are compared by content, not by time: touching a file changes nothing.
Standard library only, like :mod:`sunset.figures.deps` (loaded from its file,
so that reading the package's imports does not import the package).
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import re
import sys
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

BOOK = Path(__file__).resolve().parent
ROOT = BOOK.parent
PACKAGE = ROOT / "sunset"


def _load_deps():
    spec = importlib.util.spec_from_file_location("_sunset_figure_deps", PACKAGE / "figures" / "deps.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["_sunset_figure_deps"] = module       # (dataclasses look their module up there)
    spec.loader.exec_module(module)
    return module


deps = _load_deps()

#: A MyST code cell: ```{code-cell} LANG, its options, its source, the closing fence.
CELL = re.compile(r"^(?P<fence>`{3,}|~{3,})\{code-cell\}[^\n]*\n(?P<body>.*?)^(?P=fence)[ \t]*$", re.S | re.M)


def code_cells(text: str) -> list[str]:
    """The sources of the code cells of a MyST notebook, without their options."""
    cells = []
    for m in CELL.finditer(text):
        lines = m.group("body").splitlines()
        if lines and lines[0].strip() == "---":            # a YAML block of options
            end = next((i for i in range(1, len(lines)) if lines[i].strip() == "---"), 0)
            lines = lines[end + 1:]
        while lines and re.match(r"^:[\w-]+:", lines[0]):  # :tags: [hide-input]
            lines = lines[1:]
        cells.append("\n".join(lines))
    return cells


def _python(cell: str) -> str:
    """A cell with IPython's line magics and shell escapes made into ``pass`` (same indentation)."""
    return "\n".join(re.sub(r"^(\s*)[%!].*$", r"\1pass", line) for line in cell.splitlines())


def _every_module() -> set[str]:
    names = set()
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(ROOT).with_suffix("").parts
        names.add(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def _under(package: str) -> set[str]:
    return {m for m in _every_module() if m == package or m.startswith(package + ".")}


def _attribute_chain(node: ast.Attribute) -> tuple[str, list[str]] | None:
    """(name, [attr, ...]) of ``name.attr.attr...``, or None if the chain does not start at a name."""
    chain = []
    while isinstance(node, ast.Attribute):
        chain.append(node.attr)
        node = node.value
    return (node.id, chain[::-1]) if isinstance(node, ast.Name) else None


def _through_package(module: str, chain: list[str]) -> set[str]:
    """The modules that ``module.a.b...`` reaches: submodules on the way, then the one defining the name."""
    for attr in chain:
        sub = f"{module}.{attr}"
        if deps.module_file(sub) is not None:
            module = sub
            continue
        defining = deps._defining_module(module, attr)
        if defining == module and deps.module_file(module).name == "__init__.py" and not attr.startswith("__"):
            return _package_wide(module)                   # a name the package does not say where it gets
        return {defining}
    return {module}


def _package_wide(package: str) -> set[str]:
    """What a use of the package object as a whole may load: its lazy public API, or all of it."""
    api = set(deps.lazy_api(package).values())
    return {package} | (api if api else _under(package))


def sunset_modules(source: str) -> set[str]:
    """The ``sunset`` modules that code ``source`` imports or uses, before their own imports are followed."""
    try:
        tree = ast.parse(_python(source))
    except SyntaxError:
        return _every_module()                             # cannot read it: depend on everything
    found = set(deps.imports_in(tree))
    aliases: dict[str, str] = {}                           # a name bound to a package module -> the module
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "sunset":
                    aliases[a.asname or "sunset"] = a.name if a.asname else "sunset"
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").split(".")[0] == "sunset":
            for a in node.names:
                if a.name == "*":
                    found |= _package_wide(node.module)
                elif deps.module_file(f"{node.module}.{a.name}") is not None:
                    aliases[a.asname or a.name] = f"{node.module}.{a.name}"
        if _runs_the_package(node):
            return _every_module()                         # the package run as a program, or from a string
    inner = {id(n.value) for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and id(node) not in inner:     # sunset.pipeline.cray1.CLOCK_S, whole
            chain = _attribute_chain(node)
            if chain and chain[0] in aliases:
                found |= _through_package(aliases[chain[0]], chain[1])
        elif (isinstance(node, ast.Name) and node.id in aliases and id(node) not in inner
              and deps.module_file(aliases[node.id]).name == "__init__.py"):
            found |= _package_wide(aliases[node.id])      # the package itself passed around
    return found


def _runs_the_package(node: ast.AST) -> bool:
    """Whether ``node`` runs the package in another interpreter: ``[..., "-m", "sunset", ...]``, or a
    string of code or shell that imports or runs it (``"import sunset..."``, ``"python -m sunset ..."``)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return bool(re.search(r"\b(import|from)\s+sunset\b|-m\s+sunset\b", node.value))
    items = node.elts if isinstance(node, (ast.List, ast.Tuple)) else node.args if isinstance(node, ast.Call) else []
    words = [n.value if isinstance(n, ast.Constant) else None for n in items]
    return any(a == "-m" and isinstance(b, str) and b.split(".")[0] == "sunset" for a, b in zip(words, words[1:]))


def package_data(module: str) -> set[Path]:
    """The package's data files that ``module`` may read with ``importlib.resources``.

    Those beside it, and those in the package folders whose names its source
    spells (``resources.files("sunset") / "scenes"``).
    """
    path = deps.module_file(module)
    source = path.read_text(encoding="utf-8")
    if "resources" not in source:
        return set()
    words = {n.value for n in ast.walk(ast.parse(source)) if isinstance(n, ast.Constant) and isinstance(n.value, str)}
    folders = {path.parent} | {d for d in PACKAGE.rglob("*") if d.is_dir() and d.name in words}
    return {f for d in folders for f in d.iterdir()
            if f.is_file() and f.suffix not in (".py", ".pyc") and "__pycache__" not in f.parts}


def book_files(cells: list[str], folder: Path) -> set[Path]:
    """Files under the chapter's folder (the cells' working directory) that the cells' strings name."""
    found = set()
    for cell in cells:
        try:
            tree = ast.parse(_python(cell))
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.strip(" ./"):
                text = node.value
                if "\n" in text or len(text) > 200:
                    continue
                try:
                    target = (folder / text).resolve()
                    if not target.is_relative_to(folder) or "_build" in target.relative_to(folder).parts:
                        continue
                    is_file = target.is_file()
                except (OSError, ValueError):                   # not a name a file could have
                    continue
                if is_file:
                    found.add(target)
                elif target.is_dir():
                    found |= {f for f in target.rglob("*") if f.is_file() and "_build" not in f.parts}
    return found


def environment() -> list[str]:
    """The interpreter and every installed distribution with its version, sorted."""
    dists = {f"{(d.metadata['Name'] or '?').lower()}=={d.version}" for d in metadata.distributions()}
    return [f"python=={sys.version.split()[0]}", *sorted(dists)]


@dataclass(frozen=True)
class Fingerprint:
    """What a chapter's outputs were computed from: file -> SHA-256 of its content, and the environment."""

    files: dict[str, str]
    environment: str

    @property
    def key(self) -> str:
        text = "\n".join(f"{path} {digest}" for path, digest in sorted(self.files.items()))
        return hashlib.sha256(f"{text}\n{self.environment}".encode()).hexdigest()

    def changed(self, files: dict[str, str]) -> list[str]:
        """The files that differ from (or are missing in, or new beside) an earlier fingerprint's ``files``."""
        return sorted(p for p in set(files) | set(self.files) if files.get(p) != self.files.get(p))


def chapter_modules(md: Path) -> set[str]:
    """The package modules a chapter's code cells load, transitively."""
    direct = set()
    for cell in code_cells(md.read_text(encoding="utf-8")):
        direct |= sunset_modules(cell)
    modules = set()
    for name in direct:
        if deps.module_file(name) is not None:
            modules |= deps.closure(name)
    return modules


def chapter_files(md: Path) -> list[Path]:
    """Every file (besides its own code cells) that a chapter's execution depends on, sorted."""
    modules = chapter_modules(md)
    files = {deps.module_file(m) for m in modules}
    for m in modules:
        files |= package_data(m)
    files |= book_files(code_cells(md.read_text(encoding="utf-8")), md.resolve().parent)
    return sorted(files)


def fingerprint(md: Path, env: str | None = None) -> Fingerprint:
    """The chapter's :class:`Fingerprint` (``env``: :func:`environment`, joined, computed once by the caller)."""
    files = {}
    for f in chapter_files(md):
        name = f.relative_to(ROOT).as_posix() if f.is_relative_to(ROOT) else str(f)
        files[name] = hashlib.sha256(f.read_bytes()).hexdigest()
    return Fingerprint(files, "\n".join(environment()) if env is None else env)


if __name__ == "__main__":
    for arg in sys.argv[1:]:
        path = Path(arg)
        print(f"{path}:")
        for f in chapter_files(path):
            print(f"  {f.relative_to(ROOT) if f.is_relative_to(ROOT) else f}")
