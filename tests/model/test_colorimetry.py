"""colour-science's spectra and XYZ → sRGB without importing it: the same bits as colour-science itself."""

import subprocess
import sys

import numpy as np
import pytest

from sunset.model import colorimetry
from sunset.model.colorimetry import COLUMNS, SPECTRA, from_colour_science, spectra, xyz_to_srgb


def _numpy_is_libms() -> bool:
    """Whether NumPy's float64 exp and power are the C library's here (Python's math calls the C library's).

    Where NumPy dispatches them to its own AVX-512 kernels, their last bits differ from libm's, and so do
    colour-science's blackbody and Rayleigh columns, which the stored table holds as libm's gave them.
    """
    import math

    x = np.random.default_rng(3).uniform(-30.0, 30.0, 4096)
    y = np.random.default_rng(4).uniform(1e-3, 1e3, 4096)
    exp_same = np.array_equal(np.exp(x), [math.exp(v) for v in x])
    pow_same = np.array_equal(np.power(y, -4.05), [math.pow(v, -4.05) for v in y])
    return exp_same and pow_same


def _ulps(a, b) -> np.ndarray:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert np.all(np.sign(a) == np.sign(b))
    return np.abs(a.view(np.int64) - b.view(np.int64))


def test_stored_spectra_are_colour_sciences_bit_for_bit():
    """Bit for bit where NumPy's exp and power are libm's; within 4 ulp where they are NumPy's AVX-512 kernels."""
    ref = from_colour_science()
    assert list(SPECTRA) == list(ref) == list(COLUMNS)
    exact = _numpy_is_libms()
    for name in COLUMNS:
        if exact or name not in ("blackbody", "rayleigh"):
            assert np.array(SPECTRA[name]).tobytes() == np.array(ref[name]).tobytes(), name
        else:
            assert np.max(_ulps(SPECTRA[name], ref[name])) <= 4, name
    assert np.array_equal(spectra()["wavelengths"], np.arange(380.0, 781.0, 10.0))


def test_stored_spectra_follow_the_temperature():
    """The blackbody column is the one constant that is ours: another temperature gives another column."""
    assert from_colour_science(6000.0)["blackbody"] != SPECTRA["blackbody"]


def test_spectral_data_is_what_colour_science_gave():
    """sky.spectral_data from the stored table: the arrays the old code built from colour-science (kept here)."""
    import colour
    from colour.quality.datasets import SDS_TCS

    from sunset.constants import SUN_TEMPERATURE
    from sunset.model.sky import spectral_data

    shape = colour.SpectralShape(380, 780, 10)
    lam = np.asarray(shape.wavelengths, dtype=float)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape).values
    sun = colour.sd_blackbody(SUN_TEMPERATURE, shape).values
    checker = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    refl = {"hill": checker["foliage"].copy().align(shape).values,
            "cliff": checker["dark skin"].copy().align(shape).values,
            "beach": SDS_TCS["CIE 1995"]["TCS02"].copy().align(shape).values}
    tau_r = np.asarray(colour.phenomena.rayleigh_optical_depth(lam * 1e-7), dtype=float)
    sp = spectral_data()
    exact = _numpy_is_libms()       # else NumPy's AVX-512 exp and power: the last bits of two columns
    for got, want in [(sp.wavelengths, lam), (sp.cmfs, np.asarray(cmfs, dtype=float)),
                      (sp.sun, np.asarray(sun, dtype=float) / float(np.mean(sun))), (sp.tau[0], tau_r)] + \
            [(sp.reflectance[k], np.clip(np.asarray(v, dtype=float), 0.0, 1.0)) for k, v in refl.items()]:
        assert got.dtype == want.dtype and got.shape == want.shape
        if exact:
            assert got.tobytes() == want.tobytes()
        else:
            assert np.max(_ulps(got, want)) <= 4
    assert sp.cmfs.flags.c_contiguous              # matrix products see the layout colour-science's array had


@pytest.mark.parametrize("shape", [(3,), (5, 3), (2, 4, 3), (256, 3)])
@pytest.mark.parametrize("white", [(0.3127, 0.3290), (0.45, 0.41), (0.33, 0.35), "film"])
def test_xyz_to_srgb_is_colour_sciences_bit_for_bit(shape, white):
    import colour

    from sunset.model.eye import film_white

    white = film_white() if white == "film" else white
    xyz = np.random.default_rng(len(shape)).random(shape) * 2.0 - 0.2
    want = colour.XYZ_to_sRGB(xyz, illuminant=white, chromatic_adaptation_transform="CAT02", apply_cctf_encoding=False)
    got = xyz_to_srgb(xyz, white)
    assert got.shape == want.shape and got.tobytes() == want.tobytes()


