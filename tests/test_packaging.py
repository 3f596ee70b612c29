"""The package as people install, cite and read it on a package index.

The distribution name, licence, version, URLs and citation say the same thing
in pyproject.toml, the installed metadata, CITATION.cff, README.md and
environment.yml; the sdist carries what the test suite reads.
"""

from __future__ import annotations

import re
import tomllib
from importlib import metadata
from pathlib import Path

import pytest

import sunset
from sunset.provenance import DISTRIBUTION

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
README = (ROOT / "README.md").read_text(encoding="utf-8")
CITATION = (ROOT / "CITATION.cff").read_text(encoding="utf-8")


def cff_value(key: str, text: str = CITATION) -> str:
    """A top-level scalar of CITATION.cff (a small line reader: PyYAML is not a test dependency)."""
    m = re.search(rf"^{key}:\s*(.+?)\s*$", text, re.M)
    assert m, f"CITATION.cff has no {key}"
    return m.group(1).strip().strip('"')


def test_the_distribution_name_is_used_everywhere():
    assert PROJECT["name"] == DISTRIBUTION == "sunset-waves"
    assert f"pip install {DISTRIBUTION}" in README
    assert DISTRIBUTION in (ROOT / "environment.yml").read_text(encoding="utf-8")
    assert DISTRIBUTION in cff_value("title")


def test_licence_is_mit_in_spdx_form():
    assert PROJECT["license"] == "MIT"          # a string: the SPDX expression, not the old table
    assert PROJECT["license-files"] == ["LICENSE"]
    assert (ROOT / "LICENSE").read_text(encoding="utf-8").startswith("MIT License\n")
    assert cff_value("license") == "MIT"
    assert "License ::" not in " ".join(PROJECT["classifiers"])   # PEP 639: the expression replaces them


def test_metadata_a_package_index_shows():
    assert PROJECT["authors"] and all(a.get("name") for a in PROJECT["authors"])
    assert len(PROJECT["keywords"]) >= 5
    assert "Typing :: Typed" in PROJECT["classifiers"]
    assert (ROOT / "sunset" / "py.typed").is_file()
    urls = PROJECT["urls"]
    for key in ("Homepage", "Documentation", "Repository", "Issues"):
        assert urls[key].startswith("https://")
    assert cff_value("repository-code") == urls["Repository"]
    assert cff_value("url") == urls["Documentation"]


def test_the_version_has_one_source():
    version = PROJECT["version"]
    for source in (ROOT / "sunset").rglob("*.py"):
        assert f'"{version}"' not in source.read_text(encoding="utf-8"), f"{source} writes the version out"
    assert sunset.__version__ == metadata.version(DISTRIBUTION) == PROJECT["version"]
    assert cff_value("version") == PROJECT["version"]


def test_installed_metadata_carries_the_licence_expression():
    meta = metadata.metadata(DISTRIBUTION)
    assert meta["License-Expression"] == "MIT"
    assert meta["Name"] == DISTRIBUTION


def test_citation_cites_the_software_and_max_1981():
    assert cff_value("cff-version") == "1.2.0"
    assert cff_value("type") == "software"
    refs = CITATION.split("\nreferences:", 1)[1]
    assert "family-names: Max" in refs and "year: 1981" in refs
    assert "doi: 10.1145/965161.806820" in refs
    assert PROJECT["urls"]["Paper"] == "https://doi.org/10.1145/965161.806820"


def test_readme_image_works_on_a_package_index_page():
    """An index page has no repository beside it: every image must be an absolute https URL to a real file."""
    images = re.findall(r"!\[[^\]]*\]\(([^)\s]+)", README)
    assert images
    repo = PROJECT["urls"]["Repository"].removeprefix("https://github.com/")
    for url in images:
        assert url.startswith(f"https://raw.githubusercontent.com/{repo}/main/"), url
        assert (ROOT / url.split("/main/", 1)[1]).is_file(), f"{url} names no file of this repository"


def book_repository_url() -> str:
    """``repository: url:`` of book/_config.yml (the book's link to its repository; empty while unpublished)."""
    text = (ROOT / "book" / "_config.yml").read_text(encoding="utf-8")
    m = re.search(r"^repository:\s*\n\s+url:\s*\"?([^\"\n]*)\"?\s*$", text, re.M)
    assert m, "book/_config.yml has no repository url"
    return m.group(1).strip()


