"""How closely the two arithmetic paths agree: the NumPy reference kernels and the compiled renderer.

The compiled kernels compute the vector stage with other arithmetic than the
NumPy reference (their own float32 cosine, loops in another order), so the
two do not give the same bits; they must agree within the tolerances that
chapter 10 states and ``tests/test_kernels.py`` holds. :func:`measure`
renders every packaged scene at several times of its wave cycle, in the
three reflection modes, with and without the sea's bounces, on both paths,
and reports:

* the geometry fields' relative error per pixel (:func:`relative_errors`):
  |a − b| / |a| for points and distances, |a − b| for unit vectors and
  cosines, on the pixels where both paths see the same surfaces;
* the share of pixels whose 8-bit code is the same on both paths, and the
  cause of every differing code (:func:`classify`, one of :data:`CAUSES`).

``python -m sunset.bench.agreement --out book/data/agreement.json`` writes
the measurement that chapter 10 shows (1024² by default: about ten minutes
on two cores).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

#: The geometry fields compared, and whether each is a vector (its error is the norm of the difference).
GEOMETRY = {"direction": True, "distance": False, "point": True, "normal": True, "ray": True,
            "final_normal": True, "incidence": False, "sea_rays": True}
#: Fields whose error is absolute (unit vectors and cosines); the others' is relative to the reference's size.
ABSOLUTE = {"direction", "normal", "ray", "final_normal", "incidence", "sea_rays"}
#: What the direct ray's fields depend on, and what the final ones do: a pixel is compared only where they agree.
DIRECT_FIELDS = {"direction", "distance", "point", "normal"}

#: The causes of a differing code, in the order :func:`classify` tries them.
CAUSES = (
    "silhouette",        # the direct ray meets another surface (sea, island, sky) on the other path
    "grazing ray",       # the same surface, but its normal there differs by more than AGREE_NORMAL: the hit,
                         # moved by a rounding, sits where the slope turns fast (far off, short waves)
    "second reflection",  # one path finds the crest ahead and the other does not, or the second reflection
                         # differs by more than AGREE_RAY: the ray grazes the crest cylinder
    "reflected edge",    # the reflected ray meets another island, part or the sky on the other path, or the
                         # same island where its normal differs by more than AGREE_FINAL_NORMAL
    "shade boundary",    # the same island part, its ρ̂ a rounding away from a step of the shade codes
    "sky boundary",      # the same sky (or cloud) range, the ray's height a rounding away from a step of its codes
    "glitter edge",      # |W·R| a rounding away from sin δ or sin 3δ: track, halo or sky
    "other",             # none of these (the tests require none)
)
#: A coded value (before its floor) this close to a step of the codes, relative, is on the step (both paths'
#: frames the same, their coders' last roundings different).
ON_STEP = 1e-9


def cycle_times(scene, count: int) -> list[float]:
    """``count`` times spread over the scene's wave cycle (its sea's period; 8 s for a sea with none)."""
    period = scene.sea.period or 8.0
    return [period * k / count for k in range(count)]


def _pair(a, b, vector: bool):
    a = np.asarray(a, np.float64)
    b = np.asarray(b, np.float64)
    if vector:
        diff = np.sqrt(np.sum((a - b) ** 2, axis=-1))
        size = np.sqrt(np.sum(a * a, axis=-1))
        finite = np.all(np.isfinite(a), axis=-1) & np.all(np.isfinite(b), axis=-1)
    else:
        diff, size = np.abs(a - b), np.abs(a)
        finite = np.isfinite(a) & np.isfinite(b)
    return diff, size, finite


def relative_errors(ref, got) -> dict:
    """Each geometry field's error per compared pixel (1-D float64), where both frames have the field.

    Direct fields are compared where both paths' direct rays meet the same
    surface; the final ones (and the bounces) where, moreover, the rays
    reflect as often and end on the same surface and part.
    """
    same_direct = ref.surface == got.surface
    same_final = same_direct & (ref.final_surface == got.final_surface) & (ref.final_part == got.final_part) \
        & (ref.bounces == got.bounces)
    out = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for name, vector in GEOMETRY.items():
            a, b = getattr(ref, name), getattr(got, name)
            if a is None or b is None:
                continue
            diff, size, finite = _pair(a, b, vector)
            if name not in ABSOLUTE:
                diff = diff / np.where(size > 0, size, 1.0)
            same = same_direct if name in DIRECT_FIELDS else same_final
            same = same.reshape(same.shape + (1,) * (diff.ndim - 2))    # the two bounces of incidence, sea_rays
            out[name] = diff[finite & same]
    return out


def _island_value(frame, codes_map, sun, u):
    """B(ρ̂ + 1) + u of every pixel from its final normal, B = a quarter of its range: the part's on an island,
    the cliff's on a post (0 elsewhere)."""
    from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, POST
    from ..tape.codes import rho_hat

    normal = np.asarray(frame.final_normal, np.float64)
    rh = rho_hat(np.nan_to_num(normal), sun)
    size = np.zeros(frame.shape)
    island = frame.final_surface >= 1
    for p in (PART_HILL, PART_CLIFF, PART_BEACH):
        size[island & (frame.final_part == p)] = codes_map.for_part(p).size
    size[frame.final_surface == POST] = codes_map.cliff.size
    return (rh + 1.0) * (size / 4.0) + u


