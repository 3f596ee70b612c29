"""The lock files pin an environment that satisfies pyproject.toml.

``requirements/*.lock`` (written by ``make lock`` with uv) pin every package
of the runtime, ``test`` and ``book`` environments to one version, each with
its sha256 hashes; ``make`` installs from them with ``pip --require-hashes``.
These tests read the locks with a small parser of their own and check them
against pyproject.toml and environment.yml with ``packaging``:

* every requirement of the environment is pinned, and every pin of it
  satisfies the requirement's specifier;
* every pin is exact (``==``) and carries at least one sha256 hash;
* the three locks agree and nest: on every tested Python and platform, what
  the runtime lock installs the test lock installs at the same version, and
  what the test lock installs the book's does (markers are evaluated, not
  compared as text);
* every pin of a conda-listed package satisfies environment.yml too.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
from packaging.markers import Marker
from packaging.requirements import Requirement
from packaging.specifiers import SpecifierSet
from packaging.utils import canonicalize_name
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[1]
LOCKS = {"runtime": (), "test": ("test",), "book": ("test", "book")}
#: The Python versions the locks must cover (requires-python's lower bound and later releases).
PYTHONS = ("3.11", "3.12", "3.13")


def lock_path(name: str) -> Path:
    return ROOT / "requirements" / f"{name}.lock"


def parse_lock(text: str) -> list[tuple[str, Version, Marker | None, list[str]]]:
    """(canonical name, pinned version, marker or None, sha256 hashes) of every entry of a hashed lock."""
    entries = []
    joined = re.sub(r"\\\n", " ", text)
    for raw in joined.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line or line.startswith("-"):
            continue
        hashes = re.findall(r"--hash=sha256:([0-9a-f]{64})", line)
        spec = re.sub(r"--hash=\S+", "", line).strip()
        req = Requirement(spec)
        pins = list(req.specifier)
        if len(pins) != 1 or pins[0].operator != "==" or "*" in pins[0].version:
            raise ValueError(f"not an exact pin: {spec!r}")
        entries.append((canonicalize_name(req.name), Version(pins[0].version), req.marker, hashes))
    return entries


def project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def requirements_of(proj: dict, extras: tuple[str, ...]) -> list[Requirement]:
    reqs = [Requirement(r) for r in proj["dependencies"]]
    for extra in extras:
        reqs += [Requirement(r) for r in proj["optional-dependencies"][extra]]
    return reqs


def applies(marker: Marker | None, python: str) -> bool:
    """Whether a lock entry is installed on Linux with CPython ``python``."""
    if marker is None:
        return True
    return marker.evaluate({"python_version": python, "python_full_version": f"{python}.0",
                            "sys_platform": "linux", "platform_system": "Linux", "os_name": "posix",
                            "implementation_name": "cpython", "platform_python_implementation": "CPython",
                            "platform_machine": "x86_64", "extra": ""})


def problems(proj: dict, lock_text: str, extras: tuple[str, ...]) -> list[str]:
    """What is wrong with a lock against the project's requirements (empty: it satisfies them)."""
    out = []
    entries = parse_lock(lock_text)
    for name, version, marker, hashes in entries:
        if not hashes:
            out.append(f"{name}=={version} has no sha256 hash")
    for req in requirements_of(proj, extras):
        name = canonicalize_name(req.name)
        for python in PYTHONS:
            pins = [v for n, v, m, _ in entries if n == name and applies(m, python)]
            if len(pins) != 1:
                out.append(f"{name} is pinned {len(pins)} times for Python {python}, expected once")
            for v in pins:
                if not req.specifier.contains(v, prereleases=True):
                    out.append(f"{name}=={v} (Python {python}) does not satisfy pyproject.toml's {req}")
    return out


def test_locks_satisfy_pyproject():
    proj = project()
    for lock, extras in LOCKS.items():
        found = problems(proj, lock_path(lock).read_text(encoding="utf-8"), extras)
        assert not found, f"requirements/{lock}.lock:\n" + "\n".join(found)


def test_a_lock_that_does_not_satisfy_pyproject_is_caught():
    proj = project()
    text = lock_path("test").read_text(encoding="utf-8")
    # a requirement the lock cannot meet
    stricter = dict(proj, dependencies=[*proj["dependencies"], "numpy>=99"])
    assert any("numpy" in p and "does not satisfy" in p for p in problems(stricter, text, ("test",)))
    # a requirement the lock does not pin at all
    more = dict(proj, dependencies=[*proj["dependencies"], "pandas>=2"])
    assert any(p.startswith("pandas is pinned 0 times") for p in problems(more, text, ("test",)))
    # a pin without its hash
    unhashed = re.sub(r"(?m)^(tqdm==[^\s]+)[^\n]*\\\n(\s+--hash=[^\n]*\n)+", r"\1\n", text)
    assert unhashed != text
    assert any(p.startswith("tqdm==") and "no sha256 hash" in p for p in problems(proj, unhashed, ("test",)))


