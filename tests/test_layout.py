"""The package's layout: folders along the paper's pipeline, imports only down it, rooms of modest size.

Independent of the modules' behaviour: reads their source with ``ast``.
"""

import ast
import importlib
from pathlib import Path

import pytest

from sunset import kernels

PACKAGE = Path(__file__).resolve().parents[1] / "sunset"

#: The pipeline's stages from the bottom up; a module may import its own stage and those below it.
#: ``light`` (the RGB back end) stands beside ``tape`` and ``recorder``: it may use the model and the
#: vector stage, never the 8-bit path, and the 8-bit path never uses it.
RANK = {"model": 0, "vector": 1, "tape": 2, "recorder": 3, "light": 2}
#: Modules at the top of the package that any stage may import (they import no stage).
UTILITIES = {"errors", "constants", "io", "kernels", "provenance", "guard", "escape", "__version__"}
#: What sits on top of the pipeline and may import anything.
TOP = {"figures", "cli", "bench", "gallery", "pictures", "explorer", "__init__", "__main__"}
MAX_LINES = 500


def modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).with_suffix("")
        yield path, rel.parts


def imported(path: Path, parts) -> set[tuple[str, ...]]:
    """Every sunset module imported anywhere in the file (also inside functions), as path parts under sunset/."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    pkg = list(parts[:-1])
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg[: len(pkg) - (node.level - 1)]
                target = base + (node.module.split(".") if node.module else [])
            elif node.module and node.module.split(".")[0] == "sunset":
                target = node.module.split(".")[1:]
            else:
                continue
            if node.module is None or not target:
                for alias in node.names:
                    out.add(tuple(target + [alias.name]))
            else:
                out.add(tuple(target))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "sunset":
                    out.add(tuple(alias.name.split(".")[1:]))
    return {t for t in out if t}


def stage(parts) -> str:
    return parts[0] if len(parts) > 1 else parts[0]


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_imports_run_only_down_the_pipeline(path, parts):
    me = stage(parts)
    if me in TOP or me == "scenes":
        return
    for target in imported(path, parts):
        other = target[0]
        if other in UTILITIES:
            continue
        assert me not in UTILITIES, f"{'/'.join(parts)} is a utility but imports the stage {other}"
        assert other in RANK, f"{'/'.join(parts)} imports {'.'.join(target)}, which is above the pipeline"
        if other == me:
            continue
        assert RANK[other] < RANK[me], f"{'/'.join(parts)} ({me}) imports {'.'.join(target)} ({other}): not down"
        assert not (me == "light" and other in ("tape", "recorder")), "the RGB back end must not use the 8-bit path"


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_no_stage_imports_a_numba_twin(path, parts):
    """The twins are chosen by sunset.kernels alone; only a twin may import another twin."""
    if parts[-1].endswith("_numba") or parts[0] in TOP:
        return
    for target in imported(path, parts):
        assert not target[-1].endswith("_numba"), f"{'/'.join(parts)} imports the twin {'.'.join(target)}"


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_modules_are_rooms_of_modest_size(path, parts):
    n = len(path.read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{'/'.join(parts)} has {n} lines: split it where it holds two ideas"


def twin_kernels():
    found = []
    for path, parts in modules():
        if parts[-1].endswith("_numba") or parts[0] in TOP:
            continue
        mod = importlib.import_module("sunset." + ".".join(parts))
        for name, obj in vars(mod).items():
            if callable(obj) and hasattr(obj, "reference") and hasattr(obj, "compiled") \
                    and getattr(obj, "__module__", None) == mod.__name__:
                found.append((mod.__name__, name, obj))
    return found


def test_every_twin_kernel_has_its_compiled_twin():
    found = twin_kernels()
    assert len(found) >= 7, [f"{m}.{n}" for m, n, _ in found]
    for module, name, kernel in found:
        twin = kernel.compiled()
        assert callable(twin) and twin is not kernel.reference, f"{module}.{name}"
        assert twin.__name__ == name and twin.__module__.endswith("_numba"), f"{module}.{name} -> {twin.__module__}"


def test_the_switch_decides_which_runs(monkeypatch):
    calls = []

    @kernels.twin("sunset.vector.heightfield_numba")
    def sea_scan(*args):
        calls.append("reference")
        return "reference"

    with kernels.use_compiled(False):
        assert sea_scan() == "reference"
    assert calls == ["reference"]
    if kernels.AVAILABLE:
        import sunset.vector.heightfield_numba as twin_module
        monkeypatch.setattr(twin_module, "sea_scan", lambda *a: "twin")
        with kernels.use_compiled(True):
            assert sea_scan() == "twin"
