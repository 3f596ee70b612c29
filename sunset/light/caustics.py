"""Caustics by wavefront tracing: the sunlight as a mesh of beams, each spread over the polygon where it lands.

Watt's backward beam tracing {cite}`watt1990` and Nishita and Nakamae's
accumulation of refracted beams {cite}`nishita1994` draw caustics without
noise by following the light as a *mesh* rather than as points. This module
is that tracer, for any receiver: the post (:mod:`sunset.light.ripples`) and
an island's shore (:mod:`sunset.light.shore`) say where their water patch
is and where a ray lands on them; the mesh, the beams, their flux and its
books are here.

The mesh
--------
The patch is a parameter square (a, b) ∈ [0, 1]² that the receiver maps to
horizontal water points (x, y), with the area element J (m² per unit of
a b). A regular grid of n_a × n_b cells puts a sun ray at every vertex (the
water there: :func:`sunset.light.sunrays.sun_points`), and every cell is two
triangles: the beams. Each vertex carries the sunlight's flux per unit
parameter area, ωJ (ω the flux per horizontal area, relative to E), and what
becomes of its light: a *status*, either dark (in a crest's shadow, under the
post, on dry land: the receiver names them) or lit, and then where its
reflected and its refracted ray go (onto the receiver, past it, back into the
water, ...), with the texture coordinates of the two rays' landing points and
the refracted ray's attenuation e^(−c s) on its way.

A beam whose three vertices share a status carries the flux of its triangle,
area × the mean of its vertices' ωJ, into that status's account: R of it
reflected, 1 − R refracted (the means of the products), and where its rays
land on the receiver the beam's triangle there receives that flux spread
evenly over its area (:func:`sunset.light.raster.rasterise`): irradiance is
the flux over the landing triangle's area, the Jacobian of the ray map. Where
the map folds, the landing triangles shrink to lines and the irradiance grows
without bound while the flux stays finite: the sharp edges of the caustics.

A beam whose vertices differ (it straddles a shadow's edge, the post's
silhouette, the edge of dry land) is cut: along each of its edges whose ends
differ, :data:`CUTS` halvings find where the status changes, and the beam is
split along the chord between the two crossings into the part of its odd
vertex (a triangle) and the rest (two triangles), each with its own status,
the crossings' data taken on their own side. Three different statuses in one
beam (where two such edges cross) share it in thirds.

The books
---------
``in`` is Σ ωJ × area over every beam and every part of a cut one: the
sunlight the patch's water receives if nothing shadowed it. Every part goes
to exactly one account, so the accounts add up to ``in`` to round-off (tests).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import require_int_range, require_range
from .raster import rasterise

__all__ = ["Nodes", "Books", "trace_beams", "trace_photons", "CUTS", "REFINE_TOLERANCE", "REFINE_LEVELS",
           "BLOCK_VERTICES"]

#: Halvings that find where a status changes along a beam's edge, beyond log₂ of the mesh's cells across: the
#: place to a quarter of the edge over the cells across, so that the cut's error falls as a cell's area does.
CUTS = 2
#: A beam that lands at a glance on the receiver (cosine of incidence under REFINE_COSINE at a corner, near
#: its silhouette, where the landing point moves as the square root of the distance to the silhouette) is
#: halved (into four) while the middle of one of its edges lands farther than REFINE_TOLERANCE texels and
#: REFINE_RELATIVE of the beam's landing size from the middle of the edge's landing points, at most
#: REFINE_LEVELS times.
REFINE_COSINE = 0.3
REFINE_TOLERANCE = 0.01
REFINE_RELATIVE = 0.0
REFINE_LEVELS = 0
#: The most halvings a caller may ask for.
MAX_REFINE = 6
#: The largest tolerance (texels) and glance (a cosine; above 1: every beam that lands) a caller may ask for.
MAX_TOLERANCE = 1.0e3
MAX_GLANCE = 2.0
#: Parts rasterised at once (the refracted light's (parts, 3, wavelengths) attenuations stay small).
CHUNK = 1 << 14
#: Vertices traced at once (the mesh is traced in blocks of rows: memory stays bounded).
BLOCK_VERTICES = 1 << 16
#: Status codes: dark codes are 1..9; a lit vertex is LIT + 10 × (reflected ray's code) + (refracted ray's code),
#: code 0 meaning "onto the receiver".
LIT = 100


@dataclass
class Nodes:
    """Traced points of the mesh: parameters ``a``, ``b`` (n,), ``status`` (n,), ``flux`` ωJ (n,), Fresnel's
    ``R`` (n,), the texture coordinates of the reflected (``ur``, ``vr``) and refracted (``ut``, ``vt``) rays'
    landing points (texels; NaN where they do not land), and the refracted ray's path ``path`` (n,) through the
    water to its landing point (metres; 0 where it does not land), and ``glance`` (n,) the least cosine of
    incidence on the receiver of the rays that land (1 where none does)."""

    a: np.ndarray
    b: np.ndarray
    status: np.ndarray
    flux: np.ndarray
    R: np.ndarray
    ur: np.ndarray
    vr: np.ndarray
    ut: np.ndarray
    vt: np.ndarray
    path: np.ndarray
    glance: np.ndarray

    def take(self, index) -> "Nodes":
        return Nodes(*(getattr(self, f)[index] for f in FIELDS))

    @staticmethod
    def join(parts) -> "Nodes":
        return Nodes(*(np.concatenate([getattr(p, f) for p in parts]) for f in FIELDS))


FIELDS = ("a", "b", "status", "flux", "R", "ur", "vr", "ut", "vt", "path", "glance")


@dataclass
class Books:
    """What a receiver's tracing gathered: its two textures' fluxes and every account (relative to E, m²)."""

    reflected: np.ndarray
    refracted: np.ndarray
    accounts: dict = field(default_factory=dict)

    def add(self, name: str, value: float) -> None:
        self.accounts[name] = self.accounts.get(name, 0.0) + float(value)


def _cut(receiver, n0: Nodes, n1: Nodes, halvings: int) -> tuple[np.ndarray, Nodes, Nodes]:
    """Where the status changes along the edges n0 → n1: the parameter (the bracket's middle) and the two
    sides' nodes (the one with n0's status, the other)."""
    lo_a, lo_b, hi_a, hi_b = n0.a.copy(), n0.b.copy(), n1.a.copy(), n1.b.copy()
    for _ in range(halvings):
        mid = receiver.evaluate(0.5 * (lo_a + hi_a), 0.5 * (lo_b + hi_b))
        same = mid.status == n0.status
        lo_a, lo_b = np.where(same, mid.a, lo_a), np.where(same, mid.b, lo_b)
        hi_a, hi_b = np.where(same, hi_a, mid.a), np.where(same, hi_b, mid.b)
    side0 = receiver.evaluate(lo_a, lo_b)
    side1 = receiver.evaluate(hi_a, hi_b)
    middle = np.stack([0.5 * (lo_a + hi_a), 0.5 * (lo_b + hi_b)], axis=-1)
    side0.a, side0.b = middle[:, 0].copy(), middle[:, 1].copy()
    side1.a, side1.b = middle[:, 0].copy(), middle[:, 1].copy()
    return middle, side0, side1


def _lands(status) -> np.ndarray:
    """Whether a status's light lands on the receiver (either ray)."""
    return (status >= LIT) & (((status - LIT) // 10 == 0) | ((status - LIT) % 10 == 0))


def _moved(nodes: Nodes, a, b) -> Nodes:
    """The same nodes' data at other parameters (for a part's area only)."""
    out = nodes.take(slice(None))
    out.a, out.b = np.asarray(a, float), np.asarray(b, float)
    return out


def _thirds(nodes: Nodes, beams: np.ndarray, base: int):
    """Each beam (T, 3) shared in thirds, one to each vertex's status: the vertex's third is the quadrilateral
    (vertex, middle of one edge, centroid, middle of the other), as two parts whose corners all carry the
    vertex's data (so it lands as a point)."""
    extra, parts, status = [], [], []
    ca, cb = nodes.a[beams].mean(axis=1), nodes.b[beams].mean(axis=1)
    m = len(beams)
    for k in range(3):
        v, v1, v2 = beams[:, k], beams[:, (k + 1) % 3], beams[:, (k + 2) % 3]
        p = nodes.take(v)
        for other in (v1, v2):
            mid = _moved(p, 0.5 * (nodes.a[v] + nodes.a[other]), 0.5 * (nodes.b[v] + nodes.b[other]))
            extra += [mid, _moved(p, ca, cb)]
            parts.append(np.stack([v, base + np.arange(m), base + m + np.arange(m)], axis=1))
            status.append(nodes.status[v])
            base += 2 * m
    return extra, parts, status, base


def _split(receiver, nodes: Nodes, tri: np.ndarray, halvings: int):
    """The beams ``tri`` (T, 3) of ``nodes`` as parts of one status each: (nodes, parts (P, 3), status (P,))."""
    st = nodes.status[tri]
    same = (st[:, 0] == st[:, 1]) & (st[:, 1] == st[:, 2])
    parts, status = [tri[same]], [st[same, 0]]
    if np.all(same):
        return nodes, parts[0], status[0]
    mixed, s = tri[~same], st[~same]
    two = (s[:, 0] == s[:, 1]) | (s[:, 1] == s[:, 2]) | (s[:, 0] == s[:, 2])
    two &= np.any(_lands(s), axis=1)            # a beam none of whose light lands needs no cut: thirds
    extra, base = [], len(nodes.a)
    # two statuses: the odd vertex k and the others k1, k2; cut the edges k-k1 and k-k2
    pair, sp = mixed[two], s[two]
    k = np.where(sp[:, 1] == sp[:, 2], 0, np.where(sp[:, 0] == sp[:, 2], 1, 2))
    rows = np.arange(len(pair))
    vk, v1, v2 = pair[rows, k], pair[rows, (k + 1) % 3], pair[rows, (k + 2) % 3]
    _, c1k, c1o = _cut(receiver, nodes.take(vk), nodes.take(v1), halvings)
    _, c2k, c2o = _cut(receiver, nodes.take(vk), nodes.take(v2), halvings)
    # a cut that met a third status in between (a thin band where two boundaries nearly meet: the reflected
    # and the refracted ray's silhouettes): the far side's point is sought again from the far corner, and the
    # band goes with the far side
    for far, c in ((v1, c1o), (v2, c2o)):
        odd = np.flatnonzero(c.status != nodes.status[far])
        if odd.size:
            _, again, _ = _cut(receiver, nodes.take(far[odd]), c.take(odd), halvings)
            for f in FIELDS[2:]:
                getattr(c, f)[odd] = getattr(again, f)
    m = len(vk)
    extra += [c1k, c1o, c2k, c2o]
    i1k, i1o, i2k, i2o = (base + j * m + np.arange(m) for j in range(4))
    base += 4 * m
    parts += [np.stack([vk, i1k, i2k], axis=1), np.stack([i1o, v1, v2], axis=1), np.stack([i1o, v2, i2o], axis=1)]
    status += [nodes.status[vk], nodes.status[v1], nodes.status[v1]]
    more, p3, s3, base = _thirds(nodes, mixed[~two], base)
    nodes = Nodes.join([nodes] + extra + more)
    return nodes, np.concatenate(parts + p3), np.concatenate(status + s3)


def _refine(receiver, nodes: Nodes, parts: np.ndarray, status: np.ndarray, tolerance: float, levels: int,
            halvings: int, glance: float = REFINE_COSINE):
    """Halve (into four) the parts that land at a glance while their landing is not linear enough.

    A part is halved when one of its corners meets the receiver at a cosine under ``glance`` (REFINE_COSINE;
    above 1: every part that lands) and the middle
    of one of its edges lands farther from the middle of that edge's landing points than ``tolerance`` texels
    and than REFINE_RELATIVE of the part's landing size. A middle whose status is not the part's (the edge is a
    chord of a curved boundary: the silhouette) is replaced by the boundary's point on the way from the
    opposite corner to it (a cut), and the sliver between the chord and that point goes to the middle's status.
    """
    todo = _lands(status) & (nodes.glance[parts].min(axis=1) < glance)
    shapes = (receiver.shape_reflected[1], receiver.shape_refracted[1])
    for _ in range(levels):
        sel = np.flatnonzero(todo)
        if sel.size == 0:
            break
        P = parts[sel]
        e0, e1, opp = P, P[:, [1, 2, 0]], P[:, [2, 0, 1]]
        mid = receiver.evaluate((0.5 * (nodes.a[e0] + nodes.a[e1])).reshape(-1),
                                (0.5 * (nodes.b[e0] + nodes.b[e1])).reshape(-1))
        own = np.repeat(status[sel], 3)
        off = np.flatnonzero(mid.status != own)
        outer = None
        usable = np.ones(mid.a.size, bool)
        if off.size:
            o = nodes.take(opp.reshape(-1)[off])
            _, inner, outer = _cut(receiver, o, mid.take(off), halvings)
            # the boundary's point must lie nearer the edge than the middle of the way to the opposite corner
            far = np.hypot(inner.a - mid.a[off], inner.b - mid.b[off])
            usable[off] = far < 0.5 * np.hypot(o.a - mid.a[off], o.b - mid.b[off])
            for f in FIELDS:
                getattr(mid, f)[off] = getattr(inner, f)
        code_r, code_t = (status[sel] - LIT) // 10, (status[sel] - LIT) % 10
        dev, size = np.zeros(len(sel)), np.zeros(len(sel))
        for (un, vn), n_u, code in zip((("ur", "vr"), ("ut", "vt")), shapes, (code_r, code_t)):
            u0, v0 = getattr(nodes, un)[e0], getattr(nodes, vn)[e0]
            u1, v1 = getattr(nodes, un)[e1], getattr(nodes, vn)[e1]
            um, vm = getattr(mid, un).reshape(-1, 3), getattr(mid, vn).reshape(-1, 3)
            u1 = u1 - n_u * np.round((u1 - u0) / n_u)
            um = um - n_u * np.round((um - u0) / n_u)
            with np.errstate(invalid="ignore"):
                d = np.hypot(um - 0.5 * (u0 + u1), vm - 0.5 * (v0 + v1)).max(axis=1)
                ext = np.hypot(u1 - u0, v1 - v0).max(axis=1)
            dev = np.where(code == 0, np.fmax(dev, d), dev)
            size = np.where(code == 0, np.fmax(size, ext), size)
        split = usable.reshape(-1, 3).all(axis=1) & (dev > np.maximum(tolerance, REFINE_RELATIVE * size))
        todo[sel[~split]] = False
        if not np.any(split):
            break
        k = np.flatnonzero(split)
        base = len(nodes.a)
        take = (k[:, None] * 3 + np.arange(3)[None, :]).reshape(-1)
        extra = [mid.take(take)]
        m01, m12, m20 = (base + 3 * np.arange(len(k)) + j for j in range(3))
        a, b, c = P[k, 0], P[k, 1], P[k, 2]
        new_parts = [np.stack(x, axis=1) for x in ((m01, b, m12), (m20, m12, c), (m01, m12, m20))]
        new_status = [status[sel[k]]] * 3
        new_todo = [np.ones(len(k), bool)] * 3
        # slivers: (edge's ends, the boundary's point) with the far side's data at all three corners
        if outer is not None:
            pos = np.full(mid.a.size, -1)
            pos[off] = np.arange(off.size)
            slot = pos[take].reshape(-1, 3)                      # (split parts, 3 edges): index into outer or -1
            for edge, (x0, x1, mm) in enumerate(((a, b, m01), (b, c, m12), (c, a, m20))):
                has = slot[:, edge] >= 0
                if not np.any(has):
                    continue
                far = outer.take(slot[has, edge])
                n = int(has.sum())
                start = base + 3 * len(k) + sum(len(e.a) for e in extra[1:])
                extra += [_moved(far, nodes.a[x0[has]], nodes.b[x0[has]]), _moved(far, mid.a[take][mm[has] - base],
                          mid.b[take][mm[has] - base]), _moved(far, nodes.a[x1[has]], nodes.b[x1[has]])]
                new_parts.append(np.stack([start + np.arange(n), start + n + np.arange(n), start + 2 * n
                                           + np.arange(n)], axis=1))
                new_status.append(far.status)
                new_todo.append(np.zeros(n, bool))
        nodes = Nodes.join([nodes] + extra)
        parts[sel[k]] = np.stack([a, m01, m20], axis=1)
        parts = np.concatenate([parts] + new_parts)
        status = np.concatenate([status] + new_status)
        todo = np.concatenate([todo] + new_todo)
        todo &= nodes.glance[parts].min(axis=1) < glance
    return nodes, parts, status


def _books_of_parts(receiver, nodes: Nodes, parts: np.ndarray, status: np.ndarray, books: Books) -> None:
    """Book each part's flux and rasterise the parts that land on the receiver."""
    pa, pb = nodes.a[parts], nodes.b[parts]
    area = 0.5 * np.abs((pa[:, 1] - pa[:, 0]) * (pb[:, 2] - pb[:, 0]) - (pa[:, 2] - pa[:, 0]) * (pb[:, 1] - pb[:, 0]))
    w = nodes.flux[parts]                                    # (P, 3)
    r = nodes.R[parts]
    wr = w * r
    flux = area * (w[:, 0] + w[:, 1] + w[:, 2]) / 3.0
    refl = area * (wr[:, 0] + wr[:, 1] + wr[:, 2]) / 3.0
    trans = flux - refl
    # every status's flux at once: its light, its reflected and its refracted share
    codes, which = np.unique(status, return_inverse=True)
    by = [np.bincount(which, weights=x, minlength=len(codes)) for x in (flux, refl, trans)]
    books.add("in", by[0].sum())
    lit = status >= LIT
    for code, f_all, f_r, f_t in zip(codes, *by):
        if code < LIT:
            books.add(receiver.dark_names[int(code)], f_all)
            continue
        code_r, code_t = divmod(int(code) - LIT, 10)
        if code_r:
            books.add(receiver.reflected_names[code_r], f_r)
        if code_t:
            books.add(receiver.refracted_names[code_t], f_t)
    code_r = (status - LIT) // 10
    code_t = (status - LIT) % 10
    # reflected onto the receiver
    on = lit & (code_r == 0)
    if np.any(on):
        u, v = _unwrapped(nodes.ur[parts[on]], receiver.shape_reflected[1]), nodes.vr[parts[on]]
        tex, kept = rasterise(u, v, refl[on][:, None], receiver.shape_reflected[1], receiver.shape_reflected[0])
        books.reflected += tex[..., 0]
        books.add(receiver.reflected_names[0], np.sum(refl[on] * kept))
        books.add(receiver.reflected_clipped, np.sum(refl[on] * (1.0 - kept)))
    on = np.flatnonzero(lit & (code_t == 0))
    for k in range(0, on.size, CHUNK):
        sel = on[k:k + CHUNK]
        u, v = _unwrapped(nodes.ut[parts[sel]], receiver.shape_refracted[1]), nodes.vt[parts[sel]]
        att = np.exp(-nodes.path[parts[sel]][..., None] * receiver.attenuation)          # (P, 3, C)
        light = area[sel][:, None] * ((w[sel] * (1.0 - r[sel]))[..., None] * att).mean(axis=1)   # (P, C)
        tex, kept = rasterise(u, v, light, receiver.shape_refracted[1], receiver.shape_refracted[0])
        books.refracted += tex
        gathered = light.mean(axis=1)
        books.add(receiver.refracted_names[0], np.sum(gathered * kept))
        books.add("absorbed on the way", np.sum((trans[sel] - gathered) * kept))
        books.add(receiver.refracted_clipped, np.sum(trans[sel] * (1.0 - kept)))


def _unwrapped(u, n: int) -> np.ndarray:
    """Texture u of each part's vertices (P, 3) moved by whole turns next to its first vertex."""
    return u - n * np.round((u - u[:, :1]) / n)


def trace_beams(receiver, n_a: int, n_b: int, tolerance: float = REFINE_TOLERANCE,
                levels: int = REFINE_LEVELS, glance: float = REFINE_COSINE) -> Books:
    """Trace the mesh of n_a × n_b cells over ``receiver``'s patch, a block of rows at a time (module docstring).

    ``receiver`` gives ``evaluate(a, b) -> Nodes``, ``dark_names`` {code: account}, ``reflected_names`` and
    ``refracted_names`` {code: account} (code 0: onto the receiver), ``reflected_clipped`` and
    ``refracted_clipped`` (the accounts of light that lands beyond the texture's rows), ``shape_reflected``
    (n_v, n_u), ``shape_refracted`` (n_v, n_u, C) and ``attenuation`` (C,) the water's c(λ), m⁻¹.
    ``levels`` halvings of the beams that land at a cosine of incidence under ``glance`` (above 1: of every beam
    that lands) while they land farther than ``tolerance`` texels from straight (:func:`_refine`). An argument
    out of range (cells under 1; ``levels`` outside 0..MAX_REFINE; ``tolerance`` not in (0, MAX_TOLERANCE];
    ``glance`` not in [0, MAX_GLANCE]) is one :class:`~sunset.errors.SunsetError` naming it.
    """
    require_int_range("n_a", n_a, 1)
    require_int_range("n_b", n_b, 1)
    require_int_range("levels", levels, 0, MAX_REFINE)
    require_range("tolerance", tolerance, 0.0, MAX_TOLERANCE, "texels", lo_open=True)
    require_range("glance", glance, 0.0, MAX_GLANCE)
    books = Books(np.zeros(receiver.shape_reflected), np.zeros(receiver.shape_refracted))
    rows = max(1, BLOCK_VERTICES // (n_b + 1))
    halvings = CUTS + int(np.ceil(np.log2(max(n_a, n_b))))
    b = np.arange(n_b + 1) / n_b
    for i0 in range(0, n_a, rows):
        i1 = min(n_a, i0 + rows)
        a = np.arange(i0, i1 + 1) / n_a
        aa, bb = np.meshgrid(a, b, indexing="ij")
        nodes = receiver.evaluate(aa.reshape(-1), bb.reshape(-1))
        m = n_b + 1
        v00 = (np.arange(i1 - i0)[:, None] * m + np.arange(n_b)[None, :]).reshape(-1)
        v10, v01, v11 = v00 + m, v00 + 1, v00 + m + 1
        tri = np.concatenate([np.stack([v00, v10, v11], axis=1), np.stack([v00, v11, v01], axis=1)])
        nodes, parts, status = _split(receiver, nodes, tri, halvings)
        nodes, parts, status = _refine(receiver, nodes, parts, status, tolerance, levels, halvings, glance)
        _books_of_parts(receiver, nodes, parts, status, books)
    return books


def trace_photons(receiver, rays: int, seed: int, splat) -> Books:
    """The photon estimate of the same light: ``rays`` random points of the patch (a jittered √N × √N grid,
    drawn a block at a time: the memory stays bounded for 10⁸ of them), each carrying ωJ/N, landing as points;
    ``splat(u, v, flux, shape)`` turns the landing points into a texture (a histogram, or a kernel estimate).
    The same books as :func:`trace_beams`."""
    books = Books(np.zeros(receiver.shape_reflected), np.zeros(receiver.shape_refracted))
    m = int(np.ceil(np.sqrt(rays)))
    # the jitter of a and of b from two streams, drawn a block at a time (the same numbers for any block size)
    rng_a, rng_b = (np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(2))
    for i0 in range(0, rays, BLOCK_VERTICES):
        k = np.arange(i0, min(rays, i0 + BLOCK_VERTICES))
        a = np.minimum((k // m + rng_a.random(k.size)) / m, 1.0)
        b = np.minimum((k % m + rng_b.random(k.size)) / m, 1.0)
        nodes = receiver.evaluate(a, b)
        w = nodes.flux / rays
        status = nodes.status
        books.add("in", np.sum(w))
        for code, name in receiver.dark_names.items():
            books.add(name, np.sum(w[status == code]))
        lit = status >= LIT
        code_r, code_t = (status - LIT) // 10, (status - LIT) % 10
        refl, trans = w * nodes.R, w * (1.0 - nodes.R)
        for code, name in receiver.reflected_names.items():
            if code:
                books.add(name, np.sum(refl[lit & (code_r == code)]))
        for code, name in receiver.refracted_names.items():
            if code:
                books.add(name, np.sum(trans[lit & (code_t == code)]))
        on = lit & (code_r == 0)
        nv, nu = receiver.shape_reflected
        inside = on & (nodes.vr >= 0) & (nodes.vr <= nv)
        books.reflected += splat(nodes.ur[inside], nodes.vr[inside], refl[inside][:, None], (nv, nu))[..., 0]
        books.add(receiver.reflected_names[0], np.sum(refl[inside]))
        books.add(receiver.reflected_clipped, np.sum(refl[on & ~inside]))
        on = lit & (code_t == 0)
        nv, nu, _ = receiver.shape_refracted
        inside = on & (nodes.vt >= 0) & (nodes.vt <= nv)
        flux = trans[inside][:, None] * np.exp(-nodes.path[inside][:, None] * receiver.attenuation)
        books.refracted += splat(nodes.ut[inside], nodes.vt[inside], flux, (nv, nu))
        books.add(receiver.refracted_names[0], np.sum(flux.mean(axis=1)))
        books.add("absorbed on the way", np.sum(trans[inside] - flux.mean(axis=1)))
        books.add(receiver.refracted_clipped, np.sum(trans[on & ~inside]))
    return books
