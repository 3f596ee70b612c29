"""The Makefile's figure rules (sunset/figures/deps.py): each file depends on what its builder imports."""

import re
import subprocess
import sys
from pathlib import Path

from sunset.figures import FIGURES
from sunset.figures.deps import ALSO_WRITES, TARGETS, dependencies, module_file, rules

ROOT = Path(__file__).resolve().parents[2]


def test_every_figure_file_has_a_rule():
    assert {f for f, _ in FIGURES.values()} == set(TARGETS)
    assert {name for name, _ in TARGETS.values()} == set(FIGURES)
    for target, (_, builder) in TARGETS.items():
        assert module_file(builder) is not None, builder


def test_dependencies_follow_the_imports():
    fig2 = dependencies("fig2.png")
    assert "sunset/figures/fig2.py" in fig2 and "sunset/model/stokes_exact.py" in fig2
    assert "sunset/recorder/film.py" not in fig2 and "sunset/pipeline/frame.py" not in fig2
    assert "sunset/scenes/carlas-island.toml" not in fig2            # Figure 2 draws no scene
    film = dependencies("film.mp4")
    assert "sunset/recorder/film.py" in film and "sunset/figures/fig2.py" not in film
    assert "sunset/scenes/carlas-island.toml" in film
    for target in ("fig4.png", "fig6.png", "diagnostic.png", "reflections.png", "film.mp4"):
        deps = dependencies(target)
        assert "sunset/model/waves.py" in deps and "sunset/cli.py" in deps, target   # through imports
        assert all((ROOT / d).is_file() for d in deps), target
    # a name imported through a package's __init__ is followed to its module, not to the whole package
    assert "sunset/light" not in " ".join(dependencies("fig6.png"))


def test_rules_are_make_syntax_and_group_the_files_a_rule_writes():
    text = rules("figures")
    assert re.search(r"^figures/fig6\.png figures/fig6\.tape &: ", text, re.M)
    assert re.search(r"^figures/film\.mp4 figures/film-preview\.webp &: ", text, re.M)
    assert re.search(r"^figures/fig7\.png: .*figures/fig6\.tape", text, re.M)   # Figure 7 re-exposes Figure 6's tape
    for target, (name, _) in TARGETS.items():
        readers = ",7" if name == "6" else ""           # rewriting fig6.tape makes Figure 7 out of date
        assert f"\t$(call figure,{name}{readers})" in text   # the Makefile batches them (test_makefile.py)
    listed = re.search(r"^FIGURE_FILES := (.*)$", text, re.M).group(1).split()
    assert sorted(listed) == sorted(f"figures/{f}" for t in TARGETS for f in (t, *ALSO_WRITES.get(t, ())))


def test_runs_with_the_standard_library_alone():
    """The Makefile runs it with the system Python, before the environment exists."""
    code = ("import sys; sys.modules['numpy'] = None; import runpy; "
            f"runpy.run_path({str(ROOT / 'sunset/figures/deps.py')!r}, run_name='__main__')")
    out = subprocess.run([sys.executable, "-c", code, "figures"], capture_output=True, text=True, check=True).stdout
    assert out == rules("figures")


def test_the_lazy_public_api_is_read_from_the_source_as_the_package_resolves_it():
    """``from sunset import render`` names no module: the ``_API`` table says which one it loads."""
    import importlib.util

    import sunset
    from sunset.figures.deps import _defining_module, lazy_api

    expected = {name: importlib.util.resolve_name(module, "sunset") for name, module in sunset._API.items()}
    assert lazy_api("sunset") == expected and expected
    for name, module in expected.items():
        assert getattr(sunset, name).__module__ == module           # where the running package finds it
        assert _defining_module("sunset", name) == module
    assert _defining_module("sunset", "__version__") == "sunset"    # set by the package itself
    assert lazy_api("sunset.model") == {}                           # a package without a lazy table
