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
from dataclasses import dataclass

import numpy as np

from ..constants import ISLAND_SAMPLE_BUDGET, PART_NONE, SCANLINE_CHUNK_ELEMENTS, SEA, SKY
from ..errors import SunsetError, require_time
from ..kernels import enabled, row_strips, run_strips, strips, twin
from ..model.waves import unit_normal
from .frame import Frame
from .budget import check_work
from .heightfield import sampling, sea_columns, sea_gradient_on_scanlines
from .island_samples import islands_scan, probe_refinement
from .windsea_scan import wind_columns, wind_gradient_on_scanlines

__all__ = ["trace_direct", "sea_depth", "sea_strip", "islands_alone", "sea_geometry", "IslandPass",
           "island_key", "island_pass", "assemble_geometry", "put_unit_normals", "put_sea_normals", "put_island_normals"]

_F32 = np.float32


@dataclass(frozen=True)
class IslandPass:
    """The islands' share of the direct rays: the same at every time, so a wave cycle computes it once.

    The islands do not move, and where they are sampled depends only on the
    camera, the islands and the sea's largest elevation d (their bounding
    ellipses), never on t. This is their per-scan-line depth buffer, the
    nearest island (largest u = 1/y) at every pixel; :func:`trace_direct`
    merges the sea into a copy of it. Made by :func:`island_pass`.

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


def island_pass(scene, refine_islands: bool = True) -> IslandPass:
    """The islands' depth buffer of every scan line (:class:`IslandPass`), computed on all threads.

    The scan lines are cut into strips (:func:`sunset.kernels.run_strips`);
    each island is sampled, scan-converted and merged, nearest first wins
    (:func:`sunset.vector.island_samples.islands_scan`), in island order.
    """
    check_work(scene)                    # a wave cycle computes this pass first: the budget comes before it
    cam = scene.camera
    W, H = cam.width, cam.height
    d = scene.sea.max_elevation
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    samp = sampling(cam, d)
    s_all = cam.s_centres()
    u = np.zeros((W, H))                 # 1/yp of the nearest island, 0: none
    code = np.full((W, H), SKY, dtype=np.int8)
    budget = ISLAND_SAMPLE_BUDGET * max(samp.n, H)
    probes = [probe_refinement(island, s_all, samp, d, budget) for island in scene.islands]

    def work(c0: int, c1: int) -> int:
        return islands_scan(scene.islands, probes, s_all, c0, c1, samp, d, cam.eye_height, zeta0, dz, H, cam.sigma,
                            budget, refine_islands, u[c0:c1], code[c0:c1])

    samples = 0
    if any(m0 is not None for m0 in probes):
        # compiled, one scan line at a time: no bound on the strips; the reference pads a strip's scan lines
        # to its longest (at most 2 budget samples each, see probe_refinement)
        most = None if enabled() else max(1, SCANLINE_CHUNK_ELEMENTS // budget)
        samples = sum(run_strips(work, strips(W, most)))
    return IslandPass(key=island_key(scene, refine_islands), u=u, code=code, samples=samples, probe=probes)


def _chunk_columns(samp, W: int) -> int:
    """Scan lines per strip: SCANLINE_CHUNK_ELEMENTS samples at most (the memory bound)."""
    return max(1, min(W, SCANLINE_CHUNK_ELEMENTS // max(samp.n, 1)))


def trace_direct(scene, t: float = 0.0, *, refine_islands: bool = True, info: dict | None = None,
                 islands: IslandPass | None = None) -> Frame:
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
    islands : IslandPass, optional
        The islands' pass of this scene (:func:`island_pass`), computed once
        for many frames (a wave cycle); by default it is computed here.

    Returns
    -------
    Frame
        With the direct fields filled (direction, surface, part, distance,
        point, normal); rows top to bottom.

    Notes
    -----
    The islands go into the depth buffer first and the sea second, the sea
    winning ties: the same nearest surface, and the same first island among
    equals, as merging the sea first and each island only where it is
    strictly nearer.
    """
    require_time("t", t)
    t = float(t)
    seconds = {"sea": 0.0, "islands": 0.0, "assemble": 0.0}
    best_u, best_surf, s_all, zeta, counts = _depth_buffer(scene, t, refine_islands, islands, seconds)
    tick = time.perf_counter()
    frame = _assemble(scene, t, best_u, best_surf, s_all, zeta)
    seconds["assemble"] = time.perf_counter() - tick
    if info is not None:
        info.update(counts, seconds=seconds)
    return frame


