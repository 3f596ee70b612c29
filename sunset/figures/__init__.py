"""Every figure `make figures` writes, by name.

Each entry names the file it writes and the function that makes it; the
functions live in this package's modules, one module per group of figures.
"""

from __future__ import annotations

import time
from pathlib import Path

from ..errors import SunsetError

#: name -> (file written into the output folder, one-line description)
FIGURES: dict[str, tuple[str, str]] = {
    "1": ("fig1.png", "Figure 1: the sun's great circle C on the unit sphere, U, V, W = U × V and P(θ)"),
    "2": ("fig2.png", "Figure 2: Stokes' approximations to the wave form, and the exact wave"),
    "3": ("fig3.png", "Figure 3: perspective projection along one vertical scan line"),
    "4": ("fig4.png", "Figure 4: islands near sunset in still water"),
    "5": ("fig5.png", "Figure 5: one reflection from waves (|R_z|)"),
    "6": ("fig6.png", "Figure 6: two reflections from waves"),
    "7": ("fig7.png", "Figure 7: Figure 6's tape with early-afternoon tables"),
    "diagnostic": ("diagnostic.png", "surface classes and normals of the default scene"),
    "reflections": ("reflections.png", "the three reflection modes, diagnostic maps"),
    "film": ("film.mp4", "the colour-table animation of one wave cycle (and film-preview.webp)"),
    "rgb": ("fig6-rgb.png", "Figure 6 as the future work imagined: paint by numbers beside the RGB back end"),
    "quantisation": ("quantisation.png", "the 8-bit test: the RGB frame in 256 colours, CIEDE2000 maps"),
    "clouds": ("clouds.png", "future work: Carla's Island under clouds, the sun hidden and shown (and clouds-rgb.png)"),
    "ripples": ("ripples.png", "future work: ripples of light thrown by the waves onto a post (beams beside photons)"),
}


def parse_only(text: str | None) -> list[str]:
    """Parse ``--only 2,4,5`` into figure names, in registry order; all when None."""
    if text is None:
        return list(FIGURES)
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise SunsetError("--only needs at least one figure name")
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise SunsetError(f"unknown figure {unknown[0]!r} (known: {', '.join(FIGURES)})")
    return [n for n in FIGURES if n in names]


def make_figure(name: str, out: Path, scene, seed: int = 0, film_frames: int = 32,
                progress: bool = True, workers: int | None = None, reuse_from: Path | None = None) -> list[Path]:
    """Make one figure of ``scene`` (at its camera's size) into ``out``; returns the files written.

    ``reuse_from``: another folder where Figure 7 may find Figure 6's tape.
    """
    out = Path(out)
    if name == "1":
        from .fig1 import figure1
        return [figure1(out / "fig1.png", sun=scene.sun)]
    if name == "2":
        from .fig2 import figure2
        return [figure2(out / "fig2.png")]
    if name == "3":
        from .fig3 import figure3
        return [figure3(out / "fig3.png", scene=scene)]
    if name in ("4", "5", "6", "7"):
        from .paper import paper_figure
        return [paper_figure(name, out, scene, seed=seed, reuse_from=reuse_from)]
    if name == "diagnostic":
        from .diagnostic import diagnostic
        return [diagnostic(out / "diagnostic.png", scene=scene)]
    if name == "reflections":
        from .reflections import reflection_modes
        return [reflection_modes(out / "reflections.png", scene=scene)]
    if name == "rgb":
        from .rgb import rgb_figure6
        return [rgb_figure6(out / "fig6-rgb.png", scene, seed=seed)]
    if name == "quantisation":
        from .rgb import quantisation_figure
        return [quantisation_figure(out / "quantisation.png", scene, seed=seed)]
    if name == "clouds":
        from .future import clouds_figure, clouds_rgb_figure
        rgb = clouds_rgb_figure(out / "clouds-rgb.png", scene)       # first: clouds.png codes its traced frame
        return [clouds_figure(out / "clouds.png", scene, seed=seed), rgb]
    if name == "ripples":
        from .future import ripples_figure
        return [ripples_figure(out / "ripples.png", seed=seed)]
    if name == "film":
        from ..pipeline.film import make_film
        return list(make_film(scene, out / "film.mp4", out / "film-preview.webp", frames=film_frames,
                              seed=seed, progress=progress, workers=workers))
    raise SunsetError(f"unknown figure {name!r}")  # pragma: no cover - parse_only guards


