"""Colour science at run time without importing colour-science.

The sky model (:mod:`sunset.model.sky`), the eye (:mod:`sunset.model.eye`) and
the RGB back end's tone curve (:mod:`sunset.light.tone`) take from
colour-science a few spectra on the 10 nm grid and one transform. Importing
colour-science costs some 0.4 s of CPU in every process that does (its six
hundred modules and datasets, and SciPy's ``interpolate``, ``optimize``,
``special`` and ``spatial``), and ``sunset figures`` runs two: this module
holds what they need, the same numbers, so that no run imports it.

* :data:`SPECTRA`, read by :func:`spectra`: colour-science's spectra at
  380, 390, …, 780 nm, stored as the exact floats it computes: the CIE 1931 2°
  colour-matching functions (``colour.MSDS_CMFS``, aligned to the grid), a
  blackbody at :data:`~sunset.constants.SUN_TEMPERATURE`
  (``colour.sd_blackbody``), the Rayleigh optical depth of air (Bodhaine et
  al. 1999, ``colour.phenomena.rayleigh_optical_depth``), and the reflectances
  of the ColorChecker's *foliage* and *dark skin* (N. Ohta) and of the CIE 1995
  test colour sample TCS02. :func:`from_colour_science` computes the table
  again with colour-science (``python -m sunset.model.colorimetry`` prints it,
  to paste here after a change of the grid, the temperature or the library);
  the tests compare every number, bit for bit where NumPy's float64 ``exp``
  and ``power`` are the C library's. On a CPU with AVX-512 NumPy takes its own
  vector kernels for them, and colour-science's blackbody and Rayleigh columns
  move by up to a few ulp (the tests allow 4); the stored table, computed
  where NumPy called the C library, is the same on every machine.
* :func:`xyz_to_srgb`: ``colour.XYZ_to_sRGB(xyz, illuminant=white,
  chromatic_adaptation_transform="CAT02", apply_cctf_encoding=False)``, the
  same operations in the same order (von Kries adaptation in the CAT02 space
  from ``white`` to D65, then IEC 61966-2-1's matrix as colour-science holds
  it), so the same bits: the tests compare them.
* :func:`srgb_to_xyz`, :func:`xyz_to_lab` and :func:`delta_e_2000`: colour-science's
  ``sRGB_to_XYZ``, ``XYZ_to_Lab`` (D65) and ``delta_E(..., method="CIE 2000")``
  (Sharma, Wu and Dalal 2005), for the 8-bit test (:mod:`sunset.light.palette`),
  written out after colour-science's code (BSD-3-Clause, Colour Developers), the
  same operations in the same order: the tests compare the bits.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["SPECTRA", "spectra", "from_colour_science", "xyz_to_srgb", "srgb_to_xyz", "xyz_to_lab", "delta_e_2000",
           "CAT02", "XYZ_TO_SRGB", "SRGB_TO_XYZ", "D65"]

#: The chromatic adaptation transform CAT02 (CIECAM02), as ``colour.adaptation.CAT_CAT02``.
CAT02 = ((0.7328, 0.4296, -0.1624), (-0.7036, 1.6975, 0.0061), (0.0030, 0.0136, 0.9834))
#: CIE XYZ → linear sRGB (IEC 61966-2-1), as ``colour.models.MATRIX_XYZ_TO_sRGB``.
XYZ_TO_SRGB = ((3.2406, -1.5372, -0.4986), (-0.9689, 1.8758, 0.0415), (0.0557, -0.2040, 1.0570))
#: Linear sRGB → CIE XYZ (IEC 61966-2-1), as ``colour.models.MATRIX_sRGB_TO_XYZ``.
SRGB_TO_XYZ = ((0.4124, 0.3576, 0.1805), (0.2126, 0.7152, 0.0722), (0.0193, 0.1192, 0.9505))
#: The CIE xy chromaticity of D65, sRGB's white (CIE 1931 2°), as colour-science holds it.
D65 = (0.3127, 0.3290)

#: The spectra's columns, in :data:`SPECTRA`'s order.
COLUMNS = ("wavelengths", "cmf_x", "cmf_y", "cmf_z", "blackbody", "rayleigh", "foliage", "dark_skin", "tcs02")

#: colour-science's spectra on the grid 380, 390, …, 780 nm, by column (:data:`COLUMNS`): the exact floats of
#: :func:`from_colour_science` (colour-science 0.4.7), printed by ``python -m sunset.model.colorimetry``.
SPECTRA = {
    "wavelengths": (
        380.0, 390.0, 400.0, 410.0, 420.0, 430.0, 440.0, 450.0, 460.0, 470.0, 480.0, 490.0, 500.0, 510.0, 520.0,
        530.0, 540.0, 550.0, 560.0, 570.0, 580.0, 590.0, 600.0, 610.0, 620.0, 630.0, 640.0, 650.0, 660.0, 670.0,
        680.0, 690.0, 700.0, 710.0, 720.0, 730.0, 740.0, 750.0, 760.0, 770.0, 780.0,
    ),
    "cmf_x": (
        0.0013680000000000003, 0.0042429999999999985, 0.014309999999999996, 0.04351, 0.13437999999999994,
        0.28390000000000004, 0.34828000000000003, 0.33619999999999994, 0.29079999999999995, 0.19536,
        0.09563999999999995, 0.03201, 0.004900000000000001, 0.009300000000000004, 0.06327000000000002,
        0.1655000000000001, 0.29040000000000005, 0.4334499000000001, 0.5945000000000001, 0.7621000000000001,
        0.9162999999999999, 1.0262999999999998, 1.0622000000000005, 1.0026, 0.8544499000000004, 0.6424000000000003,
        0.44789999999999996, 0.28349999999999986, 0.16489999999999996, 0.08739999999999995, 0.04677,
        0.022699999999999998, 0.011359159999999998, 0.005790345999999999, 0.0028993269999999997,
        0.0014399709999999993, 0.0006900786, 0.00033230110000000016, 0.00016615050000000003, 8.307526999999999e-05,
        4.150994000000001e-05,
    ),
    "cmf_y": (
        3.899999999999999e-05, 0.00012000000000000002, 0.00039599999999999976, 0.0012099999999999997, 0.004,
        0.011599999999999997, 0.023000000000000007, 0.038, 0.060000000000000026, 0.09097999999999999, 0.13902,
        0.20802000000000007, 0.323, 0.503, 0.7100000000000003, 0.8620000000000001, 0.9540000000000005,
        0.9949501000000002, 0.9949999999999996, 0.9520000000000003, 0.87, 0.7569999999999996, 0.631, 0.503, 0.381,
        0.265, 0.17499999999999993, 0.10699999999999994, 0.06099999999999998, 0.032, 0.017000000000000005,
        0.008209999999999995, 0.004101999999999999, 0.002091, 0.0010470000000000002, 0.00052,
        0.00024919999999999993, 0.00012000000000000006, 6e-05, 2.9999999999999994e-05, 1.499e-05,
    ),
    "cmf_z": (
        0.0064500009999999995, 0.020050010000000007, 0.06785001000000002, 0.20740000000000003, 0.6455999999999998,
        1.3856, 1.7470600000000005, 1.7721100000000007, 1.6691999999999996, 1.28764, 0.8129501000000003,
        0.4651800000000001, 0.2720000000000002, 0.1582, 0.07824999, 0.04216, 0.02029999999999999,
        0.008749998999999994, 0.003900000000000001, 0.0021000000000000003, 0.001650000999999999, 0.0011,
        0.0008000000000000001, 0.00033999999999999997, 0.0001900000000000001, 4.9999989999999995e-05,
        2.0000000000000012e-05, 2.117582368135751e-22, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0,
    ),
    "blackbody": (
        21463.62194917955, 22304.058570168752, 23059.921652976172, 23731.319947126278, 24319.39785413499,
        24826.15241679892, 25254.2655513794, 25606.953147566735, 25887.831589545967, 26100.801475567234,
        26249.94777652138, 26339.45532540237, 26373.53832552674, 26356.382469535638, 26292.09824387318,
        26184.684031034656, 26037.997696043934, 25855.73544034726, 25641.416815152064, 25398.374899605118,
        25129.75076173103, 24838.491428118847, 24527.35068963203, 24198.892163587687, 23855.494117276645,
        23499.35563325179, 23132.503763722358, 22756.8013801026, 22373.955474862993, 21985.525716976306,
        21592.933100124937, 21197.468555117783, 20800.301425303714, 20402.48772677603, 20004.978134397195,
        19608.625650646012, 19214.192927458513, 18822.359222002113, 18433.726976051956, 18048.828015639414,
        17668.129373190368,
    ),
    "rayleigh": (
        0.44656861746354287, 0.4006451636179054, 0.3605233742277473, 0.3253386299964517, 0.2943741258395343,
        0.267032468214038, 0.2428133118193115, 0.22129563193046095, 0.20212358175197118, 0.1849951419532813,
        0.169652959412174, 0.15587691320833796, 0.14347805151588797, 0.13229362269893774, 0.12218298443273466,
        0.11302422097631226, 0.10471133434252225, 0.09715190272282592, 0.0902651210070582, 0.08398015507919225,
        0.07823475482372402, 0.0729740812619079, 0.06814971157392892, 0.06371879242732562, 0.05964331736450146,
        0.055889508314688016, 0.05242728476805121, 0.049229806980806916, 0.046273081881328545, 0.043535622231832306,
        0.04099815114470826, 0.03864334532944525, 0.03645561149569003, 0.03442089120976474, 0.032526490229251685,
        0.03076092894250968, 0.029113811045853567, 0.027575708015371212, 0.026138057285930605, 0.024793072349900303,
        0.02353366324194936,
    ),
    "foliage": (
        0.048, 0.04900000000000001, 0.05000000000000002, 0.049000000000000016, 0.05, 0.052, 0.054000000000000006,
        0.05800000000000004, 0.060999999999999985, 0.06400000000000002, 0.067, 0.07, 0.07800000000000003,
        0.10600000000000001, 0.15499999999999994, 0.18100000000000002, 0.1769999999999999, 0.15699999999999997,
        0.137, 0.12599999999999992, 0.12199999999999994, 0.11500000000000005, 0.10399999999999998,
        0.09799999999999999, 0.09800000000000003, 0.10000000000000003, 0.09699999999999996, 0.09499999999999997,
        0.095, 0.10100000000000002, 0.12500000000000003, 0.17399999999999993, 0.24699999999999997,
        0.31100000000000005, 0.34299999999999997, 0.3579999999999999, 0.36399999999999993, 0.36200000000000004,
        0.36800000000000005, 0.3549999999999998, 0.341,
    ),
    "dark_skin": (
        0.04799999999999997, 0.05500000000000002, 0.06499999999999997, 0.06800000000000003, 0.064,
        0.05899999999999997, 0.05500000000000002, 0.05300000000000002, 0.052000000000000005, 0.052000000000000005,
        0.054000000000000006, 0.057000000000000016, 0.06099999999999998, 0.06499999999999997, 0.07000000000000002,
        0.074, 0.07599999999999997, 0.07899999999999999, 0.087, 0.10000000000000002, 0.11499999999999994,
        0.12899999999999998, 0.13799999999999998, 0.14599999999999994, 0.15399999999999991, 0.16299999999999995,
        0.17300000000000004, 0.18800000000000006, 0.20400000000000004, 0.22200000000000011, 0.24200000000000005,
        0.2610000000000001, 0.282, 0.30500000000000005, 0.334, 0.3720000000000001, 0.40900000000000003,
        0.43599999999999994, 0.462, 0.448, 0.4209999999999999,
    ),
    "tcs02": (
        0.07, 0.08899999999999995, 0.11099999999999997, 0.11799999999999998, 0.12100000000000002, 0.122,
        0.12300000000000003, 0.12700000000000006, 0.131, 0.13799999999999987, 0.14999999999999994,
        0.17400000000000004, 0.20699999999999996, 0.24200000000000008, 0.26, 0.26699999999999996,
        0.27200000000000013, 0.282, 0.2990000000000001, 0.32200000000000006, 0.33499999999999996,
        0.34100000000000014, 0.342, 0.3419999999999999, 0.3410000000000003, 0.339, 0.338, 0.33600000000000024,
        0.33399999999999985, 0.3319999999999999, 0.33100000000000007, 0.3289999999999999, 0.32800000000000007,
        0.3259999999999999, 0.3240000000000002, 0.324, 0.32199999999999995, 0.32, 0.316, 0.315, 0.3139999999999999,
    ),
}


@functools.lru_cache(maxsize=None)
def spectra() -> dict:
    """:data:`SPECTRA` as read-only float64 arrays (41,), by column name (``wavelengths`` in nm)."""
    out = {}
    for name, values in SPECTRA.items():
        a = np.array(values, dtype=float)
        a.setflags(write=False)
        out[name] = a
    return out


def from_colour_science(temperature: float | None = None) -> dict:
    """:data:`SPECTRA` computed again by colour-science (imported here): the reference the tests compare with.

    ``temperature``: the blackbody's, kelvin (default :data:`~sunset.constants.SUN_TEMPERATURE`).
    """
    import colour
    from colour.quality.datasets import SDS_TCS

    from ..constants import SUN_TEMPERATURE

    shape = colour.SpectralShape(380, 780, 10)
    lam = np.asarray(shape.wavelengths, dtype=float)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape).values
    checker = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    columns = (lam, cmfs[:, 0], cmfs[:, 1], cmfs[:, 2],
               colour.sd_blackbody(SUN_TEMPERATURE if temperature is None else temperature, shape).values,
               colour.phenomena.rayleigh_optical_depth(lam * 1e-7),
               checker["foliage"].copy().align(shape).values, checker["dark skin"].copy().align(shape).values,
               SDS_TCS["CIE 1995"]["TCS02"].copy().align(shape).values)
    return {name: tuple(float(v) for v in np.asarray(c, dtype=float)) for name, c in zip(COLUMNS, columns)}


def _literal(table: dict, width: int = 116) -> str:
    """The Python text of :data:`SPECTRA` for ``table`` (floats written exactly: ``repr`` reads back the same bits)."""
    lines = ["SPECTRA = {"]
    for name, values in table.items():
        lines.append(f'    "{name}": (')
        line = "       "
        for v in values:
            item = f" {v!r},"
            if len(line) + len(item) > width:
                lines.append(line)
                line = "       "
            line += item
        lines.append(line)
        lines.append("    ),")
    lines.append("}")
    return "\n".join(lines)


def _as_xyz(xy) -> np.ndarray:
    """xy → XYZ with Y = 1, as ``colour.xyY_to_XYZ(colour.xy_to_xyY(xy))``."""
    x, y = np.asarray(xy, dtype=float)
    y_y = np.float64(1.0) / y
    return np.array([x * y_y, np.float64(1.0), (1 - (x + y)) * y_y])


def _vecmul(m: np.ndarray, v: np.ndarray) -> np.ndarray:
    """m @ v over v's last axis, as colour-science's ``vecmul``."""
    return np.matmul(m, v[..., None]).squeeze(-1)


@functools.lru_cache(maxsize=64)
def _adaptation(white: tuple[float, float]) -> np.ndarray:
    """The von Kries matrix (3, 3) in CAT02 space from ``white`` (xy) to D65, as
    ``colour.adaptation.matrix_chromatic_adaptation_VonKries``."""
    m = np.array(CAT02)
    d = _vecmul(m, _as_xyz(D65)) / _vecmul(m, _as_xyz(white))
    out = np.matmul(np.matmul(np.linalg.inv(m), np.eye(3) * d[None, :]), m)
    out.setflags(write=False)
    return out


def xyz_to_srgb(xyz, white) -> np.ndarray:
    """CIE XYZ (..., 3) seen under ``white`` (CIE xy) → linear sRGB (..., 3), adapted (CAT02) to D65.

    The bits of ``colour.XYZ_to_sRGB(xyz, illuminant=white, chromatic_adaptation_transform="CAT02",
    apply_cctf_encoding=False)``.
    """
    cat = _adaptation((float(white[0]), float(white[1])))
    return _vecmul(np.array(XYZ_TO_SRGB), _vecmul(cat, np.asarray(xyz, dtype=float)))


def _spow(a, p) -> np.ndarray:
    """sign(a) |a|^p, as colour-science's ``spow``."""
    a = np.asarray(a, dtype=float)
    return np.sign(a) * np.abs(a) ** np.asarray(p, dtype=float)