def _depth_buffer(scene, t: float, refine_islands: bool, islands: IslandPass | None, seconds: dict):
    """Every scan line's depth buffer at time ``t``: the islands' pass (computed, or a copy of ``islands``), the sea
    merged in.

    Returns (best_u, best_surf (W, H), s_all (W,), zeta (H,) bottom up, the counts of :func:`trace_direct`'s
    ``info``); adds the seconds spent on the islands and the sea to ``seconds``.
    """
    check_work(scene)
    cam = scene.camera
    W, H, h = cam.width, cam.height, cam.eye_height
    d = scene.sea.max_elevation
    samp = sampling(cam, d)
    s_all = cam.s_centres()
    dz = cam.pixel_pitch[1]
    zeta = _row_heights(cam)             # bottom up
    zeta0 = float(zeta[0])
    u_sea_lattice = samp.u()
    columns = sea_columns if scene.sea.wind is None else wind_columns     # the scan line of the sea's kind
    clock = time.perf_counter
    tick = clock()
    if islands is None:
        islands = island_pass(scene, refine_islands)
        best_u, best_surf = islands.u, islands.code  # ours alone: merge the sea in
    else:
        if islands.key != island_key(scene, refine_islands):
            raise SunsetError("islands: this island pass was computed for another "
                              "camera, islands or sea height")
        best_u, best_surf = islands.u.copy(), islands.code.copy()
    tock = clock()
    seconds["islands"] += tock - tick
    tick = tock

    def sea(c0: int, c1: int) -> int:
        # the sea: its profile on the lattice (sea_profile), scan-converted,
        # the far tail, merged with ties to the sea (sea_scan)
        return columns(scene.sea, s_all[c0:c1], u_sea_lattice, h, t,
                       zeta0, dz, H, best_u[c0:c1], best_surf[c0:c1])

    tail = 0
    if samp.n:
        # compiled, one scan line's profile at a time: no bound on the strips
        most = None if enabled() else _chunk_columns(samp, W)
        tail = sum(run_strips(sea, strips(W, most)))
    seconds["sea"] += clock() - tick
    counts = {"sea_samples": samp.n, "island_samples": islands.samples, "probe": islands.probe, "tail_pixels": tail}
    return best_u, best_surf, s_all, zeta, counts


def sea_depth(scene, t: float, islands: IslandPass) -> tuple:
    """The depth buffer of a frame of a wave cycle at ``t``: the islands' pass ``islands`` with the sea merged in.

    (best_u, best_surf (W, H) by scan line, s_all (W,), zeta (H,) bottom up), as :func:`trace_direct` makes them;
    for :func:`sea_strip`.
    """
    require_time("t", t)
    best_u, best_surf, s_all, zeta, _ = _depth_buffer(scene, float(t), True, islands, {"sea": 0.0, "islands": 0.0})
    return best_u, best_surf, s_all, zeta


def sea_strip(scene, t: float, depth: tuple, direction, r0: int, r1: int) -> Frame:
    """The direct rays of the rows ``r0:r1`` (top down) of a wave cycle's frame, as far as its sea pixels need them.

    From the frame's depth buffer ``depth`` (:func:`sea_depth`): ``surface``
    everywhere and, on the sea pixels alone, ``point`` and ``normal``
    (:func:`sea_geometry`), the same bits as :func:`trace_direct`'s there,
    in arrays of the strip's own. ``direction`` (H, W, 3) float32 is
    :func:`trace_direct`'s for the whole frame, which does not change with
    time (:func:`islands_alone`): the strip's is a view of it. ``point`` and
    ``normal`` are left unset off the sea, and ``part`` and ``distance`` are
    None: the strip is for :func:`sunset.vector.reflect.trace_sea_rays` and
    the codes of its sea pixels (:func:`sunset.tape.still.code_sea`, which
    makes a frame strip by strip while each strip is in the cache).
    """
    best_u, best_surf, s_all, zeta = depth
    W, H = best_u.shape
    n = r1 - r0
    surface = np.empty((n, W), np.int8)
    point = np.empty((n, W, 3), _F32)
    normal = np.empty((n, W, 3), _F32)
    k0, k1 = H - r1, H - r0      # the rows' pixels, counted from the bottom
    sea_geometry(best_u[:, k0:k1], best_surf[:, k0:k1], s_all, zeta[k0:k1], scene.sea, float(t), surface, point,
                 normal)
    return Frame(t=float(t), reflections=0, direction=direction[r0:r1], surface=surface, part=None, distance=None,
                 point=point, normal=normal)


