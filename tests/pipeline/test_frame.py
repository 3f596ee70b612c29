"""A frame through the pipeline on many scenes (sunset/pipeline/frame.py), property-based.

Hypothesis draws valid scenes (eye heights, windows, trains, islands, suns)
and checks what must hold for every frame: codes in range, no NaN anywhere,
classes consistent with the geometry, and determinism.
"""

import numpy as np
import pytest
from hypothesis import assume, given, HealthCheck, settings, strategies as st

from sunset.model.camera import Camera
from sunset.pipeline.frame import encode, expose, render
from sunset.constants import SEA, SKY
from sunset.errors import SunsetError
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene
from sunset.model.sun import Sun
from sunset.model.waves import Sea, WaveTrain

finite = dict(allow_nan=False, allow_infinity=False)


@st.composite
def scenes(draw):
    h = draw(st.floats(0.5, 20.0, **finite))
    zy_min = draw(st.floats(-0.6, -0.02, **finite))
    zy_max = draw(st.floats(0.0, 0.4, **finite))  # the horizon is in the picture or at its top edge
    half = draw(st.floats(0.1, 1.0, **finite))
    centre = draw(st.floats(-0.3, 0.3, **finite))
    cam = Camera(eye_height=h, width=draw(st.integers(8, 40)), height=draw(st.integers(8, 40)),
                 s_min=centre - half, s_max=centre + half, zy_min=zy_min, zy_max=zy_max)
    lam = draw(st.floats(2.0, 80.0, **finite))
    n_trains = draw(st.integers(0, 3))
    trains = tuple(
        WaveTrain(amplitude=draw(st.floats(0.0, 0.08, **finite)) * lam / (n + 1) ** 2 / 6.28,
                  wavelength=lam / (n + 1) ** 2, direction=draw(st.floats(0, 360, **finite)),
                  phase=draw(st.floats(0, 6.28, **finite)), stokes_order=draw(st.integers(1, 4)))
        for n in range(n_trains))
    islands = []
    for _ in range(draw(st.integers(0, 3))):
        top = draw(st.floats(5.0, 80.0, **finite))
        e = draw(st.floats(1e-4, 1e-2, **finite))
        g = draw(st.floats(1e-4, 1e-2, **finite))
        islands.append(Island(
            x=draw(st.floats(-800, 800, **finite)), y=draw(st.floats(20.0, 3000.0, **finite)),
            cliff=Paraboloid(top, e, draw(st.floats(-0.9, 0.9, **finite)) * 2 * np.sqrt(e * g), g),
            beach=Paraboloid(draw(st.floats(0.5, 4.0, **finite)), e / 10, 0.0, g / 10),
            cliff_top=top * draw(st.floats(0.2, 0.9, **finite)), hill_factor=draw(st.floats(0.1, 1.0, **finite)),
            cosines=tuple(Cosine(draw(st.floats(0, 3, **finite)), draw(st.floats(-0.2, 0.2, **finite)),
                                 draw(st.floats(-0.2, 0.2, **finite))) for _ in range(draw(st.integers(0, 2))))))
    sun = Sun(azimuth=draw(st.floats(-60, 60, **finite)), tilt=draw(st.floats(5, 90, **finite)),
              radius=draw(st.floats(0.2, 3.0, **finite)))
    assume(all(float(isl.height(0.0, 0.0)) < cam.eye_height for isl in islands))  # the eye is not underground
    return Scene(camera=cam, sun=sun, sea=Sea(trains), islands=tuple(islands))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scene=scenes(), t=st.floats(0, 100, **finite), mode=st.sampled_from([0, 1, 2]),
       hours=st.floats(-2.0, 8.0, **finite))
def test_every_frame_is_well_formed(scene, t, mode, hours):
    frame = render(scene, t, mode)
    H, W = scene.camera.height, scene.camera.width
    assert frame.shape == (H, W)
    # no NaN anywhere a value is defined; the undefined entries (what a sky ray
    # "hits") are NaN exactly where the frame says sky
    for name in ("direction", "distance", "ray"):
        assert not np.isnan(getattr(frame, name)).any(), name
    hit, final_hit = frame.surface != SKY, frame.final_surface != SKY
    for name, mask in (("point", hit), ("normal", hit), ("final_normal", final_hit)):
        arr = getattr(frame, name)
        assert not np.isnan(arr[mask]).any(), name
        assert np.isnan(arr[~mask]).all(), name
    assert np.all(np.isinf(frame.distance[~hit])) and np.all(np.isfinite(frame.distance[hit]))
    assert set(np.unique(frame.surface)) <= {SKY, SEA, *range(1, len(scene.islands) + 1)}
    assert set(np.unique(frame.final_surface)) <= {SKY, *range(1, len(scene.islands) + 1)}
    assert frame.bounces.max() <= max(mode, 1)
    sea = frame.surface == SEA
    assert np.all(frame.bounces[sea] >= 1)
    assert np.all(frame.bounces[~sea] == 0)
    # the final ray of a reflected ray points upward (|R_z|)
    assert np.all(frame.ray[sea][:, 2] >= 0)
    np.testing.assert_allclose(np.linalg.norm(frame.ray, axis=-1), 1.0, atol=1e-4)
    codes = encode(scene, frame, seed=3)
    assert codes.dtype == np.uint8 and codes.shape == (H, W)
    rgb = expose(scene, codes, hours)
    assert rgb.dtype == np.uint8 and rgb.shape == (H, W, 3)


