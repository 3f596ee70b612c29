"""The package's layout: the model, the stages side by side, the pipeline that chains them; no import circles;
rooms of modest size.

Independent of the modules' behaviour: reads their source with ``ast`` and ``tokenize``.
"""

import ast
import importlib
import io
import tokenize
from pathlib import Path

import pytest

from sunset import kernels

PACKAGE = Path(__file__).resolve().parents[1] / "sunset"

#: The layers from the bottom up: a module imports its own folder and the layers below it, never a layer
#: beside or above it. The model (the scene and its mathematics) at the bottom; the stages side by side
#: above it, each a set of strip kernels (a strip of rays or pixels and the data it needs in, the strip's
#: result out: the vector stage's rays, the tape's codes, the film recorder's exposure, the RGB back end's
#: shading), so that no stage runs another; the pipeline above them, the one layer that chains them and
#: holds the threads, the worker processes and the work budget.
RANK = {"model": 0, "vector": 1, "tape": 1, "recorder": 1, "light": 1, "pipeline": 2}
STAGES = {name for name, rank in RANK.items() if rank == 1}
#: What one stage hands another, the data and never the work: the frame's fields, what a code means, the tape
#: on disk; and the geometry of a ray against an island, which the reflected rays and the light on the shores
#: both use. A stage may import these modules of another stage; they import no stage module but each other.
INTERFACES = {("vector", "frame"), ("vector", "pierce"), ("tape", "codemap"), ("tape", "tapefile")}
#: Modules at the top of the package that any layer may import (they import no layer).
UTILITIES = {"errors", "constants", "io", "kernels", "provenance", "guard", "escape", "__version__"}
#: What sits on top of the pipeline and may import anything.
TOP = {"figures", "cli", "bench", "gallery", "pictures", "explorer", "__init__", "__main__"}
#: Lines of code in a module at most: docstrings, comments and blank lines are not counted, so that no
#: module is split for its documentation's sake (the largest module, cli.py, has 382).
MAX_CODE_LINES = 400


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
            if node.module is not None and target:
                out.add(tuple(target))
            for alias in node.names:         # a submodule (from ..model import waves) or a name in the module
                out.add(tuple(target + [alias.name]))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "sunset":
                    out.add(tuple(alias.name.split(".")[1:]))
    return {t for t in out if t}


def module_file(target) -> tuple[str, ...] | None:
    """The module an import names: ``target`` itself, its package, or the module holding the name it imports."""
    names = {parts for _, parts in modules()}
    for candidate in (target, target + ("__init__",), target[:-1], target[:-1] + ("__init__",)):
        if candidate in names:
            return candidate
    return None


def import_graph() -> dict:
    """Every module's imports of other sunset modules (inside functions too), as path parts."""
    graph = {}
    for path, parts in modules():
        found = {module_file(t) for t in imported(path, parts)}
        assert None not in found, f"{'/'.join(parts)} imports a sunset name that is no module: " \
                                  f"{sorted(t for t in imported(path, parts) if module_file(t) is None)}"
        graph[parts] = found - {parts}
    return graph