def srgb_to_xyz(rgb) -> np.ndarray:
    """sRGB-encoded values in [0, 1] (..., 3) → CIE XYZ (D65): the bits of ``colour.sRGB_to_XYZ(rgb)``.

    The sRGB curve decoded (IEC 61966-2-1), the sRGB matrix, then colour-science's CAT02 adaptation from
    D65 to D65 (not quite the identity in floating point, kept so the bits are the same).
    """
    v = np.asarray(rgb, dtype=float)
    lin = np.where(np.float64(0.0031308 * 12.92) >= v, v / 12.92, _spow((v + 0.055) / 1.055, 2.4))
    return _vecmul(_adaptation(D65), _vecmul(np.array(SRGB_TO_XYZ), lin))


def _f_cie1976(y, y_n):
    ratio = y / y_n
    return np.where(ratio > (24 / 116) ** 3, _spow(ratio, 1 / 3), (841 / 108) * ratio + 16 / 116)


def xyz_to_lab(xyz) -> np.ndarray:
    """CIE XYZ (..., 3) → CIE L*a*b* (..., 3) with D65's white: the bits of ``colour.XYZ_to_Lab(xyz, D65)``."""
    x, y, z = np.moveaxis(np.asarray(xyz, dtype=float), -1, 0)
    x_n, y_n, z_n = _as_xyz(D65)
    f_x, f_y, f_z = _f_cie1976(x, x_n), _f_cie1976(y, y_n), _f_cie1976(z, z_n)
    return np.stack([116 * f_y - 16, 500 * (f_x - f_y), 200 * (f_y - f_z)], axis=-1)


