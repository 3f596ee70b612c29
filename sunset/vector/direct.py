"""The direct rays, as strip kernels: the islands' and the sea's scan lines into a depth buffer, then each
strip of rows' geometry.

The paper's hidden-surface algorithm for height fields (:mod:`sunset.vector.heightfield`)
runs on every vertical scan line, for the sea and for each island
(:mod:`sunset.vector.island_samples`), keeping for every pixel the nearest
surface (the largest u = 1/y): a per-scan-line depth buffer
(:class:`DepthBuffer`). From the winning u and surface, a strip of rows gets
its direct fields: ray directions, hit points, distances and unit normals
(:func:`direct_rows`: :func:`assemble_geometry`, :func:`put_sea_normals`,
:func:`put_island_normals`).

Each function here works on one strip (of scan lines or of rows) and calls
no other stage; the pipeline (:mod:`sunset.pipeline.frame`) chains them over
a frame's strips, on its threads, with the budget checked once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..constants import ISLAND_SAMPLE_BUDGET, PART_NONE, SEA, SKY
from ..errors import SunsetError
from ..kernels import twin
from ..model.waves import unit_normal
from .frame import Frame
from .heightfield import Sampling, sea_gradient_on_scanlines
from .island_samples import islands_scan, probe_refinement

__all__ = ["IslandPass", "island_key", "check_island_pass", "DepthBuffer", "row_heights", "island_probes",
           "island_columns", "direct_rows", "sea_strip", "sea_points", "sea_geometry", "assemble_geometry", "put_unit_normals",
           "put_sea_normals", "put_island_normals", "ray_directions"]

_F32 = np.float32


@dataclass(frozen=True)
class IslandPass:
    """The islands' share of the direct rays: the same at every time, so a wave cycle computes it once.

    The islands do not move, and where they are sampled depends only on the
    camera, the islands and the sea's largest elevation d (their bounding
    ellipses), never on t. This is their per-scan-line depth buffer, the
    nearest island (largest u = 1/y) at every pixel, into (a copy of) which
    the sea of each frame is merged. Made by :func:`sunset.pipeline.frame.island_pass`.

    Attributes
    ----------
    key : tuple
        What the pass depends on (:func:`island_key`); a scene with another key is refused.
    u : ndarray (W, H) float64
        1/yp of the nearest island per (scan line, pixel from the bottom); 0: none.
    code : ndarray (W, H) int8
        Its 1-based number, or SKY.
    samples : int
        The islands' samples over all scan lines.
    probe : list
        Each island's probe refinement (None: out of view).
    """

    key: tuple
    u: np.ndarray
    code: np.ndarray
    samples: int
    probe: list


def island_key(scene, refine_islands: bool = True) -> tuple:
    """What the islands' pass depends on: the camera, the islands, the sea's largest elevation, the refinement."""
    return (scene.camera, scene.islands, float(scene.sea.max_elevation), bool(refine_islands))


def check_island_pass(scene, islands: IslandPass, refine_islands: bool = True) -> None:
    """Raise :class:`SunsetError` unless ``islands`` was computed for this camera, these islands and this sea height."""
    if islands.key != island_key(scene, refine_islands):
        raise SunsetError("islands: this island pass was computed for another camera, islands or sea height")


class DepthBuffer(NamedTuple):
    """Every scan line's nearest surface: what the direct rays of a frame are made from.

    Attributes
    ----------
    u : ndarray (W, H) float64
        1/yp of the nearest surface per (scan line, pixel from the bottom); 0: none.
    surface : ndarray (W, H) int8
        Its code: SEA, an island's 1-based number, or SKY.
    s : ndarray (W,) float64
        Each scan line's s = x/y.
    zeta : ndarray (H,) float64
        ζ = z/y at each pixel's centre, bottom up (:func:`row_heights`).
    """

    u: np.ndarray
    surface: np.ndarray
    s: np.ndarray
    zeta: np.ndarray


def row_heights(cam) -> np.ndarray:
    """ζ = z/y at the centre of every row, bottom up (H,) float64: the depth buffer's order."""
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    return zeta0 + dz * np.arange(cam.height, dtype=np.float64)


def island_probes(scene, samp: Sampling) -> tuple[int, list]:
    """The islands' sample budget per scan line and each island's probe refinement (None: out of view).

    :func:`sunset.vector.island_samples.probe_refinement` with the budget
    ISLAND_SAMPLE_BUDGET · max(n, H), what :func:`island_columns` needs for every strip.
    """
    cam = scene.camera
    budget = ISLAND_SAMPLE_BUDGET * max(samp.n, cam.height)
    s_all = cam.s_centres()
    return budget, [probe_refinement(island, s_all, samp, scene.sea.max_elevation, budget)
                    for island in scene.islands]


