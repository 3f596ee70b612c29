"""The shader's kernels: the Numba twins within their tolerances of the NumPy references; the response is the eye's.

Cross-path checks use the named tolerances of the twin modules
(:data:`sunset.light.kernel_numba.RADIANCE_RTOL`, ``DISPLAY_ATOL``,
:data:`sunset.light.paths_numba.PATHS_RTOL`); each path on its own must give
the same bytes for any number of threads.
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.light import kernel
from sunset.light.kernel_numba import DISPLAY_ATOL, RADIANCE_RTOL
from sunset.light.paths_numba import PATHS_RTOL
from sunset.light.geometry import Geometry
from sunset.light.lighting import Lighting
from sunset.light.shade import shade
from sunset.light.tone import display_linear, xyz_to_rgb_matrix
from sunset.model.eye import xyz_response
from sunset.model.scene import Scene
from sunset.pipeline.frame import render


@pytest.fixture(scope="module")
def setup():
    scene = Scene.default().with_size(64, 56)
    geometry = Geometry.from_frame(render(scene, 0.3, 2, sea_bounces=True))
    return scene, geometry


def radiance_close(got, want):
    """|got − want| ≤ RADIANCE_RTOL × the pixel's largest channel."""
    top = np.abs(want.astype(float)).max(axis=-1, keepdims=True)
    return bool(np.all(np.abs(got.astype(float) - want) <= RADIANCE_RTOL * top))


@pytest.mark.parametrize("hours", [4.0, 0.35, 0.02, -0.3])
def test_shading_twins_agree_within_the_tolerances(setup, hours):
    scene, g = setup
    light = Lighting.for_hour(scene.sun, hours)
    with kernels.use_compiled(False):
        ref = shade(g, light)
        ref_disp = display_linear(ref, light.scale)
    with kernels.use_compiled(True):
        got = shade(g, light)
        got_disp = display_linear(ref, light.scale)
    assert ref.dtype == got.dtype == np.float32 and radiance_close(got, ref)
    assert np.max(np.abs(got_disp - ref_disp)) <= DISPLAY_ATOL
    # the tolerances see a twin that is wrong by a little: 1e-5 of the light, or 1e-12 of the display
    assert not radiance_close(got * np.float32(1 + 1e-5), ref)
    assert np.max(np.abs(got_disp * (1 + 1e-12) - ref_disp)) > DISPLAY_ATOL


def test_every_kernel_has_a_twin():
    for name in ("sky_pixels", "island_pixels", "combine", "display_pixels", "display_box"):
        k = getattr(kernel, name)
        assert k.compiled() is not k.reference


def test_display_is_the_eyes_response():
    rng = np.random.default_rng(8)
    xyz = np.exp(rng.normal(-3, 3, (5000, 3))).astype(np.float32)
    xyz[:10] = 0.0
    xyz[10:20] = 1e9                                    # far past full scale: bleached to white
    m = xyz_to_rgb_matrix()
    want = xyz_response(xyz.astype(float) / 0.7, lambda x: x @ m)
    for flag in (False, True):
        with kernels.use_compiled(flag):
            np.testing.assert_allclose(display_linear(xyz, 0.7), want, rtol=1e-12, atol=1e-14)
    assert np.all(display_linear(xyz[10:20], 0.7) > 0.999)


# --------------------------------------------------------------------------- the paths and the filter (issue 15)
from sunset.light import paths  # noqa: E402
from sunset.light.fresnel import reflectance, refract  # noqa: E402
from sunset.light.render import box_filter, shade_display  # noqa: E402
from sunset.light.tone import display_filtered  # noqa: E402


def _flat(frame):
    n = frame.shape[0] * frame.shape[1]
    return [getattr(frame, k).reshape((n,) + getattr(frame, k).shape[2:]) for k in
            ("surface", "final_surface", "final_part", "final_normal", "direction", "normal", "incidence",
             "sea_rays")]


@pytest.fixture(scope="module")
def frames():
    from sunset.model.scene import load_named_scene

    out = [render(Scene.default().with_size(96, 80), 0.4, 2, sea_bounces=True),
           render(Scene.default().with_size(72, 64), 1.3, 1, sea_bounces=True)]
    out.append(render(load_named_scene("post-in-the-swell").with_size(80, 72), 0.2, 2, sea_bounces=True))
    return out


def _same(a, b):
    """Integer arrays equal; float arrays the same NaNs and within PATHS_RTOL of the array's largest value."""
    if isinstance(a, tuple):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _same(x, y)
    elif a.dtype.kind in "iub":
        assert a.dtype == b.dtype and np.array_equal(a, b)
    else:
        assert a.dtype == b.dtype and a.shape == b.shape
        assert np.array_equal(np.isnan(a), np.isnan(b))
        finite = ~np.isnan(a)
        scale = np.max(np.abs(a[finite]), initial=0.0)
        assert np.all(np.abs(a[finite].astype(float) - b[finite]) <= PATHS_RTOL * scale)


