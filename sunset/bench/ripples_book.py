"""What chapter 13 reads of the ripples' benchmark (:mod:`sunset.bench.ripples`): ``python -m
sunset.bench.ripples_book --out book/data`` writes ``ripples-bench.json`` and ``ripples-convergence.json``.

Apart from :mod:`sunset.bench.ripples`, which :mod:`sunset.bench` imports: this module runs the measurements
through :func:`sunset.bench.measure`, each in a fresh process.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

__all__ = ["write_book_data", "main"]


def write_book_data(out: Path, repeats: int = 3) -> tuple[Path, Path]:
    """Run both measurements, each in a fresh process (:func:`sunset.bench.measure`), and write what chapter 13
    reads: ``ripples-bench.json`` (the rows, the machine) and ``ripples-convergence.json``."""
    from . import machine, measure
    from .ripples import rows

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    command = f"python -m sunset.bench.ripples_book --out {out} --repeats {repeats}"
    bench = {"machine": machine(), "command": command, "ripples": rows(measure("ripples", 0, 0, repeats))}
    conv = dict(measure("ripples-convergence", 0, 0, 1)["times"], machine=machine(), command=command)
    paths = out / "ripples-bench.json", out / "ripples-convergence.json"
    for path, data in zip(paths, (bench, conv)):
        tmp = path.with_suffix(".json.part")
        tmp.write_text(json.dumps(data, indent=2) + "\n")
        tmp.replace(path)
    return paths


def main(argv=None) -> int:
    """``python -m sunset.bench.ripples_book --out book/data``: the ripples' rows and convergence for chapter 13."""
    parser = argparse.ArgumentParser(prog="python -m sunset.bench.ripples_book", description=main.__doc__)
    parser.add_argument("--out", type=Path, default=Path("book/data"))
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    if not 1 <= args.repeats <= 100:
        print(f"sunset.bench.ripples_book: repeats must be 1 to 100, got {args.repeats}", file=sys.stderr)
        return 2
    for path in write_book_data(args.out, args.repeats):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
