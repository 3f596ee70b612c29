"""Direct rays by height fields along vertical scan lines (paper, "Hidden Surfaces for Height Fields").

The eye is at the origin looking along +y; the picture plane is y = 1. The
vertical scan line at s = x/y holds the projections of the plane x = s·y. A
surface z = f(x, y) seen along that scan line projects to

    g(y) = f(s·y, y) / y,

and the ray through the pixel centre at height ζ_k on the scan line meets the
surface where g first rises above ζ_k.

Samples. The paper samples the scan line at y_i = h/(iσ), i = 1, 2, …: on the
mean sea plane f = −h these project to g(y_i) = −iσ, evenly spaced by σ. Here
σ is measured in pixels (the paper's σ = 1/4: four projected samples per
pixel), so the samples are y_i = h/(iσΔζ) with Δζ the pixel pitch, or in
reciprocal distance u_i = 1/y_i = iσΔζ/h, evenly spaced in u. Sample i = 1 is
the farthest, a quarter pixel below the horizon; the nearest is the first
whose projection lies below the bottom pixel even on the highest crest
((h − d)/|ζ_min|, d the sea's largest elevation).

Scan conversion. The paper's lost FORTRAN loop (READING-NOTES.md) walks the
samples from near to far and the pixels from the bottom up together; the
first sample i whose g rises above pixel k's centre puts the crossing of the
ray with the surface between y_(i−1) and y_i, where it is interpolated.
:func:`scan_line_reference` is that loop, one scan line at a time.
:func:`scan_convert` is the same thing for all scan lines at once: the running
maximum of g (the visible profile) is non-decreasing, so the number of samples
whose running maximum is at most ζ_k is the index of the first sample above
pixel k, and those counts come from one histogram (``np.bincount``) of the
profile in pixel units and a cumulative sum, with no loop over pixels.

Interpolation is linear in u = 1/y (i.e. in the sample index), which is exact
on a plane z = const, the mean sea level included.

The far tail. Between the farthest sample (a quarter pixel below the horizon
at σ = 1/4) and the horizon itself the sea is taken as the horizontal plane
at the farthest sample's height; this only concerns pixel centres within σ
pixels of the horizon.

Islands (:mod:`sunset.islands`) are sampled on the same scan lines, only
between the ends of each scan line's chord through the island's bounding
ellipse, on the sea's lattice in u refined by an integer factor m so that the
island's own projected samples are about σ pixels apart as well (the island's
steep faces project much more sparsely than the sea: the paper's m = 1 is
kept as an option). Each surface gives a yp for every pixel, and the nearest
(largest u) wins: the per-scan-line depth buffer. An island's probe interval
that lies, with its allowance and a pixel to spare, below the island's own
profile nearer to the eye is hidden and is not refined (samples only where
they can be seen).

Speed. The functions here are the NumPy reference. When the compiled
kernels are on (:mod:`sunset.compiled`), :func:`trace_direct` runs the scan
conversion, the far tail and the depth buffer as one compiled loop per scan
line, keeps the islands' samples compressed, and assembles the frame in one
pass, with the same arithmetic: the frames are identical.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .constants import (
    ISLAND_MAX_REFINEMENT, ISLAND_PROBE_SAMPLES, ISLAND_SAMPLE_BUDGET, NEAR_PLANE_FRACTION, PART_NONE, SCANLINE_CHUNK_ELEMENTS, SEA, SKY,
)
from . import compiled
from .errors import require_finite
from .frame import Frame
from .waves import unit_normal

_F32 = np.float32


# ---------------------------------------------------------------------------
# sampling


@dataclass(frozen=True)
class Sampling:
    """Where the sea is sampled along every scan line.

    Attributes
    ----------
    du : float
        Spacing of the samples in u = 1/y: σΔζ/h, m⁻¹.
    n : int
        Number of sea samples per scan line, i = n (nearest) … 1 (farthest).
    y_near : float
        Distance of the nearest sea sample, metres.
    y_far : float
        Distance of the farthest sea sample, h/(σΔζ), metres.
    y_clip : float
        The near clipping plane for the islands, metres.
    """

    du: float
    n: int
    y_near: float
    y_far: float
    y_clip: float

    def u(self) -> np.ndarray:
        """u_i = iσΔζ/h for i = n … 1 (near to far), float64, shape (n,)."""
        return np.arange(self.n, 0, -1, dtype=np.float64) * self.du

    def y(self) -> np.ndarray:
        """y_i = h/(iσΔζ), near to far, metres, shape (n,)."""
        return 1.0 / self.u()


def sampling(camera, sea_max_elevation: float = 0.0) -> Sampling:
    """The sample lattice y_i = h/(iσΔζ) of a camera (σ in pixels).

    Parameters
    ----------
    camera : Camera
    sea_max_elevation : float
        d, metres: the nearest sample is at (h − d)/|ζ_0| (ζ_0 the bottom
        pixel centre), so that even a crest there projects below the bottom
        pixel, unless that is nearer than the near plane
        NEAR_PLANE_FRACTION·h/|ζ_0|.
    """
    h = camera.eye_height
    dz = camera.pixel_pitch[1]
    du = camera.sigma * dz / h
    zeta0 = camera.zy_min + 0.5 * dz
    reach = max(abs(camera.zy_min), abs(camera.zy_max), dz)
    y_clip = NEAR_PLANE_FRACTION * h / reach
    if zeta0 < 0:
        y_near = max(h - sea_max_elevation, NEAR_PLANE_FRACTION * h) / -zeta0
        n = int(math.ceil(1.0 / (y_near * du))) + 1
    else:  # no pixel sees the sea
        n = 0
    return Sampling(du=du, n=n, y_near=(1.0 / (n * du)) if n else math.inf, y_far=1.0 / du, y_clip=y_clip)


# ---------------------------------------------------------------------------
# the scan conversion


def scan_line_reference(y, g, zeta):
    """The paper's yp loop on one scan line, as a plain Python loop.

    Walks the samples i from near to far and the pixels k from the bottom
    up together: while g(y_i) rises above the centre ζ_k of pixel k, the ray
    through k has passed under the surface between y_(i−1) and y_i, so yp(k)
    is interpolated there and k advances (one sample may serve several
    pixels); otherwise i advances.

    Parameters
    ----------
    y : sequence of float
        Sample distances y_i, near to far, metres (all > 0).
    g : sequence of float
        Projected heights g(y_i) = f(s·y_i, y_i)/y_i.
    zeta : sequence of float
        Pixel-centre heights ζ_k on the picture plane, bottom to top
        (increasing).

    Returns
    -------
    ndarray
        yp(k), metres, shape (len(zeta),); +inf where no sample rises above
        pixel k (the ray passes over the whole sampled surface). Interpolation
        is linear in 1/y; a pixel already below the first sample gets y_0.
    """
    yp = np.full(len(zeta), np.inf)
    k = 0
    for i in range(len(y)):
        while k < len(zeta) and g[i] > zeta[k]:
            if i == 0:
                yp[k] = y[0]
            else:
                f = (zeta[k] - g[i - 1]) / (g[i] - g[i - 1])
                u = 1.0 / y[i - 1] + f * (1.0 / y[i] - 1.0 / y[i - 1])
                yp[k] = 1.0 / u
            k += 1
    return yp


def scan_convert(u, g, zeta0: float, dzeta: float, n_pixels: int):
    """The yp loop for many scan lines at once, vectorized.

    Parameters
    ----------
    u : ndarray (C, N) or (N,)
        Reciprocal sample distances 1/y_i, near to far (decreasing), m⁻¹.
    g : ndarray (C, N)
        Projected heights at the samples; −inf marks a missing sample (it
        never rises above a pixel). Samples after the last real one in a row
        must be −inf.
    zeta0, dzeta : float
        Centre of the bottom pixel and the pixel pitch: pixel k (counted from
        the bottom) has its centre at ζ_k = zeta0 + k·dzeta.
    n_pixels : int
        K, pixels per scan line.

    Returns
    -------
    u_hit : ndarray (C, K) float64
        1/yp for every pixel, bottom up; 0 where the ray passes over every
        sample.

    Notes
    -----
    The running maximum M_i of g along the samples is the visible profile;
    the first sample above pixel k is the first i with M_i > ζ_k, i.e. the
    number of samples with M_i <= ζ_k. In pixel units r_i = (M_i − ζ_0)/Δζ,
    M_i <= ζ_k exactly when ⌈r_i⌉ <= k, so a histogram of ⌈r_i⌉ per scan line
    and its cumulative sum give every pixel's index at once.
    """
    g = np.asarray(g)
    C, N = g.shape
    K = n_pixels
    if N == 0:
        return np.zeros((C, K))
    prof = np.maximum.accumulate(g, axis=1)
    r = prof - prof.dtype.type(zeta0)
    r *= prof.dtype.type(1.0 / dzeta)
    np.ceil(r, out=r)
    np.clip(r, 0, K, out=r)
    bins = r.astype(np.int32)
    del prof, r
    bins += (np.arange(C, dtype=np.int32) * (K + 1))[:, None]
    counts = np.bincount(bins.ravel(), minlength=C * (K + 1)).reshape(C, K + 1)
    del bins
    idx = np.cumsum(counts[:, :K], axis=1)  # first sample above pixel k
    hit = idx < N
    rows = (np.arange(C) * N)[:, None]
    # the indices rise along each scan line, so these gathers read memory in order
    flat1 = np.minimum(idx, N - 1) + rows
    flat0 = np.maximum(idx - 1, 0) + rows
    g_flat = g.reshape(-1)
    g0 = np.take(g_flat, flat0).astype(np.float64)
    g1 = np.take(g_flat, flat1).astype(np.float64)
    u = np.asarray(u)
    if u.ndim == 1:
        u0 = np.take(u, flat0 - rows)
        u1 = np.take(u, flat1 - rows)
    else:
        u_flat = np.broadcast_to(u, (C, N)).reshape(-1)
        u0 = np.take(u_flat, flat0)
        u1 = np.take(u_flat, flat1)
    u0 = u0.astype(np.float64, copy=False)
    u1 = u1.astype(np.float64, copy=False)
    zeta = zeta0 + dzeta * np.arange(K, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        den = g1 - g0
        f = np.where((idx > 0) & (den > 0), (zeta[None, :] - g0) / den, 0.0)
    np.clip(f, 0.0, 1.0, out=f)
    out = u0 + f * (u1 - u0)
    out[~hit] = 0.0
    return out


# ---------------------------------------------------------------------------
# the sea along scan lines: g(y) and the gradient in the paper's b_j, c_j form


def _sea_terms(sea, s, t):
    """Per train: (ℓ, m, b = ℓ s + m per scan line, c = φ − ω t mod 2π, harmonic amplitudes)."""
    out = []
    for train in sea.trains:
        if train.amplitude <= 0:
            continue
        l, m = train.wave_vector
        c = math.remainder(train.phase - train.omega * t, 2.0 * math.pi)
        out.append((l, m, (l * s + m).astype(_F32), _F32(c), train.harmonic_amplitudes()))
    return out


def sea_profile(sea, s, u, h: float, t: float = 0.0):
    """g(y_i) = (ζ-height of the sea at (s·y_i, y_i)) for scan lines s and samples u.

    The phase of train j on the scan line x = s·y is b_j y + c_j with
    b_j = ℓ_j s + m_j and c_j = φ_j − ω_j t (the paper's form), so one
    multiply–add per sample and train; Stokes harmonics come from cos θ by
    Chebyshev polynomials (the paper's suggested speed-up).

    Parameters
    ----------
    sea : Sea
    s : ndarray (C,)
        Scan lines.
    u : ndarray (N,)
        1/y_i, m⁻¹.
    h : float
        Eye height, metres.
    t : float
        Time, seconds.

    Returns
    -------
    ndarray (C, N) float32
        g = (elevation − h)·u.
    """
    s = np.asarray(s, dtype=np.float64)
    u = np.asarray(u, dtype=np.float64)
    y = (1.0 / u).astype(_F32)
    elev = np.zeros((s.size, u.size), dtype=_F32)
    if u.size == 0:
        return elev
    phase = np.empty_like(elev)
    acc = None
    const = 0.0
    for i, (_l, _m, b, c, amps) in enumerate(_sea_terms(sea, s, t)):
        np.multiply(b[:, None], y[None, :], out=phase)
        phase += c
        np.cos(phase, out=phase)
        # Σ_n a_n cos nθ = Σ_j p_j cos^j θ (Chebyshev), by Horner's rule in place; p_0 is added once at the end
        p = _chebyshev_power(amps)
        const += p[0]
        if i == 0:
            acc = elev
        elif acc is elev:
            acc = np.empty_like(elev)
        np.multiply(phase, _F32(p[-1]), out=acc)
        for pj in p[-2:0:-1]:
            acc += _F32(pj)
            acc *= phase
        if acc is not elev:
            elev += acc
    elev += _F32(const - h)
    elev *= u.astype(_F32)[None, :]
    return elev


def _chebyshev_power(amps) -> np.ndarray:
    """p_0 … p_N with Σ_n a_n T_n(x) = Σ_j p_j x^j (T_n the Chebyshev polynomials, cos nθ = T_n(cos θ))."""
    return np.polynomial.chebyshev.cheb2poly(np.concatenate([[0.0], np.asarray(amps, dtype=float)]))


def sea_gradient_on_scanlines(sea, s, y, t: float = 0.0):
    """(∂f/∂x, ∂f/∂y) of the sea at (s·y, y), in the paper's b_j, c_j form.

    ∂f/∂x = −Σ_j ℓ_j Σ_n n a_jn sin n(b_j y + c_j), likewise ∂f/∂y with m_j
    (sin nθ = sin θ · U_(n−1)(cos θ)).

    Parameters
    ----------
    s, y : ndarray
        Same shape: the scan line of each point and its distance, metres.
    """
    s = np.asarray(s, dtype=np.float64)
    y = np.asarray(y, dtype=_F32)
    fx = np.zeros(y.shape, dtype=_F32)
    fy = np.zeros(y.shape, dtype=_F32)
    th = np.empty(y.shape, dtype=_F32)
    tmp = np.empty(y.shape, dtype=_F32)
    s32 = s.astype(_F32)
    for l, m, _b, c, amps in _sea_terms(sea, s[:0], t):
        # b = ℓ s + m per point, in float32 like the rest (one pass less than widening s)
        np.multiply(s32, _F32(l), out=th)
        th += _F32(m)
        th *= y
        th += c
        sn = np.sin(th)
        # Σ_n n a_n sin nθ = sin θ · q(cos θ), q = p′ the derivative of Σ_n a_n T_n (sin nθ = sin θ U_(n−1), n U_(n−1) = T_n′)
        q = np.polynomial.polynomial.polyder(_chebyshev_power(amps))
        if len(q) > 1:
            cs = np.cos(th, out=th)
            np.multiply(cs, _F32(q[-1]), out=tmp)
            for qj in q[-2:0:-1]:
                tmp += _F32(qj)
                tmp *= cs
            tmp += _F32(q[0])
            sn *= tmp
            slope, scale = sn, 1.0
        else:
            slope, scale = sn, q[0]
        np.multiply(slope, _F32(l * scale), out=tmp)
        fx -= tmp
        np.multiply(slope, _F32(m * scale), out=tmp)
        fy -= tmp
    return fx, fy


# ---------------------------------------------------------------------------
# islands along scan lines


def _island_lattice(island, s, samp: Sampling, d: float, refine: int):
    """The u samples of one island on scan lines s: chord ends plus the refined lattice.

    Returns (u (C, n) float64 near to far, valid (C, n) bool) or None when no
    scan line meets the bounding ellipses in front of the near plane.
    """
    y0, y1 = island.chord(s, d)
    ok = np.isfinite(y0) & (y1 > samp.y_clip)
    if not ok.any():
        return None
    y0 = np.where(ok, np.maximum(y0, samp.y_clip), 1.0)
    y1 = np.where(ok, y1, 1.0)
    ua, ub = 1.0 / y0, 1.0 / y1
    du = samp.du / refine
    j_top = np.floor(ua / du - 1e-9).astype(np.int64)
    j_bot = np.ceil(ub / du + 1e-9).astype(np.int64)
    inner = np.where(ok, np.maximum(j_top - j_bot + 1, 0), 0)
    count = np.where(ok, inner + 2, 0)
    n = int(count.max())
    p = np.arange(n)[None, :]
    u = (j_top[:, None] - (p - 1)) * du
    u = np.where(p == 0, ua[:, None], u)
    last = (count - 1)[:, None]
    u = np.where(p == last, ub[:, None], u)
    valid = p < count[:, None]
    u = np.where(valid, u, ub[:, None])
    return u, valid


def _island_profile(island, s, u, valid, h: float):
    """g = (H − h)·u on the island's samples, −inf where not valid (float32).

    Only the valid samples are evaluated (:func:`_island_profile_flat`).
    """
    g = np.full(u.shape, -np.inf, dtype=_F32)
    rows = np.nonzero(valid)[0]
    g[valid] = _island_profile_flat(island, s[rows], u[valid], h)
    return g


def _island_profile_flat(island, s_rows, uu, h: float):
    """g = (H − h)·u at samples ``uu`` (1/y) on scan lines ``s_rows`` (same shape), float32."""
    y = (1.0 / uu).astype(_F32)
    x = (s_rows * y).astype(_F32)
    hgt = island.surface(x, y, with_gradient=False)[0]
    return (hgt.astype(_F32) - _F32(h)) * uu.astype(_F32)


def _probe_refinement(island, s, samp: Sampling, d: float) -> int | None:
    """Refinement m0 of the sea's lattice that puts ISLAND_PROBE_SAMPLES across the widest chord.

    None when no scan line meets the island's bounding ellipses.
    """
    y0, y1 = island.chord(s, d)
    ok = np.isfinite(y0) & (y1 > samp.y_clip)
    if not ok.any():
        return None
    width = (1.0 / np.maximum(y0[ok], samp.y_clip) - 1.0 / y1[ok]) / samp.du  # in sea samples
    m0 = int(math.ceil(ISLAND_PROBE_SAMPLES / max(float(width.max()), 1e-12)))
    return max(1, min(m0, ISLAND_MAX_REFINEMENT))


def _island_samples(island, s, samp: Sampling, d: float, h: float, m0: int, zeta0: float, dzeta: float,
                    K: int, sigma: float, budget: int):
    """Adaptive samples of one island on scan lines s, about σ pixels apart in projection.

    A probe on the sea's lattice refined by m0 gives each probe interval's
    projected step |Δr| in pixels (clipped to the picture, so that what
    projects above or below it costs nothing), plus the change of the step
    from its neighbours (a curvature allowance); each interval is then cut
    into ⌈(|Δr| + |Δ²r|)/σ⌉ equal parts in u. Columns are scaled down to at
    most ``budget`` samples.

    Returns
    -------
    (u, valid) : (ndarray (C, T) float64 near to far, ndarray (C, T) bool), or None.
        Row c holds its samples first, then zeros (``valid`` False).
    """
    flat = _island_samples_flat(island, s, samp, d, h, m0, zeta0, dzeta, K, sigma, budget)
    if flat is None:
        return None
    uf, count = flat
    T = int(count.max()) if count.size else 0
    valid = np.arange(T)[None, :] < count[:, None]
    u = np.zeros(valid.shape)
    u[valid] = uf
    return u, valid


def _island_samples_flat(island, s, samp: Sampling, d: float, h: float, m0: int, zeta0: float, dzeta: float,
                         K: int, sigma: float, budget: int):
    """:func:`_island_samples` as one flat array: (u (S,) float64, count (C,) int64), or None.

    The samples of scan line c are ``u[start[c] : start[c] + count[c]]``,
    near to far, with start the exclusive cumulative sum of ``count``.
    """
    lat = _island_lattice(island, s, samp, d, m0)
    if lat is None:
        return None
    up, vp = lat
    C, P = up.shape
    if P < 2:
        return up[vp], vp.sum(axis=1).astype(np.int64)
    gp = _island_profile(island, s, up, vp, h).astype(np.float64)
    with np.errstate(invalid="ignore"):
        r = np.clip((gp - zeta0) / dzeta, -1.0, K + 1.0)
    pair = vp[:, 1:] & vp[:, :-1]
    dr = np.where(pair, np.diff(r, axis=1), 0.0)
    d2 = np.zeros_like(dr)
    if dr.shape[1] > 1:
        dd = np.abs(np.diff(dr, axis=1))
        d2[:, :-1] = dd
        d2[:, 1:] = np.maximum(d2[:, 1:], dd)
    n = np.where(pair, np.maximum(1, np.ceil((np.abs(dr) + d2) / sigma)), 0).astype(np.int64)
    # samples only where they can be seen: an interval that stays, with its allowance and a pixel to
    # spare, below the profile's running maximum nearer to the eye is hidden behind the island itself
    reach = np.maximum(r[:, 1:], r[:, :-1]) + np.abs(dr) + d2 + 1.0
    nearer_top = np.maximum.accumulate(np.where(vp, r, -np.inf), axis=1)[:, :-1]
    n[pair & (reach < nearer_top)] = 1
    total = n.sum(axis=1)
    over = total > budget
    if over.any():
        scale = np.where(over, budget / np.maximum(total, 1), 1.0)
        n = np.where(pair, np.maximum(1, np.floor(n * scale[:, None])), 0).astype(np.int64)
        total = n.sum(axis=1)
    has = vp.any(axis=1)
    count = np.where(has, total + 1, 0).astype(np.int64)  # + the far end of the chord
    last_valid = vp.sum(axis=1) - 1
    if compiled.enabled():
        return compiled.expand_intervals(up, n, count, last_valid), count
    # the intervals' samples in row-major order (row c, interval j, part q)
    flat_n = n.ravel()
    pair_id = np.repeat(np.arange(flat_n.size), flat_n)
    start = np.cumsum(flat_n) - flat_n
    q = np.arange(pair_id.size) - start[pair_id]
    c, j = np.divmod(pair_id, P - 1)
    ua, ub = up[c, j], up[c, j + 1]
    u = ua + (ub - ua) * (q / n[c, j])
    # and each row's far end of the chord after its intervals
    rows = np.nonzero(has)[0]
    ends = np.cumsum(total)[rows]
    u = np.insert(u, ends, up[rows, last_valid[rows]])
    return u, count


# ---------------------------------------------------------------------------
# the frame


def trace_direct(scene, t: float = 0.0, *, refine_islands: bool = True, info: dict | None = None) -> Frame:
    """Trace the direct ray through every pixel centre: sea, islands or sky.

    Parameters
    ----------
    scene : Scene
    t : float
        Time, seconds.
    refine_islands : bool
        Sample the islands on a refined lattice so their projected samples
        are about σ pixels apart (default); False uses the sea's samples
        for the islands too, as the paper did.
    info : dict, optional
        Filled with counts: ``sea_samples`` (per scan line), ``island_samples``
        (total over scan lines and islands), ``probe`` (the refinement of
        the sea's lattice the islands' probes used), ``tail_pixels`` (pixels resolved by the far tail),
        and ``seconds``: wall-clock time spent on ``sea`` (profile and scan
        conversion), ``islands`` (sampling, profile, scan conversion, depth
        test) and ``assemble`` (points, distances, normals), for the benchmark.

    Returns
    -------
    Frame
        With the direct fields filled (direction, surface, part, distance,
        point, normal); rows top to bottom.
    """
    require_finite("t", t)
    t = float(t)
    cam = scene.camera
    H, W, h = cam.height, cam.width, cam.eye_height
    d = scene.sea.max_elevation
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    samp = sampling(cam, d)
    s_all = cam.s_centres()
    zeta = zeta0 + dz * np.arange(H, dtype=np.float64)  # bottom up
    u_sea_lattice = samp.u()

    best_u = np.zeros((W, H))                 # 1/yp of the nearest surface, 0: none
    best_surf = np.full((W, H), SKY, dtype=np.int8)
    stats = {"sea_samples": samp.n, "island_samples": 0, "probe": [], "tail_pixels": 0}
    seconds = {"sea": 0.0, "islands": 0.0, "assemble": 0.0}
    clock = time.perf_counter
    tick = clock()
    # the islands' probe refinements, once for all scan lines
    probes = [_probe_refinement(island, s_all, samp, d) for island in scene.islands]
    budget = ISLAND_SAMPLE_BUDGET * max(samp.n, H)
    stats["probe"] = probes
    tock = clock()
    seconds["islands"] += tock - tick
    tick = tock

    n_per = max(samp.n, 1)
    chunk = max(1, min(W, SCANLINE_CHUNK_ELEMENTS // n_per))
    for c0 in range(0, W, chunk):
        cols = slice(c0, min(W, c0 + chunk))
        s = s_all[cols]
        # the sea
        if samp.n and compiled.enabled():
            # the scan line, the far tail and the depth buffer in one compiled pass (the same arithmetic)
            g = sea_profile(scene.sea, s, u_sea_lattice, h, t)
            stats["tail_pixels"] += compiled.scan_merge(u_sea_lattice, g, np.full(len(s), samp.n), zeta0, dz, H,
                                                        best_u[cols], best_surf[cols], SEA,
                                                        tail_u_far=u_sea_lattice[-1])
            del g
        elif samp.n:
            g = sea_profile(scene.sea, s, u_sea_lattice, h, t)
            u_hit = scan_convert(u_sea_lattice, g, zeta0, dz, H)
            # the far tail: the plane at the farthest sample's height
            tail = (u_hit == 0) & (zeta[None, :] < 0)
            if tail.any():
                g_far = g[:, -1].astype(np.float64)[:, None]
                u_far = u_sea_lattice[-1]
                u_tail = np.where(g_far < 0, zeta[None, :] * u_far / np.minimum(g_far, -1e-30), 0.0)
                u_hit = np.where(tail, np.clip(u_tail, 0.0, u_far), u_hit)
                stats["tail_pixels"] += int(tail.sum())
            del g
            sea_hit = u_hit > 0
            best_u[cols][sea_hit] = u_hit[sea_hit]
            best_surf[cols][sea_hit] = SEA
        tock = clock()
        seconds["sea"] += tock - tick
        tick = tock
        # the islands: per-scan-line depth buffer, the nearest (largest u) wins
        for k, (island, m0) in enumerate(zip(scene.islands, probes), start=1):
            if m0 is None:
                continue
            if refine_islands and compiled.enabled():
                # the same samples, kept compressed: no padding to evaluate or scan
                lat = _island_samples_flat(island, s, samp, d, h, m0, zeta0, dz, H, cam.sigma, budget)
                if lat is None:
                    continue
                u, counts = lat
                g = _island_profile_flat(island, np.repeat(s, counts), u, h)
            else:
                if refine_islands:
                    lat = _island_samples(island, s, samp, d, h, m0, zeta0, dz, H, cam.sigma, budget)
                else:
                    lat = _island_lattice(island, s, samp, d, 1)
                if lat is None:
                    continue
                u, valid = lat
                counts = valid.sum(axis=1)
                g = _island_profile(island, s, u, valid, h)
            stats["island_samples"] += int(counts.sum())
            if compiled.enabled():
                compiled.scan_merge(u, g, counts, zeta0, dz, H, best_u[cols], best_surf[cols], k)
                continue
            u_hit = scan_convert(u, g, zeta0, dz, H)
            nearer = u_hit > best_u[cols]
            best_u[cols][nearer] = u_hit[nearer]
            best_surf[cols][nearer] = k
        tock = clock()
        seconds["islands"] += tock - tick
        tick = tock
    frame = _assemble(scene, t, best_u, best_surf, s_all, zeta)
    seconds["assemble"] = clock() - tick
    if info is not None:
        info.update(stats, seconds=seconds)
    return frame


def _assemble(scene, t, best_u, best_surf, s_all, zeta) -> Frame:
    """Hit points, distances, normals and parts from 1/yp and the winning surface.

    ``best_u`` and ``best_surf`` are (scan line, pixel from the bottom); the
    frame's arrays are (row from the top, column). The geometry is one pass
    of :func:`sunset.compiled.assemble` when the compiled kernels are on,
    else :func:`_assemble_geometry`; the normals come from the gradients on
    the compressed subsets of sea and island pixels.
    """
    cam = scene.camera
    W = cam.width
    n_isl = len(scene.islands)
    if compiled.enabled():
        surf, direction, point, distance, normal, hits = compiled.assemble(best_u, best_surf, s_all, zeta, SKY, SEA,
                                                                           n_isl)
    else:
        surf, y, direction, point, distance, normal = _assemble_geometry(best_u, best_surf, s_all, zeta)
        flat_surf = surf.reshape(-1)
        flat_y = y.reshape(-1)
        hits = []
        for k in range(n_isl + 1):
            idx = np.flatnonzero(flat_surf == SEA + k)
            hits.append((idx, s_all[idx % W], flat_y[idx]))
    part = np.full(surf.shape, PART_NONE, dtype=np.int8)
    # the sea: the gradient in the b_j, c_j form, on the sea pixels only
    idx, s_hit, y_hit = hits[0]
    if len(idx):
        fx, fy = sea_gradient_on_scanlines(scene.sea, s_hit, y_hit, t)
        if compiled.enabled():
            compiled.put_unit_normals(normal, idx, fx, fy)
        else:
            normal.reshape(-1, 3)[idx] = unit_normal(fx, fy)
    for k, island in enumerate(scene.islands, start=1):
        idx, s_hit, yk = hits[k]
        if not len(idx):
            continue
        _, prt, gx, gy = island.surface((s_hit * yk).astype(_F32), yk.astype(_F32))
        part.reshape(-1)[idx] = prt
        normal.reshape(-1, 3)[idx] = unit_normal(gx.astype(_F32), gy.astype(_F32))
    return Frame(t=t, reflections=0, direction=direction, surface=surf, part=part, distance=distance,
                 point=point, normal=normal)


def _assemble_geometry(best_u, best_surf, s_all, zeta):
    """The per-pixel geometry as whole-array operations (the reference for :func:`sunset.compiled.assemble`).

    Returns surf (H, W) int8, y (H, W) float64 (NaN for sky), direction and
    point (H, W, 3) float32, distance (H, W) float32 and normal (H, W, 3)
    float32, NaN everywhere (the sea's and the islands' are filled later).
    """
    surf = np.ascontiguousarray(best_surf[:, ::-1].T)
    u = np.ascontiguousarray(best_u[:, ::-1].T)
    H, W = surf.shape
    hit = surf != SKY
    with np.errstate(divide="ignore"):
        y = np.where(hit, 1.0 / u, np.nan)                 # (H, W)
    s = s_all[None, :]
    z = zeta[::-1][:, None]
    length = np.sqrt(1.0 + s * s + z * z)                  # |(s, 1, ζ)|
    inv = 1.0 / length
    direction = np.empty((H, W, 3), dtype=_F32)
    direction[..., 0] = s * inv
    direction[..., 1] = inv
    direction[..., 2] = z * inv
    point = np.empty((H, W, 3), dtype=_F32)
    point[..., 0] = s * y
    point[..., 1] = y
    point[..., 2] = z * y
    distance = np.where(hit, y * length, np.inf).astype(_F32)
    normal = np.full((H, W, 3), np.nan, dtype=_F32)
    return surf, y, direction, point, distance, normal