def test_the_package_transforms_are_colour_sciences():
    import colour

    from sunset.light.tone import xyz_to_rgb_matrix
    from sunset.model.eye import film_white, xyz_to_linear_srgb

    def reference(xyz):
        return colour.XYZ_to_sRGB(xyz, illuminant=film_white(), chromatic_adaptation_transform="CAT02",
                                  apply_cctf_encoding=False)

    xyz = np.random.default_rng(3).random((7, 3))
    assert xyz_to_linear_srgb(xyz).tobytes() == reference(xyz).tobytes()
    assert xyz_to_rgb_matrix().tobytes() == np.asarray(reference(np.eye(3)), dtype=float).tobytes()
    assert np.array(colorimetry.XYZ_TO_SRGB).tobytes() == colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB.tobytes()
    assert np.array(colorimetry.CAT02).tobytes() == colour.adaptation.CAT_CAT02.tobytes()
    assert np.array(colorimetry.D65).tobytes() == colour.RGB_COLOURSPACES["sRGB"].whitepoint.tobytes()


def colour_modules_after(code: str) -> list[str]:
    """The colour-science modules loaded in a fresh Python once it has run ``code``."""
    code += "\nimport sys\nprint(*sorted(m for m in sys.modules if m == 'colour' or m.startswith('colour.')))\n"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return out.stdout.split()


def test_the_sky_the_tables_and_the_light_do_not_import_colour_science():
    code = ("from sunset.model.scene import Scene\n"
            "from sunset.recorder.colour_tables import tables\n"
            "from sunset.light.lighting import Lighting\n"
            "from sunset.light.tone import xyz_to_rgb_matrix\n"
            "s = Scene.default()\n"
            "tables(s.sun, 0.35); xyz_to_rgb_matrix(); Lighting.for_scene(s, 0.35)\n")
    assert colour_modules_after(code) == []


def test_the_printed_table_reads_back_as_the_table():
    namespace = {}
    exec(colorimetry._literal(SPECTRA), namespace)
    assert namespace["SPECTRA"] == SPECTRA


def _colour_pairs(n=4000, seed=5):
    """sRGB colours (n, 3) in [0, 1] and a second set: random, plus greys (C* = 0) and hues across 0°/360°."""
    rng = np.random.default_rng(seed)
    a = rng.integers(0, 256, (n, 3)) / 255.0
    b = np.clip(a + rng.integers(-40, 41, (n, 3)) / 255.0, 0.0, 1.0)
    grey = np.repeat(np.linspace(0.0, 1.0, 21)[:, None], 3, axis=1)
    a[:21], b[:21] = grey, grey[::-1]
    a[21:42], b[21:42] = grey, np.array([1.0, 0.0, 0.05])                  # grey against a red
    a[42:60], b[42:60] = np.array([1.0, 0.0, 0.08]), np.array([1.0, 0.05, 0.0])   # reds either side of a* axis
    return a, b


def test_srgb_lab_and_ciede2000_are_colour_sciences_bit_for_bit():
    import colour

    from sunset.model.colorimetry import delta_e_2000, srgb_to_xyz, xyz_to_lab

    d65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    a, b = _colour_pairs()
    for rgb in (a, b, a.reshape(40, 100, 3), a[0]):
        want_xyz = colour.sRGB_to_XYZ(rgb)
        assert srgb_to_xyz(rgb).tobytes() == want_xyz.tobytes()
        assert xyz_to_lab(want_xyz).tobytes() == colour.XYZ_to_Lab(want_xyz, d65).tobytes()
    lab_a, lab_b = (colour.XYZ_to_Lab(colour.sRGB_to_XYZ(x), d65) for x in (a, b))
    want = colour.delta_E(lab_a, lab_b, method="CIE 2000")
    got = delta_e_2000(lab_a, lab_b)
    assert got.shape == want.shape and got.tobytes() == want.tobytes()
    assert np.all(np.isfinite(got)) and np.all(got[:21][10:11] == 0.0)          # the same grey: no difference


def test_the_quantisation_test_does_not_import_colour_science():
    code = ("import numpy as np\n"
            "from sunset.light.palette import quantisation_test\n"
            "rng = np.random.default_rng(1)\n"
            "quantisation_test(rng.random((20, 30, 3)), rng.integers(0, 256, (20, 30)))\n")
    assert colour_modules_after(code) == []
