"""The book's API reference (book/api.md) documents every public name of the package."""

import re
from pathlib import Path

import sunset

API = (Path(__file__).resolve().parents[1] / "book" / "api.md").read_text(encoding="utf-8")


def documented() -> set[str]:
    names = re.findall(r"^\.\. (?:auto(?:function|class|exception|data)|py:data):: sunset\.(\w+)\s*$", API, re.M)
    return set(names)


def test_every_public_name_is_in_the_api_reference():
    missing = sorted(set(sunset.__all__) - documented())
    assert not missing, f"book/api.md lacks {missing}"


def test_the_api_reference_names_only_public_names():
    assert documented() <= set(sunset.__all__)


def test_the_public_names_exist():
    for name in sunset.__all__:
        assert hasattr(sunset, name), name


def documented_objects():
    """Every object book/api.md has autodoc render: the directives' targets and their listed members."""
    import importlib

    out = []
    for kind, target, members in re.findall(
            r"^\.\. auto(function|class|exception):: ([\w.]+)\n(?:   :members: ([\w, ]+)\n)?", API, re.M):
        module, _, name = target.rpartition(".")
        obj = getattr(importlib.import_module(module), name)
        out.append((target, obj))
        for member in filter(None, (m.strip() for m in (members or "").split(","))):
            out.append((f"{target}.{member}", getattr(obj, member)))
    return out


def test_docstrings_the_reference_renders_are_valid_restructuredtext():
    """A bare |x| is a reStructuredText substitution: autodoc fails the book's strict build on it.

    Write ``|R_z|`` (literal) instead. Checked here so that the test suite says so before the book does.
    """
    objs = documented_objects()
    assert len(objs) > 20
    for target, obj in objs:
        doc = getattr(obj, "fget", obj).__doc__ or ""
        bare = re.sub(r"``.*?``", "", doc, flags=re.S)
        found = re.findall(r"(?<![|\w])\|[^|\s][^|\n]*\|(?![|\w])", bare)
        assert not found, f"{target}: bare {found[0]!r} in its docstring (write ``{found[0]}``)"
