"""Ripples of light (sunset/light/ripples.py): flux bookkeeping, still water's closed form, convergence."""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.errors import SunsetError
from sunset.light.fresnel import reflectance
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
def still_texture(still):
    return trace_ripples(still, 0, 0.0, hours=HOURS, rays=1 << 17, texels=32)


def texel_area(tex, below=False):
    dz = (tex.z_below[1] - tex.z_below[0]) if below else (tex.z[1] - tex.z[0])
    return POST.radius * (2 * math.pi / len(tex.phi)) * dz


@pytest.mark.parametrize("scene_name", ["still", "wavy"])
def test_every_ray_ends_in_one_account_and_the_texture_holds_what_it_gathered(request, scene_name):
    scene = request.getfixturevalue(scene_name)
    tex = trace_ripples(scene, 0, 1.3, hours=HOURS, rays=1 << 15, texels=24)
    acc = tex.accounts
    assert sum(v for k, v in acc.items() if k != "in") == pytest.approx(acc["in"], rel=1e-12)
    assert tex.above.sum() * texel_area(tex) == pytest.approx(acc["reflected onto the post"], rel=1e-9)
    gathered = tex.below.sum(axis=(0, 1)) * texel_area(tex, below=True)
    assert gathered.mean() == pytest.approx(acc["refracted onto the post"], rel=1e-9)
    assert acc["reflected onto the post"] > 0 and acc["refracted onto the post"] > 0
    assert np.all(tex.above >= 0) and np.all(tex.below >= 0)


def test_still_water_lights_the_post_as_the_closed_form_of_a_mirror_says(still, still_texture):
    tex = still_texture
    p = still.sun.position(HOURS)
    horiz, phi_sun = math.hypot(p[0], p[1]), math.atan2(p[1], p[0])
    R = float(reflectance(p[2]))
    cos_d = np.cos(tex.phi - phi_sun)
    lit = cos_d > 0.3
    # reflected: a parallel beam R E in direction (−P_h, P_z) on a vertical side facing the sun
    band = (tex.z > 0.15) & (tex.z < 1.8)
    want = R * horiz * cos_d[lit]
    err = tex.above[band][:, lit] / want - 1.0
    assert np.sqrt(np.mean(err ** 2)) < 0.02
    # refracted: (1 − R) E sin e / cos θt on the beam, tan θt cos(φ − φ_sun) on the side, e^(−c s), s = |z|/cos θt
    cos_t = math.sqrt(1.0 - (1.0 - p[2] ** 2) / 1.34 ** 2)
    tan_t = math.sqrt(1.0 - cos_t ** 2) / cos_t
    lam = spectral_data().wavelengths
    c = absorption(lam) + scattering(lam)
    deep = (tex.z_below < -0.15) & (tex.z_below > -1.8)
    want = ((1.0 - R) * p[2] * tan_t * cos_d[lit][None, :, None]
            * np.exp(-np.outer(np.abs(tex.z_below[deep]), c) / cos_t)[:, None, :])
    err = tex.below[deep][:, lit].mean(axis=-1) / want.mean(axis=-1) - 1.0
    assert np.sqrt(np.mean(err ** 2)) < 0.03
    # the side away from the sun gets nothing
    dark = cos_d < -0.3
    assert tex.above[:, dark].max() == 0.0


def test_still_water_gives_a_flat_band_and_waves_give_ripples(still_texture, wavy):
    wavy_tex = trace_ripples(wavy, 0, 0.0, hours=HOURS, rays=1 << 17, texels=32)
    p = wavy.sun.position(HOURS)
    j = int(np.argmin(np.abs(np.mod(still_texture.phi - math.atan2(p[1], p[0]), 2 * math.pi))))
    band = (still_texture.z > 0.15) & (still_texture.z < 1.8)
    flat = still_texture.above[band, j]
    rippled = wavy_tex.above[band, j]
    assert flat.std() / flat.mean() < 0.03
    assert rippled.std() / rippled.mean() > 0.3


def test_the_texture_converges_as_the_rays_grow(wavy):
    ref = trace_ripples(wavy, 0, 0.0, hours=HOURS, rays=1 << 19, texels=16, seed=99).above
    err = []
    for k in (12, 14, 16):
        tex = trace_ripples(wavy, 0, 0.0, hours=HOURS, rays=1 << k, texels=16, seed=k).above
        err.append(np.sqrt(np.mean((tex - ref) ** 2)))
    # Monte Carlo: the error falls about as N^(−1/2), a factor 2 for every 4× the rays
    assert err[0] > 1.4 * err[1] > 1.4 ** 2 * err[2]


def test_same_seed_same_texture(wavy):
    a = trace_ripples(wavy, 0, 0.5, hours=HOURS, rays=5000, texels=12, seed=3)
    b = trace_ripples(wavy, 0, 0.5, hours=HOURS, rays=5000, texels=12, seed=3)
    np.testing.assert_array_equal(a.above, b.above)
    np.testing.assert_array_equal(a.below, b.below)


@pytest.mark.parametrize("kwargs, word", [
    (dict(rays=0), "rays"), (dict(rays=1 << 30), "rays"), (dict(post_index=1), "post_index"),
    (dict(hours=-2.0), "sun"), (dict(t=float("nan")), "t"), (dict(texels=1), "texels"),
    (dict(bandwidth=-1.0), "bandwidth"),
])
def test_bad_arguments(wavy, kwargs, word):
    args = dict(post_index=0, t=0.0, hours=HOURS, rays=1000, texels=8)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word):
        trace_ripples(wavy, **args)


def test_a_scene_without_posts(wavy):
    with pytest.raises(SunsetError, match="no posts"):
        trace_ripples(replace(wavy, posts=()), 0)


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
def test_the_compiled_splat_gives_the_references_bits():
    from sunset.light.ripples import _splat

    for args in _splat_cases():
        want = _splat.reference(*args)
        got = _splat.compiled()(*args)
        assert got.shape == want.shape and got.dtype == want.dtype
        np.testing.assert_array_equal(got.view(np.uint8), want.view(np.uint8))


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


def test_the_textures_are_the_same_bits_either_way(wavy, still):
    for scene in (wavy, still):
        with kernels.use_compiled(False):
            want = trace_ripples(scene, 0, 0.4, hours=HOURS, rays=1 << 14, texels=24)
        with kernels.use_compiled(True):
            got = trace_ripples(scene, 0, 0.4, hours=HOURS, rays=1 << 14, texels=24)
        for a, b in ((got.above, want.above), (got.below, want.below)):
            np.testing.assert_array_equal(a.view(np.uint8), b.view(np.uint8))
