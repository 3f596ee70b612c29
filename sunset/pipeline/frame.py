"""A frame through the pipeline: the stages chained strip by strip, the budget checked once.

A frame is made in the paper's order, each stage a strip kernel run over the
frame's strips on the threads (:func:`sunset.kernels.run_strips`):

1. the depth buffer, by strips of scan lines: the islands
   (:func:`island_pass`, :func:`sunset.vector.direct.island_columns`), then
   the sea's scan line merged in (:func:`depth_buffer`, the sea's kernel
   chosen by its kind, :func:`sea_stage`);
2. by strips of rows: the direct rays' geometry
   (:func:`sunset.vector.direct.direct_rows`), the reflected rays
   (:func:`sunset.vector.reflect.trace_sea_rays`), the codes
   (:func:`sunset.tape.codes.encode_strip`) and the exposure
   (:func:`sunset.recorder.dicomed.lookup`).

:func:`render` makes the full :class:`~sunset.vector.frame.Frame` (points,
normals, directions and, with ``sea_bounces``, each sea bounce) for the
callers that ask for it: the API, the RGB back end, the diagnostics.
:func:`code_frame` is the 8-bit path, which keeps only what the codes need:
after the depth buffer each strip of rows goes through the direct rays, the
reflected rays and the codes one after the other while its arrays are in the
cache, and no field of the whole frame is made but the codes.

The work budget (:func:`sunset.vector.budget.check_work`) is checked once
where a frame begins, and its sampling of the sea passed down.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..constants import SCANLINE_CHUNK_ELEMENTS, SEA, SKY
from ..errors import SunsetError, real_number, require_bool, require_instance, require_int_range, require_time
from ..kernels import enabled, row_strips, run_strips, strips, twin
from ..model.scene import SceneLike, as_scene
from ..recorder.dicomed import add_sun, check_codes, exposure_table, lookup
from ..tape.codemap import code_map
from ..tape.codes import check_frame, encode_sea_rows, encode_strip
from ..vector.direct import (DepthBuffer, IslandPass, check_island_pass, direct_rows, island_columns, island_key,
                             island_probes, put_sea_normals, row_heights, sea_geometry, sea_strip)
from ..vector.frame import Frame
from ..vector.heightfield import sea_columns
from ..vector.windsea_crests import wind_sea_rays
from ..vector.windsea_scan import wind_columns, wind_normals, wind_sea_geometry
from ..vector.reflect import trace_sea_rays
from ..vector.budget import Work, check_work as check_budget

__all__ = ["sea_stage", "island_pass", "depth_buffer", "trace_direct", "trace_reflections",
           "render", "encode", "expose", "CyclePass", "still_key", "check_cycle_pass", "code_frame", "code_rows", "code_strip",
           "CODE_STRIP_PIXELS", "SEA_STRIP_PIXELS", "FUSED_STRIP_PIXELS"]

_F32 = np.float32

#: Pixels in a strip of :func:`encode` at most: its compiled kernel keeps no temporaries, so its strips
#: are larger than the other stages' (fewer calls; with several threads, still about four strips a thread).
CODE_STRIP_PIXELS = 1 << 18

#: Pixels in a strip of :func:`code_frame` at most: its arrays (about 80 bytes a pixel) stay in a core's cache.
SEA_STRIP_PIXELS = 1 << 15

#: Pixels in a strip of :func:`code_frame` at most when the strip is one compiled fused pass, which keeps no
#: array of the strip but its codes: taller strips read each scan line of the depth buffer in longer runs
#: (at 1024², 64 rows instead of 32: about 4 % less CPU time in the fused pass, measured in one process).
FUSED_STRIP_PIXELS = 1 << 16


# --------------------------------------------------------------------------- the depth buffer
class SeaStage(NamedTuple):
    """The strip kernels of a kind of sea, each a twin (:func:`sunset.kernels.twin` picks NumPy or compiled).

    ``columns(sea, s, u, h, t, zeta0, dzeta, H, best_u, best_surf) -> tail pixels``: a strip of scan lines, the
    profile scan-converted and merged into the depth buffer (:func:`sunset.vector.heightfield.sea_columns`);
    ``normals(sea, t, normal, idx, s, y)``: the sea pixels' unit normals of a strip of rows
    (:func:`sunset.vector.direct.put_sea_normals`); ``geometry(...)``: a wave cycle's strip of sea pixels
    (:func:`sunset.vector.direct.sea_geometry`); ``rays(scene, frame, reflections)``: the reflected rays of a
    strip of rows (:func:`sunset.vector.reflect.trace_sea_rays`); ``fused``: whether the compiled fused pass of
    the 8-bit path (:mod:`sunset.pipeline.fused_numba`) knows this sea (else its strips run the stages one
    after the other).
    """

    columns: object
    normals: object
    geometry: object
    rays: object
    fused: bool


#: The sea of wave trains (the paper's).
TRAINS = SeaStage(columns=sea_columns, normals=put_sea_normals, geometry=sea_geometry, rays=trace_sea_rays, fused=True)
#: A wind sea, its FFT tile read by the scan line (:mod:`sunset.vector.windsea_scan`), its second
#: reflections marched over the tile (:mod:`sunset.vector.windsea_crests`).
WIND = SeaStage(columns=wind_columns, normals=wind_normals, geometry=wind_sea_geometry, rays=wind_sea_rays,
                fused=False)


def sea_stage(sea) -> SeaStage:
    """The strip kernels of ``sea``'s kind: the trains' (:data:`TRAINS`) or a wind sea's (:data:`WIND`).

    The one place where the kind of sea picks its kernels; which of each
    kernel's twins runs is :mod:`sunset.kernels`' choice. The trains'
    kernels refuse a wind sea. Another kind of sea plugs in here as another
    :class:`SeaStage` whose kernels take the same strips.
    """
    return TRAINS if sea.wind is None else WIND


def _check_work(scene, work):
    return check_budget(scene) if work is None else work


def island_pass(scene, refine_islands: bool = True, *, work: Work | None = None) -> IslandPass:
    """The islands' depth buffer of every scan line (:class:`~sunset.vector.direct.IslandPass`), on all threads.

    The scan lines are cut into strips; each strip's islands are sampled,
    scan-converted and merged, nearest first wins
    (:func:`sunset.vector.direct.island_columns`), in island order. ``work``:
    the frame's budget, checked already (:func:`sunset.vector.budget.check_work`).
    """
    work = _check_work(scene, work)      # a wave cycle computes this pass first: the budget comes before it
    cam = scene.camera
    W, H = cam.width, cam.height
    samp = work.sampling
    u = np.zeros((W, H))                 # 1/yp of the nearest island, 0: none
    code = np.full((W, H), SKY, dtype=np.int8)
    budget, probes = island_probes(scene, samp)

    def work_on(c0: int, c1: int) -> int:
        return island_columns(scene, samp, budget, probes, refine_islands, c0, c1, u[c0:c1], code[c0:c1])

    samples = 0
    if any(m0 is not None for m0 in probes):
        # compiled, one scan line at a time: no bound on the strips; the reference pads a strip's scan lines
        # to its longest (at most 2 budget samples each, see probe_refinement)
        most = None if enabled() else max(1, SCANLINE_CHUNK_ELEMENTS // budget)
        samples = sum(run_strips(work_on, strips(W, most)))
    return IslandPass(key=island_key(scene, refine_islands), u=u, code=code, samples=samples, probe=probes)


def depth_buffer(scene, t: float, *, islands: IslandPass | None = None, refine_islands: bool = True,
                 work: Work | None = None, info: dict | None = None) -> DepthBuffer:
    """Every scan line's depth buffer at time ``t``: the islands' pass (computed, or a copy of ``islands``), the sea
    merged in, by strips of scan lines on all threads.

    ``info``: filled with the counts and seconds of :func:`trace_direct`'s ``info``.
    """
    require_time("t", t)
    t = float(t)
    work = _check_work(scene, work)
    cam = scene.camera
    W, H, h = cam.width, cam.height, cam.eye_height
    samp = work.sampling
    s_all = cam.s_centres()
    dz = cam.pixel_pitch[1]
    zeta = row_heights(cam)              # bottom up
    zeta0 = float(zeta[0])
    u_sea_lattice = samp.u()
    columns = sea_stage(scene.sea).columns
    clock = time.perf_counter
    tick = clock()
    if islands is None:
        islands = island_pass(scene, refine_islands, work=work)
        best_u, best_surf = islands.u, islands.code  # ours alone: merge the sea in
    else:
        check_island_pass(scene, islands, refine_islands)
        best_u, best_surf = islands.u.copy(), islands.code.copy()
    tock = clock()
    seconds = {"islands": tock - tick}
    tick = tock

    def sea(c0: int, c1: int) -> int:
        # the sea: its profile on the lattice (sea_profile), scan-converted,
        # the far tail, merged with ties to the sea (sea_scan)
        return columns(scene.sea, s_all[c0:c1], u_sea_lattice, h, t,
                       zeta0, dz, H, best_u[c0:c1], best_surf[c0:c1])

    tail = 0
    if samp.n:
        # compiled, one scan line's profile at a time: no bound on the strips;
        # the reference's strips hold SCANLINE_CHUNK_ELEMENTS samples at most
        # (the memory bound)
        most = None
        if not enabled():
            most = max(1, min(W, SCANLINE_CHUNK_ELEMENTS // max(samp.n, 1)))
        tail = sum(run_strips(sea, strips(W, most)))
    seconds["sea"] = clock() - tick
    if info is not None:
        info.update({"sea_samples": samp.n, "island_samples": islands.samples, "probe": islands.probe,
                     "tail_pixels": tail, "seconds": seconds})
    return DepthBuffer(best_u, best_surf, s_all, zeta)


# --------------------------------------------------------------------------- the full frame
def direct_frame(t: float, H: int, W: int) -> Frame:
    """A frame of H × W pixels with its direct fields made (unset): for :func:`sunset.vector.direct.direct_rows`."""
    return Frame(t=t, reflections=0, direction=np.empty((H, W, 3), _F32), surface=np.empty((H, W), np.int8),
                 part=np.empty((H, W), np.int8), distance=np.empty((H, W), _F32), point=np.empty((H, W, 3), _F32),
                 normal=np.empty((H, W, 3), _F32))


def _assemble(scene, t: float, depth: DepthBuffer) -> Frame:
    """The direct fields of every pixel from the depth buffer, strip by strip of rows on all threads."""
    W, H = depth.u.shape
    frame = direct_frame(t, H, W)
    normals = sea_stage(scene.sea).normals
    run_strips(lambda r0, r1: direct_rows(scene, t, depth, r0, r1, frame.rows(r0, r1), normals), row_strips(H, W))
    return frame


def trace_direct(scene, t: float = 0.0, *, refine_islands: bool = True, info: dict | None = None,
                 islands: IslandPass | None = None, work: Work | None = None) -> Frame:
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
    work : Work, optional
        The frame's budget, checked already.

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
    counts: dict = {}
    depth = depth_buffer(scene, t, islands=islands, refine_islands=refine_islands, work=work, info=counts)
    tick = time.perf_counter()
    frame = _assemble(scene, t, depth)
    counts["seconds"]["assemble"] = time.perf_counter() - tick
    if info is not None:
        info.update(counts)
    return frame


def trace_reflections(scene, frame: Frame, reflections: int,
                      sea_bounces: bool = True) -> Frame:
    """Trace the reflected rays of the sea pixels and fill the frame's final
    fields, strip by strip of rows.

    Parameters
    ----------
    scene : Scene
    frame : Frame
        After :meth:`Frame.finish_direct` (done here, strip by strip, if it
        was not).
    reflections : {0, 1, 2}
        0: R_z → |R_z|, straight to the sky. 1: one reflection, |R_z|, then the
        islands or the sky (Figures 4, 5). 2: secondary reflections off the
        crest cylinder, then |R_z|, then the islands or the sky (Figure 6).
        (:mod:`sunset.vector.reflect`.)
    sea_bounces : bool
        Also record each sea bounce in ``incidence`` and ``sea_rays`` (for
        the RGB back end); without them a frame needs 32 bytes a pixel less.

    Returns
    -------
    Frame
        The same frame, with ``reflections`` set and ``bounces``, ``ray``,
        ``final_surface``, ``final_part`` and ``final_normal`` filled for sea
        pixels (``final_normal`` is NaN where the ray ends in the sky).
    """
    require_int_range("reflections", reflections, 0, 2)
    finish = frame.bounces is None
    if finish:
        frame.allocate_final(sea_bounces)
    elif sea_bounces and frame.incidence is None:
        frame.incidence = np.full(frame.shape + (2,), np.nan, np.float32)
        frame.sea_rays = np.full(frame.shape + (2, 3), np.nan, np.float32)
    frame.reflections = reflections
    rays = sea_stage(scene.sea).rays

    def rows(r0: int, r1: int) -> None:
        if finish:
            # rows all of sea: their ray and final normal are written by
            # the reflected rays
            frame.finish_rows(r0, r1, sea_rows=False)
        part = frame.rows(r0, r1)
        if np.any(part.surface == SEA):
            rays(scene, part, reflections)

    # every ray is traced on its own, so strips of rows go to the threads
    run_strips(rows, row_strips(*frame.shape))
    return frame


def render(scene: SceneLike, t: float = 0.0, reflections: int = 2, *, islands: IslandPass | None = None,
           sea_bounces: bool = False, work: Work | None = None) -> Frame:
    """Trace every pixel of ``scene`` at time ``t`` (seconds): the full :class:`Frame`.

    Direct rays by the height-field scan line (``trace_direct`` in this
    module), then reflected rays (``trace_reflections``), and, when the scene has a
    cloud layer or posts in the water, those seen directly and by reflection
    (:mod:`sunset.vector.clouds`, :mod:`sunset.vector.posts`).

    Parameters
    ----------
    scene : Scene, str or path
        A scene, the name of a packaged scene (``"storm-swell"``) or a scene TOML file.
    t : float
        Time in seconds (the sea moves; nothing else does).
    reflections : {0, 1, 2}
        0: reflected rays go straight to the sky (a diagnostic); 1: one
        reflection, then the islands or the sky (Figures 4, 5); 2: up to two
        reflections, the second off the crest ahead (Figure 6).
    islands : IslandPass, optional
        The islands' share of the direct rays, which does not change with
        time (``island_pass`` in this module): a wave cycle computes it once and passes
        it to every frame.
    sea_bounces : bool
        Also record each sea bounce (``Frame.incidence``, ``Frame.sea_rays``),
        which the RGB back end shades and the 8-bit tape does not read: 32
        bytes a pixel more, and the time to write them. Off by default, so
        that ``render`` → ``encode`` → ``expose`` makes what the tape needs;
        the RGB back end (:mod:`sunset.pipeline.rgb`) and the diagnostics that
        read the bounces ask for them.
    work : Work, optional
        The frame's budget, checked already (:func:`sunset.vector.budget.check_work`);
        by default it is checked here.

    Returns
    -------
    Frame
        For every pixel, the direct ray's fields (``direction``, ``surface``,
        ``part``, ``distance``, ``point``, ``normal``) and the final ray's
        (``bounces``, ``ray``, ``final_surface``, ``final_part``,
        ``final_normal``); ``incidence`` and ``sea_rays`` only with
        ``sea_bounces`` (else None). 69 bytes a pixel, 101 with the
        bounces.
    """
    from ..vector.clouds import add_clouds, reflected_clouds
    from ..vector.posts import add_posts, reflected_posts

    scene = as_scene(scene)
    require_time("t", real_number("t", t))
    require_int_range("reflections", reflections, 0, 2)
    require_bool("sea_bounces", sea_bounces)
    if islands is not None:
        require_instance("islands", islands, IslandPass)
    frame = trace_direct(scene, t, islands=islands, work=work)
    if scene.clouds is not None:
        add_clouds(scene, frame)
    if scene.posts:
        add_posts(scene, frame)
    trace_reflections(scene, frame, reflections, sea_bounces)
    if scene.clouds is not None:
        reflected_clouds(scene, frame)
    if scene.posts:
        reflected_posts(scene, frame)
    return frame


# --------------------------------------------------------------------------- codes and exposure
def encode(scene: SceneLike, frame: Frame, seed: int = 0) -> np.ndarray:
    """Code every pixel of a traced frame into 8 bits (the tape), strip by strip of rows on all threads.

    Reads only the frame's final fields (:func:`sunset.tape.codes.encode_strip`).

    Parameters
    ----------
    scene : Scene, str or path
        Supplies the sun (U, V, W, δ) and the picture size (a packaged scene's
        name or a scene file also do).
    frame : Frame
        A frame whose reflections have been traced.
    seed : int
        Seed of the dither (:func:`sunset.tape.codes.dither`), the same
        for every frame, so a still scene codes the same way in every frame.

    Returns
    -------
    ndarray (H, W) uint8
        Codes in the ranges of :data:`~sunset.tape.codemap.CODE_MAP`.
    """
    scene = as_scene(scene)
    require_int_range("seed", seed, 0, 2**32 - 1)
    cam = scene.camera
    check_frame(frame, (cam.height, cam.width))
    cmap = code_map(scene)
    H, W = frame.shape
    codes = np.empty((H, W), np.uint8)
    run_strips(lambda r0, r1: encode_strip(scene, frame.rows(r0, r1), seed, r0, cmap, codes[r0:r1]),
               strips(H, max(1, CODE_STRIP_PIXELS // W)))
    return codes


def expose(scene: SceneLike, codes: np.ndarray, hours: float) -> np.ndarray:
    """Expose a frame of codes: three passes through the tables, then the sun.

    Parameters
    ----------
    scene : Scene, str or path
        Only its camera (raster position → direction) and its sun are used (a
        packaged scene's name or a scene file also do).
    codes : ndarray (H, W) uint8
        One frame of the tape.
    hours : float
        Hours before sunset.

    Returns
    -------
    ndarray (H, W, 3) uint8
        sRGB image.
    """
    scene = as_scene(scene)
    real_number("hours", hours)
    check_codes(scene, codes)
    # the three passes, one through each filter, as one lookup of the
    # code's (red, green, blue)
    lut = exposure_table(scene, hours)             # (256, 3)
    rgb = np.empty(codes.shape + (3,), np.uint8)
    run_strips(lambda r0, r1: lookup(lut, codes[r0:r1], rgb[r0:r1]),
               row_strips(*codes.shape))
    add_sun(scene, codes, hours, rgb)
    return rgb


# --------------------------------------------------------------------------- the 8-bit path
@dataclass(frozen=True)
class CyclePass:
    """What every frame of a wave cycle's tape shares (:func:`sunset.pipeline.cycle.cycle_pass`); read only.

    Attributes
    ----------
    key : tuple
        What it depends on (:func:`still_key`): the island pass's key, the sun and the dither's seed.
    islands : IslandPass
        The islands' depth buffer of every scan line.
    direction : ndarray (H, W, 3) float32
        Every pixel's direct ray D (the frames' ``direction``).
    codes : ndarray (H, W) uint8
        Each pixel's code when the sea does not take it: its direct ray's, on an island or in the sky.
    seed : int
        The dither's seed (:func:`sunset.tape.codes.dither`).
    """

    key: tuple
    islands: IslandPass
    direction: np.ndarray
    codes: np.ndarray
    seed: int


def still_key(scene, seed: int) -> tuple:
    """What a :class:`CyclePass` depends on: the islands' pass, the sun (the codes) and the seed (the dither)."""
    return (island_key(scene), scene.sun, int(seed))


