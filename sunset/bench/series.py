"""Stokes' series by computer (issue 13, :mod:`sunset.model.series`), timed for ``make bench``.

Each order is computed from scratch (a new :class:`~sunset.model.series.StokesSeries`,
not the cached :func:`~sunset.model.series.stokes_series`): the recurrence, the
amplitudes, and the speed and crest curvature in α, ε and ω.
"""

from __future__ import annotations

import statistics
import time

#: (order, exact): exact order 30 with every amplitude a_n (the issue's "order 30 exact in
#: under a minute"); exact order 80 (the book's) and float64 to 100 and 200 with a₁..a₄.
SERIES_ORDERS = ((30, True), (80, True), (100, False), (200, False))


def series_once(order: int, exact: bool) -> None:
    """One Stokes series of ``order``, with what the book asks of it."""
    from ..model.series import StokesSeries

    s = StokesSeries(order, exact)
    for n in range(1, (order if order <= 30 else 4) + 1):
        s.amplitude(n, "alpha")
    for parameter in ("alpha", "epsilon", "omega"):
        s.speed(parameter)
        s.crest_curvature(parameter)


def measure_series(width: int, height: int, repeats: int, orders=SERIES_ORDERS) -> dict:
    """Seconds for each of ``orders``: one warm-up, then ``repeats`` runs (the picture size is not used)."""
    out = {}
    for order, exact in orders:
        series_once(order, exact)
        runs = []
        for _ in range(repeats):
            start = time.perf_counter()
            series_once(order, exact)
            runs.append(time.perf_counter() - start)
        out[f"order {order}, {'exact' if exact else 'float64'}"] = runs
    return out


def rows(result: dict) -> list[dict]:
    """The JSON rows of a :func:`measure_series` result run by :func:`sunset.bench.measure`."""
    return [{"what": f"Stokes' series, {what}", "median_s": statistics.median(times), "runs_s": list(times),
             "peak_rss_mib": result["peak_rss_mib"]} for what, times in result["times"].items()]


def format_rows(series_rows: list[dict]) -> str:
    """Plain-text lines for the table that ``make bench`` prints."""
    return "\n".join(f"{r['what']:48s} {'':16s} {r['median_s']:9.3f}" for r in series_rows)
