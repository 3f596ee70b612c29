"""Posts in the vector stage: direct and reflected rays meeting a vertical cylinder.

A post (:class:`~sunset.model.posts.Post`) is too thin and too steep for the
height-field scan line: its side is vertical. A ray meets it where the
quadratic of :meth:`~sunset.model.posts.Post.pierce` has its smaller root
ahead of the ray, between the post's foot and top. Direct rays are tested only
in the box of pixels the post can cover (its projection is bounded by the
projections of its top and foot circles); a post nearer than what the ray met
replaces it, like an island in the depth buffer. A sea pixel's reflected ray
that meets a post before any island ends on the post (its origin is the
pixel's first reflection point, as for the clouds).
"""

from __future__ import annotations

import numpy as np

from ..constants import POST, SEA
from .frame import Frame
from .pierce import pierce_islands

__all__ = ["post_box", "add_posts", "reflected_posts"]


def post_box(post, camera) -> tuple[slice, slice]:
    """Rows and columns of the pixels the post can cover (an empty box when it is behind the eye)."""
    h = camera.eye_height
    ang = np.linspace(0.0, 2.0 * np.pi, 33)
    x = post.x + post.radius * 1.0001 * np.cos(ang)
    y = post.y + post.radius * 1.0001 * np.sin(ang)
    if np.any(y <= 1e-6):
        y_min = 1e-6
    else:
        y_min = float(y.min())
    y = np.maximum(y, y_min)
    s = np.concatenate([x / y, x / y])
    z = np.concatenate([(post.top - h) / y, (-post.depth - h) / y])
    if post.y + post.radius <= 0:
        return slice(0, 0), slice(0, 0)
    ds, dz = camera.pixel_pitch
    c0 = max(0, int(np.floor((s.min() - camera.s_min) / ds)) - 1)
    c1 = min(camera.width, int(np.ceil((s.max() - camera.s_min) / ds)) + 2)
    r0 = max(0, int(np.floor((camera.zy_max - z.max()) / dz)) - 1)
    r1 = min(camera.height, int(np.ceil((camera.zy_max - z.min()) / dz)) + 2)
    return slice(r0, max(r0, r1)), slice(c0, max(c0, c1))


def add_posts(scene, frame: Frame) -> Frame:
    """Put the posts into a direct frame: a post nearer than what the direct ray met replaces it.

    Sets ``surface`` to :data:`~sunset.constants.POST`, ``part`` to the
    post's index from 1, and the point (eye at the origin), distance and unit
    normal of those pixels.
    """
    h = scene.camera.eye_height
    for j, post in enumerate(scene.posts, start=1):
        rows, cols = post_box(post, scene.camera)
        d = frame.direction[rows, cols].astype(np.float64)
        if d.size == 0:
            continue
        q = np.zeros(d.shape)
        q[..., 2] = h
        t = post.pierce(q, d)
        near = np.isfinite(t) & (t < frame.distance[rows, cols])
        if not near.any():
            continue
        hit = q[near] + t[near][:, None] * d[near]
        sub = (frame.surface[rows, cols], frame.part[rows, cols], frame.point[rows, cols],
               frame.distance[rows, cols], frame.normal[rows, cols])
        sub[0][near] = POST
        sub[1][near] = j
        sub[2][near] = hit - np.array([0.0, 0.0, h])
        sub[3][near] = t[near]
        sub[4][near] = post.normal(hit)
    return frame


def reflected_posts(scene, frame: Frame) -> Frame:
    """End the sea pixels' reflected rays on a post they meet before any island (or the sky)."""
    h = scene.camera.eye_height
    sea = frame.surface == SEA
    direct = frame.surface == POST
    frame.final_surface[direct] = POST
    frame.final_part[direct] = frame.part[direct]
    frame.final_normal[direct] = frame.normal[direct]
    if not sea.any():
        return frame
    q = frame.point[sea].astype(np.float64) + np.array([0.0, 0.0, h])
    r = frame.ray[sea].astype(np.float64)
    best = np.full(len(q), np.inf)
    which = np.zeros(len(q), np.int64)
    for j, post in enumerate(scene.posts, start=1):
        t = post.pierce(q, r)
        nearer = t < best
        best[nearer] = t[nearer]
        which[nearer] = j
    hit = np.isfinite(best)
    if scene.islands and hit.any():                 # an island in front of the post keeps the ray
        idx = np.nonzero(hit)[0]
        t_isl, _, _ = pierce_islands(scene.islands, h, q[idx] - np.array([0.0, 0.0, h]), r[idx])
        hit[idx[t_isl < best[idx]]] = False
    if not hit.any():
        return frame
    idx = tuple(a[hit] for a in np.nonzero(sea))
    p = q[hit] + best[hit][:, None] * r[hit]
    normals = np.empty((int(hit.sum()), 3))
    for j, post in enumerate(scene.posts, start=1):
        sel = which[hit] == j
        if sel.any():
            normals[sel] = post.normal(p[sel])
    frame.final_surface[idx] = POST
    frame.final_part[idx] = which[hit]
    frame.final_normal[idx] = normals
    if frame.cloud_depth is not None:
        frame.cloud_depth[idx] = np.nan
    return frame
