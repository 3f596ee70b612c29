"""The direct rays of a frame: the sea's and the islands' scan lines merged, then the per-pixel geometry.

:func:`trace_direct` runs the paper's hidden-surface algorithm for height
fields (:mod:`sunset.vector.heightfield`) on every vertical scan line, for the
sea and then for each island (:mod:`sunset.vector.island_samples`), keeping
for every pixel the nearest surface (the largest u = 1/y): a per-scan-line
depth buffer. From the winning u and surface it builds the frame's direct
fields: ray directions, hit points, distances and unit normals
(:func:`assemble_geometry`, :func:`put_unit_normals`).
"""

from __future__ import annotations

import time

import numpy as np

from ..constants import ISLAND_SAMPLE_BUDGET, PART_NONE, SCANLINE_CHUNK_ELEMENTS, SEA, SKY
from ..errors import require_finite
from ..kernels import twin
from ..model.waves import unit_normal
from .frame import Frame
from .heightfield import sampling, sea_gradient_on_scanlines, sea_profile, sea_scan
from .island_samples import island_scan, probe_refinement

__all__ = ["trace_direct", "assemble_geometry", "put_unit_normals"]

_F32 = np.float32


def trace_direct(scene, t: float = 0.0, *, refine_islands: bool = True, info: dict | None = None) -> Frame:
    """Trace the direct ray through every pixel centre: sea, islands or sky.

    Parameters
    ----------
    scene : Scene
    t : float
        Time, seconds.
    refine_islands : bool
        Sample the islands on a refined lattice so their projected samples
        are about σ pixels apart (default); False uses the sea's samples
        for the islands too, as the paper did.
    info : dict, optional
        Filled with counts: ``sea_samples`` (per scan line), ``island_samples``
        (total over scan lines and islands), ``probe`` (the refinement of
        the sea's lattice the islands' probes used), ``tail_pixels`` (pixels resolved by the far tail),
        and ``seconds``: wall-clock time spent on ``sea`` (profile and scan
        conversion), ``islands`` (sampling, profile, scan conversion, depth
        test) and ``assemble`` (points, distances, normals), for the benchmark.

    Returns
    -------
    Frame
        With the direct fields filled (direction, surface, part, distance,
        point, normal); rows top to bottom.
    """
    require_finite("t", t)
    t = float(t)
    cam = scene.camera
    H, W, h = cam.height, cam.width, cam.eye_height
    d = scene.sea.max_elevation
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    samp = sampling(cam, d)
    s_all = cam.s_centres()
    zeta = zeta0 + dz * np.arange(H, dtype=np.float64)  # bottom up
    u_sea_lattice = samp.u()

    best_u = np.zeros((W, H))                 # 1/yp of the nearest surface, 0: none
    best_surf = np.full((W, H), SKY, dtype=np.int8)
    stats = {"sea_samples": samp.n, "island_samples": 0, "probe": [], "tail_pixels": 0}
    seconds = {"sea": 0.0, "islands": 0.0, "assemble": 0.0}
    clock = time.perf_counter
    tick = clock()
    # the islands' probe refinements, once for all scan lines
    probes = [probe_refinement(island, s_all, samp, d) for island in scene.islands]
    budget = ISLAND_SAMPLE_BUDGET * max(samp.n, H)
    stats["probe"] = probes
    tock = clock()
    seconds["islands"] += tock - tick
    tick = tock

    n_per = max(samp.n, 1)
    chunk = max(1, min(W, SCANLINE_CHUNK_ELEMENTS // n_per))
    for c0 in range(0, W, chunk):
        cols = slice(c0, min(W, c0 + chunk))
        s = s_all[cols]
        # the sea: its profile on the lattice, scan-converted, and the far tail
        if samp.n:
            g = sea_profile(scene.sea, s, u_sea_lattice, h, t)
            stats["tail_pixels"] += sea_scan(u_sea_lattice, g, zeta0, dz, H, best_u[cols], best_surf[cols])
            del g
        tock = clock()
        seconds["sea"] += tock - tick
        tick = tock
        # the islands: per-scan-line depth buffer, the nearest (largest u) wins
        for k, (island, m0) in enumerate(zip(scene.islands, probes), start=1):
            if m0 is not None:
                stats["island_samples"] += island_scan(island, s, samp, d, h, m0, zeta0, dz, H, cam.sigma, budget,
                                                       refine_islands, best_u[cols], best_surf[cols], k)
        tock = clock()
        seconds["islands"] += tock - tick
        tick = tock
    frame = _assemble(scene, t, best_u, best_surf, s_all, zeta)
    seconds["assemble"] = clock() - tick
    if info is not None:
        info.update(stats, seconds=seconds)
    return frame


def _assemble(scene, t, best_u, best_surf, s_all, zeta) -> Frame:
    """Hit points, distances, normals and parts from 1/yp and the winning surface.

    ``best_u`` and ``best_surf`` are (scan line, pixel from the bottom); the
    frame's arrays are (row from the top, column). The geometry comes from
    :func:`assemble_geometry`; the normals from the gradients on the
    compressed subsets of sea and island pixels.
    """
    surf, direction, point, distance, normal, hits = assemble_geometry(best_u, best_surf, s_all, zeta,
                                                                       len(scene.islands))
    part = np.full(surf.shape, PART_NONE, dtype=np.int8)
    # the sea: the gradient in the b_j, c_j form, on the sea pixels only
    idx, s_hit, y_hit = hits[0]
    if len(idx):
        fx, fy = sea_gradient_on_scanlines(scene.sea, s_hit, y_hit, t)
        put_unit_normals(normal, idx, fx, fy)
    for k, island in enumerate(scene.islands, start=1):
        idx, s_hit, yk = hits[k]
        if not len(idx):
            continue
        _, prt, gx, gy = island.surface((s_hit * yk).astype(_F32), yk.astype(_F32))
        part.reshape(-1)[idx] = prt
        normal.reshape(-1, 3)[idx] = unit_normal(gx.astype(_F32), gy.astype(_F32))
    return Frame(t=t, reflections=0, direction=direction, surface=surf, part=part, distance=distance,
                 point=point, normal=normal)


@twin("sunset.vector.direct_numba")
def assemble_geometry(best_u, best_surf, s_all, zeta, n_islands: int):
    """The per-pixel geometry from the depth buffer, as whole-array operations.

    Returns surf (H, W) int8; direction and point (H, W, 3) float32; distance
    (H, W) float32; normal (H, W, 3) float32, NaN everywhere (the sea's and
    the islands' are filled later); and ``hits``: for the sea (k = 0) and each
    island k, the flat indices of its pixels, their s and their y.
    """
    surf, y, direction, point, distance, normal = _assemble_geometry(best_u, best_surf, s_all, zeta)
    W = surf.shape[1]
    flat_surf = surf.reshape(-1)
    flat_y = y.reshape(-1)
    hits = []
    for k in range(n_islands + 1):
        idx = np.flatnonzero(flat_surf == SEA + k)
        hits.append((idx, s_all[idx % W], flat_y[idx]))
    return surf, direction, point, distance, normal, hits


@twin("sunset.vector.direct_numba")
def put_unit_normals(normal, idx, fx, fy) -> None:
    """Write the unit normals (−f_x, −f_y, 1)/|·| into the flat pixels ``idx`` of ``normal`` (H, W, 3), in place."""
    normal.reshape(-1, 3)[idx] = unit_normal(fx, fy)


def _assemble_geometry(best_u, best_surf, s_all, zeta):
    """The per-pixel geometry as whole-array operations.

    Returns surf (H, W) int8, y (H, W) float64 (NaN for sky), direction and
    point (H, W, 3) float32, distance (H, W) float32 and normal (H, W, 3)
    float32, NaN everywhere (the sea's and the islands' are filled later).
    """
    surf = np.ascontiguousarray(best_surf[:, ::-1].T)
    u = np.ascontiguousarray(best_u[:, ::-1].T)
    H, W = surf.shape
    hit = surf != SKY
    with np.errstate(divide="ignore"):
        y = np.where(hit, 1.0 / u, np.nan)                 # (H, W)
    s = s_all[None, :]
    z = zeta[::-1][:, None]
    length = np.sqrt(1.0 + s * s + z * z)                  # |(s, 1, ζ)|
    inv = 1.0 / length
    direction = np.empty((H, W, 3), dtype=_F32)
    direction[..., 0] = s * inv
    direction[..., 1] = inv
    direction[..., 2] = z * inv
    point = np.empty((H, W, 3), dtype=_F32)
    point[..., 0] = s * y
    point[..., 1] = y
    point[..., 2] = z * y
    distance = np.where(hit, y * length, np.inf).astype(_F32)
    normal = np.full((H, W, 3), np.nan, dtype=_F32)
    return surf, y, direction, point, distance, normal
