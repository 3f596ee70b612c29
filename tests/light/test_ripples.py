"""Ripples of light on a post (sunset/light/ripples.py, postrays.py): still water's closed forms, the books, the
photon estimate (kernel and histogram) against the beams, the twins within their tolerances, bad arguments."""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.errors import SunsetError
from sunset.light.fresnel import reflectance
from sunset.light.postrays import PostReceiver, post_rays
from sunset.light.ripples import trace_ripples
from sunset.light.water import absorption, scattering
from sunset.model.posts import Post
from sunset.model.scene import load_named_scene
from sunset.model.sky import spectral_data
from sunset.model.waves import Sea

POST = Post(x=0.5, y=10.0, radius=0.3, top=2.0, depth=2.0)
HOURS = 2.0


@pytest.fixture(scope="module")
def wavy():
    return replace(load_named_scene("carlas-island"), posts=(POST,))


@pytest.fixture(scope="module")
def still(wavy):
    return replace(wavy, sea=Sea(()))


@pytest.fixture(scope="module")
def swell():
    return load_named_scene("post-in-the-swell")


def _texel_cos(tex, phi_sun):
    """cos(φ − φ_sun) averaged over each texel's width, 0 behind the silhouettes: the closed form's texel mean."""
    d = 2 * math.pi / len(tex.phi)
    lo = np.angle(np.exp(1j * (tex.phi - d / 2 - phi_sun)))
    half = math.pi / 2
    return (np.sin(np.clip(lo + d, -half, half)) - np.sin(np.clip(lo, -half, half))) / d


def _closed_forms(still, tex):
    """Still water: R |P_h| cos(φ − φ_sun) above; (1 − R) sin e tan θt cos(φ − φ_sun) e^(−c|z|/cos θt) below,
    both as texel means, on the lit side (cos > 0.3) and away from the ends (0.15 m)."""
    p = still.sun.position(HOURS)
    phi_sun = math.atan2(p[1], p[0])
    R = float(reflectance(p[2]))
    cos = _texel_cos(tex, phi_sun)
    lit = np.cos(tex.phi - phi_sun) > 0.3
    band = (tex.z > 0.15) & (tex.z < POST.top - 0.15)
    above = tex.above[band][:, lit] / (R * math.hypot(p[0], p[1]) * cos[lit]) - 1.0
    cos_t = math.sqrt(1.0 - (1.0 - p[2] ** 2) / 1.34 ** 2)
    lam = spectral_data().wavelengths
    k = (absorption(lam) + scattering(lam)) / cos_t
    dz = tex.z_below[1] - tex.z_below[0]
    deep = (tex.z_below < -0.15) & (tex.z_below > -POST.depth + 0.15)
    z = tex.z_below[deep][:, None]
    mean_exp = (np.exp(k * (z + dz / 2)) - np.exp(k * (z - dz / 2))) / (k * dz)      # e^(kz) over the texel
    want = (1 - R) * p[2] * math.sqrt(1 - cos_t ** 2) / cos_t * cos[lit][None, :, None] * mean_exp[:, None, :]
    below = tex.below[deep][:, lit] / want - 1.0
    return above, below


def test_still_water_lights_the_post_as_the_closed_forms_of_a_mirror_and_a_lens_say(still):
    tex = trace_ripples(still, 0, 0.0, HOURS, cell=0.01, texels=32, refine=4)
    above, below = _closed_forms(still, tex)
    assert np.sqrt(np.mean(above ** 2)) < 1e-3 and np.abs(above).max() < 3e-3
    assert np.sqrt(np.mean(below ** 2)) < 1e-3 and np.abs(below).max() < 5e-3
    # the side away from the sun gets nothing
    p = still.sun.position(HOURS)
    assert tex.above[:, np.cos(tex.phi - math.atan2(p[1], p[0])) < -0.3].max() == 0.0


def test_the_photons_tell_the_same_closed_forms_more_roughly(still):
    tex = trace_ripples(still, 0, 0.0, HOURS, method="photons", rays=1 << 17, texels=32)
    above, below = _closed_forms(still, tex)
    assert np.sqrt(np.mean(above ** 2)) < 0.02 and np.sqrt(np.mean(below ** 2)) < 0.03