def check_cycle_pass(scene, seed: int, still: CyclePass) -> None:
    """Raise :class:`SunsetError` unless ``still`` was computed for this scene's camera, islands, sun and ``seed``."""
    if still.key != still_key(scene, seed):
        raise SunsetError("islands: this cycle pass was computed for another camera, islands, sea height, sun or seed")


def code_frame(scene: SceneLike, t: float, reflections: int = 2, seed: int = 0, islands=None, *,
               work: Work | None = None) -> np.ndarray:
    """The codes (H, W) uint8 of ``scene`` at ``t``: the frame traced and coded strip by strip.

    ``islands``: what many frames share, when they do: the scene's island
    pass (:func:`island_pass`), or the still part of a wave cycle
    (:func:`sunset.pipeline.cycle.cycle_pass`), with which only the sea's
    pixels are traced and coded (the same bytes). A scene with clouds or
    posts is traced whole (:func:`render`) and coded (:func:`encode`): their
    stages work on the whole frame.
    """
    scene = as_scene(scene)
    require_time("t", t)
    require_int_range("reflections", reflections, 0, 2)
    require_int_range("seed", seed, 0, 2**32 - 1)
    t = float(t)
    still = islands if isinstance(islands, CyclePass) else None
    if still is not None:
        check_cycle_pass(scene, seed, still)
        islands = still.islands
    if scene.clouds is not None or scene.posts:
        return encode(scene, render(scene, t, reflections, islands=islands, sea_bounces=False, work=work), seed)
    work = _check_work(scene, work)
    return code_rows(scene, t, reflections, seed, depth_buffer(scene, t, islands=islands, work=work), still)


