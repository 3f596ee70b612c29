"""The wind sea's tile (issue 31, :mod:`sunset.model.ocean`), timed for ``make bench``.

Two questions. How does one instant of the tile (height and both slopes, three
inverse FFTs) cost with its size N? And how does it cost with the number of
spectral components, against summing the same components as Max summed his
trains, one cosine each at every grid point? The FFT's cost does not depend on
how many of its N² lattice points are filled; the direct sum's grows with each.
Also timed: sampling a million points of the tile (bilinear, a strip at a time
in the renderer). And a whole 8-bit frame of a wind sea (render + encode) as
its tile holds more and more components, beside the same frame of Carla's
Island with more and more of Max's trains (:func:`measure_wind_frames`): the
count enters the wind sea's frame only through the tile's FFTs, whose cost
does not depend on it.
"""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

#: Tile sizes N of the first measurement (L = 256 m; a 7 m/s wind, fully developed).
OCEAN_SIZES = (64, 128, 256, 512, 1024)
#: Component counts at N = 256 (the FFT) and those also summed directly (the trains' way).
OCEAN_COMPONENTS = (4, 64, 1024, 16384, 65024)
OCEAN_DIRECT = (4, 64, 1024)
OCEAN_COMPONENT_N = 256
#: Points sampled in one call.
OCEAN_SAMPLES = 1_000_000


def _runs(fn, repeats: int) -> list[float]:
    fn(0)
    out = []
    for i in range(repeats):
        start = time.perf_counter()
        fn(i + 1)
        out.append(time.perf_counter() - start)
    return out


def _sea(n: int):
    from ..model.windsea import WindSea

    return WindSea(7.0, 90.0, math.inf, 1, n, 256.0, 64.0)


def _keep(h0: np.ndarray, count: int) -> np.ndarray:
    """h₀ with only the ``count`` largest components kept (ties by position)."""
    order = np.argsort(-np.abs(h0).ravel(), kind="stable")
    out = np.zeros(h0.size, complex)
    out[order[:count]] = h0.ravel()[order[:count]]
    return out.reshape(h0.shape)


def _direct(tile, xs: np.ndarray, t: float) -> np.ndarray:
    """z on the grid by summing one cosine per filled lattice point (ẑ(k) and its conjugate at −k each give half)."""
    spec = tile.amplitudes(t)
    z = np.zeros((xs.size, xs.size))
    for i, j in zip(*np.nonzero(tile.mask & (np.abs(spec) > 0))):
        a, phase = abs(spec[i, j]), math.atan2(spec[i, j].imag, spec[i, j].real)
        z += a * np.cos(np.add.outer(tile.ky[i, j] * xs, tile.kx[i, j] * xs) + phase)
    return z


def measure_ocean(width: int, height: int, repeats: int, sizes=OCEAN_SIZES, components=OCEAN_COMPONENTS,
                  direct=OCEAN_DIRECT, samples: int = OCEAN_SAMPLES) -> dict:
    """Seconds per run of each measurement (the picture size is not used)."""
    from ..model.ocean import OceanTile

    out = {}
    for n in sizes:
        sea = _sea(n)
        out[f"build N={n}"] = _runs(lambda i: _sea(n).tile, repeats)
        tile = sea.tile
        out[f"instant N={n}"] = _runs(lambda i: tile.fields(0.37 * i), repeats)
    sea = _sea(OCEAN_COMPONENT_N)
    xs = np.arange(OCEAN_COMPONENT_N) * sea.tile.spacing
    for count in components:
        tile = OceanTile(_keep(sea.amplitudes, count), sea.tile_size, sea.cycle)
        out[f"components {count}, FFT"] = _runs(lambda i: tile.fields(0.37 * i), repeats)
        if count in direct:
            out[f"components {count}, direct sum"] = _runs(lambda i: _direct(tile, xs, 0.37 * i), repeats)
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, sea.tile_size, samples), rng.uniform(0, sea.tile_size, samples)
    tile = sea.tile
    tile.fields(0.0)
    out[f"sample {samples} points"] = _runs(lambda i: tile.sample(x, y, 0.0), repeats)
    return out


#: The frame of the last question: a packaged wind sea with the tile's largest components kept, and Carla's Island
#: with this many of Max's trains (its four, then shorter ones on the λ/n² ladder); render + encode, 2 reflections.
WIND_FRAME_SCENE = "carlas-island-in-the-wind"
WIND_FRAME_SIZE = 512
WIND_FRAME_COMPONENTS = (4, 64, 1024, 16384, 65024)
WIND_FRAME_TRAINS = (4, 8, 16)


def measure_wind_frames(width: int, height: int, repeats: int, components=WIND_FRAME_COMPONENTS,
                        trains=WIND_FRAME_TRAINS) -> dict:
    """Seconds of a whole 8-bit frame (render + encode) against the spectral components, beside Max's trains.

    Each run is at a new time, so a wind sea's runs include its tile's three
    FFTs; its bound over every time is computed before the runs (once per scene).
    """
    from dataclasses import replace

    from .. import encode, render
    from ..model.ocean import OceanTile
    from ..model.scene import Scene
    from ..model.waves import Sea, WaveTrain

    out = {}
    wind_scene = Scene.named(WIND_FRAME_SCENE).with_size(width, height)
    ws = wind_scene.sea.wind
    for count in components:
        tile = OceanTile(_keep(ws.amplitudes, count), ws.tile_size, ws.cycle)
        ws.__dict__["tile"] = tile           # the cached tile of this (frozen) sea, replaced
        tile.bound_every_time
        out[f"{width}x{height} frame, wind sea of {count} components"] = _runs(
            lambda i: encode(wind_scene, render(wind_scene, 0.37 * i, 2)), repeats)
    ws.__dict__.pop("tile")
    base = Scene.named("carlas-island").with_size(width, height)
    for n in trains:
        first = base.sea.trains          # its four, then shorter ones on the λ/n² ladder (sunset.bench's scaling rows)
        more = [WaveTrain(0.01, first[0].wavelength / m ** 2, direction=(37.0 * m) % 360.0, phase=float(m))
                for m in range(len(first) + 1, n + 1)]
        sc = replace(base, sea=Sea(tuple(first[:n]) + tuple(more)))
        out[f"{width}x{height} frame, {n} wave trains (Max's)"] = _runs(lambda i: encode(sc, render(sc, 0.37 * i, 2)),
                                                                        repeats)
    return out


def rows(result: dict, what: str = "wind-sea tile") -> list[dict]:
    """The JSON rows of a :func:`measure_ocean` (or :func:`measure_wind_frames`) result run by :func:`sunset.bench.measure`."""
    return [{"what": f"{what}, {name}", "median_s": statistics.median(times), "runs_s": list(times),
             "peak_rss_mib": result["peak_rss_mib"]} for name, times in result["times"].items()]


def format_rows(ocean_rows: list[dict]) -> str:
    """Plain-text lines for the table that ``make bench`` prints."""
    return "\n".join(f"{r['what']:48s} {'':16s} {r['median_s']:9.4f}" for r in ocean_rows)
