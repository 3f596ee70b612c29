"""Posts in the vector stage (sunset/vector/posts.py): direct rays, still-water reflections, codes."""

from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import POST, SEA
from sunset.model.posts import Post
from sunset.model.scene import load_named_scene
from sunset.model.waves import Sea
from sunset.pipeline.frame import encode, render
from sunset.tape.codes import CODE_MAP
from sunset.vector.posts import post_box

from ..agree import assert_codes_agree

POSTS = (Post(x=-1.5, y=14.0, radius=0.25, top=2.5, depth=3.0), Post(x=2.2, y=22.0, radius=0.3, top=3.5, depth=3.0))


@pytest.fixture(scope="module")
def scene():
    return replace(load_named_scene("carlas-island").with_size(72, 64), posts=POSTS)


def eye_rays(scene):
    cam = scene.camera
    s = cam.s_centres()[None, :] * np.ones((cam.height, 1))
    z = cam.zy_centres()[:, None] * np.ones((1, cam.width))
    d = np.stack([s, np.ones_like(s), z], -1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def test_direct_rays_meet_the_posts_where_nothing_is_nearer(scene):
    f = render(scene, 0.3, 2)
    plain = render(replace(scene, posts=()), 0.3, 2)
    d = eye_rays(scene)
    q = np.broadcast_to(np.array([0.0, 0.0, scene.camera.eye_height]), d.shape)
    t = np.minimum(POSTS[0].pierce(q, d), POSTS[1].pierce(q, d))
    want = t < plain.distance                 # nearer than the sea, island or sky (inf)
    np.testing.assert_array_equal(f.surface == POST, want)
    assert want.sum() > 20
    np.testing.assert_allclose(f.distance[want], t[want], rtol=1e-5)
    # the box holds every pixel a post covers
    for post in POSTS:
        rows, cols = post_box(post, scene.camera)
        hit = np.isfinite(post.pierce(q, d))
        inside = np.zeros_like(hit)
        inside[rows, cols] = True
        assert not (hit & ~inside).any()


def test_still_water_reflects_a_post_as_the_eye_mirrored_below_the_sea_sees_it(scene):
    still = replace(scene, sea=Sea(()), islands=())
    f = render(still, 0.0, 1)
    d = eye_rays(still)
    h = still.camera.eye_height
    mirror = d * np.array([1.0, 1.0, -1.0])                       # from the eye's mirror image at z = −h
    q = np.broadcast_to(np.array([0.0, 0.0, -h]), d.shape)
    t = np.minimum(POSTS[0].pierce(q, mirror), POSTS[1].pierce(q, mirror))
    sea = f.surface == SEA
    # the mirrored ray meets the post above the water (z > 0 in the mirror world is below it in ours)
    z_hit = q[..., 2] + t * mirror[..., 2]
    want = sea & np.isfinite(t) & (z_hit >= 0)
    got = sea & (f.final_surface == POST)
    assert want.sum() > 20
    assert np.mean(got[sea] == want[sea]) > 0.995


def test_posts_are_coded_as_wood_on_both_kernel_paths(scene):
    with kernels.use_compiled(False):
        ref = render(scene, 0.3, 2)
        a = encode(scene, ref)
    with kernels.use_compiled(True):
        f = render(scene, 0.3, 2)
        b = encode(scene, f)
    assert_codes_agree(scene, ref, f, a, b, 0, "posts")
    post = f.final_surface == POST
    assert post.any() and np.all(CODE_MAP.cliff.contains(b[post]))