def test_rays_above_the_horizon_with_no_island_see_sky():
    scene = Scene(camera=Camera(width=16, height=16, zy_min=-0.2, zy_max=0.2))
    frame = render(scene, 0.0, 2)
    zeta = scene.camera.zy_centres()
    assert np.all(frame.surface[zeta > 1e-3] == SKY)
    assert np.all(frame.surface[zeta < -1e-3] == SEA)


def test_island_partly_out_of_the_picture():
    base = Scene.default().with_size(40, 30)
    isl = base.islands[0]
    cam = base.camera
    # put the island's apex just outside the left edge of the window
    moved = Island(**{**isl.__dict__, "x": (cam.s_min - 0.02) * isl.y})
    frame = render(Scene(camera=cam, sun=base.sun, sea=base.sea, islands=(moved,)), 0.0, 2)
    assert (frame.surface == 1).any()


def test_sun_below_the_horizon_is_exposed_without_error():
    scene = Scene.default().with_size(24, 20)
    codes = encode(scene, render(scene, 0.0, 2), seed=0)
    night = expose(scene, codes, -3.0)
    assert night.shape == (20, 24, 3)


def test_determinism():
    scene = Scene.default().with_size(40, 32)
    a = encode(scene, render(scene, 1.5, 2), seed=5)
    b = encode(scene, render(scene, 1.5, 2), seed=5)
    assert a.tobytes() == b.tobytes()


@pytest.mark.parametrize("kw", [{"t": float("nan")}, {"reflections": 3}, {"reflections": -1}])
def test_bad_render_arguments(kw):
    with pytest.raises(SunsetError):
        render(Scene.default().with_size(8, 8), **{"t": 0.0, "reflections": 2, **kw})


# -- many frames over both cores (cycle.code_frames, film.render_cycle) ----------------------

def test_frames_over_two_processes_are_byte_identical_to_one():
    from sunset.pipeline.film import render_cycle
    from sunset.pipeline.cycle import code_frames
    from sunset.pipeline.frame import code_frame

    scene = Scene.default().with_size(40, 32)
    times = [0.0, 0.7, 1.9, 3.3, 4.1]
    serial = code_frames(scene, times, 2, seed=5, workers=1)
    seen = []
    parallel = code_frames(scene, times, 2, seed=5, workers=2, on_frame=lambda i, c: seen.append(i))
    assert serial.dtype == np.uint8 and serial.shape == (5, 32, 40)
    assert serial.tobytes() == parallel.tobytes()
    assert seen == list(range(5))  # in order, one call per frame
    # each frame is the single-frame vector stage
    assert np.array_equal(serial[3], code_frame(scene, 3.3, 2, 5))
    a = render_cycle(scene, 4, seed=1, progress=False, workers=1)
    b = render_cycle(scene, 4, seed=1, progress=True, workers=2)
    assert a.codes.tobytes() == b.codes.tobytes() and np.array_equal(a.times, b.times)


def test_a_warm_process_gives_every_frame_to_the_workers_with_the_same_bytes(monkeypatch):
    # a process that has not coded a frame of the kind renders the first itself (the forked workers inherit the
    # loaded kernels); once it has, every frame goes to the workers: the same bytes either way, in order
    from sunset.pipeline import cycle

    scene = Scene.default().with_size(36, 30)
    times = [0.0, 0.9, 2.1, 3.0]
    serial = cycle.code_frames(scene, times, 2, seed=2, workers=1)
    here = []
    monkeypatch.setattr(cycle, "_WARM", set())
    real = cycle.code_frame
    monkeypatch.setattr(cycle, "code_frame", lambda *a, **k: here.append(a[1]) or real(*a, **k))
    for warm in (False, True):
        here.clear()
        seen = []
        got = cycle.code_frames(scene, times, 2, seed=2, workers=2, on_frame=lambda i, c: seen.append(i))
        assert got.tobytes() == serial.tobytes() and seen == list(range(4))
        assert here == ([] if warm else [0.0])     # the parent coded frame 0 only when cold
        assert cycle._warm_key(scene) in cycle._WARM


