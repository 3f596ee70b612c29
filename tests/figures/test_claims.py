"""Tests for sunset.figures.claims: the paper's figure claims, measured.

References are independent: Stokes' series' heights and curvatures in
closed form (sums of n² a_n with signs); the still-water reflection of the
sun against the mirror law (same azimuth, depression = elevation) and the
lean of the sun's path from P(θ); the reflected rays pointing down against
R_z = D_z − 2(D·N)N_z written out; Figure 5 against Figure 6 from the rule
that only twice-reflected rays can change.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset import Scene
from sunset.recorder.colour_tables import glitter_weights
from sunset.errors import SunsetError
from sunset.figures import claims
from sunset.figures.paper import AFTERNOON_HOURS, SUNSET_HOURS
from sunset.pipeline.frame import code_frame, render
from sunset.model.stokes import stokes_coefficients

SCENE = Scene.default()


# --------------------------------------------------------------------------- Figure 2
@pytest.mark.parametrize("alpha", [0.05, 0.2, 0.3, 0.4])
def test_stokes_shape_against_closed_forms(alpha):
    a = stokes_coefficients(alpha, 4)
    n = np.arange(1, 5)
    sh = claims.stokes_shape(alpha)
    assert sh.crest_height == pytest.approx(a.sum(), rel=1e-6)
    assert sh.trough_depth == pytest.approx(-(a * (-1.0) ** n).sum(), rel=1e-6)
    assert sh.crest_curvature == pytest.approx((n**2 * a).sum(), rel=1e-4)
    assert sh.trough_curvature == pytest.approx(abs((n**2 * a * (-1.0) ** n).sum()), rel=1e-4)


def test_stokes_shape_sharp_crests_wide_troughs():
    small, big = claims.stokes_shape(1e-3), claims.stokes_shape(0.3)
    assert small.crest_fraction == pytest.approx(0.5, abs=1e-3)      # a cosine
    assert small.crest_curvature == pytest.approx(small.trough_curvature, rel=1e-2)
    assert big.crest_fraction < 0.47 and big.crest_curvature > 3 * big.trough_curvature
    with pytest.raises(SunsetError, match="alpha"):
        claims.stokes_shape(float("nan"))


# --------------------------------------------------------------------------- Figure 4
def _window_scene():
    """Still water, a small window around the sun's reflection (fast)."""
    cam = replace(SCENE.camera, width=180, height=90, s_min=-0.14, s_max=0.04, zy_min=-0.11, zy_max=-0.02)
    return replace(SCENE, camera=cam).still()


@pytest.fixture(scope="module")
def still():
    sc = _window_scene()
    return sc, code_frame(sc, 0.0, 1, 0)


def test_glitter_weights_track_full_at_the_sun_halo_part_way():
    sun = SCENE.sun
    for hours in (0.1, SUNSET_HOURS, 1.0, 2.5):
        w = glitter_weights(sun, hours)
        from sunset.tape.codes import CODE_MAP
        tr = w[CODE_MAP.track.start:CODE_MAP.track.stop]
        ha = w[CODE_MAP.halo.start:CODE_MAP.halo.stop]
        assert tr.max() == 1.0 and 0.0 < ha.max() <= 0.5
        others = np.ones(256, bool)
        others[CODE_MAP.track.start:CODE_MAP.halo.stop] = False
        assert not w[others].any()
    with pytest.raises(SunsetError, match="halo_radius"):
        glitter_weights(sun, 1.0, halo_radius=-1.0)


def test_track_and_halo_resolve_elevation_equally():
    """The root of the fix: halo codes as fine in elevation as track codes, lit over the same elevations."""
    from sunset.tape.codes import CODE_MAP
    assert CODE_MAP.track.size == CODE_MAP.halo.size
    sun = SCENE.sun
    w = glitter_weights(sun, SUNSET_HOURS)
    lit_track = np.flatnonzero(w[CODE_MAP.track.start:CODE_MAP.track.stop] > 0)
    lit_halo = np.flatnonzero(w[CODE_MAP.halo.start:CODE_MAP.halo.stop] > 0)
    np.testing.assert_array_equal(lit_track, lit_halo)


