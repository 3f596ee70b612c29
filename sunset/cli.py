"""The ``sunset`` command: figures, one frame, a tape's exposure, the film, the player.

Every user error (a bad scene file, a bad number, an unknown figure, an
unwritable output, a damaged tape, a full disk) prints one line
``sunset: error: …`` and exits with status 2, with no traceback and no new
output file: a command's outputs land together when all are complete
(:func:`sunset.io.all_or_nothing`). Ctrl-C exits with status 130, SIGTERM
with 143 and SIGHUP with 129, each with one line and the temporary files
removed.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
from pathlib import Path

from . import __version__
from .constants import MAX_CYCLE_FRAMES, MAX_FPS, MAX_HOURS_FROM_SUNSET, MAX_PIXELS
from .errors import SunsetError, shown
from .guard import (Interrupted, check_environment, check_stop, config_fallback, one_line, signals_stop_the_command,
                    silenced_stdout)

EXAMPLES = {
    "figures": """examples:
  sunset figures                      # everything `make figures` writes, into figures/
  sunset figures --only 2,6 --size 512x512 --out /tmp/figs""",
    "render": """examples:
  sunset scene > my.toml && sunset render my.toml -o frame.png
  sunset render my.toml --reflections 1 --hours 2 --size 400x400 -o f.png --tape f.tape
  sunset render carlas-island --shading rgb --samples 4 -o rgb.png       # Fresnel, the water's colour, 2x2 AA
  sunset render carlas-island --shading rgb --depth 16 -o rgb16.png       # or -o frame.npy: float32 for grading""",
    "expose": """examples:
  sunset expose f.tape --hours 4.5 -o afternoon.png""",
    "film": """examples:
  sunset film my.toml --frames 16 --size 320x320 -o film.mp4
  sunset film my.toml --from-hours 1.5 --to-hours -0.25 -o film.mp4 --preview film.gif
  sunset film my.toml --shading rgb --samples 4 --frames 16 --size 320x320 -o rgb.mp4""",
    "player": """examples:
  sunset player carlas-island -o carla.html         # open carla.html in a browser, no network needed
  sunset player my.toml -o my.html --frames 16 --size 320x320 --from-hours 3 --to-hours -0.25""",
    "scene": """examples:
  sunset scene > my.toml
  sunset scene storm-swell > storm.toml     # any packaged scene (sunset scene --list names them)""",
    "info": """examples:
  sunset info                         # the versions every output records, and the settings in force""",
    "export": """examples:
  sunset export pov carlas-island -o scene.pov && povray +Iscene.pov +W1020 +H1023 -A +FN
  sunset export pov my.toml --time 1.5 --size 320x320 -o scene.pov""",
}

#: The environment variables the command line reads, shown by ``sunset --help`` and the README.
ENVIRONMENT = """environment variables:
  SUNSET_WORKERS=N    processes that render a film's frames when --jobs is not given
                      (default: every CPU this process may use)
  SUNSET_COMPILED=0   the NumPy kernels, not the compiled (Numba) twins: slower, the same
                      pictures within the tests' tolerances; each output records the path

Progress bars are drawn only when stderr is a terminal; --quiet turns them
and the log lines off. `sunset info` prints the versions every output records."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit status 2."""

    def error(self, message):  # noqa: D401 - argparse API
        sub = self.prog.partition(" ")[2]
        raise SunsetError(f"{sub}: {message}" if sub else message)


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like WIDTHxHEIGHT, e.g. 512x512, got {text!r}") from None
    if w <= 0 or h <= 0:
        raise argparse.ArgumentTypeError(f"size must be positive, got {text!r}")
    if w * h > MAX_PIXELS:
        raise argparse.ArgumentTypeError(f"size {text!r} is too large (at most {MAX_PIXELS:,} pixels)")
    return w, h


def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def _count(text: str, most: int | None = None) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if v <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    if most is not None and v > most:
        raise argparse.ArgumentTypeError(f"expected at most {most}, got {text!r}")
    return v


def _fps(text: str) -> int:
    return _count(text, MAX_FPS)


def _frames(text: str) -> int:
    return _count(text, MAX_CYCLE_FRAMES)


def _hours(text: str) -> float:
    v = _number(text)                     # every place on the sun's 24-hour circle is within ±12 h of sunset
    if abs(v) > MAX_HOURS_FROM_SUNSET:
        raise argparse.ArgumentTypeError(f"must be within ±{MAX_HOURS_FROM_SUNSET:g} hours of sunset, got {text!r}")
    return v


