"""The islands' pass compiled (island_samples_numba.islands_scan) against the NumPy reference.

The twin does a strip of scan lines in one call, every scan line on its
own, with its own float32 cosine; the reference samples, profiles and
scan-converts each island over the whole strip with array operations. Each
path's depth buffer (1/yp and the island's code) and sample count are the
same bytes whatever the cut into strips and the number of threads; across
the paths the depth buffers agree as tests/agree.py says and the sample
counts within SAMPLES_RTOL (the adaptive cut rounds the profile's steps up).
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import ISLAND_SAMPLE_BUDGET, SKY
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene, as_scene
from sunset.vector.heightfield import sampling
from sunset.vector.island_samples import islands_scan, probe_refinement
from sunset.pipeline.frame import island_pass

from ..agree import assert_depth_agrees

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="no Numba: no compiled kernels")

#: The islands' sample counts on the two paths, relative: an interval's parts are ⌈(|Δr| + |Δ²r|)/σ⌉, and a
#: rounding of the profile can move a step across an integer.
SAMPLES_RTOL = 1e-3

SCENES = ["carlas-island", "archipelago-at-dusk", "still-lake-at-noon", "storm-swell"]


def depth_buffer(scene, refine, scan, cuts):
    """The islands' depth buffer of ``scene`` made by ``scan`` strip by strip: (u, code, samples)."""
    cam = scene.camera
    W, H = cam.width, cam.height
    d = scene.sea.max_elevation
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    samp = sampling(cam, d)
    s_all = cam.s_centres()
    probes = [probe_refinement(island, s_all, samp, d) for island in scene.islands]
    budget = ISLAND_SAMPLE_BUDGET * max(samp.n, H)
    u = np.zeros((W, H))
    code = np.full((W, H), SKY, np.int8)
    n = 0
    for c0, c1 in cuts:
        n += scan(scene.islands, probes, s_all, c0, c1, samp, d, cam.eye_height, zeta0, dz, H, cam.sigma, budget,
                  refine, u[c0:c1], code[c0:c1])
    return u, code, n


def random_cuts(rng, W):
    edges = np.unique(np.concatenate([[0, W], rng.integers(1, W, rng.integers(1, 9))]))
    return list(zip(edges[:-1].tolist(), edges[1:].tolist()))


def assert_same(got, want):
    np.testing.assert_array_equal(got[0].view(np.uint64), want[0].view(np.uint64))
    np.testing.assert_array_equal(got[1], want[1])
    assert got[2] == want[2]


def assert_agree(got, want):
    assert_depth_agrees(want[0], want[1], got[0], got[1])
    assert abs(got[2] - want[2]) <= SAMPLES_RTOL * want[2]


@pytest.mark.parametrize("refine", [True, False])
@pytest.mark.parametrize("name", SCENES)
def test_the_compiled_strip_agrees_with_the_numpy_one(name, refine):
    scene = as_scene(name).with_size(330, 250)
    W = scene.camera.width
    want = depth_buffer(scene, refine, islands_scan.reference, [(0, W)])
    assert (want[1] > 0).any() and want[2] > 0           # islands are seen: the comparison is not empty
    rng = np.random.default_rng(len(name))
    whole = depth_buffer(scene, refine, islands_scan.compiled(), [(0, W)])
    assert_agree(whole, want)
    for cuts in (random_cuts(rng, W), [(c, c + 1) for c in range(W)]):
        assert_same(depth_buffer(scene, refine, islands_scan.compiled(), cuts), whole)
        # the reference does not depend on the cut either (a strip's longest scan line is no different)
        assert_same(depth_buffer(scene, refine, islands_scan.reference, cuts), want)


def random_island(rng):
    cliff = Paraboloid(rng.uniform(20, 120), rng.uniform(2e-4, 5e-3), rng.uniform(-1e-4, 1e-4), rng.uniform(2e-4, 5e-3))
    beach = Paraboloid(rng.uniform(-2, 8), rng.uniform(1e-5, 2e-4), 0.0, rng.uniform(1e-5, 2e-4))
    cosines = tuple(Cosine(rng.uniform(0, 15), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1),
                           float(rng.choice([0.0, rng.uniform(-3, 3)]))) for _ in range(rng.integers(0, 4)))
    return Island(x=rng.uniform(-900, 900), y=rng.uniform(150, 4000), cliff=cliff, beach=beach,
                  cliff_top=cliff.height * rng.uniform(0.2, 0.9), hill_factor=rng.uniform(0.1, 1.0), cosines=cosines)


@pytest.mark.parametrize("seed", range(12))
def test_random_islands_with_phases_and_hills_agree_with_the_numpy_ones(seed):
    rng = np.random.default_rng(seed)
    base = Scene.default().with_size(int(rng.integers(40, 260)), int(rng.integers(30, 200)))
    scene = Scene(camera=base.camera, sun=base.sun, sea=base.sea,
                  islands=tuple(random_island(rng) for _ in range(rng.integers(1, 7))))
    W = scene.camera.width
    for refine in (True, False):
        want = depth_buffer(scene, refine, islands_scan.reference, [(0, W)])
        assert_agree(depth_buffer(scene, refine, islands_scan.compiled(), random_cuts(rng, W)), want)


def test_the_comparison_sees_a_wrong_island():
    # an island moved by ten centimetres is outside the tolerances: the tests above would see a wrong twin
    scene = as_scene("carlas-island").with_size(330, 250)
    isl = scene.islands[0]
    moved = Island(x=isl.x + 0.1, y=isl.y, cliff=isl.cliff, beach=isl.beach, cliff_top=isl.cliff_top,
                   hill_factor=isl.hill_factor, cosines=isl.cosines, name=isl.name)
    other = Scene(camera=scene.camera, sun=scene.sun, sea=scene.sea, islands=(moved,) + scene.islands[1:])
    W = scene.camera.width
    want = depth_buffer(scene, True, islands_scan.reference, [(0, W)])
    got = depth_buffer(other, True, islands_scan.compiled(), [(0, W)])
    with pytest.raises(AssertionError):
        assert_agree(got, want)


@pytest.mark.parametrize("size", [(1020, 1023), (517, 389)])
def test_the_island_pass_agrees_on_both_paths_and_not_with_the_threads(size):
    scene = as_scene("archipelago-at-dusk").with_size(*size)
    with kernels.use_compiled(False), kernels.use_threads(1):
        want = island_pass(scene)
    assert len({c for c in np.unique(want.code) if c > 0}) >= 3      # many islands seen
    runs = []
    for n in (1, 2, 3):
        with kernels.use_compiled(True), kernels.use_threads(n):
            got = island_pass(scene)
        runs.append((got.u, got.code, got.samples))
    assert_agree(runs[0], (want.u, want.code, want.samples))
    for run in runs[1:]:
        assert_same(run, runs[0])
