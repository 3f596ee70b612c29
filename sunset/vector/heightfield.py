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

Islands are sampled on the same scan lines (:mod:`sunset.vector.island_samples`);
each surface gives a yp for every pixel, and the nearest (largest u) wins: the
per-scan-line depth buffer, assembled into the frame by
:mod:`sunset.vector.direct`.

Speed. The functions here are the NumPy reference, written to be read.
:func:`sea_scan` has a Numba twin (:mod:`sunset.vector.heightfield_numba`,
chosen by :mod:`sunset.kernels`) that runs the scan conversion, the far tail
and the depth buffer as one compiled loop per scan line, and
:func:`sea_columns` (the profile, then the scan) one that computes each scan
line's profile, cosines included, and scan-converts it at once. The two
paths agree within the tolerances of chapter 10.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..constants import (
    NEAR_PLANE_FRACTION, SEA,
)
from ..errors import SunsetError
from ..kernels import twin

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
    y_near = (1.0 / (n * du)) if n else math.inf
    return Sampling(du=du, n=n, y_near=y_near, y_far=1.0 / du, y_clip=y_clip)


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


#: What the trains' kernels say of a wind sea (its kernels are sunset.vector.windsea_scan's and windsea_crests').
WIND_REFUSED = ("sea: a wind sea has no trains for this kernel: its strip kernels are sunset.vector.windsea_scan's "
                "and windsea_crests' (sunset.pipeline.frame.sea_stage picks them)")


def _sea_terms(sea, s, t):
    """Per train: (ℓ, m, b = ℓ s + m per scan line, c = φ − ω t mod 2π, harmonic amplitudes).

    A wind sea has no trains: it is refused (:data:`WIND_REFUSED`), not drawn flat.
    """
    if sea.wind is not None:
        raise SunsetError(WIND_REFUSED)
    out = []
    for train in sea.trains:
        if train.amplitude <= 0:
            continue
        l, m = train.wave_vector
        c = math.remainder(train.phase - train.omega * t, 2.0 * math.pi)
        out.append((l, m, (l * s + m).astype(_F32), _F32(c), train.harmonic_amplitudes()))
    return out


def _profile_arrays(s, u):
    """The profile's inputs as float64 arrays, y = 1/u in float32, and the profile (C, N) float32, zeros."""
    s = np.asarray(s, dtype=np.float64)
    u = np.asarray(u, dtype=np.float64)
    return s, u, (1.0 / u).astype(_F32), np.zeros((s.size, u.size), dtype=_F32)