def _samples(text: str) -> int:
    from .light.render import MAX_SAMPLES

    v = _count(text, MAX_SAMPLES)
    if math.isqrt(v) ** 2 != v:
        raise argparse.ArgumentTypeError(f"samples must be a square number (1, 4, 9, 16, ...: a k x k grid), "
                                         f"got {text!r}")
    return v


def _shading_options(p) -> None:
    p.add_argument("--shading", choices=("codes", "rgb"), default="codes",
                   help="codes: the paper's 8-bit tape and colour tables (default); rgb: the RGB back end "
                        "(Fresnel, the water's colour, anti-aliasing)")
    p.add_argument("--samples", type=_samples, default=None,
                   help="rgb only: samples per pixel on a k x k grid (1, 4, 9, 16, ...; default 1)")


def _check_shading(args) -> int:
    """The samples per pixel for ``--shading rgb``; a one-line error for options that do not fit the shading."""
    if args.shading != "rgb":
        if args.samples is not None:
            raise SunsetError("--samples needs --shading rgb (the 8-bit codes take one sample per pixel)")
        if getattr(args, "depth", None) is not None:
            raise SunsetError("--depth needs --shading rgb")
        return 1
    if getattr(args, "tape", None):
        raise SunsetError("--tape needs --shading codes (the RGB back end writes no tape)")
    return 1 if args.samples is None else args.samples


def _seed(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"seed must be a whole number, got {text!r}") from None
    if not 0 <= v < 2**32:
        raise argparse.ArgumentTypeError(f"seed must be in 0..2**32-1, got {text!r}")
    return v


def _scene_path(arg: str) -> Path | None:
    """The scene file ``arg`` names, or None for a packaged scene's name."""
    if not arg.strip():
        raise SunsetError("the scene path is empty")
    try:
        exists = os.path.lexists(arg)
    except (OSError, ValueError):
        exists = False
    from .model.scene import scene_names

    if arg in scene_names() or (not exists and "/" not in arg and not arg.endswith(".toml")):
        return None
    return Path(arg)


def _load_scene(arg: str):
    from .model.scene import as_scene, scene_from_file

    path = _scene_path(arg)
    return as_scene(arg) if path is None else scene_from_file(path)