def test_a_worker_hands_back_the_free_memory_it_inherited():
    from sunset.pipeline.cycle import release_inherited_memory

    assert release_inherited_memory() is True      # glibc's malloc_trim (the tests run on glibc)


def test_frame_workers(monkeypatch):
    import os

    import sunset.guard
    import sunset.pipeline.workers
    from sunset.pipeline.workers import frame_workers, usable_cpus

    # never more than the usable CPUs, whatever --jobs or SUNSET_WORKERS say
    monkeypatch.delenv("SUNSET_WORKERS", raising=False)
    assert frame_workers(10**6, 10**6) == frame_workers(None, 10**6) == len(os.sched_getaffinity(0))
    monkeypatch.setenv("SUNSET_WORKERS", "1000000")
    assert frame_workers(None, 10**6) == len(os.sched_getaffinity(0))
    monkeypatch.setattr(sunset.guard, "usable_cpus", lambda: 8)
    monkeypatch.setattr(sunset.pipeline.workers, "usable_cpus", lambda: 8)
    assert frame_workers(4, 3) == 3
    assert frame_workers(1, 10) == 1
    # by default every CPU the process may use (not capped at two), never more than the frames
    monkeypatch.delenv("SUNSET_WORKERS", raising=False)
    assert frame_workers(None, 10**6) == usable_cpus() == 8
    assert frame_workers(None, 1) == 1
    monkeypatch.setenv("SUNSET_WORKERS", "3")
    assert frame_workers(None, 10) == 3
    assert frame_workers(5, 10) == 5            # --jobs wins over the variable
    with pytest.raises(SunsetError, match="workers"):
        frame_workers(0, 5)


def test_a_frame_records_the_sea_bounces_only_when_asked():
    # the 8-bit tape does not read Frame.incidence / Frame.sea_rays: render makes them only on request
    from sunset.pipeline.frame import code_frame, encode, render

    scene = Scene.default().with_size(80, 64)
    lean = render(scene, 0.8, 2)
    full = render(scene, 0.8, 2, sea_bounces=True)
    assert full.incidence is not None and full.sea_rays is not None
    assert lean.incidence is None and lean.sea_rays is None
    for name in ("direction", "surface", "part", "distance", "point", "normal", "bounces", "ray", "final_surface",
                 "final_part", "final_normal"):
        np.testing.assert_array_equal(getattr(lean, name), getattr(full, name), err_msg=name)
    np.testing.assert_array_equal(code_frame(scene, 0.8, 2, seed=3), encode(scene, full, seed=3))
    np.testing.assert_array_equal(encode(scene, lean, seed=3), encode(scene, full, seed=3))
    # the first bounce, from the direct ray's own fields: cos i = -D.N and R1 = D - 2 (D.N) N
    sea = full.surface == SEA
    d, n = full.direction[sea].astype(float), full.normal[sea].astype(float)
    dn = np.sum(d * n, axis=1)
    np.testing.assert_allclose(full.incidence[sea, 0], -dn, atol=1e-6)
    np.testing.assert_allclose(full.sea_rays[sea, 0], d - 2 * dn[:, None] * n, atol=1e-6)


def test_the_rgb_back_end_asks_for_the_sea_bounces_and_gets_the_same_bytes():
    # the RGB back end's rays: the same bytes as the stages called one by one with the bounces recorded
    from sunset.light.geometry import Geometry
    from sunset.light.render import frame_light, shade_display
    from sunset.pipeline.frame import trace_direct, trace_reflections
    from sunset.pipeline.rgb import render_rgb, trace_geometry

    scene = Scene.default().with_size(72, 56)
    explicit = Geometry.from_frame(trace_reflections(scene, trace_direct(scene, 0.6), 2, sea_bounces=True))
    got = trace_geometry(scene, 0.6, 2)
    for name, value in vars(explicit).items():
        if isinstance(value, np.ndarray):
            assert getattr(got, name).tobytes() == value.tobytes(), name
    want = shade_display(explicit, frame_light(scene, 0.6, 0.35))
    assert render_rgb(scene, 0.6, 0.35).tobytes() == want.tobytes()
    with pytest.raises(SunsetError, match="sea_bounces=True"):
        Geometry.from_frame(render(scene, 0.6, 2))               # the default frame: no bounces to shade
