"""Which source files each figure file depends on: the Makefile's rules.

``make figures`` has one rule for each file in ``figures/``, so that make
rebuilds only what is out of date. This module writes those rules
(``make`` writes them to ``figures/.deps.mk`` and includes them): each figure file depends
on the package modules its builder can import, found statically by following
the ``import`` statements (also those inside functions) through the package,
and on the scene it renders.

A name imported from a package (``from ..model import Scene``) is followed to
the module that defines it when the package's ``__init__.py`` re-exports it,
so that a package ``__init__`` does not make every figure depend on every
module.

A rule's recipe is ``$(call figure,NAME[,READERS])`` (the Makefile defines
it): under ``make figures`` or ``make all`` it only adds NAME (and the figures
that read its files, :data:`READS`) to the figures out of date,
and ``figures`` then makes all of them in ONE ``sunset figures --only ...``
process (the imports, the compiled kernels, the shared frames and both cores
are paid for once); a file asked for by itself (``make figures/fig2.png``) is
made by its own process. The module runs with the standard library alone (the Makefile runs it
before the environment exists): ``python3 sunset/figures/deps.py``.
"""

from __future__ import annotations

import ast
import functools
import sys
from pathlib import Path

#: The package's folder (this file is sunset/figures/deps.py).
PACKAGE = Path(__file__).resolve().parents[1]
ROOT = PACKAGE.parent

#: Every file a figure rule writes -> (the figure's name for ``sunset figures --only``, the builder module).
TARGETS: dict[str, tuple[str, str]] = {
    "fig1.png": ("1", "sunset.figures.fig1"),
    "fig2.png": ("2", "sunset.figures.fig2"),
    "fig3.png": ("3", "sunset.figures.fig3"),
    "fig4.png": ("4", "sunset.figures.paper"),
    "fig5.png": ("5", "sunset.figures.paper"),
    "fig6.png": ("6", "sunset.figures.paper"),
    "fig7.png": ("7", "sunset.figures.paper"),
    "diagnostic.png": ("diagnostic", "sunset.figures.diagnostic"),
    "reflections.png": ("reflections", "sunset.figures.reflections"),
    "film.mp4": ("film", "sunset.recorder.film"),
    "fig6-rgb.png": ("rgb", "sunset.figures.rgb"),
    "quantisation.png": ("quantisation", "sunset.figures.rgb"),
    "clouds.png": ("clouds", "sunset.figures.future"),
    "ripples.png": ("ripples", "sunset.figures.future"),
}

#: Files a figure rule writes besides its target (same rule, grouped).
ALSO_WRITES = {"fig6.png": ("fig6.tape",), "film.mp4": ("film-preview.webp",), "clouds.png": ("clouds-rgb.png",)}

#: Figures that read a file another rule writes (Figure 7 re-exposes Figure 6's tape): under ``make figures``
#: the writer's rule names the reader too, since rewriting the file makes the reader out of date.
READS = {"7": "fig6.tape"}

#: Figures that do not render the default scene (Figure 2 plots Stokes waves; the ripples have their own scene).
NO_SCENE = {"2", "ripples"}

#: Packaged scenes a figure loads besides (or instead of) the default one.
OTHER_SCENES = {"clouds": ("carlas-island-clouds",), "ripples": ("post-in-the-swell",)}

#: Modules every figure goes through: the command line and the figure registry.
COMMON = ("sunset.__main__", "sunset.cli", "sunset.figures")

#: The scene every other figure renders.
DEFAULT_SCENE = "sunset/scenes/carlas-island.toml"


@functools.lru_cache(maxsize=None)
def module_file(name: str) -> Path | None:
    """The source file of a dotted module name inside the package, or None."""
    parts = name.split(".")
    if parts[0] != "sunset":
        return None
    base = PACKAGE.joinpath(*parts[1:])
    if (base / "__init__.py").is_file():
        return base / "__init__.py"
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py")
    return None


def _package_of(name: str) -> str:
    f = module_file(name)
    return name if f is not None and f.name == "__init__.py" else name.rpartition(".")[0]


