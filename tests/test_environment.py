"""pyproject.toml and environment.yml declare the same environment.

The set of (package name, version constraint) pairs of the runtime
dependencies plus the ``book`` and ``test`` extras in pyproject.toml must
equal the set of packages in environment.yml (conda and pip sections), and
the Python constraint must match ``requires-python``. The Makefile must
install extras that exist. environment.yml is read with a small line parser
(PyYAML is not a test dependency), so the file keeps the plain
``- name constraint`` form.
"""

import re
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.specifiers import SpecifierSet
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
EXTRAS = ("book", "test")
#: Conda entries that are tools of conda itself, not project dependencies.
CONDA_ONLY = {"pip", "python"}


def normal(requirement: str) -> tuple[str, str]:
    """(canonical name, sorted specifier) of one requirement string."""
    req = Requirement(requirement)
    if req.marker is not None or req.extras or req.url:
        raise ValueError(f"keep requirements plain (no markers, extras or URLs): {requirement!r}")
    return canonicalize_name(req.name), str(SpecifierSet(str(req.specifier)))


def pyproject_requirements(text: str) -> tuple[set[tuple[str, str]], str]:
    project = tomllib.loads(text)["project"]
    reqs = list(project["dependencies"])
    for extra in EXTRAS:
        reqs += project["optional-dependencies"][extra]
    return {normal(r) for r in reqs}, str(SpecifierSet(project["requires-python"]))


def environment_requirements(text: str) -> tuple[set[tuple[str, str]], str | None, str]:
    """Packages of environment.yml (conda and pip lists), its python spec and env name."""
    name = None
    python = None
    reqs = set()
    in_deps = False
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].rstrip()
        if not line.strip():
            continue
        top = re.match(r"^(\w[\w-]*):\s*(.*)$", line)
        if top:
            in_deps = top.group(1) == "dependencies"
            if top.group(1) == "name":
                name = top.group(2).strip()
            continue
        if not in_deps:
            continue
        item = re.match(r"^\s*-\s*(.+?)\s*$", line)
        if not item or item.group(1).endswith(":"):
            continue  # the "- pip:" header of the pip sub-list
        spec = item.group(1).replace(" ", "")
        if "=" in spec and not re.search(r"[<>!=~]=|[<>]", spec):
            raise ValueError(f"write conda pins with ==, not =: {spec!r}")
        pkg, constraint = normal(spec)
        if pkg == "python":
            python = constraint
        elif pkg not in CONDA_ONLY:
            reqs.add((pkg, constraint))
    return reqs, python, name


def disagreements(pyproject_text: str, environment_text: str) -> list[str]:
    """Human-readable differences between the two declarations (empty: they agree)."""
    py_reqs, py_python = pyproject_requirements(pyproject_text)
    env_reqs, env_python, _ = environment_requirements(environment_text)
    out = []
    for name, spec in sorted(py_reqs - env_reqs):
        out.append(f"pyproject.toml has {name}{spec}, environment.yml "
                   + (f"has {name}{dict(env_reqs).get(name)}" if name in dict(env_reqs) else "lacks it"))
    for name, spec in sorted(env_reqs - py_reqs):
        if name not in dict(py_reqs):
            out.append(f"environment.yml has {name}{spec}, pyproject.toml lacks it")
    if env_python != py_python:
        out.append(f"python: environment.yml says {env_python!r}, requires-python says {py_python!r}")
    return out


PYPROJECT = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
ENVIRONMENT = (ROOT / "environment.yml").read_text(encoding="utf-8")


def test_pyproject_and_environment_agree():
    problems = disagreements(PYPROJECT, ENVIRONMENT)
    assert not problems, "pyproject.toml and environment.yml disagree:\n" + "\n".join(problems)


def test_environment_is_named_after_the_distribution_and_lists_everything():
    reqs, python, name = environment_requirements(ENVIRONMENT)
    assert name == tomllib.loads(PYPROJECT)["project"]["name"] == "sunset-waves"
    assert python is not None
    names = {n for n, _ in reqs}
    for needed in ("numpy", "scipy", "matplotlib", "colour-science", "pillow", "imageio",
                   "imageio-ffmpeg", "jupyter-book", "sphinxcontrib-bibtex", "sphinx-mathjax-offline",
                   "pytest", "hypothesis"):
        assert needed in names


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace("  - scipy>=1.13\n", ""), "environment.yml lacks it"),
    (lambda t: t.replace("  - scipy>=1.13\n", "  - scipy>=1.14\n"), "environment.yml has scipy>=1.14"),
    (lambda t: t.replace("  - scipy>=1.13\n", "  - scipy>=1.13\n  - pandas\n"), "pyproject.toml lacks it"),
    (lambda t: t.replace("  - jupyter-book>=1,<2\n", "  - jupyter-book<2,>=1\n"), None),  # same set
    (lambda t: t.replace("  - python>=3.11\n", "  - python>=3.10\n"), "python:"),
    (lambda t: t.replace("      - sphinx-mathjax-offline>=0.0.2\n", ""), "sphinx-mathjax-offline"),
])
def test_a_disagreement_is_caught(edit, words):
    edited = edit(ENVIRONMENT)
    assert edited != ENVIRONMENT or words is None
    problems = disagreements(PYPROJECT, edited)
    if words is None:
        assert problems == []
    else:
        assert any(words in p for p in problems), problems


def test_a_disagreement_in_pyproject_is_caught():
    edited = PYPROJECT.replace('"hypothesis>=6.100"', '"hypothesis>=6.100", "pytest-xdist"')
    assert edited != PYPROJECT
    assert any("pytest-xdist" in p for p in disagreements(edited, ENVIRONMENT))


def test_makefile_installs_the_locks_of_extras_that_exist():
    """The Makefile installs the locked environments; `make lock` compiles them from extras that exist."""
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    extras = set(tomllib.loads(PYPROJECT)["project"]["optional-dependencies"])
    used = set(re.findall(r"--extra (\w+)", makefile))
    assert used and used <= extras
    assert set(EXTRAS) <= used
    assert "--require-hashes -r requirements/test.lock" in makefile
    assert "--require-hashes -r requirements/book.lock" in makefile
    # The stamps depend on pyproject.toml and the lock, so a change of dependencies reinstalls.
    assert re.search(r"^\$\(VENV\)/\.stamp-test: pyproject\.toml requirements/test\.lock", makefile, re.M)
    assert re.search(r"^\$\(VENV\)/\.stamp-book: pyproject\.toml requirements/book\.lock", makefile, re.M)
