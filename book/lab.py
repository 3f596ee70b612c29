#!/usr/bin/env python3
"""``make lab``: JupyterLab on book/, offline, every chapter opened as a notebook that runs as the build runs it.

Usage::

    python book/lab.py [--no-browser] [--port N]

The chapters are jupytext MyST notebooks (``.md``): JupyterLab opens them
with jupytext's notebook viewer by default (a settings override, written to
a temporary folder with the rest of this session's configuration), runs them
in the kernel the book's build uses (``python3`` of this environment, the
package imported from this working tree through ``PYTHONPATH``, the same
quiet IPython profile as ``book/build.py``) and in the chapter's folder, as
myst-nb does. Saving a notebook writes its ``.md`` back (jupytext: no
``.ipynb`` beside it).

Offline: JupyterLab's news feed, its update check and the extension
manager's PyPI look-ups are off; everything else it serves comes from this
environment. ``book/explore_check.py`` starts the same server (with
:func:`lab_command` and :func:`lab_environment`) for its browser check.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

BOOK = Path(__file__).resolve().parent
ROOT = BOOK.parent

#: File types JupyterLab opens with jupytext's notebook view instead of the Markdown editor.
DEFAULT_VIEWERS = {"markdown": "Jupytext Notebook", "myst": "Jupytext Notebook"}

#: The server's configuration (a Python config file): nothing fetched from the network.
LAB_CONFIG = """\
c.LabApp.news_url = None                                         # no announcements feed
c.LabApp.check_for_updates_class = "jupyterlab.NeverCheckForUpdate"
c.LabApp.extension_manager = "readonly"                           # no PyPI search for extensions
c.LabApp.app_settings_dir = {settings!r}                          # DEFAULT_VIEWERS: chapters open as notebooks
"""


#: What this module takes from book/build.py: the kernels' profile and the function that writes it.
FROM_BUILD = ("KERNEL_CONFIG", "quiet_kernel_profile")


def _from_build() -> dict:
    """book/build.py's :data:`FROM_BUILD`, the build's own code, run without the rest of build.py.

    Only those two definitions are compiled (found with :mod:`ast`), so that
    the lab's kernels get the build's profile without importing what the
    build needs besides (PyYAML, which the test environment lacks).
    """
    import ast

    source = (BOOK / "build.py").read_text(encoding="utf-8")
    tree = ast.parse(source)
    keep = [node for node in tree.body
            if (isinstance(node, ast.FunctionDef) and node.name in FROM_BUILD)
            or (isinstance(node, ast.Assign) and any(getattr(t, "id", None) in FROM_BUILD for t in node.targets))]
    if len(keep) != len(FROM_BUILD):
        raise RuntimeError(f"book/build.py no longer defines {', '.join(FROM_BUILD)}")
    namespace = {"Path": Path}
    exec(compile(ast.Module(body=keep, type_ignores=[]), str(BOOK / "build.py"), "exec"), namespace)
    return namespace


def lab_environment(workdir: Path, base: dict | None = None) -> dict:
    """The environment of the server and its kernels: the build's ``PYTHONPATH`` and IPython profile."""
    env = dict(os.environ if base is None else base)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    env["IPYTHONDIR"] = str(_from_build()["quiet_kernel_profile"](Path(workdir)))
    return env


def lab_config(workdir: Path) -> Path:
    """Write the server's configuration and the settings override into ``workdir``; the config file's path."""
    settings = Path(workdir) / "lab-settings"
    settings.mkdir(parents=True, exist_ok=True)
    overrides = {"@jupyterlab/docmanager-extension:plugin": {"defaultViewers": DEFAULT_VIEWERS},
                 # and no question whether to fetch Jupyter's news: the answer is no
                 "@jupyterlab/apputils-extension:notification": {"fetchNews": "false", "checkForUpdates": False}}
    (settings / "overrides.json").write_text(json.dumps(overrides, indent=2) + "\n", encoding="utf-8")
    config = Path(workdir) / "jupyter_lab_config.py"
    config.write_text(LAB_CONFIG.format(settings=str(settings)), encoding="utf-8")
    return config


def lab_command(workdir: Path, root: Path = BOOK, *, browser: bool = True, port: int | None = None,
                token: str | None = None) -> list[str]:
    """The command that starts JupyterLab on ``root`` with this session's configuration (see :func:`lab_config`)."""
    cmd = [sys.executable, "-m", "jupyterlab", f"--config={lab_config(workdir)}",
           f"--ServerApp.root_dir={root}", "--ServerApp.ip=127.0.0.1"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-root")        # CI's machines and containers run as root
    if not browser:
        cmd.append("--no-browser")
    if port is not None:
        cmd += [f"--ServerApp.port={port}", "--ServerApp.port_retries=0"]
    if token is not None:
        cmd.append(f"--IdentityProvider.token={token}")
    return cmd


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--no-browser", action="store_true", help="do not open a browser (print the URL)")
    parser.add_argument("--port", type=int, default=None, help="the server's port (default: 8888 or the next free)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="sunset-lab-") as tmp:
        cmd = lab_command(Path(tmp), browser=not args.no_browser, port=args.port)
        print("lab.py:", " ".join(cmd), flush=True)
        try:
            return subprocess.run(cmd, env=lab_environment(Path(tmp)), cwd=BOOK).returncode
        except KeyboardInterrupt:
            return 130


if __name__ == "__main__":
    sys.exit(main())
