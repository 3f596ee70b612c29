"""Ripples of light on the shore (sunset/light/shore.py): flux accounts, true areas, still water's closed form
(beams and photons), another island in the way, the owner of a point, convergence, bad arguments,
determinism, and the shore as a light source of the RGB back end (on by default)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset.errors import SunsetError
from sunset.light.fresnel import reflectance
from sunset.light.render import frame_light
from sunset.pipeline.rgb import trace_geometry
from sunset.light.shade import shade
from sunset.light.shore import (OWNER_TOLERANCE, frame_texels, owner, radius_at, shore_lookup, smooth_surface,
                                texel_areas, trace_shore, water_line)
from sunset.model.islands import Island, Paraboloid
from sunset.model.scene import load_named_scene
from sunset.model.waves import Sea
from sunset.pipeline.frame import render

HOURS = 2.0
#: A cliff that rises straight from the water (slope about 39° at the water line, r_w = 100 m) off a gentle
#: shelf 3 m down: the steep receiver the beaches of Carla's Island are not.
CLIFF = Island(x=-60.0, y=700.0, cliff=Paraboloid(40.0, 0.004, 0.0005, 0.0045),
               beach=Paraboloid(-2.0, 1e-4, 0.0, 1e-4), cliff_top=30.0, hill_factor=0.5, name="cliff")


@pytest.fixture(scope="module")
def carla():
    return load_named_scene("carlas-island")


@pytest.fixture(scope="module")
def wavy(carla):
    return replace(carla, islands=(CLIFF,) + carla.islands)


@pytest.fixture(scope="module")
def still(carla):
    """The cliff alone on still water (no other island shadows its water or stands in its light)."""
    return replace(carla, islands=(CLIFF,), sea=Sea(()))


def test_the_water_line_and_the_radius_at_a_height_are_on_the_smooth_surface():
    phi = np.linspace(0.0, 2 * math.pi, 37)
    for z in (-2.5, 0.0, 3.0, 35.0):
        r = radius_at(CLIFF, phi, z)
        h, _, _ = smooth_surface(CLIFF, CLIFF.x + r * np.cos(phi), CLIFF.y + r * np.sin(phi))
        np.testing.assert_allclose(h, z, atol=1e-9)
    np.testing.assert_array_equal(water_line(CLIFF, phi), radius_at(CLIFF, phi, 0.0))


def test_texel_areas_against_a_fine_cartesian_sum():
    # the true area of a patch of the surface, from a fine grid in x, y: Σ √(1 + |∇H|²) ΔxΔy over the points
    # whose (φ, w) fall in the texel block; the midpoint rule in (φ, w) must agree
    phi_edges = np.linspace(1.0, 1.3, 4)
    w_edges = np.linspace(-20.0, 40.0, 5)
    area = texel_areas(CLIFF, phi_edges, w_edges).sum()
    pe, we = np.meshgrid(np.linspace(phi_edges[0], phi_edges[-1], 9), w_edges[[0, -1]])
    rad = water_line(CLIFF, pe) - we
    bx, by = CLIFF.x + rad * np.cos(pe), CLIFF.y + rad * np.sin(pe)
    xs = np.linspace(bx.min() - 2, bx.max() + 2, 1201)
    ys = np.linspace(by.min() - 2, by.max() + 2, 1201)
    x, y = np.meshgrid(xs, ys)
    phi = np.mod(np.arctan2(y - CLIFF.y, x - CLIFF.x), 2 * math.pi)
    w = water_line(CLIFF, phi) - np.hypot(x - CLIFF.x, y - CLIFF.y)
    inside = (phi >= phi_edges[0]) & (phi < phi_edges[-1]) & (w >= w_edges[0]) & (w < w_edges[-1])
    _, gx, gy = smooth_surface(CLIFF, x[inside], y[inside])
    brute = np.sum(np.sqrt(1 + gx * gx + gy * gy)) * (xs[1] - xs[0]) * (ys[1] - ys[0])
    assert area == pytest.approx(brute, rel=3e-3)


@pytest.mark.parametrize("method", ["beams", "photons"])
@pytest.mark.parametrize("scene_name, index", [("still", 0), ("wavy", 0), ("carla", 0), ("carla", 1)])
def test_every_ray_ends_in_one_account_and_the_texture_holds_what_it_gathered(request, scene_name, index, method):
    scene = request.getfixturevalue(scene_name)
    tex = trace_shore(scene, index, 1.3, HOURS, method=method, cell=3.0, rays=1 << 14, texels=16)
    acc = tex.accounts
    assert sum(v for k, v in acc.items() if k != "in") == pytest.approx(acc["in"], rel=1e-12)
    assert np.sum(tex.reflected * tex.area) == pytest.approx(acc["reflected onto the shore"], rel=1e-9)
    gathered = np.sum(tex.refracted * tex.area[..., None], axis=(0, 1))
    assert gathered.mean() == pytest.approx(acc["refracted onto the shore"], rel=1e-9)
    assert acc["refracted onto the shore"] > 0
    assert np.all(tex.reflected >= 0) and np.all(tex.refracted >= 0)


@pytest.mark.parametrize("method, kwargs, rms", [("beams", dict(cell=0.25), 0.006),
                                                  ("photons", dict(rays=1 << 17), 0.03)])
def test_still_water_lights_the_cliff_as_the_closed_form_of_a_mirror_says(still, method, kwargs, rms):
    tex = trace_shore(still, 0, 0.0, HOURS, method=method, texels=24, **kwargs)
    p = still.sun.position(HOURS)
    R = float(reflectance(p[2]))
    r = np.array([-p[0], -p[1], p[2]])                    # the reflected beam's direction
    phi, w = np.meshgrid(tex.phi, tex.w)
    rad = water_line(CLIFF, phi) - w
    x, y = CLIFF.x + rad * np.cos(phi), CLIFF.y + rad * np.sin(phi)
    z, gx, gy = smooth_surface(CLIFF, x, y)
    n = np.stack([-gx, -gy, np.ones_like(gx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    want = R * np.maximum(-(n @ r), 0.0)
    # where the beam reaches: back along −r to the sea (z = 0) without passing under the island, from water
    # that is in the patch (w between −L and 0) and that the sun reaches past the island
    s = np.linspace(0.0, 1.0, 201)[1:-1]
    back = z / r[2]                                       # distance back to the sea
    px = x[..., None] - s * back[..., None] * r[0]
    py = y[..., None] - s * back[..., None] * r[1]
    pz = z[..., None] * (1 - s)
    clear = np.all(smooth_surface(CLIFF, px, py)[0] < pz - 1e-6, axis=-1) & (z > 0.05)
    wx, wy = x - back * r[0], y - back * r[1]
    wphi = np.arctan2(wy - CLIFF.y, wx - CLIFF.x)
    ww = water_line(CLIFF, wphi) - np.hypot(wx - CLIFF.x, wy - CLIFF.y)
    sun = np.linspace(0.0, 400.0, 401)[1:]
    lit = np.all(smooth_surface(CLIFF, wx[..., None] + sun * p[0], wy[..., None] + sun * p[1])[0]
                 < sun * p[2], axis=-1)
    reach = clear & lit & (ww < -0.5) & (ww > -tex.reach + 1.0)
    # texels whose kernel sees only reached texels (2 texels each way)
    core = reach.copy()
    for di in (-2, -1, 1, 2):
        core &= np.roll(reach, di, axis=1)
        shifted = np.zeros_like(reach)
        if di > 0:
            shifted[di:] = reach[:-di]
        else:
            shifted[:di] = reach[-di:]
        core &= shifted
    assert core.sum() > 40
    err = tex.reflected[core] / want[core] - 1.0
    assert np.sqrt(np.mean(err ** 2)) < rms
    # and where the beam cannot reach above the water (the cliff's back), nothing
    dark = (n @ r > 0.05) & (z > 1.0)
    assert dark.sum() > 40 and tex.reflected[dark].max() == 0.0


def test_the_photons_fall_on_the_beams_as_they_grow(carla):
    beams = trace_shore(carla, 0, 0.0, 0.35, cell=1.0, texels=12).refracted.mean(axis=-1)
    err = []
    for k in (11, 13, 15):
        tex = trace_shore(carla, 0, 0.0, 0.35, method="photons", rays=1 << k, texels=12, bandwidth=0.0, seed=k)
        err.append(np.sqrt(np.mean((tex.refracted.mean(axis=-1) - beams) ** 2)))
    # Monte Carlo about the beams: the distance falls about as N^(−1/2), a factor 2 for every 4× the rays
    assert err[0] > 1.4 * err[1] > 1.4 ** 2 * err[2]


def test_same_seed_same_texture_and_the_beams_on_any_number_of_threads(wavy):
    from sunset import kernels

    a = trace_shore(wavy, 0, 0.5, HOURS, method="photons", rays=3000, texels=8, seed=3)
    b = trace_shore(wavy, 0, 0.5, HOURS, method="photons", rays=3000, texels=8, seed=3)
    np.testing.assert_array_equal(a.reflected, b.reflected)
    np.testing.assert_array_equal(a.refracted, b.refracted)
    assert a.accounts == b.accounts
    c = trace_shore(wavy, 0, 0.5, HOURS, cell=4.0, texels=8)
    with kernels.use_threads(1):
        d = trace_shore(wavy, 0, 0.5, HOURS, cell=4.0, texels=8)
    assert c.reflected.tobytes() == d.reflected.tobytes() and c.accounts == d.accounts


#: An islet 50 m off the cliff's sun-facing shore: in the way of some of the light the water throws at the
#: cliff, and standing in the cliff's band.
def _islet(scene):
    p = scene.sun.position(HOURS)
    u = np.array([p[0], p[1]]) / np.hypot(p[0], p[1])
    phi = np.arctan2(u[1], u[0])
    r = water_line(CLIFF, phi) + 50.0
    return Island(x=float(CLIFF.x + r * u[0]), y=float(CLIFF.y + r * u[1]), cliff=Paraboloid(12.0, 0.04, 0.0, 0.04),
                  beach=Paraboloid(-1.0, 0.01, 0.0, 0.01), cliff_top=10.0, hill_factor=0.5, name="islet")


def test_another_island_in_the_way_takes_the_light_and_keeps_its_own_points(still):
    islet = _islet(still)
    both = replace(still, islands=(CLIFF, islet))
    alone = trace_shore(still, 0, 0.0, HOURS, cell=1.0, texels=24)
    tex = trace_shore(both, 0, 0.0, HOURS, cell=1.0, texels=24)
    acc = tex.accounts
    assert acc["reflected onto another island"] > 0 and acc["in an island's shadow"] > 0
    assert acc["reflected onto the shore"] < alone.accounts["reflected onto the shore"]
    # the islet's own points lie in the cliff's band (its (φ, w) are the cliff's), yet they are the islet's
    rng = np.random.default_rng(8)
    ang, rad = rng.uniform(0, 2 * np.pi, 2000), rng.uniform(0, 15, 2000)
    x, y = islet.x + rad * np.cos(ang), islet.y + rad * np.sin(ang)
    pts = np.stack([x, y, islet.height(x, y)], axis=-1)
    pts = pts[pts[:, 2] > 0.1]
    lit = replace(tex, reflected=np.ones_like(tex.reflected))
    assert np.mean(shore_lookup(lit, CLIFF, pts) > 0.99) > 0.9   # the band's coordinates reach them
    assert np.all(owner(both.islands, pts) == 1)
    cliff_pts = np.stack([CLIFF.x + 120 * np.cos(ang), CLIFF.y + 120 * np.sin(ang), np.zeros(2000)], axis=-1)
    cliff_pts[:, 2] = CLIFF.height(cliff_pts[:, 0], cliff_pts[:, 1])
    assert np.all(owner(both.islands, cliff_pts) == 0)
    off = cliff_pts + [0.0, 0.0, 2 * OWNER_TOLERANCE]            # a post's side above the ground: no one's
    assert np.all(owner(both.islands, off) == -1)


@pytest.mark.parametrize("kwargs, word", [
    (dict(rays=0, method="photons"), "rays"), (dict(rays=1 << 30, method="photons"), "rays"),
    (dict(island_index=4), "island_index"), (dict(island_index=-1), "island_index"), (dict(hours=-2.0), "sun"),
    (dict(t=float("nan")), "t"), (dict(texels=1), "texels"), (dict(bandwidth=-1.0, method="photons"), "bandwidth"),
    (dict(inland=1e4), "inland"), (dict(inland=float("nan")), "inland"), (dict(cell=-1.0), "cell"),
    (dict(cell=1e-3), "cell"), (dict(method="x"), "method"), (dict(refine=7), "refine"),
])
def test_bad_arguments(wavy, kwargs, word):
    args = dict(island_index=0, t=0.0, hours=HOURS, texels=8, cell=5.0)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word) as info:
        trace_shore(wavy, **args)
    assert "\n" not in str(info.value)


def test_a_scene_without_islands(wavy):
    with pytest.raises(SunsetError, match="no islands"):
        trace_shore(replace(wavy, islands=()), 0)


def test_the_shore_source_adds_the_texture_times_the_direct_light_only_on_direct_island_points(carla):
    # the sun behind the eye, so that the sun-facing shores face the camera
    scene = replace(carla, islands=(CLIFF,), sun=replace(carla.sun, azimuth=180.0)).with_size(64, 64)
    g = trace_geometry(scene, 0.0, 2)
    hours = 1.0
    base = frame_light(scene, 0.0, hours, shore=False)
    assert not base.extra_irradiance                     # the scene has no posts
    light = frame_light(scene, 0.0, hours)               # on by default
    assert len(light.extra_irradiance) == 1
    source = light.extra_irradiance[-1]
    bare = shade(g, base).reshape(-1, 3)
    lit = shade(g, light).reshape(-1, 3)
    points = g.island_point + np.array([0.0, 0.0, scene.camera.eye_height])
    e = shore_lookup(source.textures[0], CLIFF, points)
    parts = g.final_kind[g.island_index]
    extra = np.zeros_like(bare)
    extra[g.island_index] = e[:, None] * np.stack([base.island_direct[c] for c in parts])
    assert (e > 0).sum() > 20
    np.testing.assert_allclose(lit, bare + extra, rtol=1e-5, atol=1e-9)
    frame = render(scene, 0.0, 2)
    assert np.all(e[frame.bounces.reshape(-1)[g.island_index] > 0] == 0)


def test_the_frames_textures_are_as_fine_as_the_picture_and_no_finer(carla):
    """A texel of the RGB back end's shore texture is about SHORE_TEXEL_PIXELS pixels across where the island's
    water line is nearest the eye (projected by the camera, not by the module), within the clamps."""
    from sunset.constants import RIPPLE_MAX_REACH, SHORE_INLAND, SHORE_MIN_TEXELS, SHORE_TEXEL_PIXELS, SHORE_TEXELS

    band = RIPPLE_MAX_REACH + SHORE_INLAND
    seen = set()
    for size in (8, 48, 96, 160, 1000):
        scene = carla.with_size(size, size)
        for k, island in enumerate(scene.islands):
            n = frame_texels(scene, k)
            ring = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
            r = water_line(island, ring)
            x, y = island.x + r * np.cos(ring), island.y + r * np.sin(ring)
            d = float(np.hypot(x, y).min())
            # a texel's side seen face on at that distance, in pixels
            cols = lambda m: float(np.diff(scene.camera.to_pixel(np.array([0.0, m / d]), np.zeros(2))[0])[0])  # noqa: E731
            if SHORE_MIN_TEXELS < n < SHORE_TEXELS:
                assert cols(band / n) <= SHORE_TEXEL_PIXELS * (1 + 1e-3) < cols(band / (n - 1))
            elif n == SHORE_MIN_TEXELS:                    # coarser would do: held at the least
                assert cols(band / n) <= SHORE_TEXEL_PIXELS * (1 + 1e-3)
            else:                                          # finer would be wanted: held at the most
                assert n == SHORE_TEXELS and cols(band / (n - 1)) > SHORE_TEXEL_PIXELS * (1 - 1e-3)
            seen.add(n)
    assert SHORE_MIN_TEXELS in seen and SHORE_TEXELS in seen and len(seen) > 3
    # the frame's light traces them so
    scene = replace(carla, islands=carla.islands[:1]).with_size(48, 48)
    source = frame_light(scene, 0.0, 1.0).extra_irradiance[-1]
    assert source.textures[0].reflected.shape[0] == frame_texels(scene, 0) < SHORE_TEXELS


def test_a_sea_given_by_its_wind_throws_no_ripples():
    """The tracers read the sea as its trains' cosines; a wind sea has none, and its light is the hour's alone
    (not the flat band a still mirror would throw)."""
    from sunset.model.posts import Post

    scene = load_named_scene("carlas-island-in-the-wind").with_size(64, 64)
    assert scene.sea.wind is not None and scene.islands
    scene = replace(scene, posts=(Post(x=0.5, y=10.0, radius=0.3, top=2.0, depth=2.0),))
    assert frame_light(scene, 0.0, 1.0).extra_irradiance == []
    assert len(frame_light(replace(scene, sea=load_named_scene("carlas-island").sea), 0.0, 1.0).extra_irradiance) == 2


def test_a_frames_light_keeps_only_what_the_shading_reads():
    """A film keeps the light of each frame it meets (sunset.light.film.LIGHT_CACHE of them): the shores' light
    holds the reflected texture, its areas and heights, and no untraced refracted texture (a zero view)."""
    import gc
    import tracemalloc

    from sunset.light.lighting import Lighting

    scene = load_named_scene("carlas-island")
    kept = []
    for make in (lambda: Lighting.for_scene(scene, 1.0), lambda: frame_light(scene, 0.0, 1.0)):
        make()
        gc.collect()
        tracemalloc.start()
        light = make()
        gc.collect()
        kept.append(tracemalloc.get_traced_memory()[0])
        tracemalloc.stop()
    textures = light.extra_irradiance[-1].textures
    arrays = sum(t.reflected.nbytes + t.area.nbytes + t.height.nbytes for t in textures)
    assert all(np.all(t.refracted == 0) and t.refracted.base is not None for t in textures)
    # the refracted zeros would be tens of times the reflected texture; what is kept is the three arrays and small
    # change (the lookups' closures, the accounts)
    assert arrays < kept[1] - kept[0] < arrays + 2**20, (kept, arrays)