def island_columns(scene, samp: Sampling, budget: int, probes: list, refine_islands: bool, c0: int, c1: int,
                   u, code) -> int:
    """The islands' depth buffer of the scan lines ``c0:c1`` into ``u`` and ``code`` (W', H); their samples.

    Each island is sampled, scan-converted and merged, nearest first wins
    (:func:`sunset.vector.island_samples.islands_scan`), in island order.
    """
    cam = scene.camera
    dz = cam.pixel_pitch[1]
    return islands_scan(scene.islands, probes, cam.s_centres(), c0, c1, samp, scene.sea.max_elevation,
                        cam.eye_height, cam.zy_min + 0.5 * dz, dz, cam.height, cam.sigma, budget, refine_islands,
                        u, code)


def direct_rows(scene, t: float, depth: DepthBuffer, r0: int, r1: int, out: Frame, normals=None) -> None:
    """The direct fields of the rows ``r0:r1`` (top down) of a frame, from the depth buffer, into ``out``.

    ``out`` holds just those rows (a strip's own arrays, or a frame's rows:
    :meth:`~sunset.vector.frame.Frame.rows`). Hit points, distances,
    directions (:func:`assemble_geometry`), then the normals from the
    gradients on the compressed subsets of sea and island pixels
    (``normals``, the sea's kind's kernel: the trains' :func:`put_sea_normals`
    by default; :func:`put_island_normals`) and the islands' parts.
    """
    best_u, best_surf, s_all, zeta = depth
    H = best_u.shape[1]
    k0, k1 = H - r1, H - r0      # the rows' pixels, counted from the bottom
    hits = assemble_geometry(best_u[:, k0:k1], best_surf[:, k0:k1], s_all, zeta[k0:k1], len(scene.islands),
                             (out.surface, out.direction, out.point, out.distance, out.normal))
    out.part.fill(PART_NONE)
    # the sea: the gradient in the b_j, c_j form, on the sea pixels only
    idx, s_hit, y_hit = hits[0]
    if len(idx):
        (normals or put_sea_normals)(scene.sea, t, out.normal, idx, s_hit, y_hit)
    for k, island in enumerate(scene.islands, start=1):
        idx, s_hit, yk = hits[k]
        if not len(idx):
            continue
        put_island_normals(island, out.normal, out.part, idx, s_hit, yk)


def sea_strip(scene, t: float, depth: tuple, direction, r0: int, r1: int, geometry=None) -> Frame:
    """The direct rays of the rows ``r0:r1`` (top down) of a wave cycle's frame, as far as its sea pixels need them.

    From the frame's depth buffer ``depth`` (:class:`DepthBuffer`): ``surface``
    everywhere and, on the sea pixels alone, ``point`` and ``normal``
    (``geometry``, the sea's kind's kernel: the trains' :func:`sea_geometry`
    by default), the same bits as :func:`direct_rows`' there,
    in arrays of the strip's own. ``direction`` (H, W, 3) float32 is the
    whole frame's, which does not change with time: the strip's is a view of
    it. ``point`` and ``normal`` are left unset off the sea, and ``part`` and
    ``distance`` are None: the strip is for
    :func:`sunset.vector.reflect.trace_sea_rays` and the codes of its sea
    pixels (a wave cycle's frame, :func:`sunset.pipeline.frame.code_frame`).
    """
    best_u, best_surf, s_all, zeta = depth
    W, H = best_u.shape
    n = r1 - r0
    surface = np.empty((n, W), np.int8)
    point = np.empty((n, W, 3), _F32)
    normal = np.empty((n, W, 3), _F32)
    k0, k1 = H - r1, H - r0      # the rows' pixels, counted from the bottom
    (geometry or sea_geometry)(best_u[:, k0:k1], best_surf[:, k0:k1], s_all, zeta[k0:k1], scene.sea, float(t),
                               surface, point, normal)
    return Frame(t=float(t), reflections=0, direction=direction[r0:r1], surface=surface, part=None, distance=None,
                 point=point, normal=normal)


@twin("sunset.vector.direct_numba")
def sea_geometry(best_u, best_surf, s_all, zeta, sea, t: float, surface, point, normal) -> None:
    """The direct fields of the sea pixels alone, from the depth buffer: :func:`assemble_geometry` and
    :func:`put_sea_normals`, skipping everything else.

    ``best_u``, ``best_surf`` (W, K) hold K pixels of every scan line, from
    the bottom, at heights ``zeta`` (K,). Fills ``surface`` (K, W) int8, rows
    from the top, and, where it is the sea, ``point`` and ``normal`` (K, W, 3)
    float32 with the same bits as :func:`direct_rows` (elsewhere they are not written).
    A sea of trains (a wind sea's is :func:`sunset.vector.windsea_scan.wind_sea_geometry`).
    """
    idx, s, y = sea_points(best_u, best_surf, s_all, zeta, surface, point)
    if len(idx):
        put_sea_normals(sea, t, normal, idx, s, y)