def test_the_paths_twin_is_the_reference_within_the_tolerance(frames):
    for f in frames:
        args = _flat(f)
        _same(paths.trace_paths.reference(*args, 1.34), paths.trace_paths.compiled()(*args, 1.34))
    # a throughput off by 1e-6 (relative) is caught
    tau = paths.trace_paths.compiled()(*_flat(frames[0]), 1.34)[2]
    with pytest.raises(AssertionError):
        _same(paths.trace_paths.reference(*_flat(frames[0]), 1.34)[2], tau * np.float32(1 + 1e-6))


def test_the_paths_twin_agrees_on_hostile_values():
    rng = np.random.default_rng(3)
    n = 4000
    surface = rng.integers(-3, 3, n).astype(np.int8)
    final_surface = rng.integers(-3, 3, n).astype(np.int8)
    final_part = rng.integers(0, 4, n).astype(np.int8)
    vec = lambda *s: rng.normal(size=s).astype(np.float32)  # noqa: E731
    final_normal, direction, normal = vec(n, 3), vec(n, 3), vec(n, 3)
    final_normal[::7] = np.nan
    incidence = rng.uniform(-0.2, 1.2, (n, 2)).astype(np.float32)
    incidence[::3, 1] = np.nan
    incidence[::11, 0] = np.nan
    sea_rays = vec(n, 2, 3)
    sea_rays[::5, 1] = sea_rays[::5, 0]                     # R2 = R1: the normal's length is floored
    args = (surface, final_surface, final_part, final_normal, direction, normal, incidence, sea_rays)
    _same(paths.trace_paths.reference(*args, 1.33), paths.trace_paths.compiled()(*args, 1.33))


def test_the_paths_are_snells_and_fresnels_law(frames):
    """The first bounce against sunset.light.fresnel's refract and reflectance, computed independently."""
    f = frames[0]
    args = _flat(f)
    kind, _, tau, layers = paths.trace_paths.reference(*args, 1.34)
    sea = np.flatnonzero(args[0] == 0)
    index, up, weight = layers[0]
    np.testing.assert_array_equal(index, sea)
    c = np.clip(args[6][sea, 0].astype(float), 0, 1)
    t = refract(args[4][sea].astype(float), args[5][sea].astype(float), c, 1.34)
    want = -t / np.linalg.norm(t, axis=-1, keepdims=True)
    np.testing.assert_allclose(up, want, atol=3e-6)
    np.testing.assert_allclose(weight, (1 - reflectance(c, 1.34)) / 1.34**2, rtol=1e-6)
    one = ~np.isfinite(args[6][sea, 1]) & (args[7][sea, 0, 2] >= 0)
    np.testing.assert_allclose(tau[sea[one]], reflectance(c[one], 1.34), rtol=1e-6)
    assert np.all(tau[args[0] != 0] == 1)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_the_filtered_response_is_the_response_then_the_box(k):
    rng = np.random.default_rng(k)
    xyz = np.exp(rng.normal(-3, 3, (k * 23, k * 31, 3))).astype(np.float32)
    xyz[0, :k] = 1e9
    for flag in (False, True):
        runs = []
        for n in (1, 2):
            with kernels.use_compiled(flag), kernels.use_threads(n):
                want = box_filter(display_linear(xyz, 0.7), k)
                runs.append(display_filtered(xyz, 0.7, k))
        assert runs[0].dtype == want.dtype and runs[0].tobytes() == runs[1].tobytes()      # any thread count
        assert np.max(np.abs(runs[0] - want)) <= DISPLAY_ATOL
        if not flag:
            assert runs[0].tobytes() == want.tobytes()          # the NumPy path is the response, then the box


def test_the_filter_twin_is_the_reference_within_the_tolerance():
    rng = np.random.default_rng(5)
    xyz = np.exp(rng.normal(-2, 3, (12, 18, 3))).astype(np.float32)
    m = xyz_to_rgb_matrix()
    for k in (1, 2, 3):
        a = kernel.display_box.reference(xyz, 0.5, m, 0.6, 0.3, k)
        b = kernel.display_box.compiled()(xyz, 0.5, m, 0.6, 0.3, k)
        assert a.shape == b.shape == (12 // k, 18 // k, 3) and np.max(np.abs(a - b)) <= DISPLAY_ATOL


def test_the_geometry_is_the_same_bytes_on_each_path_for_any_thread_count(frames):
    """Byte-identical on one path for 1–3 threads and many strips; within PATHS_RTOL across the paths."""
    import dataclasses

    f = frames[2]
    by_path = {}
    for flag in (False, True):
        runs = []
        for n in (1, 2, 3):
            with kernels.use_compiled(flag), kernels.use_threads(n), \
                    pytest.MonkeyPatch.context() as mp:
                mp.setattr("sunset.constants.STRIP_PIXELS", 512)        # many strips even on a small frame
                runs.append(Geometry.from_frame(f))
        for g in runs[1:]:
            for field in dataclasses.fields(g):
                a, b = getattr(runs[0], field.name), getattr(g, field.name)
                if isinstance(a, np.ndarray):
                    assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), field.name
                else:
                    assert a == b
        by_path[flag] = runs
    for field in dataclasses.fields(by_path[False][0]):
        a, b = getattr(by_path[False][0], field.name), getattr(by_path[True][0], field.name)
        if isinstance(a, np.ndarray):
            _same(a, b)
        else:
            assert a == b
    runs = by_path[False]
    g = runs[0]
    np.testing.assert_array_equal(g.final_normal.reshape(f.shape + (3,)),
                                  np.nan_to_num(f.final_normal, nan=0.0))
    light = Lighting.for_hour(Scene.default().sun, 0.4)
    want = shade_display(g, light, 1)
    for n in (1, 2):
        with kernels.use_threads(n):
            assert shade_display(g, light, 1).tobytes() == want.tobytes()