def _sky_values(frame, codes_map, sun, u, v):
    """(the value floored for each pixel's sky, track or halo index, |W·R| + (v − ½)·dither) of every pixel.

    The sky's n√z + u, the track's and the halo's n·asin(z)/e_max + u, each
    with its own range's n, chosen by the group of the pixel's code.
    """
    from ..constants import TRACK_DITHER
    from ..tape.codes import track_elevation_max

    ray = np.asarray(frame.ray, np.float64)
    z = np.clip(ray[..., 2], 0.0, 1.0)
    elevation = np.arcsin(z) / track_elevation_max(sun)
    value = np.sqrt(z) * codes_map.sky.size + u
    wr = np.abs(ray @ np.asarray(sun.W)) + (v - 0.5) * (TRACK_DITHER * math.sin(sun.delta))
    return value, elevation, wr


def _across(a, b) -> np.ndarray:
    """Whether a step of the codes lies between the two paths' values a and b (less than one apart), or on a."""
    return ((np.floor(a) != np.floor(b)) & (np.abs(a - b) < 1.0)) | \
        (np.abs(a - np.round(a)) <= ON_STEP * np.maximum(1.0, np.abs(a)))


def _across_threshold(a, b, edge: float) -> np.ndarray:
    """Whether the threshold ``edge`` lies between a and b, or a is on it."""
    return ((a < edge) != (b < edge)) | (np.abs(a - edge) <= ON_STEP * edge)


def classify(scene, ref, got, codes_ref, codes_got, seed: int = 0) -> np.ndarray:
    """The cause (an index into :data:`CAUSES`) of every pixel whose code differs, in row-major order.

    ``ref`` and ``got`` are the two paths' frames of ``scene`` (with their
    reflections traced), ``codes_ref`` and ``codes_got`` their codes with the
    dither of ``seed``. Each pixel gets the first cause that holds, in the
    order of :data:`CAUSES`, the geometry's ones where it differs by more
    than the tolerances of :mod:`sunset.kernels`. Within them, a code boundary
    (shade, sky, glitter) counts only where a step of the codes lies between
    the two paths' values that the code floors (or compares with sin δ and
    sin 3δ), less than one step apart, or where the value is on the step
    (:data:`ON_STEP`); any other differing code is "other".
    """
    from .. import kernels
    from ..constants import CLOUD, HALO_FACTOR, POST, SKY
    from ..tape.codes import code_map, dither

    diff = np.asarray(codes_ref) != np.asarray(codes_got)
    cause = np.full(ref.shape, len(CAUSES) - 1, np.int8)
    left = diff.copy()

    def take(mask, name):
        hit = left & mask
        cause[hit] = CAUSES.index(name)
        left[hit] = False

    cmap, sun = code_map(scene), scene.sun
    H, W = ref.shape
    u = dither(seed, 0, (H, W), 0)
    v = dither(seed, 0, (H, W), 1)
    take(ref.surface != got.surface, "silhouette")
    with np.errstate(invalid="ignore"):
        take(_pair(ref.normal, got.normal, True)[0] > kernels.AGREE_NORMAL, "grazing ray")
        ray_moved = _pair(ref.ray, got.ray, True)[0] > kernels.AGREE_RAY
        take((ref.bounces != got.bounces) | ((ref.bounces == 2) & ray_moved), "second reflection")
        take((ref.final_surface != got.final_surface) | (ref.final_part != got.final_part)
             | (_pair(ref.final_normal, got.final_normal, True)[0] > kernels.AGREE_FINAL_NORMAL), "reflected edge")
    with np.errstate(invalid="ignore"):
        a, b = _island_value(ref, cmap, sun, u), _island_value(got, cmap, sun, u)
        shaded = (ref.final_surface >= 1) | (ref.final_surface == POST)
        take(shaded & _across(a, b), "shade boundary")
        (s_a, e_a, w_a), (s_b, e_b, w_b) = _sky_values(ref, cmap, sun, u, v), _sky_values(got, cmap, sun, u, v)
        groups = cmap.group(codes_ref)
        sky = (ref.final_surface == SKY) & (groups == cmap.group(codes_got))
        for rng, (x, y) in ((cmap.sky, (s_a, s_b)), (cmap.track, (e_a * cmap.track.size + u, e_b * cmap.track.size + u)),
                            (cmap.halo, (e_a * cmap.halo.size + u, e_b * cmap.halo.size + u))):
            here = sky & (groups == cmap.ranges.index(rng))
            take(here & _across(x, y), "sky boundary")
        if cmap.cloud is not None:               # a cloud: its index, ⌊n (d + T)/(T + B) + u⌋, in the sky's row
            clouds = scene.clouds
            scale = cmap.cloud.size / (clouds.max_top + clouds.max_bottom)
            x, y = ((np.asarray(f.cloud_depth, np.float64) + clouds.max_top) * scale + u for f in (ref, got))
            take((ref.final_surface == CLOUD) & _across(x, y), "sky boundary")
        edge = _across_threshold(w_a, w_b, math.sin(sun.delta)) | \
            _across_threshold(w_a, w_b, math.sin(HALO_FACTOR * sun.delta))
        take((ref.final_surface == SKY) & edge, "glitter edge")
    return cause[diff]


