"""Posts in the water (sunset/model/posts.py): the cylinder's quadratic against a brute-force walk; validation."""

import math

import numpy as np
import pytest

from sunset.errors import SunsetError
from sunset.model.posts import Post
from sunset.model.scene import Scene, load_named_scene

POST = Post(x=1.0, y=12.0, radius=0.3, top=2.5, depth=3.0)


def walk(q, r, post, t_max=60.0, n=600_001):
    """First t on a fine grid where the ray is inside the cylinder between foot and top (brute force)."""
    t = np.linspace(0.0, t_max, n)
    p = q + t[:, None] * r
    inside = (np.hypot(p[:, 0] - post.x, p[:, 1] - post.y) <= post.radius) & (p[:, 2] <= post.top) \
        & (p[:, 2] >= -post.depth)
    return t[np.argmax(inside)] if inside.any() else np.inf


def test_pierce_against_a_brute_force_walk():
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(60):
        q = np.array([rng.uniform(-3, 3), rng.uniform(0, 6), rng.uniform(-1, 3)])
        target = np.array([POST.x + rng.uniform(-0.5, 0.5), POST.y + rng.uniform(-0.5, 0.5), rng.uniform(-4, 4)])
        r = (target - q) / np.linalg.norm(target - q)
        got = float(POST.pierce(q, r))
        want = walk(q, r, POST)
        if np.isinf(want):
            # a miss, or a hit through the top or foot cap (not the side): the side test says no
            assert np.isinf(got) or abs((q + got * r)[2] - POST.top) < 1e-3 or abs((q + got * r)[2] + POST.depth) < 1e-3
        else:
            hits += 1
            if np.isfinite(got):
                assert got == pytest.approx(want, abs=2e-4)
            else:              # entered through the top or the foot (a cap), which is not the side
                p = q + want * r
                assert p[2] >= POST.top - 1e-3 or p[2] <= -POST.depth + 1e-3
    assert hits > 20


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_pierce_shapes(shape):
    q = np.broadcast_to(np.array([0.0, 0.0, 2.0]), shape + (3,))
    r = np.broadcast_to(np.array([POST.x, POST.y, 0.0]) / math.hypot(POST.x, POST.y), shape + (3,))
    t = POST.pierce(q, r)
    assert t.shape == shape
    np.testing.assert_allclose(t, math.hypot(POST.x, POST.y) - POST.radius, rtol=1e-12)


def test_rays_starting_inside_or_pointing_away_miss():
    assert np.isinf(POST.pierce(np.array([1.0, 12.0, 0.0]), np.array([1.0, 0.0, 0.0])))
    assert np.isinf(POST.pierce(np.array([0.0, 0.0, 2.0]), np.array([0.0, -1.0, 0.0])))
    assert np.isinf(POST.pierce(np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0])))   # vertical: a = 0


def test_surface_coordinates_and_normal():
    phi = np.array([0.0, 1.0, 3.0, 5.5])
    p = np.stack([POST.x + POST.radius * np.cos(phi), POST.y + POST.radius * np.sin(phi), np.full(4, 0.7)], -1)
    f, z = POST.surface_coordinates(p)
    np.testing.assert_allclose(f, phi, atol=1e-12)
    np.testing.assert_allclose(z, 0.7)
    np.testing.assert_allclose(POST.normal(p), np.stack([np.cos(phi), np.sin(phi), np.zeros(4)], -1), atol=1e-12)


@pytest.mark.parametrize("kwargs, word", [
    (dict(radius=0.0), "radius"), (dict(radius=50.0), "radius"), (dict(top=-1.0), "top"), (dict(top=1e4), "top"),
    (dict(depth=-1.0), "depth"), (dict(albedo=1.5), "albedo"), (dict(x=0.0, y=0.1), "eye inside"),
    (dict(x=float("nan")), "x"),
])
def test_bad_posts(kwargs, word):
    args = dict(x=1.0, y=12.0, radius=0.3, top=2.5, depth=3.0)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word):
        Post(**args)


def test_posts_in_a_scene_file():
    base = load_named_scene("carlas-island")
    text = base.to_toml() + "\n[[posts]]\nx = 1.0\ny = 12.0\nradius = 0.3\ntop = 2.5\ndepth = 3.0\n"
    scene = Scene.from_toml(text)
    assert scene.posts == (Post(1.0, 12.0, 0.3, 2.5, 3.0),)
    assert Scene.from_toml(scene.to_toml()) == scene
    with pytest.raises(SunsetError, match=r"posts\[0\]\.radius"):
        Scene.from_toml(text.replace("radius = 0.3", "radius = -0.3"))
    many = base.to_toml() + "".join(f"\n[[posts]]\nx = {k + 1.0}\ny = 12.0\nradius = 0.1\ntop = 1.0\ndepth = 1.0\n"
                                    for k in range(17))
    with pytest.raises(SunsetError, match="at most 16"):
        Scene.from_toml(many)