@twin("sunset.vector.heightfield_numba")
def sea_profile(sea, s, u, h: float, t: float = 0.0):
    """g(y_i) = (ζ-height of the sea at (s·y_i, y_i)) for scan lines s, samples u.

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
    s, u, y, elev = _profile_arrays(s, u)
    if u.size == 0:
        return elev
    theta = np.empty_like(elev)
    poly = np.empty_like(elev)
    const = 0.0
    for _l, _m, b, c, amps in _sea_terms(sea, s, t):
        # θ = b_j y + c_j on every (scan line, sample), then cos θ in place
        np.multiply(b[:, None], y[None, :], out=theta)
        theta += c
        np.cos(theta, out=theta)
        # Σ_n a_n cos nθ = Σ_k p_k cos^k θ (Chebyshev): Horner's rule for the
        # terms k ≥ 1; the constants p_0 of every train are added once, below
        p = _chebyshev_power(amps)
        np.multiply(theta, _F32(p[-1]), out=poly)
        for pk in p[-2:0:-1]:
            poly += _F32(pk)
            poly *= theta
        elev += poly
        const += p[0]
    elev += _F32(const - h)
    elev *= u.astype(_F32)[None, :]
    return elev


def _chebyshev_power(amps) -> np.ndarray:
    """p_0 … p_N with Σ_n a_n T_n(x) = Σ_j p_j x^j (T_n the Chebyshev polynomials, cos nθ = T_n(cos θ)); read-only.

    Kept for the last few amplitude lists (by their bytes): every strip of every frame asks for the same.
    """
    return _chebyshev_power_of(np.asarray(amps, dtype=float).tobytes())


@functools.lru_cache(maxsize=64)
def _chebyshev_power_of(amps: bytes) -> np.ndarray:
    p = np.polynomial.chebyshev.cheb2poly(np.concatenate([[0.0], np.frombuffer(amps, dtype=float)]))
    p.flags.writeable = False
    return p


@twin("sunset.vector.slopes_numba")
def sea_gradient_on_scanlines(sea, s, y, t: float = 0.0):
    """(∂f/∂x, ∂f/∂y) of the sea at (s·y, y), in the paper's b_j, c_j form.

    ∂f/∂x = −Σ_j ℓ_j Σ_n n a_jn sin n(b_j y + c_j), likewise ∂f/∂y with m_j
    (sin nθ = sin θ · U_(n−1)(cos θ)).

    Parameters
    ----------
    s, y : ndarray
        Same shape: the scan line of each point and its distance, metres.
    """
    s = np.asarray(s, dtype=_F32)
    y = np.asarray(y, dtype=_F32)
    fx = np.zeros(y.shape, dtype=_F32)
    fy = np.zeros(y.shape, dtype=_F32)
    for l, m, _b, c, amps in _sea_terms(sea, s[:0], t):
        # θ = b_j y + c_j with b_j = ℓ_j s + m_j
        theta = (s * _F32(l) + _F32(m)) * y + c
        cos_theta = np.cos(theta)
        # Σ_n n a_n sin nθ = sin θ · q(cos θ), q = p′ the derivative of Σ_n a_n T_n
        # (sin nθ = sin θ U_(n−1)(cos θ), n U_(n−1) = T_n′), by Horner's rule
        q = np.polynomial.polynomial.polyder(_chebyshev_power(amps))
        dq = np.full(y.shape, _F32(q[-1]))
        for qk in q[-2::-1]:
            dq *= cos_theta
            dq += _F32(qk)
        slope = np.sin(theta) * dq
        fx -= _F32(l) * slope
        fy -= _F32(m) * slope
    return fx, fy


# ---------------------------------------------------------------------------
# islands along scan lines


# ---------------------------------------------------------------------------
# the frame


@twin("sunset.vector.heightfield_numba")
def sea_scan(u, g, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """Scan-convert the sea's profile on C scan lines and merge it into their depth buffers.

    Parameters
    ----------
    u : ndarray (n,)
        The sea's lattice in u = 1/y, near to far.
    g : ndarray (C, n)
        The profile :func:`sea_profile` on it.
    zeta0, dzeta : float
        The bottom pixel centre's ζ and the pixel pitch.
    n_pixels : int
        Pixels on a scan line.
    best_u, best_surf : ndarray (C, n_pixels)
        The depth buffer (the islands' already), updated in place: 1/yp of
        the sea where it is hit and not farther than what is there (the sea
        wins ties).

    Returns
    -------
    int
        Pixels resolved by the far tail: between the farthest sample and the
        horizon the sea is the plane at the farthest sample's height.
    """
    zeta = zeta0 + dzeta * np.arange(n_pixels, dtype=np.float64)
    u_hit = scan_convert(u, g, zeta0, dzeta, n_pixels)
    tail = (u_hit == 0) & (zeta[None, :] < 0)
    tail_pixels = 0
    if tail.any():
        g_far = g[:, -1].astype(np.float64)[:, None]
        u_far = u[-1]
        u_tail = np.where(g_far < 0, zeta[None, :] * u_far / np.minimum(g_far, -1e-30), 0.0)
        u_hit = np.where(tail, np.clip(u_tail, 0.0, u_far), u_hit)
        tail_pixels = int(tail.sum())
    sea_hit = (u_hit > 0) & (u_hit >= best_u)
    best_u[sea_hit] = u_hit[sea_hit]
    best_surf[sea_hit] = SEA
    return tail_pixels


@twin("sunset.vector.heightfield_numba")
def sea_columns(sea, s, u, h: float, t: float, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """The sea on C scan lines: :func:`sea_profile`, then :func:`sea_scan` into the depth buffer.

    Parameters and the result as those two functions'. The compiled twin
    computes each scan line's profile and scan-converts it at once, with no
    (C, n) array.
    """
    return sea_scan(u, sea_profile(sea, s, u, h, t), zeta0, dzeta, n_pixels, best_u, best_surf)
