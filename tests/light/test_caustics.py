"""Caustics by wavefront tracing (sunset/light/caustics.py): where a single cosine wave's caustics fall on the
post against the analytic fold of the ray map, the error falling as the cell size squared, and the cut beams."""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset.light import caustics
from sunset.light.frontline import front_line as exact_front_line, locate_fold
from sunset.light.caustics import LIT, Nodes, trace_beams
from sunset.light.ripples import trace_ripples
from sunset.model.scene import load_named_scene
from sunset.model.waves import Sea, WaveTrain

HOURS = 2.5                                  # the sun 20° high: no crest shadows a wave of slope 7°
A, WAVELENGTH, PHASE = 0.02, 1.0, 0.3


@pytest.fixture(scope="module")
def cosine():
    """post-in-the-swell's post on a single cosine wave travelling towards the sun."""
    base = load_named_scene("post-in-the-swell")
    p = base.sun.position(HOURS)
    azimuth = math.degrees(math.atan2(p[1], p[0]))
    return replace(base, sea=Sea((WaveTrain(A, WAVELENGTH, direction=azimuth, phase=PHASE),)))


def front_line(scene, edges, phi, L):
    """:func:`sunset.light.frontline.front_line` for the ``cosine`` scene."""
    return exact_front_line(scene.posts[0], scene.sun.position(HOURS), A, WAVELENGTH, PHASE, edges, phi, L)


def _folds_read_off(column, z, folds):
    """Each fold's height as :func:`locate_fold` reads it off ``column`` about the brightest texel nearest it."""
    dz = z[1] - z[0]
    peaks = z[1:-1][(column[1:-1] > column[:-2]) & (column[1:-1] >= column[2:])]
    edges = np.r_[z - dz / 2, z[-1] + dz / 2]
    return np.array([locate_fold(column, edges, peaks[np.argmin(np.abs(peaks - f))]) for f in folds])


def test_a_fold_is_read_off_texel_means_to_a_hundredth_of_a_texel():
    """The locator against texels of a fold's light over a linear background, made here in closed form."""
    rng = np.random.default_rng(30)
    edges = np.linspace(0.0, 0.6, 25)
    dz = edges[1] - edges[0]
    for _ in range(40):
        fold, side = rng.uniform(0.2, 0.4), rng.choice([-1, 1])
        lo, hi = edges[:-1], edges[1:]
        d_lo, d_hi = np.maximum(side * (lo - fold), 0.0), np.maximum(side * (hi - fold), 0.0)
        light = side * 2 * (np.sqrt(d_hi) - np.sqrt(d_lo)) / dz          # |z − fold|^(−1/2) on the bright side
        column = rng.uniform(0.1, 1.0) + rng.uniform(-0.5, 0.5) * edges[:-1] + rng.uniform(0.01, 0.2) * light
        peak = int(np.argmax(column))
        assert abs(locate_fold(column, edges, 0.5 * (lo[peak] + hi[peak])) - fold) < 0.01 * dz


def test_a_cosine_waves_caustics_lie_on_the_post_where_the_ray_maps_folds_are(cosine):
    from sunset.light.postrays import PostReceiver

    tex = trace_ripples(cosine, 0, 0.0, HOURS, cell=0.02, texels=96)
    p = cosine.sun.position(HOURS)
    j = int(np.argmin(np.abs(np.angle(np.exp(1j * (tex.phi - math.atan2(p[1], p[0])))))))
    col, z, dz = tex.above[:, j], tex.z, tex.z[1] - tex.z[0]
    post = cosine.posts[0]
    L = PostReceiver(cosine, 0, 0.0, HOURS, 96).L
    want, folds, where = front_line(cosine, np.r_[z - dz / 2, z[-1] + dz / 2], tex.phi[j], L)
    # every isolated fold (none other within three texels, its water inside the patch), read off the texture
    # to a fraction of a texel: within a texel of the ray map's fold (measured: 0.25 at most), and the exact
    # texels read the same way within a sixth (the locator's own error)
    alone = (np.sort(np.abs(folds[:, None] - folds[None, :]), axis=1)[:, 1] > 3 * dz) & (where < L - WAVELENGTH)
    alone &= (folds > 0.05) & (folds < post.top - 0.05)
    off = np.abs(_folds_read_off(col, z, folds[alone]) - folds[alone]) / dz
    own = np.abs(_folds_read_off(want, z, folds[alone]) - folds[alone]) / dz
    assert alone.sum() > 12 and off.max() <= 1.0 and own.max() < 1 / 6
    # and the light between the folds to 6 % rms
    band = (z > 0.05) & (z < post.top - 0.05)
    assert np.sqrt(np.mean((col[band] / want[band] - 1) ** 2)) < 0.06