def code_rows(scene, t: float, reflections: int, seed: int, depth: DepthBuffer,
              still: CyclePass | None = None) -> np.ndarray:
    """The codes (H, W) uint8 of a frame from its depth buffer: :func:`code_strip` by strips of rows on all threads.

    Checked already: the scene, ``t``, ``reflections``, ``seed`` and ``still``.
    """
    W, H = depth.u.shape
    cmap = code_map(scene)
    codes = np.empty((H, W), np.uint8)
    # the fused pass knows the trains only: a wind sea's strips go through its stages one after the other
    # (each stage's own twin)
    fused = sea_stage(scene.sea).fused
    strip = code_strip if fused else code_strip.reference
    most = FUSED_STRIP_PIXELS if fused and enabled() else SEA_STRIP_PIXELS
    run_strips(lambda r0, r1: strip(scene, t, reflections, seed, depth, r0, r1, cmap, codes[r0:r1], still),
               strips(H, max(1, most // W)))
    return codes


@twin("sunset.pipeline.fused_numba")
def code_strip(scene, t: float, reflections: int, seed: int, depth: DepthBuffer,
               r0: int, r1: int, cmap, codes, still: CyclePass | None = None) -> None:
    """The codes of the rows ``r0:r1`` (top down) of a frame from its depth
    buffer, into ``codes`` (r1 − r0, W).

    The stages one after the other on the strip's own arrays, while they
    are in the cache: the direct rays' geometry
    (:func:`sunset.vector.direct.direct_rows`), the reflected rays
    (:func:`sunset.vector.reflect.trace_sea_rays`), the codes
    (:func:`sunset.tape.codes.encode_strip`). With ``still``, a wave cycle's
    still part: only the sea's pixels are traced
    (:func:`sunset.vector.direct.sea_strip`) and coded
    (:func:`sunset.tape.codes.encode_sea_rows`), the others' codes are
    ``still``'s. No array of the whole frame is made but the codes. The
    compiled twin does the same in one fused pass over the strip
    (:mod:`sunset.pipeline.fused_numba`).
    """
    n, W = r1 - r0, depth.u.shape[0]
    stage = sea_stage(scene.sea)
    if still is None:
        part = direct_frame(t, n, W)
        direct_rows(scene, t, depth, r0, r1, part, stage.normals)
        part.allocate_final(sea_bounces=False)
        # rows all of sea: written by the reflected rays
        part.finish_rows(0, n, sea_rows=False)
    else:
        part = sea_strip(scene, t, depth, still.direction, r0, r1, stage.geometry)
        # the final fields: written by the reflections on the sea pixels,
        # read only there
        part.bounces = np.empty((n, W), np.uint8)
        part.ray = np.empty((n, W, 3), np.float32)
        part.final_surface = np.empty((n, W), np.int8)
        part.final_part = np.empty((n, W), np.int8)
        part.final_normal = np.empty((n, W, 3), np.float32)
    part.reflections = reflections
    if np.any(part.surface == SEA):
        stage.rays(scene, part, reflections)
    if still is None:
        encode_strip(scene, part, seed, r0, cmap, codes)
    else:
        encode_sea_rows(codes, part, still.codes[r0:r1], seed, r0, scene.sun, cmap)