def test_still_reflection_is_one_oblong_patch_under_the_sun(still):
    sc, codes = still
    g = claims.glitter_map(sc, codes, SUNSET_HOURS)
    m = claims.still_reflection(sc, g, SUNSET_HOURS)
    assert m.pixels > 50
    # the mirror law: the image stands under the sun, as far below the horizon as the sun is above it
    assert m.centre_azimuth == pytest.approx(m.sun_azimuth, abs=0.3)
    assert m.centre_depression == pytest.approx(m.sun_elevation, abs=0.3)
    # oblong: wider than tall, and wider than the disk; one patch, not two streaks
    assert m.aspect > 1.0 and m.row_width > m.disk
    assert m.double_rows < 0.1
    # trapezoidal: its rows drift sideways with depth as the mirrored sun's path does
    assert m.lean == pytest.approx(m.lean_expected, abs=0.35)
    assert abs(m.lean_expected) > 0.5


def test_the_old_halo_reach_made_two_streaks(still):
    """The fault the fix removed: the halo lit 3δ of elevation, the track δ: two long side streaks."""
    sc, codes = still
    old = glitter_weights(sc.sun, SUNSET_HOURS, halo_radius=3 * sc.sun.delta)
    m_old = claims.still_reflection(sc, claims.glitter_map(sc, codes, SUNSET_HOURS, weights=old),
                                    SUNSET_HOURS)
    m_new = claims.still_reflection(sc, claims.glitter_map(sc, codes, SUNSET_HOURS), SUNSET_HOURS)
    assert m_old.double_rows > 0.3 > 0.1 > m_new.double_rows
    assert m_old.height > m_new.height


def test_still_reflection_bad_input(still):
    sc, codes = still
    with pytest.raises(SunsetError, match="shape"):
        claims.still_reflection(sc, np.zeros((3, 3)), 1.0)
    with pytest.raises(SunsetError, match="threshold"):
        claims.still_reflection(sc, np.zeros((90, 180)), 1.0, threshold=0.0)
    with pytest.raises(SunsetError, match="uint8"):
        claims.glitter_map(sc, codes.astype(int), 1.0)
    empty = claims.still_reflection(sc, np.zeros((90, 180)), 1.0)
    assert empty.pixels == 0 and empty.double_rows == 0.0


# --------------------------------------------------------------------------- Figures 5, 6, 7
@pytest.fixture(scope="module")
def modes():
    sc = SCENE.with_size(96, 96)
    return sc, claims.reflection_modes(sc, 0.0)


def test_rays_pointing_down_are_met_on_downslopes(modes):
    sc, m = modes
    f = render(sc, 0.0, 1)
    d, n = f.direction.astype(float), f.normal.astype(float)
    dn = np.einsum("ijk,ijk->ij", d, n)
    rz = d[..., 2] - 2 * dn * n[..., 2]
    np.testing.assert_array_equal(m.down, m.sea & (rz < 0))
    assert m.down.any() and m.down_on_downslopes == 1.0
    assert 0.0 < m.down_share < m.downslope_share < 1.0


def test_only_twice_reflected_rays_change_from_figure_5_to_6(modes):
    sc, m = modes
    assert not (m.changed & ~m.sea).any()
    assert m.changed.any() and m.changed_twice == 1.0
    assert 0.0 < m.twice_changed <= 1.0
    assert 0.0 < m.twice_share < 0.5
    f6 = render(sc, 0.0, 2)
    assert m.twice_share == pytest.approx(float(np.mean(f6.bounces[f6.surface == 0] == 2)))


def test_afternoon_glitter_round_trip():
    sc = SCENE.with_size(96, 96)
    f6 = render(sc, 0.0, 2)
    a = claims.afternoon_glitter(sc, f6, AFTERNOON_HOURS)
    el = np.degrees(np.arcsin(np.clip(f6.ray[..., 2], -1, 1)))
    to_sky = (f6.bounces > 0) & (f6.final_surface == -1)
    assert a.highest_reflection == pytest.approx(float(el[to_sky].max()), abs=1e-4)
    assert a.highest_single <= a.highest_reflection
    # at glitter_from_hours the sun stands exactly as high as the highest reflected ray
    e = math.degrees(math.asin(sc.sun.position(a.glitter_from_hours)[2]))
    assert e == pytest.approx(a.highest_reflection, abs=1e-6)
    assert a.has_glitter == (a.sun_elevation <= a.highest_reflection)
    assert 0.0 < a.steepest_face < 90.0 and a.face_needed == pytest.approx(a.sun_elevation / 2)
    low = claims.afternoon_glitter(sc, f6, 0.2)
    assert low.has_glitter