def test_the_error_falls_as_the_cell_size_squared(cosine):
    """Against the front line's exact light (:func:`front_line`): the rms error over the column facing the sun
    falls by about four for every halving of the beams (measured: orders 2.0 and 2.1 from 4 cm to 1 cm)."""
    from sunset.light.postrays import PostReceiver

    p = cosine.sun.position(HOURS)
    L = PostReceiver(cosine, 0, 0.0, HOURS, 48).L
    err = []
    for cell in (0.04, 0.02):
        tex = trace_ripples(cosine, 0, 0.0, HOURS, cell=cell, texels=48)
        j = int(np.argmin(np.abs(np.angle(np.exp(1j * (tex.phi - math.atan2(p[1], p[0])))))))
        z, dz = tex.z, tex.z[1] - tex.z[0]
        want, _, _ = front_line(cosine, np.r_[z - dz / 2, z[-1] + dz / 2], tex.phi[j], L)
        band = (z > 0.05) & (z < cosine.posts[0].top - 0.05)
        err.append(np.sqrt(np.mean((tex.above[band, j] - want[band]) ** 2)))
    assert math.log2(err[0] / err[1]) > 1.8


def test_away_from_the_silhouettes_and_the_far_water_the_swells_beams_converge_as_the_cell_size_squared():
    """The post in the swell, each mesh against the next finer one (no exact light to set them against), on the
    water within 4 m of the post and for light meeting it at a cosine of at least 0.3 (NearPost: the whole
    texture's order is under 2, chapter 13): the rms and the mean absolute difference of each texture fall by
    at least 4 from 2 cm and 1 cm to 1 cm and 5 mm (measured: orders 2.45 and 2.37 reflected, 2.45 and 2.74
    refracted)."""
    from sunset.bench.ripples import near_textures, self_orders
    from sunset.figures.future import RIPPLE_HOURS

    textures = near_textures(load_named_scene("post-in-the-swell"), RIPPLE_HOURS, (0.02, 0.01, 0.005))
    for which in (0, 1):
        orders = self_orders(textures, which)
        assert orders["L2_order"][0] >= 2.0 and orders["L1_order"][0] >= 2.0


class Strip:
    """A toy receiver: status 101 (the reflected ray lands) where a + b < 1, else 111; lands at (a, b) × 4."""

    dark_names = {1: "dark"}
    reflected_names = {0: "on", 1: "past"}
    refracted_names = {0: "under", 1: "deep"}
    reflected_clipped, refracted_clipped = "over", "below"
    shape_reflected, shape_refracted = (4, 4), (4, 4, 1)
    attenuation = np.zeros(1)

    def evaluate(self, a, b):
        a, b = np.asarray(a, float), np.asarray(b, float)
        on = a + b < 1.0
        n = len(a)
        return Nodes(a, b, np.where(on, LIT + 1, LIT + 11), np.ones(n), np.full(n, 0.25), np.where(on, 4 * a, np.nan),
                     np.where(on, 4 * b, np.nan), np.full(n, np.nan), np.full(n, np.nan), np.zeros(n), np.ones(n))


def test_a_beam_across_a_boundary_is_cut_where_the_status_changes():
    # cells whose diagonal does not follow the line a + b = 1: the light on is R times the triangle's area, 1/2,
    # but for the cuts' last bracket, which shrinks as fast as a cell's area
    for n in (3, 7, 10, 40):
        books = trace_beams(Strip(), n, n + 1)
        acc = books.accounts
        assert acc["in"] == pytest.approx(1.0, rel=1e-12)
        # the last bracket is 2^-CUTS of an edge over the cells across: at most that strip of every cut beam
        # along the line (of length √2) goes the wrong way
        assert acc["on"] + acc["over"] == pytest.approx(0.25 * 0.5, rel=2.0 ** -caustics.CUTS * 3 / n ** 2)
        assert books.reflected.sum() == pytest.approx(acc["on"], rel=1e-12)
        assert sum(v for k, v in acc.items() if k != "in") == pytest.approx(1.0, rel=1e-12)
    assert caustics.CUTS >= 2


@pytest.mark.parametrize("kwargs, word", [
    (dict(n_a=0), "n_a"), (dict(n_b=2.5), "n_b"), (dict(levels=-1), "levels"),
    (dict(levels=caustics.MAX_REFINE + 1), "levels"), (dict(levels=True), "levels"), (dict(tolerance=0.0), "tolerance"),
    (dict(tolerance=float("nan")), "tolerance"), (dict(tolerance=2e3), "tolerance"), (dict(glance=-0.1), "glance"),
    (dict(glance=float("inf")), "glance"), (dict(glance="all"), "glance"),
])
def test_trace_beams_names_an_argument_out_of_range(kwargs, word):
    from sunset.errors import SunsetError

    args = dict(n_a=4, n_b=4)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word) as info:
        trace_beams(Strip(), **args)
    assert "\n" not in str(info.value)
    trace_beams(Strip(), 4, 4, tolerance=caustics.MAX_TOLERANCE, levels=caustics.MAX_REFINE, glance=0.0)