def check_budgets(names, scene) -> None:
    """Refuse, before any figure is made, a size at which a figure's frame exceeds its budget, naming the figure.

    The budgets are :mod:`sunset.vector.budget`'s and :mod:`sunset.light.budget`'s.
    """
    from ..pipeline.budget import check_rgb_work
    from ..vector.budget import check_work

    checks = {"rgb": lambda: check_rgb_work(scene, _rgb_samples()), "quantisation": lambda: check_rgb_work(scene, 1)}
    if "clouds" in names:
        from .future import cloudy

        checks["clouds"] = lambda: check_rgb_work(cloudy(scene), 1)
    for name in names:
        try:
            if name in checks or name in ("4", "5", "6", "7", "diagnostic", "reflections", "film"):
                checks.get(name, lambda: check_work(scene))()
        except SunsetError as exc:
            cam = scene.camera
            raise SunsetError(f"figure {name} at {cam.width}x{cam.height}: {exc}") from None


def _rgb_samples() -> int:
    from .rgb import RGB_SAMPLES

    return RGB_SAMPLES


def make_figures(out: str | Path = "figures", only: str | None = None, size: tuple[int, int] | None = None,
                 seed: int = 0, scene=None, progress: bool = True, log=print,
                 film_frames: int = 32, workers: int | None = None) -> list[Path]:
    """Make the figures named by ``only`` (all by default) into ``out``.

    ``workers`` processes render the film's frames (default: ``$SUNSET_WORKERS``
    or every usable CPU, :func:`sunset.pipeline.workers.frame_workers`).
    """
    from ..model.scene import Scene

    names = parse_only(only)
    scene = Scene.default() if scene is None else scene
    if size:
        scene = scene.with_size(*size)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise SunsetError(f"{out}: cannot write figures there: it is a file, not a folder")
    check_budgets(names, scene)
    created = [p for p in (out, *out.parents) if not p.exists()]       # deepest first
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SunsetError(f"{out}: cannot create the output folder ({exc.strerror})") from None
    try:
        return _make_all(names, out, scene, seed=seed, progress=progress, log=log, film_frames=film_frames,
                         workers=workers)
    except BaseException:
        for folder in created:               # a failed run leaves no new folder either
            try:
                folder.rmdir()
            except OSError:
                break
        raise


def _make_all(names, out: Path, scene, log=print, **kw) -> list[Path]:
    """Make the figures in a hidden folder inside ``out``; move them into ``out`` together when all are made.

    A figure that fails (or Ctrl-C) leaves ``out`` as it was: no new file and
    no replaced one; the hidden folder is removed in every case (one that a
    killed process left is removed by the next run, :func:`sunset.io.remove_stale_temporaries`).
    Figure 7 finds Figure 6's tape in the hidden folder when both are made,
    else in ``out`` from an earlier run.
    """
    import os
    import shutil
    import tempfile

    from ..io import check_stop, check_writable, land_in, remove_stale_temporaries

    remove_stale_temporaries(out)
    try:
        stage = Path(tempfile.mkdtemp(prefix=f".sunset-{os.getpid()}-", suffix=".part", dir=out))
    except OSError as exc:
        raise SunsetError(f"{out}: cannot write figures there ({exc.strerror or exc})") from None
    from . import shared
    from .lanes import plan, Queue, SideLane

    units, two = plan(names, kw.get("workers"))
    lane = None
    try:
        made: dict[str, list[Path]] = {}

        def make_here(unit):
            for name in unit:
                start = time.perf_counter()
                made[name] = make_figure(name, stage, scene, reuse_from=out, **kw)
                _logged(log, name, made[name], out, time.perf_counter() - start)

        with shared.sharing():                         # frames, codes and lights computed once (sunset.figures.shared)
            if two:                                    # two processes, one queue of units (sunset.figures.lanes)
                queue = Queue(len(units))
                lane = SideLane(units, queue, lambda n: make_figure(n, stage, scene, reuse_from=out, **kw)).start()
                k = 1
                while k is not None:
                    make_here(units[k])
                    k = None if lane.finished() else queue.take()     # finished: nothing left, or it failed
                for name, files, seconds in lane.results():
                    made[name] = [Path(f) for f in files]
                    _logged(log, name, made[name], out, seconds)
            else:
                make_here(names)
        written = []
        for name in names:
            written += [f for f in made[name] if f not in written]
        extra = [p for p in sorted(stage.iterdir()) if p not in written]       # fig6.tape and the like
        targets = [out / p.name for p in written + extra]
        for target in targets:                # every target replaceable before the first one is replaced
            check_writable(target)
        check_stop()
        land_in(written + extra, out)
    finally:
        if lane is not None:
            lane.stop()
        shutil.rmtree(stage, ignore_errors=True)
    return [out / p.name for p in written]


def _logged(log, name: str, files, out: Path, seconds: float) -> None:
    log(f"{FIGURES[name][1]}: {', '.join(str(out / f.name) for f in files)} ({seconds:.1f} s)")
