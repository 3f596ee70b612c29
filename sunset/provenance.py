"""What made an output: the versions every file this package writes records.

Every PNG (the rendered frames and the matplotlib figures), the MP4, the
tape and the player's page carry :func:`provenance`: the versions of sunset,
Python, NumPy, Numba and colour-science, and the path the kernels took
(:func:`sunset.kernels.path`: ``compiled``, ``numpy (numba missing)``,
``numpy (SUNSET_COMPILED=0)`` or ``mixed: ...`` where some compiled kernels
fell back), since the two paths agree within tolerances, not to the bit.
``sunset info`` prints it with the rest of :func:`environment` (the platform,
the settings). Nothing in it changes from run to run on one machine and
path (no time, no host name), so outputs stay byte-identical.

The versions are read from the installed packages' metadata, not by importing
them (importing Numba takes a second).
"""

from __future__ import annotations

import json
import os
import platform
import sys
from importlib import metadata

__all__ = ["DISTRIBUTION", "package_version", "provenance", "provenance_json", "stamped", "environment", "info_text"]

#: The name this package is installed under (``pip install sunset-waves``); it imports as ``sunset``.
DISTRIBUTION = "sunset-waves"

#: The distributions whose versions every output records, by the name shown.
RECORDED = {"sunset": DISTRIBUTION, "numpy": "numpy", "numba": "numba", "colour-science": "colour-science"}

#: Further distributions ``sunset info`` lists.
ALSO_LISTED = ("scipy", "matplotlib", "pillow", "imageio", "imageio-ffmpeg", "tqdm")


def package_version(distribution: str) -> str:
    """The installed version of ``distribution``, or ``"not installed"``."""
    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return "not installed"


def _kernels() -> str:
    """The path the kernels took: :func:`sunset.kernels.path` (``compiled``, ``numpy (...)``, ``mixed: ...``).

    Asked of the kernel switch when it is loaded (it is, whenever a frame was
    rendered); otherwise what it will choose, without importing Numba:
    ``numpy (SUNSET_COMPILED=0)``, ``numpy (numba missing)`` or ``compiled``
    (a kernel that fails to compile is found only when it is first used).
    """
    switch = sys.modules.get("sunset.kernels")
    if switch is not None and callable(getattr(switch, "path", None)):
        return switch.path()
    if os.environ.get("SUNSET_COMPILED", "1") == "0":
        return "numpy (SUNSET_COMPILED=0)"
    return "numpy (numba missing)" if package_version("numba") == "not installed" else "compiled"


def provenance() -> dict[str, str]:
    """What made an output: the versions of sunset, Python, NumPy, Numba, colour-science, and the kernels' path.

    >>> list(provenance())
    ['sunset', 'python', 'numpy', 'numba', 'colour-science', 'kernels']
    """
    out = {"sunset": package_version(DISTRIBUTION), "python": platform.python_version()}
    for shown, dist in RECORDED.items():
        if shown != "sunset":
            out[shown] = package_version(dist)
    out["kernels"] = _kernels()
    return out


def provenance_json() -> str:
    """:func:`provenance` as compact JSON with sorted keys (what the files store)."""
    return json.dumps(provenance(), sort_keys=True, separators=(",", ":"))


def stamped(metadata: dict[str, str] | None = None) -> dict[str, str]:
    """``metadata`` with what every image this package writes carries: ``Software`` and ``sunset:provenance``.

    The text chunks of a PNG (and the description of the film's preview):
    ``Software`` (``sunset <version>``) first unless given, then ``metadata``
    in its order, then ``sunset:provenance`` (:func:`provenance_json`) unless
    given. A dict that has both already comes back equal, in the same order.
    Every value goes through :func:`sunset.escape.metadata_text` (printable
    UTF-8 and line feeds: a scene's title cannot put a NUL or a control
    character into a tag).

    >>> list(stamped({"sunset:settings": "{}"}))
    ['Software', 'sunset:settings', 'sunset:provenance']
    """
    given = dict(metadata or {})
    out = {} if "Software" in given else {"Software": f"sunset {package_version(DISTRIBUTION)}"}
    out.update(given)
    out.setdefault("sunset:provenance", provenance_json())
    from .escape import metadata_text

    return {key: metadata_text(value) for key, value in out.items()}


def environment() -> dict[str, str]:
    """Everything ``sunset info`` prints: :func:`provenance`, more packages, the platform and the settings."""
    from . import kernels  # noqa: F401 - loaded, the kernels' path is the switch's (is Numba importable?)

    env = dict(provenance())
    for dist in ALSO_LISTED:
        env[dist] = package_version(dist)
    env["platform"] = platform.platform()
    env["python executable"] = sys.executable
    env["cpus"] = str(os.cpu_count() or 1)
    env["SUNSET_WORKERS"] = os.environ.get("SUNSET_WORKERS", "(unset)")
    env["SUNSET_COMPILED"] = os.environ.get("SUNSET_COMPILED", "(unset)")
    return env


def info_text(env: dict[str, str] | None = None) -> str:
    """``env`` (default :func:`environment`) as aligned ``name  value`` lines."""
    env = environment() if env is None else env
    from .escape import terminal_text

    width = max(map(len, env))
    return "".join(f"{k:<{width}}  {terminal_text(v)}\n" for k, v in env.items())
