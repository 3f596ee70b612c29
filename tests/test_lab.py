"""``make lab`` (book/lab.py) starts JupyterLab as the book's build runs its chapters, offline.

Read from the configuration it writes, without JupyterLab (``make
explore-check`` starts the server itself, opens a chapter as a notebook in
Chromium and runs one through jupytext and nbclient in this kernel setup).
"""

import importlib.util
import json
import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"


def load(name):
    spec = importlib.util.spec_from_file_location(f"sunset_book_{name}", BOOK / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


lab = load("lab")


def build_kernel_config() -> str:
    """book/build.py's KERNEL_CONFIG, read here with ast (build.py imports PyYAML, not in the test environment)."""
    import ast

    for node in ast.parse((BOOK / "build.py").read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", None) == "KERNEL_CONFIG":
            return ast.literal_eval(node.value)
    raise AssertionError("book/build.py has no KERNEL_CONFIG")


def option(cmd, name):
    values = [a.split("=", 1)[1] for a in cmd if a.startswith(f"--{name}=")]
    assert len(values) == 1, (name, cmd)
    return values[0]


def test_the_server_serves_book_on_loopback_with_this_environment(tmp_path):
    cmd = lab.lab_command(tmp_path)
    assert cmd[:3] == [__import__("sys").executable, "-m", "jupyterlab"]
    assert Path(option(cmd, "ServerApp.root_dir")) == BOOK
    assert option(cmd, "ServerApp.ip") == "127.0.0.1"
    assert "--no-browser" not in cmd
    quiet = lab.lab_command(tmp_path, browser=False, port=8123, token="t0k")
    assert "--no-browser" in quiet and option(quiet, "ServerApp.port") == "8123"
    assert option(quiet, "IdentityProvider.token") == "t0k" and option(quiet, "ServerApp.port_retries") == "0"


def test_nothing_is_fetched_from_the_network(tmp_path):
    config = Path(option(lab.lab_command(tmp_path), "config")).read_text(encoding="utf-8")
    assert re.search(r"^c\.LabApp\.news_url = None\b", config, re.M)
    assert re.search(r'^c\.LabApp\.check_for_updates_class = "jupyterlab\.NeverCheckForUpdate"', config, re.M)
    assert re.search(r'^c\.LabApp\.extension_manager = "readonly"', config, re.M)
    settings = Path(re.search(r"^c\.LabApp\.app_settings_dir = '([^']+)'", config, re.M).group(1))
    overrides = json.loads((settings / "overrides.json").read_text(encoding="utf-8"))
    assert overrides["@jupyterlab/apputils-extension:notification"] == {"fetchNews": "false",
                                                                         "checkForUpdates": False}


def test_chapters_open_as_jupytext_notebooks(tmp_path):
    config = Path(option(lab.lab_command(tmp_path), "config")).read_text(encoding="utf-8")
    settings = Path(re.search(r"^c\.LabApp\.app_settings_dir = '([^']+)'", config, re.M).group(1))
    overrides = json.loads((settings / "overrides.json").read_text(encoding="utf-8"))
    viewers = overrides["@jupyterlab/docmanager-extension:plugin"]["defaultViewers"]
    assert viewers == {"markdown": "Jupytext Notebook", "myst": "Jupytext Notebook"}
    # every chapter is a jupytext MyST notebook with the python3 kernel the build uses
    for chapter in sorted(BOOK.glob("[0-9][0-9]*.md")):
        head = chapter.read_text(encoding="utf-8").split("---", 2)[1]
        assert "format_name: myst" in head and "name: python3" in head, chapter.name


def test_kernels_run_as_the_build_runs_them(tmp_path):
    env = lab.lab_environment(tmp_path, base={"PYTHONPATH": "/elsewhere", "HOME": "/home/reader"})
    # the package from this working tree first, as book/build.py puts it
    assert env["PYTHONPATH"].split(os.pathsep) == [str(ROOT), "/elsewhere"]
    assert env["HOME"] == "/home/reader"
    # the build's quiet IPython profile, the same text
    profile = Path(env["IPYTHONDIR"]) / "profile_default" / "ipython_kernel_config.py"
    assert profile.read_text(encoding="utf-8") == build_kernel_config()
    assert "running over TCP without encryption" in build_kernel_config()
    # kernels start in the chapter's folder, as myst-nb runs them (run_in_temp off)
    assert re.search(r"^\s*run_in_temp:\s*false", (BOOK / "_config.yml").read_text(encoding="utf-8"), re.M)


def test_make_lab_and_explore_check_are_wired():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^lab: \$\(VENV\)/\.stamp-book\n\t\$\(PY\) book/lab\.py$", makefile, re.M)
    assert re.search(r"^explore-check: \$\(VENV\)/\.stamp-book\n\t\$\(PY\) book/explore_check\.py$", makefile, re.M)
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    steps = [line for line in ci if line.startswith("run_step ")]
    # after Chromium is installed, and never skipped there: a missing Chromium fails the check
    assert steps.index("run_step explore-check make explore-check") > steps.index("run_step chromium install_chromium")
    check = (BOOK / "explore_check.py").read_text(encoding="utf-8")
    assert "skip" not in check.lower().replace("never skipped", "")
