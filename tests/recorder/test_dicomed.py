"""The film recorder stage (sunset/recorder/dicomed.py): three passes and the sun's disk."""

import math

import numpy as np
import pytest

from sunset.model import eye
from sunset.model.camera import Camera
from sunset.tape.codes import CODE_MAP
from sunset.pipeline.frame import expose
from sunset.recorder.dicomed import sun_coverage
from sunset.recorder.colour_tables import sun_colour, tables
from sunset.errors import SunsetError
from sunset.io import png_bytes
from sunset.model.scene import Scene
from sunset.model.sun import Sun


SUN = Sun(azimuth=2.0, tilt=50.0, radius=0.75)


def sun_camera(sun, hours, half=0.05, size=64):
    """A camera whose window is centred on the sun's picture-plane position."""
    p = sun.position(hours)
    s, z = p[0] / p[1], p[2] / p[1]
    return Camera(width=size, height=size, s_min=s - half, s_max=s + half, zy_min=z - half, zy_max=z + half)


# --------------------------------------------------------------------------- the sun's disk
def test_sun_coverage_area_and_extent():
    hours = 0.5
    cam = sun_camera(SUN, hours, size=96)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    assert cov.min() >= 0 and cov.max() == 1
    ds, dz = cam.pixel_pitch
    p = SUN.position(hours)
    # gnomonic area of a small cap of radius δ seen at angle α off the axis: π tan²δ / cos³α
    cos_a = p[1]
    expect = math.pi * math.tan(SUN.delta) ** 2 / cos_a**3
    assert math.isclose(cov.sum() * ds * dz, expect, rel_tol=0.01)


def test_sun_coverage_is_monotone_towards_the_rim():
    hours = 0.5
    cam = sun_camera(SUN, hours, half=0.03, size=128)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((cam.height, cam.width))
    full[rows, cols] = cov
    r = cam.height // 2
    row = full[r]
    c = int(np.argmax(row))
    assert np.all(np.diff(row[c:]) <= 0) and np.all(np.diff(row[:c + 1]) >= 0)
    assert 0 < row.min() or row[0] == 0
    partial = (full > 0) & (full < 1)
    assert partial.any()                               # an anti-aliased rim


def test_sun_coverage_stops_at_the_horizon():
    hours = 0.0                                         # the sun's centre on the horizon
    cam = sun_camera(SUN, hours, size=80)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((cam.height, cam.width))
    full[rows, cols] = cov
    zc = cam.zy_centres()
    dz = cam.pixel_pitch[1]
    assert np.all(full[zc + dz / 2 <= 0] == 0)
    assert full[zc - dz / 2 >= 0].max() == 1
    # about half of the disk is left
    p = SUN.position(hours)
    half = 0.5 * math.pi * math.tan(SUN.delta) ** 2 / p[1] ** 3
    assert math.isclose(full.sum() * cam.pixel_pitch[0] * dz, half, rel_tol=0.03)


def test_sun_out_of_view_or_behind():
    cam = Camera(width=16, height=16)
    rows, cols, cov = sun_coverage(cam, SUN, 4.5)       # high in the sky, above the window
    assert cov.size == 0 or cov.max() == 0
    behind = Sun(azimuth=180.0, tilt=40.0, radius=0.75)
    assert sun_coverage(cam, behind, 0.5)[2].size == 0


def test_sun_disk_rule_in_expose():
    hours = 0.5
    cam = sun_camera(SUN, hours, size=64)
    scene = Scene(camera=cam, sun=SUN)
    sky_code = CODE_MAP.sky.start + 5
    hill_code = CODE_MAP.hill.start + 3
    codes = np.full((64, 64), sky_code, np.uint8)
    codes[32:, 32:] = hill_code                          # an island covering one quarter
    rgb = expose(scene, codes, hours)
    t = tables(SUN, hours)
    sun_byte = np.rint(255 * eye.srgb_encode(sun_colour(SUN, hours))).astype(int)
    # the pixel at the sun's centre (a sky pixel) is sun colour
    c = cam.to_pixel(*(SUN.position(hours)[[0, 2]] / SUN.position(hours)[1]))
    cx, cy = int(round(c[0])), int(round(c[1]))
    cy -= 2                                              # stay in the sky quarter
    assert np.array_equal(rgb[cy, cx - 3].astype(int), sun_byte)
    # far away: the table's sky colour; the island quarter: the hill entry, never the sun
    assert np.array_equal(rgb[0, 0], t[:, sky_code])
    assert np.all(rgb[32:, 32:] == t[:, hill_code])
    # rim pixels lie between the two colours
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((64, 64))
    full[rows, cols] = cov
    rim = (full > 0.2) & (full < 0.8) & (codes == sky_code)
    assert rim.any()
    lo = np.minimum(sun_byte, t[:, sky_code].astype(int))
    hi = np.maximum(sun_byte, t[:, sky_code].astype(int))
    assert np.all((rgb[rim] >= lo - 1) & (rgb[rim] <= hi + 1))
    assert not np.any(np.all(rgb[rim] == t[:, sky_code], axis=-1))


def test_expose_passes_and_determinism():
    scene = Scene(camera=Camera(width=40, height=30), sun=SUN)
    rng = np.random.default_rng(0)
    codes = rng.integers(0, 256, size=(30, 40), dtype=np.uint8)
    a = expose(scene, codes, 1.5)
    t = tables(SUN, 1.5)
    # with the sun out of this window, each pass is a pure table look-up
    for k in range(3):
        assert np.array_equal(a[..., k], t[k][codes])
    b = expose(scene, codes.copy(), 1.5)
    assert a.dtype == np.uint8 and a.shape == (30, 40, 3)
    assert png_bytes(a) == png_bytes(b)


def test_expose_rejects_bad_codes():
    scene = Scene(camera=Camera(width=8, height=6), sun=SUN)
    with pytest.raises(SunsetError, match="uint8"):
        expose(scene, np.zeros((6, 8), np.int32), 1.0)
    with pytest.raises(SunsetError, match="shape"):
        expose(scene, np.zeros((8, 6), np.uint8), 1.0)


def test_the_compiled_lookup_is_np_take():
    from sunset import kernels
    from sunset.recorder.dicomed import lookup

    rng = np.random.default_rng(31)
    lut = rng.integers(0, 256, (256, 3), dtype=np.uint8)
    codes = rng.integers(0, 256, (37, 53), dtype=np.uint8)
    for c in (codes, codes[::2, 3:], codes.T):         # strips, views and transposes of a tape's frame
        want = np.empty(c.shape + (3,), np.uint8)
        lookup.reference(lut, c, want)
        got = np.zeros_like(want)
        lookup.compiled()(lut, c, got)
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(want, lut[c])    # and the reference is the table read per pixel
    # a tape exposed on both paths (each with its own colour tables, which agree within a tolerance): the same
    # bytes every time on each path, and no pixel visibly different between them
    from sunset.light.palette import FIGURE_MAX_DE00, picture_agreement

    scene = Scene.default().with_size(64, 48)
    tape = rng.integers(0, 256, (48, 64), dtype=np.uint8)
    for hours in (0.0, 1.5):
        with kernels.use_compiled(False):
            want = expose(scene, tape, hours)
            assert expose(scene, tape, hours).tobytes() == want.tobytes()
        with kernels.use_compiled(True):
            got = expose(scene, tape, hours)
            assert expose(scene, tape, hours).tobytes() == got.tobytes()
        assert picture_agreement(got, want)["max_de00"] <= FIGURE_MAX_DE00