@pytest.mark.parametrize("method", ["beams", "photons"])
@pytest.mark.parametrize("scene_name", ["still", "wavy", "swell"])
def test_every_rays_flux_ends_in_one_account_and_the_texture_holds_what_it_gathered(request, scene_name, method):
    scene = request.getfixturevalue(scene_name)
    hours = 1.0 if scene_name == "swell" else HOURS
    tex = trace_ripples(scene, 0, 1.3, hours, method=method, cell=0.1, rays=1 << 15, texels=24, bandwidth=0.0)
    acc = tex.accounts
    assert sum(v for k, v in acc.items() if k != "in") == pytest.approx(acc["in"], rel=1e-12)
    post = scene.posts[0]
    dphi = 2 * math.pi / len(tex.phi)
    assert tex.above.sum() * post.radius * dphi * (tex.z[1] - tex.z[0]) == pytest.approx(
        acc["reflected onto the post"], rel=1e-9)
    gathered = tex.below.sum(axis=(0, 1)) * post.radius * dphi * (tex.z_below[1] - tex.z_below[0])
    assert gathered.mean() == pytest.approx(acc["refracted onto the post"], rel=1e-9)
    assert acc["reflected onto the post"] > 0 and acc["refracted onto the post"] > 0
    assert np.all(tex.above >= 0) and np.all(tex.below >= 0)
    if scene_name == "still":          # the light in is the sunlight on the patch's water, E sin e A
        p = scene.sun.position(hours)
        rec = PostReceiver(scene, 0, 1.3, hours, 24)
        assert acc["in"] == pytest.approx(p[2] * rec.area, rel=1e-12)


def test_the_photon_histogram_falls_on_the_beams_as_the_rays_grow(swell):
    beams = trace_ripples(swell, 0, 0.4, 1.0, cell=0.025, texels=12).above
    err = []
    for k in (13, 15, 17):
        tex = trace_ripples(swell, 0, 0.4, 1.0, method="photons", rays=1 << k, texels=12, bandwidth=0.0, seed=k)
        err.append(np.sqrt(np.mean((tex.above - beams) ** 2)))
    # Monte Carlo about the beams: the distance falls about as N^(−1/2), a factor 2 for every 4× the photons
    assert err[0] > 1.5 * err[1] > 1.5 ** 2 * err[2]


def test_same_seed_same_texture_and_the_beams_need_none(wavy):
    a = trace_ripples(wavy, 0, 0.5, HOURS, method="photons", rays=5000, texels=12, seed=3)
    b = trace_ripples(wavy, 0, 0.5, HOURS, method="photons", rays=5000, texels=12, seed=3)
    assert a.above.tobytes() == b.above.tobytes() and a.below.tobytes() == b.below.tobytes()
    c = trace_ripples(wavy, 0, 0.5, HOURS, cell=0.2, texels=12)
    with kernels.use_threads(1):
        d = trace_ripples(wavy, 0, 0.5, HOURS, cell=0.2, texels=12)
    assert c.above.tobytes() == d.above.tobytes() and c.below.tobytes() == d.below.tobytes()
    assert c.accounts == d.accounts


@pytest.mark.parametrize("kwargs, word", [
    (dict(rays=0, method="photons"), "rays"), (dict(rays=1 << 30, method="photons"), "rays"),
    (dict(post_index=1), "post_index"), (dict(hours=-2.0), "sun"), (dict(t=float("nan")), "t"),
    (dict(texels=1), "texels"), (dict(bandwidth=-1.0, method="photons"), "bandwidth"), (dict(cell=0.0), "cell"),
    (dict(cell=float("nan")), "cell"), (dict(cell=1e-4), "cell"), (dict(method="rays"), "method"),
    (dict(refine=-1), "refine"), (dict(refine=99), "refine"),
])
def test_bad_arguments(wavy, kwargs, word):
    args = dict(post_index=0, t=0.0, hours=HOURS, texels=8)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word) as info:
        trace_ripples(wavy, **args)
    assert "\n" not in str(info.value)


def test_a_scene_without_posts(wavy):
    with pytest.raises(SunsetError, match="no posts"):
        trace_ripples(replace(wavy, posts=()), 0)


@pytest.mark.skipif(not kernels.AVAILABLE, reason="Numba is not installed")
def test_the_compiled_post_rays_agree_within_their_tolerance(swell, still):
    from sunset.light.postrays_numba import COORD_ATOL

    rng = np.random.default_rng(6)
    a, b = rng.random(100_000), rng.random(100_000)
    for scene, hours in ((swell, 1.0), (still, HOURS)):
        rec = PostReceiver(scene, 0, 0.7, hours, 24)
        tab = rec.table
        want = post_rays.reference(a, b, tab.a, tab.kx, tab.ky, tab.c, rec.geo)
        got = post_rays.compiled()(a, b, tab.a, tab.kx, tab.ky, tab.c, rec.geo)
        same = got[0] == want[0]
        assert same.mean() > 1 - 1e-4                         # a code differs only at a silhouette, by round-off
        for g, w in zip(got[1:], want[1:]):
            np.testing.assert_allclose(np.nan_to_num(g[same]), np.nan_to_num(w[same]), rtol=0, atol=COORD_ATOL)