def islands_alone(scene, islands: IslandPass) -> Frame:
    """The direct frame of the islands and the sky alone (no sea): what every frame of a cycle shows where the sea
    does not reach. :func:`trace_direct`'s geometry of the island pass ``islands``, with nothing merged in."""
    if islands.key != island_key(scene, True):
        raise SunsetError("islands: this island pass was computed for another camera, islands or sea height")
    cam = scene.camera
    return _assemble(scene, 0.0, islands.u, islands.code, cam.s_centres(), _row_heights(cam))


def _row_heights(cam) -> np.ndarray:
    """ζ = z/y at the centre of every row, bottom up (H,) float64: the depth buffer's order."""
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    return zeta0 + dz * np.arange(cam.height, dtype=np.float64)


@twin("sunset.vector.direct_numba")
def sea_geometry(best_u, best_surf, s_all, zeta, sea, t: float, surface, point, normal) -> None:
    """The direct fields of the sea pixels alone, from the depth buffer: :func:`assemble_geometry` and
    :func:`put_sea_normals`, skipping everything else.

    ``best_u``, ``best_surf`` (W, K) hold K pixels of every scan line, from
    the bottom, at heights ``zeta`` (K,). Fills ``surface`` (K, W) int8, rows
    from the top, and, where it is the sea, ``point`` and ``normal`` (K, W, 3)
    float32 with the same bits as :func:`_assemble` (elsewhere they are not written).
    """
    surface[...] = best_surf[:, ::-1].T
    idx = np.flatnonzero(surface == SEA)
    if not len(idx):
        return
    W = surface.shape[1]
    y = 1.0 / best_u[:, ::-1].T.reshape(-1)[idx]
    s = s_all[idx % W]
    z = zeta[::-1][idx // W]
    flat = point.reshape(-1, 3)
    flat[idx, 0] = s * y
    flat[idx, 1] = y
    flat[idx, 2] = z * y
    put_sea_normals(sea, t, normal, idx, s, y)


def _assemble(scene, t, best_u, best_surf, s_all, zeta) -> Frame:
    """Hit points, distances, normals and parts from 1/yp and the winning surface, strip by strip of rows.

    ``best_u`` and ``best_surf`` are (scan line, pixel from the bottom); the
    frame's arrays are (row from the top, column). The geometry comes from
    :func:`assemble_geometry`; the normals from the gradients on the
    compressed subsets of sea and island pixels.
    """
    W, H = best_u.shape
    frame = Frame(t=t, reflections=0, direction=np.empty((H, W, 3), _F32), surface=np.empty((H, W), np.int8),
                  part=np.empty((H, W), np.int8), distance=np.empty((H, W), _F32), point=np.empty((H, W, 3), _F32),
                  normal=np.empty((H, W, 3), _F32))

    def rows(r0: int, r1: int) -> None:
        k0, k1 = H - r1, H - r0      # the rows' pixels, counted from the bottom
        out = (frame.surface[r0:r1], frame.direction[r0:r1], frame.point[r0:r1], frame.distance[r0:r1],
               frame.normal[r0:r1])
        hits = assemble_geometry(best_u[:, k0:k1], best_surf[:, k0:k1], s_all, zeta[k0:k1], len(scene.islands), out)
        normal = frame.normal[r0:r1]
        part = frame.part[r0:r1]
        part.fill(PART_NONE)
        # the sea: the gradient in the b_j, c_j form, on the sea pixels only
        idx, s_hit, y_hit = hits[0]
        if len(idx):
            put_sea_normals(scene.sea, t, normal, idx, s_hit, y_hit)
        for k, island in enumerate(scene.islands, start=1):
            idx, s_hit, yk = hits[k]
            if not len(idx):
                continue
            put_island_normals(island, normal, part, idx, s_hit, yk)

    run_strips(rows, row_strips(H, W))
    return frame


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
    and :func:`put_unit_normals`; the twin does both in one pass.
    """
    gradient = sea_gradient_on_scanlines if sea.wind is None else wind_gradient_on_scanlines
    fx, fy = gradient(sea, s, y, t)
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
    length = np.sqrt(1.0 + s * s + z * z)                  # |(s, 1, ζ)|
    inv = 1.0 / length
    direction[..., 0] = s * inv
    direction[..., 1] = inv
    direction[..., 2] = z * inv
    point[..., 0] = s * y
    point[..., 1] = y
    point[..., 2] = z * y
    distance[...] = np.where(hit, y * length, np.inf)
    normal.fill(np.nan)
    return surf, y