def test_keeping_freed_memory_can_be_turned_off(monkeypatch):
    monkeypatch.setenv("SUNSET_KEEP_MEMORY", "0")
    assert kernels.keep_freed_memory() is False


# --------------------------------------------------------------------------- the fused response (issue 15)
def _hard_xyz(shape, seed):
    rng = np.random.default_rng(seed)
    xyz = np.exp(rng.normal(-3, 4, shape + (3,))).astype(np.float32)
    flat = xyz.reshape(-1, 3)
    flat[:7] = [[0, 0, 0], [1, 0, 1], [1e30, 1e30, 1e30], [1e-30, 1e-30, 1e-30], [0, 1e-13, 0], [5, -1, 2],
                [1e9, 1e9, 1e-9]]
    return xyz


@pytest.mark.parametrize("exponent", [0.6, 0.5, 0.73, 2.0])
def test_the_fused_twin_is_the_reference_within_the_tolerance(exponent):
    """One pass, yⁿ with the C library's pow, for any exponent (NumPy takes 0.5 as a square root and 2 as a
    product: the same values within the tolerance)."""
    m = xyz_to_rgb_matrix()
    for k, shape in ((1, (37, 41)), (2, (30, 44)), (3, (27, 33))):
        xyz = _hard_xyz(shape, k)
        want = kernel.display_box.reference(xyz, 0.7, m, exponent, 2.0, k)
        got = kernel.display_box.compiled()(xyz, 0.7, m, exponent, 2.0, k)
        assert np.max(np.abs(got - want)) <= DISPLAY_ATOL
        flat = xyz.reshape(-1, 3)
        want_px = kernel.display_pixels.reference(flat, 0.7, m, exponent, 2.0)
        assert np.max(np.abs(kernel.display_pixels.compiled()(flat, 0.7, m, exponent, 2.0) - want_px)) <= DISPLAY_ATOL


def _lookup_args(f):
    n = f.shape[0] * f.shape[1]
    flat = _flat(f)
    kind, normal, _, _ = paths.trace_paths.reference(*flat, 1.34)
    field = lambda k: getattr(f, k).reshape((n,) + getattr(f, k).shape[2:])  # noqa: E731
    depth = None if f.cloud_depth is None else f.cloud_depth.reshape(-1)
    return field("ray"), field("final_surface"), field("bounces"), field("point"), kind, normal, depth


def _same_lists(a, b):
    assert a.keys() == b.keys()
    for k in a:
        _same(a[k], b[k])


def test_the_lookups_twin_is_the_reference_within_the_tolerance(frames):
    for f in frames:
        ray, fs, bounces, point, kind, normal, depth = _lookup_args(f)
        for d in (depth, None, np.where(fs == -2, 3.5, np.nan).astype(np.float32)):
            args = (ray, fs, bounces, point, kind, normal, 17)
            _same_lists(paths.lookups.reference(*args, d), paths.lookups.compiled()(*args, d))


def test_the_lookups_twin_agrees_on_hostile_values():
    """Normals past ±1 and on the grid's edges, every kind, clouds and direct and reflected hits."""
    rng = np.random.default_rng(5)
    n = 5000
    ray = rng.normal(size=(n, 3)).astype(np.float32)
    ray[::9, 2] = 1.0
    ray[::13, 2] = 0.0
    normal = rng.uniform(-1.3, 1.3, (n, 3)).astype(np.float32)
    normal[::4, :2] = rng.choice([-1.0, 1.0, 0.0, -0.0], (len(normal[::4]), 2))
    point = rng.normal(size=(n, 3)).astype(np.float32)
    kind = rng.integers(-1, 4, n).astype(np.int8)
    fs = rng.integers(-3, 3, n).astype(np.int8)
    bounces = rng.integers(0, 3, n).astype(np.uint8)
    depth = rng.uniform(0, 9, n).astype(np.float32)
    args = (ray, fs, bounces, point, kind, normal, 5)
    ref = paths.lookups.reference(*args, depth)
    _same_lists(ref, paths.lookups.compiled()(*args, depth))
    assert np.all(ref["island_g"] >= 0) and np.all(ref["island_f"] >= 0) and np.all(ref["island_f"] <= 1)
    assert np.isnan(ref["sky_cloud"]).any() and np.isnan(ref["island_point"]).any()
