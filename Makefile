# sunset: `make figures` and `make test` on a fresh machine with only Python 3.
# Each target makes .venv on first use and installs the locked environment
# (requirements/*.lock, exact versions with hashes) and then the project
# (editable), behind stamp files that depend on pyproject.toml and the lock.
# Outputs are real files with real dependencies: a second `make all` with
# nothing changed does nothing, and touching a module rebuilds what uses it.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check
SUNSET := $(PY) -m sunset
# Extra options for `jupyter-book build`; CI sets BOOK_EXECUTE=force.
BOOK_EXECUTE ?= cache
# Extra options for every `sunset figures` run of `make figures` (e.g. --quiet, --jobs 2).
FIGURE_FLAGS ?=
# The lock: `make lock` re-resolves it after pyproject.toml changes (keeping the
# pins it can); `make lock LOCK_FLAGS=--upgrade` moves every pin to the newest release.
UV_VERSION  := 0.13.8
LOCK_PYTHON := 3.11
LOCK_FLAGS  ?=
UV          := .venv-lock/bin/uv
UV_COMPILE  = $(UV) pip compile pyproject.toml --universal --python-version $(LOCK_PYTHON) --generate-hashes \
              --quiet --custom-compile-command 'make lock' $(LOCK_FLAGS)

.PHONY: all figures test book book-check lab explore-check pdf bench bench-player lock clean help
.DELETE_ON_ERROR:

help:
	@echo "make all       everything, in dependency order: the figures, the film and the book"
	@echo "make figures   regenerate the paper's figures and the film into figures/ (only what is out of date)"
	@echo "make test      run the test suite"
	@echo "make book      build the Jupyter Book into book/_build/html (BOOK_EXECUTE=force re-runs every chapter)"
	@echo "make book-check  open every page of the built book in headless Chromium and check it"
	@echo "make lab       JupyterLab on book/, offline: every chapter opens as a notebook (and sunset.explore())"
	@echo "make explore-check  make lab's server and sunset.explore() driven in headless Chromium"
	@echo "make pdf       the whole book as one PDF with bookmarks and a paged contents, book/_build/pdf/sunset-book.pdf, checked (Chromium, offline)"
	@echo "make bench     time the renderer (writes figures/bench.json)"
	@echo "make bench-player  time the colour-table player in headless Chromium (figures/player-bench.json)"
	@echo "make lock      re-resolve requirements/*.lock after pyproject.toml changes (LOCK_FLAGS=--upgrade: newest releases)"
	@echo "make clean     remove what make wrote: figures/, the environments, the book's build, the caches"

# ---------------------------------------------------------------- the environment
$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.stamp-test: pyproject.toml requirements/test.lock | $(VENV)/bin/python
	$(PIP) install --quiet --require-hashes -r requirements/test.lock
	$(PIP) install --quiet --no-deps -e .
	touch $@

$(VENV)/.stamp-book: pyproject.toml requirements/book.lock $(VENV)/.stamp-test
	$(PIP) install --quiet --require-hashes -r requirements/book.lock
	touch $@

$(UV):
	$(PYTHON) -m venv .venv-lock
	.venv-lock/bin/python -m pip install --quiet --disable-pip-version-check uv==$(UV_VERSION)

lock: $(UV)
	$(UV_COMPILE) --extra test --extra book -o requirements/book.lock
	$(UV_COMPILE) --extra test -c requirements/book.lock -o requirements/test.lock
	$(UV_COMPILE) -c requirements/book.lock -o requirements/runtime.lock

# ---------------------------------------------------------------- figures and film
# One rule per file in figures/, with the package modules its builder imports
# (found by sunset/figures/deps.py, regenerated whenever a source changes).
# Under `make figures` (or `make all`) a stale file's rule only names its figure
# ($(call figure,NAME[,READERS]): READERS read its files, as Figure 7 reads
# fig6.tape), and `figures` then makes every named one in ONE
# `sunset figures --only ...` process, all or nothing; a file asked for by
# itself (`make figures/fig2.png`) is made by its own process.
FIGURE_ENV := $(VENV)/.stamp-test
STALE_FIGURES :=
comma := ,
empty :=
space := $(empty) $(empty)
figure = $(eval STALE_FIGURES += $(1) $(2))$(if $(filter figures all,$(MAKECMDGOALS)),,$(SUNSET) figures --only $(1) --out figures $(FIGURE_FLAGS))
SOURCES    := $(shell find sunset -name '*.py' -o -name '*.toml')

