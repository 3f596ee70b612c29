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


@pytest.mark.parametrize("path", ["environment.yml", "Makefile", "CITATION.cff", "requirements/test.lock",
                                  "requirements/book.lock", "requirements/runtime.lock",
                                  "book/images/fig6-510x512.png", "book/api.md", "tests/test_lock.py"])
def test_the_sdist_carries_what_the_tests_read(path):
    """MANIFEST.in includes every file that the tests open (pyproject, README and LICENSE go in by themselves)."""
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
    assert covered, f"MANIFEST.in does not ship {path}"