#: The platforms a lock is checked on: (sys_platform, platform_system, os_name, platform_machine).
PLATFORMS = (("linux", "Linux", "posix", "x86_64"), ("linux", "Linux", "posix", "aarch64"),
             ("darwin", "Darwin", "posix", "arm64"), ("win32", "Windows", "nt", "AMD64"))


def installed(entries, python: str, platform: tuple[str, str, str, str]) -> dict[str, Version]:
    """{name: version} that a lock installs with CPython ``python`` on ``platform`` (its markers evaluated)."""
    sys_platform, system, os_name, machine = platform
    env = {"python_version": python, "python_full_version": f"{python}.0", "sys_platform": sys_platform,
           "platform_system": system, "os_name": os_name, "implementation_name": "cpython",
           "platform_python_implementation": "CPython", "platform_machine": machine, "extra": ""}
    return {n: v for n, v, m, _ in entries if m is None or m.evaluate(env)}


def nesting_problems(small_text: str, big_text: str) -> list[str]:
    """Where the smaller lock installs a package the bigger one does not, or another version of it.

    Compared by what each lock installs on every tested Python and platform, so that the same
    set written with different markers (uv widens a marker when a second dependent appears) agrees.
    """
    small, big = parse_lock(small_text), parse_lock(big_text)
    out = []
    for python in PYTHONS:
        for platform in PLATFORMS:
            a, b = installed(small, python, platform), installed(big, python, platform)
            for name, version in sorted(a.items()):
                if b.get(name) != version:
                    out.append(f"{name}=={version} on Python {python}, {platform[0]}/{platform[3]}: "
                               f"the bigger lock has {b.get(name)}")
    return out


def test_the_locks_agree_and_nest():
    for small, big in (("runtime", "test"), ("test", "book")):
        found = nesting_problems(lock_path(small).read_text(encoding="utf-8"),
                                 lock_path(big).read_text(encoding="utf-8"))
        assert not found, f"{small}.lock installs what {big}.lock does not:\n" + "\n".join(found[:20])


def test_a_lock_that_does_not_nest_is_caught():
    test_text = lock_path("test").read_text(encoding="utf-8")
    book_text = lock_path("book").read_text(encoding="utf-8")
    # another version of numpy in the smaller lock
    bumped = re.sub(r"(?m)^numpy==[^\s;]+", "numpy==1.0.0", test_text)
    assert bumped != test_text
    assert any(p.startswith("numpy==1.0.0") for p in nesting_problems(bumped, book_text))
    # a package the bigger lock leaves out on one platform only
    narrowed = re.sub(r"(?m)^(tqdm==[^\s;]+)", r"\1 ; sys_platform != 'win32'", book_text)
    assert narrowed != book_text
    assert any(p.startswith("tqdm==") and "win32" in p for p in nesting_problems(test_text, narrowed))


def test_locks_are_made_by_make_lock():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^lock:", makefile, re.M)
    for name in LOCKS:
        text = lock_path(name).read_text(encoding="utf-8")
        assert "make lock" in text.split("\n\n", 1)[0], f"{name}.lock does not say how it is refreshed"
        # `make` installs from the lock, with hashes checked
        assert f"--require-hashes -r requirements/{name}.lock" in makefile or name == "runtime"


@pytest.mark.parametrize("python", PYTHONS)
def test_environment_yml_accepts_the_locked_versions(python):
    """Every locked version of a package environment.yml lists satisfies environment.yml's constraint."""
    env = {}
    in_deps = False
    for raw in (ROOT / "environment.yml").read_text(encoding="utf-8").splitlines():
        line = raw.split("#", 1)[0].rstrip()
        if re.match(r"^\w", line):
            in_deps = line.startswith("dependencies:")
            continue
        item = re.match(r"^\s*-\s*([A-Za-z][\w.-]*)\s*([<>=!~,.\w]*)\s*$", line)
        if in_deps and item:
            env[canonicalize_name(item.group(1))] = SpecifierSet(item.group(2))
    assert "numpy" in env and "jupyter-book" in env
    for name, version, marker, _ in parse_lock(lock_path("book").read_text(encoding="utf-8")):
        if name in env and applies(marker, python):
            assert env[name].contains(version, prereleases=True), f"{name}=={version} vs environment.yml {env[name]}"