def _absolute(module: str, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = _package_of(module).split(".")
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


@functools.lru_cache(maxsize=None)
def _imports(name: str, top_level: bool = False) -> tuple[str, ...]:
    """Dotted names of the package modules that ``name`` imports: anywhere in its source, or at its top level.

    Each module is read once per run (every figure's closure asks for the same modules).
    """
    path = module_file(name)
    if path is None:
        return ()
    return imports_in(ast.parse(path.read_text(encoding="utf-8"), str(path)), name, top_level)


def imports_in(tree: ast.AST, name: str = "__main__", top_level: bool = False) -> tuple[str, ...]:
    """Dotted names of the package modules that the parsed source ``tree`` of module ``name`` imports.

    A name imported from a package that re-exports it is followed to its defining module
    (:func:`_defining_module`). ``book/chapter_deps.py`` reads a chapter's code cells with it.
    """
    out = []
    for node in (tree.body if top_level else ast.walk(tree)):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names if a.name.split(".")[0] == "sunset"]
        elif isinstance(node, ast.ImportFrom):
            target = _absolute(name, node)
            if target.split(".")[0] != "sunset":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if module_file(sub) is not None:
                    out.append(sub)
                else:
                    out.append(_defining_module(target, alias.name))
    return tuple(out)


@functools.lru_cache(maxsize=None)
def lazy_api(package: str) -> dict[str, str]:
    """The names a package's ``__init__.py`` loads on first use (its ``_API`` table, PEP 562) -> their modules.

    ``sunset/__init__.py`` imports its public names lazily, so ``from sunset import render`` names no
    module in an ``import`` statement: the table says which one it loads.
    """
    path = module_file(package)
    if path is None or path.name != "__init__.py":
        return {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        target = node.target if isinstance(node, ast.AnnAssign) else (
            node.targets[0] if isinstance(node, ast.Assign) and len(node.targets) == 1 else None)
        if isinstance(target, ast.Name) and target.id == "_API" and node.value is not None:
            table = ast.literal_eval(node.value)
            return {name: package + module if module.startswith(".") else module for name, module in table.items()}
    return {}


@functools.lru_cache(maxsize=None)
def _defining_module(package: str, name: str) -> str:
    """The module that a package re-exports (or lazily loads) ``name`` from, or the package itself."""
    path = module_file(package)
    if path is None or path.name != "__init__.py":
        return package
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.ImportFrom) and any((a.asname or a.name) == name for a in node.names):
            target = _absolute(package, node)
            sub = f"{target}.{name}"
            return sub if module_file(sub) is not None else target
    return lazy_api(package).get(name, package)


def closure(start: str, router: bool = False) -> set[str]:
    """``start`` and every package module it imports, directly or not.

    The imports of a package's ``__init__.py`` are not followed (it only
    re-exports; the names imported through it are followed to their modules),
    but the ``__init__.py`` files of the packages on the way are included. A
    ``router`` (the command line, the figure registry) imports each command's
    or figure's modules inside the function that runs it: only its top-level
    imports are followed.
    """
    seen: set[str] = {start}
    todo = list(_imports(start, top_level=router)) + [".".join(start.split(".")[:i]) for i in range(1, start.count(".") + 1)]
    while todo:
        name = todo.pop()
        if name in seen or module_file(name) is None:
            continue
        seen.add(name)
        parts = name.split(".")
        todo += [".".join(parts[:i]) for i in range(1, len(parts))]
        path = module_file(name)
        if path.name != "__init__.py":
            todo += _imports(name, top_level=name in COMMON)
    return seen


def dependencies(target: str) -> list[str]:
    """Source files (relative to the repository) that ``figures/<target>`` depends on, sorted."""
    figure, builder = TARGETS[target]
    modules = closure(builder)
    for router in COMMON:
        modules |= closure(router, router=True)
    files = {module_file(m).relative_to(ROOT).as_posix() for m in modules}
    if figure not in NO_SCENE:
        files.add(DEFAULT_SCENE)
    files.update(f"sunset/scenes/{name}.toml" for name in OTHER_SCENES.get(figure, ()))
    return sorted(files)


def rules(out: str = "figures") -> str:
    """The Makefile rules for every figure file, in a form ``make`` includes."""
    lines = ["# Written by `python3 sunset/figures/deps.py` (make regenerates it): do not edit.",
             f"FIGURE_FILES := {' '.join(f'{out}/{t}' for t in TARGETS)} "
             + " ".join(f"{out}/{x}" for xs in ALSO_WRITES.values() for x in xs), ""]
    for target, (figure, _) in TARGETS.items():
        files = (target, *ALSO_WRITES.get(target, ()))
        outputs = " ".join(f"{out}/{x}" for x in files)
        grouped = " &:" if target in ALSO_WRITES else ":"
        extra = f" {out}/{READS[figure]}" if figure in READS else ""
        readers = " ".join(name for name, read in READS.items() if read in files)
        lines.append(f"{outputs}{grouped} {' '.join(dependencies(target))}{extra} $(FIGURE_ENV)")
        lines.append(f"\t$(call figure,{figure}{',' + readers if readers else ''})")
        lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.stdout.write(rules(*sys.argv[1:]))