def delta_e_2000(lab_1, lab_2) -> np.ndarray:
    """CIEDE2000 colour difference of two CIE L*a*b* arrays (..., 3) (Sharma, Wu and Dalal 2005): the bits of
    ``colour.delta_E(lab_1, lab_2, method="CIE 2000")``."""
    l_1, a_1, b_1 = np.moveaxis(np.asarray(lab_1, dtype=float), -1, 0)
    l_2, a_2, b_2 = np.moveaxis(np.asarray(lab_2, dtype=float), -1, 0)
    c_bar_ab_7 = ((np.hypot(a_1, b_1) + np.hypot(a_2, b_2)) / 2) ** 7
    g = 0.5 * (1 - np.sqrt(c_bar_ab_7 / (c_bar_ab_7 + 25**7)))
    a_p_1 = (1 + g) * a_1
    a_p_2 = (1 + g) * a_2
    c_p_1 = np.hypot(a_p_1, b_1)
    c_p_2 = np.hypot(a_p_2, b_2)
    h_p_1 = np.where(np.logical_and(b_1 == 0, a_p_1 == 0), 0, np.degrees(np.arctan2(b_1, a_p_1)) % 360)
    h_p_2 = np.where(np.logical_and(b_2 == 0, a_p_2 == 0), 0, np.degrees(np.arctan2(b_2, a_p_2)) % 360)
    delta_l_p = l_2 - l_1
    delta_c_p = c_p_2 - c_p_1
    h_p_2_s_1 = h_p_2 - h_p_1
    c_p_1_m_2 = c_p_1 * c_p_2
    delta_h_p = np.select([c_p_1_m_2 == 0, np.fabs(h_p_2_s_1) <= 180, h_p_2_s_1 > 180, h_p_2_s_1 < -180],
                          [0, h_p_2_s_1, h_p_2_s_1 - 360, h_p_2_s_1 + 360])
    delta_big_h_p = 2 * np.sqrt(c_p_1_m_2) * np.sin(np.deg2rad(delta_h_p / 2))
    l_bar_p = (l_1 + l_2) / 2
    c_bar_p = (c_p_1 + c_p_2) / 2
    a_h_p_1_s_2 = np.fabs(h_p_1 - h_p_2)
    h_p_1_a_2 = h_p_1 + h_p_2
    h_bar_p = np.select([c_p_1_m_2 == 0, a_h_p_1_s_2 <= 180, np.logical_and(a_h_p_1_s_2 > 180, h_p_1_a_2 < 360),
                         np.logical_and(a_h_p_1_s_2 > 180, h_p_1_a_2 >= 360)],
                        [h_p_1_a_2, h_p_1_a_2 / 2, (h_p_1_a_2 + 360) / 2, (h_p_1_a_2 - 360) / 2])
    t = (1 - 0.17 * np.cos(np.deg2rad(h_bar_p - 30)) + 0.24 * np.cos(np.deg2rad(2 * h_bar_p))
         + 0.32 * np.cos(np.deg2rad(3 * h_bar_p + 6)) - 0.20 * np.cos(np.deg2rad(4 * h_bar_p - 63)))
    delta_theta = 30 * np.exp(-(((h_bar_p - 275) / 25) ** 2))
    c_bar_p_7 = c_bar_p**7
    r_c = 2 * np.sqrt(c_bar_p_7 / (c_bar_p_7 + 25**7))
    l_bar_p_2 = (l_bar_p - 50) ** 2
    s_l = 1 + ((0.015 * l_bar_p_2) / np.sqrt(20 + l_bar_p_2))
    s_c = 1 + 0.045 * c_bar_p
    s_h = 1 + 0.015 * c_bar_p * t
    r_t = -np.sin(np.deg2rad(2 * delta_theta)) * r_c
    return np.sqrt((delta_l_p / (1 * s_l)) ** 2 + (delta_c_p / (1 * s_c)) ** 2 + (delta_big_h_p / (1 * s_h)) ** 2
                   + r_t * (delta_c_p / (1 * s_c)) * (delta_big_h_p / (1 * s_h)))


if __name__ == "__main__":          # python -m sunset.model.colorimetry: the table, from colour-science
    print(_literal(from_colour_science()))