def sea_points(best_u, best_surf, s_all, zeta, surface, point):
    """:func:`sea_geometry`'s ``surface`` and the sea pixels' ``point``, whatever the sea; their (flat index, s, y)."""
    surface[...] = best_surf[:, ::-1].T
    idx = np.flatnonzero(surface == SEA)
    W = surface.shape[1]
    y = 1.0 / best_u[:, ::-1].T.reshape(-1)[idx]
    s = s_all[idx % W]
    z = zeta[::-1][idx // W]
    flat = point.reshape(-1, 3)
    flat[idx, 0] = s * y
    flat[idx, 1] = y
    flat[idx, 2] = z * y
    return idx, s, y


@twin("sunset.vector.direct_numba")
def assemble_geometry(best_u, best_surf, s_all, zeta, n_islands: int, out):
    """The per-pixel geometry from the depth buffer, as whole-array operations.

    ``best_u``, ``best_surf`` (W, K) hold K pixels of every scan line, from
    the bottom, at heights ``zeta`` (K,); ``out`` = (surf (K, W) int8,
    direction and point (K, W, 3) float32, distance (K, W) float32, normal
    (K, W, 3) float32) is filled, rows from the top, the normal NaN
    everywhere (the sea's and the islands' are filled later). Returns
    ``hits``: for the sea (k = 0) and each island k, the flat indices of its
    pixels in ``out``, their s and their y.
    """
    surf, y = _assemble_geometry(best_u, best_surf, s_all, zeta, out)
    W = surf.shape[1]
    flat_surf = surf.reshape(-1)
    flat_y = y.reshape(-1)
    hits = []
    for k in range(n_islands + 1):
        idx = np.flatnonzero(flat_surf == SEA + k)
        hits.append((idx, s_all[idx % W], flat_y[idx]))
    return hits


@twin("sunset.vector.direct_numba")
def put_unit_normals(normal, idx, fx, fy) -> None:
    """Write the unit normals (−f_x, −f_y, 1)/|·| into the flat pixels ``idx`` of ``normal`` (H, W, 3), in place."""
    normal.reshape(-1, 3)[idx] = unit_normal(fx, fy)


@twin("sunset.vector.direct_numba")
def put_island_normals(island, normal, part, idx, s, y) -> None:
    """An island's pixels: the part and the unit normal of its surface at (s·y, y) into ``idx``, in place.

    :meth:`sunset.model.islands.Island.surface` (float32) and
    :func:`sunset.model.waves.unit_normal`; the twin does both in one pass.
    """
    _, prt, gx, gy = island.surface((s * y).astype(_F32), y.astype(_F32))
    part.reshape(-1)[idx] = prt
    normal.reshape(-1, 3)[idx] = unit_normal(gx.astype(_F32), gy.astype(_F32))


@twin("sunset.vector.slopes_numba")
def put_sea_normals(sea, t: float, normal, idx, s, y) -> None:
    """The sea pixels' unit normals: the slopes on the scan lines, then (−f_x, −f_y, 1)/|·| into ``idx``, in place.

    :func:`sunset.vector.heightfield.sea_gradient_on_scanlines` at (s·y, y)
    and :func:`put_unit_normals`; the twin does both in one pass. A sea of
    trains: a wind sea is refused (its normals are
    :func:`sunset.vector.windsea_scan.wind_normals`').
    """
    fx, fy = sea_gradient_on_scanlines(sea, s, y, t)
    put_unit_normals(normal, idx, fx, fy)


def _assemble_geometry(best_u, best_surf, s_all, zeta, out):
    """The per-pixel geometry as whole-array operations, into ``out`` (see :func:`assemble_geometry`).

    Returns surf (H, W) int8 and y (H, W) float64 (NaN for sky).
    """
    surf, direction, point, distance, normal = out
    surf[...] = best_surf[:, ::-1].T
    u = np.ascontiguousarray(best_u[:, ::-1].T)
    H, W = surf.shape
    hit = surf != SKY
    with np.errstate(divide="ignore"):
        y = np.where(hit, 1.0 / u, np.nan)                 # (H, W)
    s = s_all[None, :]
    z = zeta[::-1][:, None]
    length = ray_directions(s_all, zeta, direction)
    point[..., 0] = s * y
    point[..., 1] = y
    point[..., 2] = z * y
    distance[...] = np.where(hit, y * length, np.inf)
    normal.fill(np.nan)
    return surf, y


def ray_directions(s_all, zeta, direction) -> np.ndarray:
    """The unit direct rays (s, 1, ζ)/|(s, 1, ζ)| into ``direction`` (K, W, 3) float32, rows from the top, for scan
    lines at ``s_all`` (W,) and rows at heights ``zeta`` (K,) from the bottom; returns the lengths |(s, 1, ζ)| (K, W).

    They depend on the camera alone: a wave cycle's frames share them (:func:`sea_strip`).
    """
    s = s_all[None, :]
    z = zeta[::-1][:, None]
    length = np.sqrt(1.0 + s * s + z * z)                  # |(s, 1, ζ)|
    inv = 1.0 / length
    direction[..., 0] = s * inv
    direction[..., 1] = inv
    direction[..., 2] = z * inv
    return length