def _splat_cases():
    """Hits of every kind: inside, at the texture's ends and beyond them (the nearest texel takes them whole),
    across φ's seam, one channel and many, none; a tiny bandwidth (one texel) and a wide one."""
    rng = np.random.default_rng(7)
    phi_edges = np.linspace(0.0, 2 * math.pi, 23)
    z_edges = np.linspace(-0.4, 2.0, 33)
    n = 4000
    phi = rng.random(n) * 2 * math.pi
    phi[:50] = rng.random(50) * 1e-3                          # by the seam
    z = rng.uniform(-0.8, 2.4, n)                             # some beyond either end
    z[50:60] = [-0.4, 2.0, -0.4 - 1e-9, 2.0 + 1e-9, -0.45, 2.05, -3.0, 5.0, 0.0, 1.0]
    dz = z_edges[1] - z_edges[0]
    for weight in (rng.random(n), rng.random((n, 5)), rng.random((n, 41))):
        for h in (1.5 * dz, 0.3 * dz, 3.2 * dz):
            yield phi, z, weight, phi_edges, z_edges, 0.3, h
    yield phi[:0], z[:0], np.zeros((0, 3)), phi_edges, z_edges, 0.3, 1.5 * dz
    yield phi[:1], z[:1], np.ones(1), phi_edges, z_edges, 0.3, 1.5 * dz
    yield phi, z, rng.random(n), phi_edges, z_edges, 0.3, 40 * dz    # a stencil wider than the post's round


@pytest.mark.skipif(not kernels.AVAILABLE, reason="Numba is not installed")
def test_the_compiled_splat_agrees_within_its_tolerance():
    from sunset.light.ripples import _splat
    from sunset.light.ripples_numba import SPLAT_RTOL

    for args in _splat_cases():
        want = _splat.reference(*args)
        got = _splat.compiled()(*args)
        assert got.shape == want.shape and got.dtype == want.dtype
        np.testing.assert_allclose(got, want, rtol=0, atol=SPLAT_RTOL * max(want.max(initial=0.0), 1e-300))
        assert got.tobytes() == _splat.compiled()(*args).tobytes()


def test_the_splat_is_the_kernel_summed_texel_by_texel():
    """The reference against an independent computation: each hit's kernel over the texels, one hit at a time."""
    from sunset.light.ripples import _splat

    rng = np.random.default_rng(3)
    phi_edges = np.linspace(0.0, 2 * math.pi, 13)
    z_edges = np.linspace(0.0, 1.0, 9)
    dz = z_edges[1] - z_edges[0]
    phi, z, w = rng.random(30) * 2 * math.pi, rng.uniform(-0.2, 1.2, 30), rng.random((30, 2))
    h, radius = 1.5 * dz, 0.2
    want = np.zeros((8, 12, 2))
    centres_phi = 0.5 * (phi_edges[1:] + phi_edges[:-1])
    centres_z = 0.5 * (z_edges[1:] + z_edges[:-1])
    for p, q, wk in zip(phi, z, w):
        dphi = np.angle(np.exp(1j * (centres_phi - p)))          # the shorter way round
        d2 = (radius * dphi[None, :]) ** 2 + (centres_z[:, None] - q) ** 2
        ker = np.maximum(1.0 - d2 / h ** 2, 0.0)
        if ker.sum() > 0:
            want += (ker / ker.sum())[..., None] * wk
        else:
            want[np.clip(int(np.floor((q - z_edges[0]) / dz)), 0, 7), int(p // (phi_edges[1])) % 12] += wk
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            np.testing.assert_allclose(_splat(phi, z, w, phi_edges, z_edges, radius, h), want, rtol=1e-12, atol=1e-15)


def test_the_textures_agree_on_either_path(swell):
    for method in ("beams", "photons"):
        with kernels.use_compiled(False):
            want = trace_ripples(swell, 0, 0.4, 1.0, method=method, cell=0.2, rays=1 << 14, texels=16)
        with kernels.use_compiled(True):
            got = trace_ripples(swell, 0, 0.4, 1.0, method=method, cell=0.2, rays=1 << 14, texels=16)
        for a, b in ((got.above, want.above), (got.below, want.below)):
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * max(b.max(), 1e-300))
