"""The work and memory budgets beyond the 8-bit frame (issue 12, 10–12): RGB, clouds, posts, islands, films.

The predictions (:mod:`sunset.vector.budget`, :mod:`sunset.light.budget`)
are checked against what the renderer does: peaks measured with
:mod:`tracemalloc` on the NumPy reference kernels (whose arrays it sees), and
the cloud layer's (sample, pixel) pairs counted as the scan makes them. The
refusals are checked to come before any work: the renderer is replaced by
one that fails the test if it is called.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
import pytest

import sunset.vector.clouds as vclouds
from sunset.bench.memory import measure_rgb_bytes
from sunset.constants import (CLOUD_STRIP_PAIRS, MAX_FRAME_BYTES, MAX_FRAME_SAMPLES, MAX_ISLANDS, RGB_BYTES_PER_RAY,
                              RGB_LIGHT_BYTES)
from sunset.bench.memory import _traced_peak
from sunset.errors import SunsetError
from sunset.kernels import use_compiled
from sunset.light.budget import rgb_bytes
from sunset.pipeline.budget import check_rgb_work
from sunset.model.clouds import CloudCell, Clouds
from sunset.model.scene import Scene, load_named_scene
from sunset.vector.budget import check_work, predict_work
from tests.test_hostile_input import one_line_error, run


def peak_of(fn) -> int:
    fn()                                      # tables and kernels made once
    return _traced_peak(fn)


@pytest.fixture
def no_tracing(monkeypatch):
    """Any ray traced fails the test (the sea's and the islands' scan lines, the islands' probes): a refusal
    must come first."""
    import sunset.pipeline.frame as frame
    import sunset.vector.direct as vdirect

    def refuse(*_, **__):
        raise AssertionError("rays were traced before the budget refused the request")

    monkeypatch.setattr(frame, "run_strips", refuse)
    monkeypatch.setattr(vdirect, "probe_refinement", refuse)


def hostile_clouds(scene: Scene) -> Scene:
    """A cloud 15 km tall whose base is 198 m above the eye, sampled at the finest sigma: each of its samples
    covers hundreds of pixels (at 512x512 it took 14 s and 3.3 GB before the strips and the bound)."""
    cell = CloudCell(x=0.0, y=3000.0, a=2900.0, b=2900.0, top=15000.0, bottom=0.0)
    return replace(scene, clouds=Clouds(level=200.0, cells=(cell,)), camera=replace(scene.camera, sigma=0.0625))


# --------------------------------------------------------------------------- RGB: --shading rgb --samples N

def test_rgb_memory_is_measured_within_its_constants():
    """The hour's light and the growth per traced ray, measured, stay within RGB_LIGHT_BYTES and RGB_BYTES_PER_RAY."""
    light, per_ray = measure_rgb_bytes(Scene.default(), samples=4, sizes=((40, 32), (80, 64)))
    assert 20 * 2**20 < light <= RGB_LIGHT_BYTES, light    # its grid, computed in blocks of rows: some 37 MB
    assert 100 < per_ray <= RGB_BYTES_PER_RAY, per_ray


@pytest.mark.parametrize("name", ["carlas-island", "carlas-island-clouds", "post-in-the-swell"])
def test_rgb_frame_peak_is_within_the_prediction(tmp_path, name):
    """A whole RGB frame written as PNG, supersampled 2x2: its traced peak is at most the predicted bytes."""
    from sunset.pipeline.rgb import write_rgb_frame

    scene = load_named_scene(name).with_size(48, 40)
    with use_compiled(False):
        peak = peak_of(lambda: write_rgb_frame(scene, tmp_path / "a.png", samples=4))
    assert peak <= rgb_bytes(48, 40, 4) == check_rgb_work(scene, 4)
    assert peak > 20 * 2**20                             # the light's grid is most of a small frame's peak


def test_rgb_film_peak_is_within_the_prediction():
    """film --shading rgb keeps a cycle's geometries and shades frame by frame: within rgb_bytes(..., frames)."""
    from sunset.pipeline.rgb import film_frames, trace_cycle

    scene = Scene.default().with_size(40, 32)

    def film():
        geometries = trace_cycle(scene, [0.0, 0.5, 1.0], samples=4, progress=False)
        for _ in film_frames(scene, geometries, [1.0, 0.5, 0.0, -0.2], samples=4):
            pass

    with use_compiled(False):
        peak = peak_of(film)
    assert peak <= rgb_bytes(40, 32, 4, frames=3)


def test_rgb_over_budget_is_refused_before_any_ray(capsys, tmp_path, no_tracing):
    """Supersampling multiplies the rays: one line naming samples (or frames for a film), exit 2, no output."""
    out = tmp_path / "rgb.png"
    code, _, err = run(capsys, "render", "carlas-island", "--shading", "rgb", "--samples", "16", "--size",
                       "1000x1000", "-o", out)
    line = one_line_error(code, err, "samples:", "1000x1000", "16 samples per pixel", "MiB")
    assert f"{MAX_FRAME_BYTES // 2**20:,} MiB" in line
    code, _, err = run(capsys, "render", "carlas-island", "--shading", "rgb", "--samples", "256", "--size",
                       "300x300", "-o", out)
    one_line_error(code, err, "samples:", "rays")
    code, _, err = run(capsys, "film", "carlas-island", "--shading", "rgb", "--frames", "1000", "--size",
                       "200x200", "-o", tmp_path / "f.mp4", "--preview", tmp_path / "p.gif")
    one_line_error(code, err, "frames:", "1000 frames")
    assert list(tmp_path.iterdir()) == []
    # the 1000x1000 frame at 16 samples is over; at 4 samples it is within the budget
    assert rgb_bytes(1000, 1000, 16) > MAX_FRAME_BYTES >= rgb_bytes(1000, 1000, 4)


def test_rgb_supersampled_work_names_samples():
    """The k-times finer frame's own work (here its memory) is checked too, and the message says why."""
    scene = hostile_clouds(Scene.default()).with_size(300, 300)
    check_rgb_work(scene, 1)
    with pytest.raises(SunsetError, match=r"^samples: 16 samples per pixel trace the picture at 1200x1200: clouds"):
        check_rgb_work(scene, 16)


# --------------------------------------------------------------------------- clouds

def _pairs_made(scene, monkeypatch) -> int:
    """The (sample, pixel) pairs the cloud scan makes (every one goes through numpy.unique)."""
    made = []
    real = np.unique

    def counting(a, *args, **kw):
        made.append(np.asarray(a).size)
        return real(a, *args, **kw)

    monkeypatch.setattr(vclouds.np, "unique", counting)
    try:
        vclouds.cloud_scan(scene)
    finally:
        monkeypatch.setattr(vclouds.np, "unique", real)
    return sum(made)


@pytest.mark.parametrize("hostile", [False, True])
def test_cloud_pairs_and_memory_are_bounded(monkeypatch, hostile):
    """The predicted pairs bound the scan's; its peak is within the largest strip's predicted bytes."""
    base = load_named_scene("carlas-island-clouds").with_size(96, 80)
    scene = hostile_clouds(base) if hostile else base
    work = predict_work(scene)
    made = _pairs_made(scene, monkeypatch)
    assert 0 < made <= work.cloud_pairs_bound
    cloud_bytes = work.bytes - predict_work(replace(scene, clouds=None)).bytes
    assert peak_of(lambda: vclouds.cloud_scan(scene)) <= cloud_bytes


def test_cloud_strips_change_nothing(monkeypatch):
    """Scanned in strips of a few scan lines, the cloud layer is bit-identical to one strip."""
    scene = hostile_clouds(load_named_scene("carlas-island-clouds")).with_size(64, 48)
    whole = vclouds.cloud_scan(scene)
    monkeypatch.setattr(vclouds, "CLOUD_STRIP_PAIRS", 5000)
    count, pairs = vclouds.column_work(scene.clouds.cells[0], scene.clouds.level - scene.camera.eye_height,
                                       scene.camera.s_centres(), scene.camera.zy_min + 0.5 * scene.camera.pixel_pitch[1],
                                       scene.camera.pixel_pitch[1], 48, scene.camera.sigma)
    assert len(vclouds.cloud_strips(count, pairs)) > 5
    assert np.array_equal(vclouds.cloud_scan(scene), whole)
    assert CLOUD_STRIP_PAIRS > 5000


def test_tall_clouds_are_refused_up_front(capsys, tmp_path, no_tracing):
    """A cloud layer whose samples would cover too many pixels: one line naming the clouds, before any ray."""
    path = tmp_path / "c.toml"
    path.write_text(hostile_clouds(load_named_scene("carlas-island-clouds")).to_toml())
    start = time.perf_counter()
    code, _, err = run(capsys, "render", path, "--size", "1020x1023", "-o", tmp_path / "a.png")
    one_line_error(code, err, "clouds:", "cells", f"{MAX_FRAME_SAMPLES:.3g}")
    assert time.perf_counter() - start < 20
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.toml"]


# --------------------------------------------------------------------------- islands and posts

def test_many_islands_at_a_large_size_are_refused(capsys, tmp_path, no_tracing):
    """127 islands at 2000x2000 may take ~1e10 island samples: refused up front, naming the islands."""
    base = Scene.default()
    crowd = replace(base, islands=(base.islands * 43)[:MAX_ISLANDS])
    path = tmp_path / "crowd.toml"
    path.write_text(crowd.to_toml())
    start = time.perf_counter()
    code, _, err = run(capsys, "render", path, "--size", "2000x2000", "-o", tmp_path / "a.png")
    one_line_error(code, err, f"islands: {MAX_ISLANDS} islands at 2000x2000", "use fewer islands")
    assert time.perf_counter() - start < 20
    assert predict_work(crowd.with_size(2000, 2000)).island_samples_bound > MAX_FRAME_SAMPLES
    for argv in (("film", path, "--frames", "2", "--size", "2000x2000", "-o", tmp_path / "f.mp4"),
                 ("player", path, "--frames", "2", "--size", "2000x2000", "-o", tmp_path / "p.html")):
        code, _, err = run(capsys, *argv, "-q")                  # a wave cycle's island pass comes after the check
        one_line_error(code, err, f"islands: {MAX_ISLANDS} islands at 2000x2000")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["crowd.toml"]


def test_many_islands_at_a_small_size_render(capsys, tmp_path):
    """The same 127 islands at 64x48 are within the bound and render; the islands' samples stay in the bound."""
    from sunset.pipeline.frame import trace_direct

    base = Scene.default()
    crowd = replace(base, islands=(base.islands * 43)[:MAX_ISLANDS]).with_size(64, 48)
    work = check_work(crowd)
    assert work.samples <= MAX_FRAME_SAMPLES
    info = {}
    trace_direct(crowd, 0.0, info=info)
    assert 0 < info["island_samples"] <= work.island_samples_bound
    path = tmp_path / "crowd.toml"
    path.write_text(crowd.to_toml())
    code, _, err = run(capsys, "render", path, "-o", tmp_path / "a.png", "-q")
    assert code == 0, err
    assert (tmp_path / "a.png").is_file()


def test_posts_are_counted():
    """Each post tests at most every pixel twice (direct box, reflected rays)."""
    scene = load_named_scene("post-in-the-swell").with_size(64, 48)
    work = predict_work(scene)
    assert work.post_tests_bound == 2 * len(scene.posts) * 64 * 48 > 0
    assert work.samples == (work.sea_samples + work.island_samples_bound + work.cloud_samples
                            + work.cloud_pairs_bound + work.post_tests_bound)


@pytest.mark.parametrize("name", ["carlas-island", "archipelago-at-dusk", "carlas-island-clouds", "storm-swell",
                                  "post-in-the-swell", "still-lake-at-noon"])
def test_packaged_scenes_are_within_the_work_bound(name):
    """Every packaged scene at the paper's size, and at 4x that, is within MAX_FRAME_SAMPLES."""
    for w, h in ((1020, 1023), (2040, 2046)):
        assert check_work(load_named_scene(name).with_size(w, h)).samples <= MAX_FRAME_SAMPLES


# --------------------------------------------------------------------------- films: frames in parallel

def test_parallel_frames_keep_to_the_memory_budget(monkeypatch):
    """Each worker holds a frame: with the budget set to fewer than two frames, the frames are coded here alone."""
    import concurrent.futures

    import sunset.constants as C
    from sunset.pipeline.cycle import code_frames

    scene = Scene.default().with_size(24, 16)
    one = predict_work(scene).bytes
    monkeypatch.setattr(C, "MAX_FRAME_BYTES", one + one // 2)

    def no_pool(*_, **__):
        raise AssertionError("a second worker would exceed the memory budget")

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", no_pool)
    codes = code_frames(scene, [0.0, 0.5, 1.0], workers=3)
    assert codes.shape == (3, 16, 24)