def test_every_url_of_the_project_names_one_repository_and_its_book():
    """pyproject.toml, CITATION.cff, README.md (links and picture) and book/_config.yml name one place.

    The Repository URL is the one source: Issues is its issue tracker, Homepage and
    Documentation the book on its Pages site; CITATION.cff cites the same two, and
    no file names another repository or Pages site.
    """
    urls = PROJECT["urls"]
    m = re.fullmatch(r"https://github\.com/([\w.-]+)/([\w.-]+)", urls["Repository"])
    assert m, urls["Repository"]
    owner, name = m.groups()
    book = f"https://{owner}.github.io/{name}/"
    assert urls["Issues"] == urls["Repository"] + "/issues"
    assert urls["Homepage"] == urls["Documentation"] == book
    assert cff_value("repository-code") == urls["Repository"]
    assert cff_value("url") == book
    texts = {"pyproject.toml": (ROOT / "pyproject.toml").read_text(encoding="utf-8"), "CITATION.cff": CITATION,
             "README.md": README, "environment.yml": (ROOT / "environment.yml").read_text(encoding="utf-8")}
    allowed = {f"github.com/{owner}/{name}", f"raw.githubusercontent.com/{owner}/{name}", f"{owner}.github.io/{name}"}
    for file, text in texts.items():
        for host, path in re.findall(r"https?://((?:[\w-]+\.)*(?:github\.com|githubusercontent\.com|github\.io))"
                                     r"(/[\w.-]+(?:/[\w.-]+)?)?", text):
            named = host + ("/" + "/".join(path.strip("/").split("/")[:2]) if "github.io" not in host
                            else "/" + path.strip("/").split("/")[0]) if path else host
            assert named in allowed, f"{file} names {named}, not {urls['Repository']}"
    repository = book_repository_url()
    assert repository in ("", urls["Repository"]), f"book/_config.yml's repository url is {repository}"


def test_readme_says_whether_the_urls_resolve_yet():
    """While the book's repository link is empty (nothing published), README.md says so, naming both places;
    once book/_config.yml links the repository, the note must go."""
    note = re.search(r"\*\*Not yet published\.\*\*(.+?)\n\n", README, re.S)
    if book_repository_url():
        assert note is None, "the book links its repository: remove README's 'Not yet published' note"
        return
    assert note, "README.md must say that the project URLs do not resolve yet"
    text = " ".join(note.group(1).split())
    assert f"<{PROJECT['urls']['Repository']}>" in text and f"<{PROJECT['urls']['Documentation']}>" in text
    assert "make book" in text and "book/images/fig6-510x512.png" in text
    assert "pip install ." in README


@pytest.mark.parametrize("path", ["environment.yml", "Makefile", "CITATION.cff", "requirements/test.lock",
                                  "requirements/book.lock", "requirements/runtime.lock",
                                  "book/images/fig6-510x512.png", "book/api.md", "tests/test_lock.py",
                                  "book/_config.yml", "book/_toc.yml", "book/_ext/numbers_sci.py", "book/intro.md",
                                  "book/symbols.md", "book/browser_check.py", "book/_static/sunset.css",
                                  "book/01-camera.md", "book/references.bib", "book/build.py"])
def test_the_sdist_carries_what_the_tests_read(path):
    """MANIFEST.in includes every file that the tests open (pyproject, README and LICENSE go in by themselves).

    The rules are applied in order, as setuptools does: include, recursive-include,
    graft, then prune and global-exclude take away.
    """
    assert (ROOT / path).exists()
    manifest = (ROOT / "MANIFEST.in").read_text(encoding="utf-8")
    rules = [line.split() for line in manifest.splitlines() if line.strip() and not line.startswith("#")]
    covered = False
    for rule in rules:
        if rule[0] == "include" and path in rule[1:]:
            covered = True
        elif rule[0] == "recursive-include" and path.startswith(rule[1] + "/") and any(
                Path(path).match(p) for p in rule[2:]):
            covered = True
        elif rule[0] == "graft" and path.startswith(rule[1] + "/"):
            covered = True
        elif rule[0] == "prune" and path.startswith(rule[1] + "/"):
            covered = False
        elif rule[0] == "global-exclude" and any(Path(path).match(p) for p in rule[1:]):
            covered = False
    assert covered, f"MANIFEST.in does not ship {path}"


def test_the_classifiers_claim_only_the_pythons_the_readme_reports_tested():
    """Each 'Python :: 3.X' classifier names a version that README.md's section on tested Pythons reports a run
    of the suite on, and requires-python starts at the lowest of them."""
    claimed = sorted(c.rsplit(" :: ", 1)[1] for c in PROJECT["classifiers"]
                     if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c))
    assert claimed, "no Python version classifiers"
    section = re.search(r"^### Which Pythons and which versions are tested\n(.+?)(?=^#)", README, re.S | re.M)
    assert section, "README.md has no section on the tested Pythons"
    text = " ".join(section.group(1).split())
    for version in claimed:
        assert re.search(rf"CPython {re.escape(version)}\.\d+", text), f"README reports no test run on {version}"
    assert PROJECT["requires-python"] == f">={claimed[0]}"
