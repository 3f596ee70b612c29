"""A wave cycle's still part computed once (sunset/pipeline/cycle.py): each frame then traces and codes only its sea.

The codes of a frame coded with a cycle pass must be the bytes of the whole
vector stage (render, then encode) on the same kernel path, for every scene,
reflection mode, seed and number of threads; and the compiled kernels of the
sea-only path (direct.sea_geometry, codes.encode_sea_rows) must agree with
their NumPy references as tests/agree.py says.
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA, SKY
from sunset.errors import SunsetError
from sunset.model.islands import Island, Paraboloid
from sunset.model.scene import as_scene, Scene
from sunset.model.waves import Sea
from sunset.pipeline.cycle import cycle_pass
from sunset.tape import codes
from sunset.pipeline.frame import code_frame, depth_buffer, encode, render, trace_direct, trace_reflections
from sunset.vector import direct
from sunset.vector.frame import Frame

from ..agree import assert_codes_agree

#: The sea pixels' unit normals at the same depth buffer on both paths, absolute: a float32 rounding or two.
NORMAL_ATOL = 2.5e-7


def scenes():
    default = Scene.default().with_size(97, 83)
    lone = Island(x=10.0, y=300.0, cliff=Paraboloid(40.0, 0.01, 0.0, 0.01), beach=Paraboloid(3.0, 1e-4, 0.0, 1e-4),
                  cliff_top=20.0)
    return {
        "default": default,
        "still sea": Scene(camera=default.camera, sun=default.sun, sea=Sea(()), islands=default.islands),
        "no islands": Scene(camera=default.camera, sun=default.sun, sea=default.sea, islands=()),
        "near island": Scene(camera=default.camera, sun=default.sun, sea=default.sea, islands=(lone,)),
        "storm-swell": as_scene("storm-swell").with_size(90, 70),
        "archipelago-at-dusk": as_scene("archipelago-at-dusk").with_size(101, 64),
        "still-lake-at-noon": as_scene("still-lake-at-noon").with_size(64, 50),
    }


@pytest.mark.parametrize("name", list(scenes()))
@pytest.mark.parametrize("compiled", [False, True])
def test_a_cycle_pass_and_the_strips_code_the_bytes_of_the_whole_vector_stage(name, compiled):
    scene = scenes()[name]
    with kernels.use_compiled(compiled):
        for seed in (0, 7):
            cp = cycle_pass(scene, seed)
            for mode in (0, 1, 2):
                for t in (0.0, 1.3):
                    want = encode(scene, render(scene, t, mode), seed=seed)
                    for n in (1, 2, 3):
                        with kernels.use_threads(n):
                            got = code_frame(scene, t, mode, seed, islands=cp)
                            # the whole frame strip by strip (compiled: the fused pass), no still part
                            alone = code_frame(scene, t, mode, seed)
                        np.testing.assert_array_equal(got, want, err_msg=f"{name} seed {seed} mode {mode} t {t}")
                        np.testing.assert_array_equal(alone, want, err_msg=f"{name} seed {seed} mode {mode} t {t}")
    frame = render(scene, 1.3, 2)
    assert (frame.surface == SEA).any() or name == "still-lake-at-noon"


def test_a_larger_frame_on_both_paths_and_threads():
    scene = Scene.default().with_size(300, 260)          # many strips of rows and of scan lines
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            want = encode(scene, render(scene, 0.4, 2), seed=3)
            cp = cycle_pass(scene, 3)
            for n in (1, 2, 3):
                with kernels.use_threads(n):
                    np.testing.assert_array_equal(code_frame(scene, 0.4, 2, 3, islands=cp), want)


def test_the_still_codes_are_the_frames_codes_where_the_sea_does_not_reach():
    scene = Scene.default().with_size(120, 90)
    cp = cycle_pass(scene, 5)
    for t in (0.0, 2.2):
        frame = render(scene, t, 2)
        off = frame.surface != SEA
        assert off.any() and (frame.surface[off] >= 1).any() and (frame.surface[off] == SKY).any()
        np.testing.assert_array_equal(cp.codes[off], encode(scene, frame, seed=5)[off])
        np.testing.assert_array_equal(cp.direction, frame.direction)
    assert cp.seed == 5                                  # each frame's dither: the seed's (codes.dither)
    # handed out read only: a frame cannot spoil the next one
    for a in (cp.codes, cp.direction):
        with pytest.raises(ValueError):
            a.flat[0] = 0


def sea_strips(scene, t, cp, edges):
    """The strips direct.sea_strip makes for the rows cut at ``edges``, and the whole frame they make together."""
    depth = depth_buffer(scene, t, islands=cp.islands)
    parts = [direct.sea_strip(scene, t, depth, cp.direction, r0, r1) for r0, r1 in zip(edges[:-1], edges[1:])]
    whole = Frame(t=t, reflections=0, direction=cp.direction, surface=np.concatenate([p.surface for p in parts]),
                  part=None, distance=None, point=np.concatenate([p.point for p in parts]),
                  normal=np.concatenate([p.normal for p in parts]))
    return parts, whole


@pytest.mark.parametrize("compiled", [False, True])
def test_the_sea_pixels_direct_fields_are_trace_directs(compiled):
    scene = Scene.default().with_size(150, 110)
    H = scene.camera.height
    with kernels.use_compiled(compiled):
        cp = cycle_pass(scene)
        for t in (0.0, 3.1):
            full = trace_direct(scene, t)
            for edges in ([0, H], [0, 40, H], [0, 1, 57, 58, H]):
                parts, lean = sea_strips(scene, t, cp, edges)
                np.testing.assert_array_equal(lean.surface, full.surface)
                sea = full.surface == SEA
                assert sea.any() and not sea.all()
                for name in ("point", "normal"):
                    assert getattr(lean, name)[sea].tobytes() == getattr(full, name)[sea].tobytes(), name
                for p, r0 in zip(parts, edges):
                    assert np.shares_memory(p.direction, cp.direction) and p.part is None and p.distance is None
                    np.testing.assert_array_equal(p.direction, cp.direction[r0:r0 + p.shape[0]])


def cycle_depth(scene, t):
    cp = cycle_pass(scene)
    return depth_buffer(scene, t, islands=cp.islands)


@pytest.mark.parametrize("name", ["default", "storm-swell", "still sea"])
def test_the_compiled_sea_geometry_agrees_with_the_numpy_one(name):
    scene = scenes()[name].with_size(131, 97)
    best_u, best_surf, s_all, zeta = cycle_depth(scene, 0.9)
    W, H = best_u.shape
    rng = np.random.default_rng(5)
    edges = np.unique(np.concatenate([[0, H], rng.integers(1, H, 4)])).tolist()
    out = {}
    for which, fn in (("numpy", direct.sea_geometry.reference), ("numba", direct.sea_geometry.compiled())):
        surface = np.full((H, W), 99, np.int8)
        point = np.full((H, W, 3), 7.0, np.float32)
        normal = np.full((H, W, 3), 7.0, np.float32)
        for r0, r1 in zip(edges[:-1], edges[1:]):        # strips of rows, as code_frame cuts a cycle's frame
            k0, k1 = H - r1, H - r0
            fn(best_u[:, k0:k1], best_surf[:, k0:k1], s_all, zeta[k0:k1], scene.sea, 0.9, surface[r0:r1],
               point[r0:r1], normal[r0:r1])
        out[which] = (surface, point, normal)
    (s_ref, p_ref, n_ref), (surface, point, normal) = out["numpy"], out["numba"]
    np.testing.assert_array_equal(surface, s_ref)            # the same depth buffer: the same surfaces
    sea = surface == SEA
    np.testing.assert_array_equal(point[sea], p_ref[sea])    # and points: y = 1/u, x = s·y, z = ζ·y
    assert np.linalg.norm(normal[sea] - n_ref[sea], axis=-1).max() <= NORMAL_ATOL
    sea = surface == SEA
    assert sea.any() and (point[~sea] == 7.0).all()           # nothing written off the sea
    assert np.allclose(np.linalg.norm(normal[sea], axis=-1), 1.0, atol=1e-6)


def sea_frame(scene, t, mode, cp):
    _, frame = sea_strips(scene, t, cp, [0, scene.camera.height])
    shape = frame.shape
    frame.bounces = np.zeros(shape, np.uint8)
    frame.ray = np.full(shape + (3,), np.nan, np.float32)
    frame.final_surface = np.full(shape, 55, np.int8)         # no surface: read on the sea alone
    frame.final_part = np.zeros(shape, np.int8)
    frame.final_normal = np.full(shape + (3,), np.nan, np.float32)
    return trace_reflections(scene, frame, mode, sea_bounces=False)


@pytest.mark.parametrize("name", ["default", "archipelago-at-dusk", "near island"])
def test_the_compiled_sea_codes_agree_with_the_numpy_ones(name):
    scene = scenes()[name]
    cp = cycle_pass(scene, 11)
    frame = sea_frame(scene, 0.8, 2, cp)
    H, W = frame.shape
    sun, cmap = scene.sun, codes.code_map(scene)
    rng = np.random.default_rng(9)
    edges = np.unique(np.concatenate([[0, H], rng.integers(1, H, 5)])).tolist()
    want = np.zeros((H, W), np.uint8)
    codes.encode_sea_rows.reference(want, frame, cp.codes, 11, 0, sun, cmap)
    got = np.zeros((H, W), np.uint8)
    for r0, r1 in zip(edges[:-1], edges[1:]):
        codes.encode_sea_rows.compiled()(got[r0:r1], frame.rows(r0, r1), cp.codes[r0:r1], 11, r0, sun, cmap)
    sea = frame.surface == SEA
    np.testing.assert_array_equal(got[~sea], cp.codes[~sea])
    assert_codes_agree(scene, frame, frame, np.where(sea, want, 0), np.where(sea, got, 0), 11, name)
    # the reference cut into the same strips: the same bytes
    strips = np.zeros((H, W), np.uint8)
    for r0, r1 in zip(edges[:-1], edges[1:]):
        codes.encode_sea_rows.reference(strips[r0:r1], frame.rows(r0, r1), cp.codes[r0:r1], 11, r0, sun, cmap)
    np.testing.assert_array_equal(strips, want)
    sea = frame.surface == SEA
    assert sea.any() and (want[~sea] == cp.codes[~sea]).all()
    assert codes.CODE_MAP.track.contains(want[sea]).any() or codes.CODE_MAP.halo.contains(want[sea]).any()


def test_an_unknown_island_part_on_the_sea_is_refused_on_both_paths():
    scene = scenes()["default"]
    cp = cycle_pass(scene)
    frame = sea_frame(scene, 0.0, 2, cp)
    hit = (frame.surface == SEA) & (frame.final_surface >= 1)
    assert hit.any()
    frame.final_part[hit] = -3
    out = np.empty(frame.shape, np.uint8)
    for compiled in (False, True):
        with kernels.use_compiled(compiled), pytest.raises(SunsetError, match="got -3"):
            codes.encode_sea_rows(out, frame, cp.codes, 0, 0, scene.sun, codes.code_map(scene))


def test_a_cycle_pass_is_for_its_scene_and_seed():
    scene = Scene.default().with_size(60, 40)
    cp = cycle_pass(scene, 4)
    for other, seed in ((scene, 5), (scene.with_size(61, 40), 4), (scenes()["no islands"].with_size(60, 40), 4)):
        with pytest.raises(SunsetError, match="another camera"):
            code_frame(other, 0.0, 2, seed, islands=cp)
    with pytest.raises(SunsetError, match="t must be"):
        code_frame(scene, float("nan"), 2, 4, islands=cp)
    with pytest.raises(SunsetError, match="reflections"):
        code_frame(scene, 0.0, 3, 4, islands=cp)


@pytest.mark.parametrize("name", ["carlas-island-clouds", "post-in-the-swell"])
def test_scenes_with_clouds_or_posts_are_coded_the_whole_way(name):
    scene = as_scene(name).with_size(80, 60)
    cp = cycle_pass(scene, 2)
    np.testing.assert_array_equal(code_frame(scene, 0.5, 2, 2, islands=cp),
                                  encode(scene, render(scene, 0.5, 2), seed=2))