def _outputs(outputs: dict, suffixes: dict | None = None, inputs: dict | None = None) -> None:
    """Check every output of a command before the work: writable, not empty, none the same file as another."""
    from .io import check_distinct, check_writable

    for label, path in outputs.items():
        if path is None:
            continue
        try:
            check_writable(path, (suffixes or {}).get(label, ()))
        except SunsetError as exc:
            raise SunsetError(f"{label}: {exc}") from None
    check_distinct(outputs, inputs)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="sunset", description="Nelson Max's 1981 'Waves and Islands in the Sunset', reproduced.",
                     epilog=ENVIRONMENT, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"sunset {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    def add(name, help_, quiet="print nothing but errors"):
        epilog = EXAMPLES[name] + ("\n\n" + ENVIRONMENT if name in ("figures", "render", "film") else "")
        p = sub.add_parser(name, help=help_, description=help_, epilog=epilog,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        p.add_argument("-q", "--quiet", action="store_true", help=quiet)
        return p

    jobs_help = "processes that render frames (default: $SUNSET_WORKERS, else every CPU this process may use)"

    p = add("figures", "Write the paper's figures, diagnostics and the film (what `make figures` runs).")
    p.add_argument("--out", default="figures", help="output folder (default: figures)")
    p.add_argument("--only", help="comma-separated figure names: 1,2,3,4,5,6,7,diagnostic,reflections,film")
    p.add_argument("--size", type=_size, help="size of Figures 4–7 and the film, WxH (default 1020x1023)")
    p.add_argument("--seed", type=_seed, default=0, help="dither seed (default 0)")
    p.add_argument("--frames", type=_frames, default=32,
                   help=f"frames per wave cycle in the film (default 32, at most {MAX_CYCLE_FRAMES})")
    p.add_argument("-j", "--jobs", type=_count, help=jobs_help)

    p = add("render", "Render one frame of a scene to PNG (and optionally its tape).")
    p.add_argument("scene", help="scene TOML file (or the name of a packaged scene, e.g. carlas-island)")
    p.add_argument("--time", type=_number, default=0.0, help="time t in seconds (default 0)")
    p.add_argument("--size", type=_size, help="WxH in pixels (default: the scene's camera)")
    p.add_argument("--reflections", type=int, choices=(0, 1, 2), default=2, help="reflection mode (default 2)")
    p.add_argument("--hours", type=_hours, default=0.35, help="hours before sunset for the colour tables")
    p.add_argument("--seed", type=_seed, default=0, help="dither seed (default 0)")
    p.add_argument("--still", action="store_true", help="render on still water (Figure 4)")
    p.add_argument("-o", "--output", required=True, help="output PNG (with --shading rgb also .npy: float32)")
    p.add_argument("--tape", help="also write the 8-bit tape here")
    _shading_options(p)
    p.add_argument("--depth", type=int, choices=(8, 16), default=None,
                   help="rgb only: bits per channel of the PNG (default 8)")

    p = add("expose", "Expose a saved tape through the colour tables (the film recorder alone).")
    p.add_argument("tape", help="a tape written by `sunset render --tape` or `sunset film --tape`")
    p.add_argument("--hours", type=_hours, required=True, help="hours before sunset")
    p.add_argument("--frame", type=int, default=0, help="which frame of the tape (default 0)")
    p.add_argument("-o", "--output", required=True, help="output PNG")

    p = add("film", "Render one wave cycle once and film it while the sun sets (colour-table animation).")
    p.add_argument("scene", help="scene TOML file (or a packaged scene name)")
    p.add_argument("--frames", type=_frames, default=32,
                   help=f"frames per wave cycle (default 32, at most {MAX_CYCLE_FRAMES})")
    p.add_argument("--from-hours", type=_hours, default=1.5, help="hours before sunset at the start (default 1.5)")
    p.add_argument("--to-hours", type=_hours, default=-0.25, help="hours before sunset at the end (default -0.25)")
    p.add_argument("--size", type=_size, help="WxH in pixels")
    p.add_argument("--reflections", type=int, choices=(0, 1, 2), default=2)
    p.add_argument("--seed", type=_seed, default=0)
    p.add_argument("--fps", type=_fps, default=24, help="frames per second of the film (default 24)")
    p.add_argument("-o", "--output", required=True, help="output MP4")
    p.add_argument("--preview", help="also write a small looping preview here (.gif or .webp)")
    p.add_argument("--tape", help="also write the cycle's tape here")
    _shading_options(p)
    p.add_argument("-j", "--jobs", type=_count, help=jobs_help)

    p = add("player", "Write the colour-table player: one wave cycle and an afternoon of colour tables in one "
                      "self-contained HTML file.")
    p.add_argument("scene", help="scene TOML file (or a packaged scene name)")
    p.add_argument("-o", "--output", required=True, help="output HTML file")
    p.add_argument("--frames", type=_frames, default=32,
                   help=f"frames per wave cycle (default 32, at most {MAX_CYCLE_FRAMES})")
    p.add_argument("--size", type=_size, help="WxH in pixels (default: the scene's picture, 512 on its longer side)")
    p.add_argument("--from-hours", type=_hours, default=1.5, help="hours before sunset at the start of the "
                                                                   "hours slider (default 1.5)")
    p.add_argument("--to-hours", type=_hours, default=-0.25, help="hours before sunset at its end (default -0.25)")
    p.add_argument("--reflections", type=int, choices=(0, 1, 2), default=2)
    p.add_argument("--seed", type=_seed, default=0)

    p = add("scene", "Print a scene as TOML (the default: Carla's Island), to start a scene file from.")
    p.add_argument("name", nargs="?", help="a packaged scene (default: carlas-island)")
    p.add_argument("--list", action="store_true", help="list the packaged scenes instead")

    add("info", "Print the versions every output records (sunset, Python, NumPy, Numba, colour-science), "
                "the kernels in use and the settings.")

    p = add("export", "Write a scene for another renderer: POV-Ray 3.7 (sea and islands as isosurfaces).")
    p.add_argument("format", choices=("pov",), help="pov: a POV-Ray 3.7 scene file")
    p.add_argument("scene", help="scene TOML file (or a packaged scene name)")
    p.add_argument("--time", type=_number, default=0.0, help="time t in seconds (default 0)")
    p.add_argument("--size", type=_size, help="WxH in pixels (default: the scene's camera)")
    p.add_argument("-o", "--output", required=True, help="output .pov file")
    return parser


def _cmd_figures(args) -> None:
    from .figures import make_figures

    if not args.out.strip():
        raise SunsetError("--out: the output folder is empty")
    make_figures(args.out, only=args.only, size=args.size, seed=args.seed,
                 progress=not args.quiet, log=(lambda *_: None) if args.quiet else
                 (lambda msg: print(msg, file=sys.stderr)), film_frames=args.frames, workers=args.jobs)


def _cmd_render(args) -> None:
    from .io import PNG_SUFFIXES, all_or_nothing

    samples = _check_shading(args)
    if args.shading == "rgb":
        return _cmd_render_rgb(args, samples)
    _outputs({"-o": args.output, "--tape": args.tape}, {"-o": PNG_SUFFIXES},   # before the long work
             {"the scene": _scene_path(args.scene)})
    scene = _load_scene(args.scene)
    from .figures.paper import expose_png, render_tape
    from .tape.tapefile import write_tape

    if args.size:
        scene = scene.with_size(*args.size)
    if args.still:
        scene = scene.still()
    tape = render_tape(scene, args.time, args.reflections, args.seed)
    with all_or_nothing():
        if args.tape is not None:
            write_tape(args.tape, tape)
        expose_png(tape, args.hours, Path(args.output))


def _cmd_render_rgb(args, samples: int) -> None:
    from .light.output import check_rgb_output

    depth = args.depth or 8
    _outputs({"-o": args.output}, inputs={"the scene": _scene_path(args.scene)})
    check_rgb_output(args.output, depth)               # before the long work
    scene = _load_scene(args.scene)
    if args.size:
        scene = scene.with_size(*args.size)
    if args.still:
        scene = scene.still()
    from .figures.paper import png_metadata
    from .pipeline.rgb import write_rgb_frame

    settings = {"t": args.time, "hours": args.hours, "reflections": args.reflections, "shading": "rgb",
                "samples": samples, "depth": depth}
    write_rgb_frame(scene, args.output, t=args.time, hours=args.hours, samples=samples,
                    reflections=args.reflections, depth=depth, metadata=png_metadata(scene, settings))


def _cmd_expose(args) -> None:
    from .figures.paper import expose_png
    from .io import PNG_SUFFIXES
    from .tape.tapefile import read_tape

    _outputs({"-o": args.output}, {"-o": PNG_SUFFIXES}, {"the tape": args.tape})
    tape = read_tape(args.tape)
    expose_png(tape, args.hours, Path(args.output), frame=args.frame)


def _cmd_film(args) -> None:
    from .pipeline.film import make_film
    from .recorder.film import FILM_SUFFIXES, PREVIEW_SUFFIXES

    samples = _check_shading(args)
    _outputs({"-o": args.output, "--preview": args.preview, "--tape": args.tape},
             {"-o": FILM_SUFFIXES, "--preview": PREVIEW_SUFFIXES}, {"the scene": _scene_path(args.scene)})
    scene = _load_scene(args.scene)
    if args.size:
        scene = scene.with_size(*args.size)
    if args.shading == "rgb":
        _rgb_film(scene, args, samples)
        return
    make_film(scene, args.output, args.preview, frames=args.frames, from_hours=args.from_hours,
              to_hours=args.to_hours, reflections=args.reflections, seed=args.seed, fps=args.fps,
              tape_path=args.tape, progress=not args.quiet, workers=args.jobs)


def _cmd_player(args) -> None:
    from .pipeline.film import write_player
    from .recorder.player import HTML_SUFFIXES

    _outputs({"-o": args.output}, {"-o": HTML_SUFFIXES}, {"the scene": _scene_path(args.scene)})   # before the work
    scene = _load_scene(args.scene)
    write_player(scene, args.output, frames=args.frames, size=args.size, from_hours=args.from_hours,
                 to_hours=args.to_hours, reflections=args.reflections, seed=args.seed, progress=not args.quiet)


def _rgb_film(scene, args, samples: int) -> None:
    """``film --shading rgb``: one cycle's geometry traced once, re-shaded per hour (:mod:`sunset.light.film`)."""
    from .pipeline.rgb import film_frames, trace_cycle
    from .recorder.film import FILM_CYCLES, _check_film, cycle_times, film_hours, write_video
    from .pipeline.workers import frame_workers

    _check_film(args.output, args.preview, args.from_hours, args.to_hours, FILM_CYCLES, args.fps)
    times = cycle_times(scene, args.frames)
    hours = film_hours(args.from_hours, args.to_hours, FILM_CYCLES * args.frames)
    workers = frame_workers(args.jobs, len(hours))                # --jobs: processes that shade the frames
    geometries = trace_cycle(scene, times, args.reflections, samples, progress=not args.quiet)
    cam = scene.camera
    write_video(film_frames(scene, geometries, hours, samples, times=times, workers=workers), len(hours),
                (cam.width, cam.height), args.output, args.preview, fps=args.fps, progress=not args.quiet)


def _cmd_scene(args) -> None:
    from .model.scene import DEFAULT_SCENE, load_named_scene, scene_names

    if args.list:
        text = "".join(f"{name}\n" for name in scene_names())
    else:
        text = load_named_scene(args.name or DEFAULT_SCENE).to_toml()
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as exc:                    # a full disk, a closed pipe: say so once, not again at exit
        with silenced_stdout():
            raise SunsetError(f"cannot write to standard output ({exc.strerror or exc})") from None


def _cmd_export(args) -> None:
    from .io import write_bytes
    from .model.pov import pov_scene

    _outputs({"-o": args.output}, {"-o": (".pov",)}, {"the scene": _scene_path(args.scene)})
    scene = _load_scene(args.scene)
    if args.size:
        scene = scene.with_size(*args.size)
    write_bytes(args.output, pov_scene(scene, args.time).encode("utf-8"))


def _cmd_info(args) -> None:
    from .provenance import environment, info_text
    from .pipeline.workers import frame_workers, usable_cpus

    env = {**environment(), "usable cpus": str(usable_cpus())}
    env["frame workers"] = f"{frame_workers(frames=2**31)} (--jobs, else SUNSET_WORKERS, else the usable cpus)"
    sys.stdout.write(info_text(env))


COMMANDS = {"figures": _cmd_figures, "render": _cmd_render, "expose": _cmd_expose, "film": _cmd_film,
            "player": _cmd_player, "scene": _cmd_scene, "export": _cmd_export, "info": _cmd_info}
RENDERING = frozenset({"figures", "render", "expose", "film", "player"})


# Options that take a value which may look like an option ("--size -5x10",
# "--hours -0.5"): argparse would read such a value as an unknown option and
# say only "expected one argument"; joined as "--size=-5x10" the value reaches
# its parser, which says what is wrong with it.
_VALUE_OPTIONS = frozenset({"--size", "--time", "--hours", "--from-hours", "--to-hours", "--frames",
                            "--seed", "--fps", "--frame", "--reflections", "--samples", "--depth", "--jobs", "-j"})


def _join_values(argv: list[str]) -> list[str]:
    out: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in _VALUE_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-") \
                and not argv[i + 1].startswith("--"):
            out.append(f"{arg}={argv[i + 1]}")
            i += 2
            continue
        out.append(arg)
        i += 1
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    0 ok, 2 user error, 128 + n on signal n.
    """
    config_fallback()
    with signals_stop_the_command():
        try:
            words = list(sys.argv[1:] if argv is None else argv)
            args = build_parser().parse_args(_join_values(words))
            check_environment()           # thread counts, before Numba loads
            if args.command in RENDERING:     # big arrays reused, not faulted in
                from .kernels import keep_freed_memory
                keep_freed_memory()
            COMMANDS[args.command](args)
            # a signal whose exception Python swallowed still ends the command
            check_stop()
        except SunsetError as exc:
            print(f"sunset: error: {one_line(exc)}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            print("sunset: interrupted", file=sys.stderr)
            return 130
        except Interrupted as exc:
            name = signal.Signals(exc.signum).name
            print(f"sunset: stopped by {name}", file=sys.stderr)
            return 128 + exc.signum
        except MemoryError:
            print("sunset: error: out of memory "
                  "(use a smaller picture or fewer frames)", file=sys.stderr)
            return 2
        # the file system said no where no check foresaw it
        except OSError as exc:
            name = getattr(exc, "filename", None)
            where = f"{shown(name)}: " if name else ""
            message = one_line(where + (exc.strerror or str(exc)))
            print(f"sunset: error: {message}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