def _summary(err: np.ndarray) -> dict:
    if err.size == 0:
        return {"pixels": 0}
    q = np.quantile(err, [0.5, 0.999, 0.9999])
    return {"pixels": int(err.size), "median": float(q[0]), "q999": float(q[1]), "q9999": float(q[2]),
            "max": float(err.max())}


def _direct(scene, t: float) -> dict:
    """Both paths' direct frames of ``scene`` at ``t`` (False: NumPy, True: compiled)."""
    from .. import kernels
    from ..pipeline.frame import trace_direct

    out = {}
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            out[compiled] = trace_direct(scene, t)
    return out


def compare(scene, t: float, reflections: int, sea_bounces: bool, seed: int = 0, direct: dict | None = None) -> dict:
    """One scene at one time in one mode on both paths: the geometry errors and the codes' agreement.

    ``direct``: both paths' direct frames (:func:`_direct`), when a caller has them already.
    """
    import copy

    from .. import kernels
    from ..pipeline.frame import encode, trace_reflections

    direct = direct or _direct(scene, t)
    frames, codes = {}, {}
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            frames[compiled] = trace_reflections(scene, copy.deepcopy(direct[compiled]), reflections, sea_bounces)
            codes[compiled] = encode(scene, frames[compiled], seed=seed)
    ref, got = frames[False], frames[True]
    causes = classify(scene, ref, got, codes[False], codes[True], seed)
    pixels = ref.shape[0] * ref.shape[1]
    return {"t": t, "reflections": reflections, "sea_bounces": sea_bounces, "pixels": pixels,
            "differing": int(causes.size), "identical_share": 1.0 - causes.size / pixels,
            "causes": {name: int(np.count_nonzero(causes == i)) for i, name in enumerate(CAUSES)},
            "geometry": {name: _summary(err) for name, err in relative_errors(ref, got).items()}}


def measure(names=None, size: int = 1024, times: int = 4, modes=(0, 1, 2), bounces=(False, True), seed: int = 0,
            log=None) -> dict:
    """:func:`compare` over scenes × times of their cycle × modes × with and without the sea's bounces."""
    from ..model.scene import as_scene, scene_names

    runs = []
    start = time.perf_counter()
    for name in sorted(names or scene_names()):
        scene = as_scene(name).with_size(size, size)
        for t in cycle_times(scene, times):
            direct = _direct(scene, t)
            for mode in modes:
                for sea_bounces in bounces:
                    run = compare(scene, t, mode, sea_bounces, seed, direct)
                    run["scene"] = name
                    runs.append(run)
                    if log:
                        log(f"{name} t={t:.3f} mode {mode} bounces {sea_bounces}: {run['differing']} codes differ "
                            f"({time.perf_counter() - start:.0f} s)")
    return {"size": size, "times": times, "seed": seed, "runs": runs}


def totals(result: dict) -> dict:
    """Per scene: pixels, differing codes, the share identical, and the differing codes by cause."""
    out: dict = {}
    for run in result["runs"]:
        row = out.setdefault(run["scene"], {"pixels": 0, "differing": 0, "worst_share": 1.0,
                                            "causes": dict.fromkeys(CAUSES, 0)})
        row["pixels"] += run["pixels"]
        row["differing"] += run["differing"]
        row["worst_share"] = min(row["worst_share"], run["identical_share"])
        for name, n in run["causes"].items():
            row["causes"][name] += n
    for row in out.values():
        row["identical_share"] = 1.0 - row["differing"] / row["pixels"]
    return out


def dumps(result: dict) -> str:
    """The measurement as JSON text, one run to a line."""
    head = {k: v for k, v in result.items() if k != "runs"}
    runs = ",\n".join(json.dumps(r) for r in result["runs"])
    return json.dumps(head, indent=1)[:-2] + ',\n "runs": [\n' + runs + "\n ]\n}\n"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m sunset.bench.agreement", description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("figures/agreement.json"))
    p.add_argument("--size", type=int, default=1024)
    p.add_argument("--times", type=int, default=4, help="times per wave cycle (default 4)")
    p.add_argument("--scene", action="append", help="only this packaged scene (repeatable)")
    args = p.parse_args(argv)
    if args.size < 8 or args.times < 1:
        print("sunset.bench.agreement: error: --size must be at least 8 and --times at least 1", file=sys.stderr)
        return 2
    from . import machine

    result = measure(args.scene, args.size, args.times, log=lambda s: print(s, file=sys.stderr, flush=True))
    result["machine"] = machine()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