def circles(graph: dict) -> list[list]:
    """The strongly connected components of more than one module (Tarjan): each holds an import circle."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted("/".join(m) for m in component))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_no_import_circles():
    """No module imports itself round a circle, counting the imports inside functions."""
    assert circles(import_graph()) == []


def test_the_circle_finder_finds_circles():
    graph = {("a",): {("b",)}, ("b",): {("c",)}, ("c",): {("a",)}, ("d",): {("a",)}, ("e",): set()}
    assert circles(graph) == [["a", "b", "c"]]
    graph[("c",)] = set()
    assert circles(graph) == []


def test_imported_counts_imports_inside_functions(tmp_path):
    source = tmp_path / "m.py"
    source.write_text("def f():\n    from ..model import waves\n    from .frame import Frame\n", encoding="utf-8")
    assert imported(source, ("vector", "m")) == {("model",), ("model", "waves"), ("vector", "frame"),
                                                 ("vector", "frame", "Frame")}
    assert {module_file(t) for t in imported(source, ("vector", "m"))} == {("model", "__init__"), ("model", "waves"),
                                                                         ("vector", "frame")}


def layer_violations(path, parts) -> list[str]:
    """The imports of a module that go beside or above its layer (a stage running or reading another)."""
    me = parts[0]
    if me in TOP or me == "scenes":
        return []
    found = []
    # each module once: a folder alone (from ..model import waves) comes with the module it names
    for target in sorted({t[:2] for t in imported(path, parts) if len(t) > 1 or t[0] in UTILITIES}):
        other = target[0]
        if other in UTILITIES:
            continue
        if me in UTILITIES:
            found.append(f"{'/'.join(parts)} is a utility but imports the layer {other}")
        elif other not in RANK:
            found.append(f"{'/'.join(parts)} imports {'.'.join(target)}, which is above the pipeline")
        elif other == me or RANK[other] < RANK[me]:
            continue
        elif me in STAGES and tuple(target[:2]) in INTERFACES:
            continue
        else:
            where = "beside" if RANK[other] == RANK[me] else "above"
            found.append(f"{'/'.join(parts)} ({me}) imports {'.'.join(target)} ({other}), {where} its layer")
    return found


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_imports_run_only_down_the_layers(path, parts):
    assert layer_violations(path, parts) == []


def test_the_layer_rule_refuses_a_stage_running_another(tmp_path):
    source = tmp_path / "m.py"
    source.write_text("from ..vector.render import render\nfrom ..vector.frame import Frame\n", encoding="utf-8")
    assert len(layer_violations(source, ("tape", "m"))) == 1                 # render runs the vector stage
    assert layer_violations(source, ("pipeline", "m")) == []                 # the pipeline chains the stages
    source.write_text("def f():\n    from ..pipeline import frame\n", encoding="utf-8")
    assert len(layer_violations(source, ("light", "m"))) == 1                # a stage never calls up


def test_interfaces_import_no_stage():
    for stage, name in sorted(INTERFACES):
        path = PACKAGE / stage / f"{name}.py"
        for target in imported(path, (stage, name)):
            assert target[0] in UTILITIES or target[0] == "model" or tuple(target[:2]) in INTERFACES, \
                f"{stage}/{name} is what stages hand each other but imports {'.'.join(target)}"


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_no_stage_imports_a_numba_twin(path, parts):
    """The twins are chosen by sunset.kernels alone; only a twin may import another twin."""
    if parts[-1].endswith("_numba") or parts[0] in TOP:
        return
    for target in imported(path, parts):
        assert not target[-1].endswith("_numba"), f"{'/'.join(parts)} imports the twin {'.'.join(target)}"


def code_lines(text: str) -> int:
    """Lines that hold code: not blank, not only a comment, not part of a docstring (a string statement)."""
    docs = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
            docs.update(range(node.lineno, node.end_lineno + 1))
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT, tokenize.ENCODING,
            tokenize.ENDMARKER}
    lines = set()
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type not in skip:
            lines.update(range(token.start[0], token.end[0] + 1))
    return len(lines - docs)


def test_code_lines_leave_out_the_documentation():
    text = ('"""A module.\n\nIts docstring.\n"""\n\n# a comment\nimport os  # and one after code\n\n\n'
            'def f(x):\n    """What f does,\n    on two lines."""\n    s = """a string\n    that is data"""\n'
            '    return (x +\n            1)\n')
    assert code_lines(text) == 6          # the import, the def, the string's two lines, the return's two
    assert code_lines("") == 0


@pytest.mark.parametrize("path, parts", list(modules()), ids=lambda v: "/".join(v) if isinstance(v, tuple) else "")
def test_modules_are_rooms_of_modest_size(path, parts):
    n = code_lines(path.read_text(encoding="utf-8"))
    assert n <= MAX_CODE_LINES, f"{'/'.join(parts)} has {n} lines of code: split it where it holds two ideas"


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
