# sunset: `make figures` and `make test` on a fresh machine with only Python 3.
# Each target makes .venv on first use and installs the project (editable) with
# the extras it needs, behind stamp files that depend on pyproject.toml.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
# Extra options for `jupyter-book build`; CI sets BOOK_EXECUTE=force.
BOOK_EXECUTE ?= cache

.PHONY: figures test book book-check bench bench-player clean help

help:
	@echo "make figures   regenerate the paper's figures and the film into figures/"
	@echo "make test      run the test suite"
	@echo "make book      build the Jupyter Book into book/_build/html (BOOK_EXECUTE=force re-runs every chapter)"
	@echo "make book-check  open every page of the built book in headless Chromium and check it"
	@echo "make bench     time the renderer (writes figures/bench.json)"
	@echo "make bench-player  time the colour-table player's frames in headless Chromium (figures/player-bench.json)"
	@echo "make clean     remove the venv, builds and generated figures"

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.stamp-test: pyproject.toml | $(VENV)/bin/python
	$(PIP) install --quiet --disable-pip-version-check -e '.[test]'
	touch $@

$(VENV)/.stamp-book: pyproject.toml $(VENV)/.stamp-test
	$(PIP) install --quiet --disable-pip-version-check -e '.[test,book]'
	touch $@

figures: $(VENV)/.stamp-test
	$(PY) -m sunset figures --out figures

test: $(VENV)/.stamp-test
	$(PY) -m pytest

book: $(VENV)/.stamp-book
	$(PY) book/build.py --execute $(BOOK_EXECUTE)

book-check: $(VENV)/.stamp-book
	$(PY) book/browser_check.py book/_build/html

bench: $(VENV)/.stamp-test
	$(PY) -m sunset.bench --out figures/bench.json

bench-player: $(VENV)/.stamp-test
	$(PY) -m sunset player carlas-island -o figures/player.html --quiet
	$(PY) book/browser_check.py --player-bench figures/player.html --out figures/player-bench.json

clean:
	rm -rf $(VENV) book/_build figures/*.png figures/*.mp4 figures/*.gif figures/*.webp figures/*.json figures/*.html .pytest_cache