figures/.deps.mk: $(SOURCES)
	@mkdir -p figures
	@$(PYTHON) sunset/figures/deps.py figures > $@.tmp && mv $@.tmp $@

# (not for `make clean`, which would otherwise write the rules only to remove them)
ifneq ($(filter-out clean,$(or $(MAKECMDGOALS),help)),)
-include figures/.deps.mk
endif

figures: $(FIGURE_FILES)
	$(if $(strip $(STALE_FIGURES)),$(SUNSET) figures --only $(subst $(space),$(comma),$(sort $(STALE_FIGURES))) --out figures $(FIGURE_FLAGS),@echo "make: figures/ is up to date")

# ---------------------------------------------------------------- the book
# Any source of the book or of the package makes the book out of date; build.py then
# re-executes exactly the chapters whose code cells or imported modules changed
# (book/chapter_deps.py) and takes the others from the execution cache.
BOOK_SOURCES := $(wildcard book/*.md book/*.yml book/*.bib book/*.py book/images/* book/data/*) $(SOURCES)
BOOK_STAMP   := book/_build/html/.stamp

$(BOOK_STAMP): $(BOOK_SOURCES) $(VENV)/.stamp-book
	$(PY) book/build.py --execute $(BOOK_EXECUTE)
	touch $@

# `make book` always builds (the execution cache keeps it quick); `make all` only when a source changed.
book: $(VENV)/.stamp-book
	$(PY) book/build.py --execute $(BOOK_EXECUTE)
	touch $(BOOK_STAMP)

book-check: $(VENV)/.stamp-book
	$(PY) book/browser_check.py book/_build/html

# JupyterLab on the chapters (jupytext), run in the build's kernel settings (book/lab.py).
lab: $(VENV)/.stamp-book
	$(PY) book/lab.py

# make lab's server, a chapter run through jupytext, and sunset.explore() in Chromium (book/explore_check.py).
explore-check: $(VENV)/.stamp-book
	$(PY) book/explore_check.py

# The PDF's check compares its numbering with the HTML book's, so the HTML book comes first.
pdf: $(BOOK_STAMP) $(VENV)/.stamp-book
	$(PY) book/pdf.py --execute $(BOOK_EXECUTE)

# `make pdf` always prints; `make all` only when a source of the book changed.
BOOK_PDF := book/_build/pdf/sunset-book.pdf

$(BOOK_PDF): $(BOOK_SOURCES) book/pdf.css $(BOOK_STAMP) $(VENV)/.stamp-book
	$(PY) book/pdf.py --execute $(BOOK_EXECUTE)

all: figures $(BOOK_STAMP) $(BOOK_PDF)

test: $(VENV)/.stamp-test
	$(PY) -m pytest

bench: $(VENV)/.stamp-test
	$(PY) -m sunset.bench --out figures/bench.json

bench-player: $(VENV)/.stamp-test
	$(PY) -m sunset player carlas-island -o figures/player.html --quiet
	$(PY) -m tests.recorder.player_browser figures/player.html --out figures/player-bench.json

# Everything make and the test suite write; figures/.gitkeep and the sources stay.
CLEAN_FIGURES := $(filter-out figures/.gitkeep,$(wildcard figures/* figures/.deps.mk figures/.deps.mk.tmp))

clean:
	rm -rf $(VENV) .venv-lock book/_build book/.jupyter_cache build dist .pytest_cache .hypothesis $(CLEAN_FIGURES)
	rm -rf sunset_waves.egg-info sunset.egg-info
	find sunset tests book -name __pycache__ -type d -prune -exec rm -rf {} +
