"""What "the two paths agree" asserts in the tests: the tolerances of sunset.kernels, field by field and code by code.

Not a test module (no ``test_`` prefix): the helpers that tests of the
compiled kernels share. The geometry is compared by
:func:`sunset.bench.agreement.relative_errors` (where both paths' rays meet
the same surfaces), each field against its constant of :mod:`sunset.kernels`;
the codes by the share of identical pixels and the cause of every differing
one (:func:`sunset.bench.agreement.classify`), none of which may be "other".
"""

import numpy as np

from sunset import kernels
from sunset.bench.agreement import CAUSES, classify, relative_errors

#: The tolerance (a name in sunset.kernels) each geometry field is held to, and whether on every compared pixel
#: (True) or on all but a share 1 − AGREE_GEOMETRY_SHARE of them (False).
FIELD_TOLERANCE = {"direction": ("AGREE_DIRECTION", True), "distance": ("AGREE_POINT", False),
                   "point": ("AGREE_POINT", False), "normal": ("AGREE_NORMAL", False), "ray": ("AGREE_RAY", False),
                   "incidence": ("AGREE_RAY", False), "sea_rays": ("AGREE_RAY", False),
                   "final_normal": ("AGREE_FINAL_NORMAL", False)}


def share_of(share: float, pixels: int) -> int:
    """The most pixels a share of ``pixels`` allows: rounded up to a whole pixel (a tenth of a pixel is one)."""
    return int(np.ceil(share * pixels - 1e-9))


def assert_geometry_agrees(ref, got, context=""):
    """Every geometry field of ``got`` within its tolerance of ``ref``'s, on the pixels where both see the same."""
    for name, err in relative_errors(ref, got).items():
        constant, everywhere = FIELD_TOLERANCE[name]
        tol = getattr(kernels, constant)
        allowed = 0 if everywhere else share_of(1.0 - kernels.AGREE_GEOMETRY_SHARE, err.size)
        over = int(np.count_nonzero(err > tol))
        assert over <= allowed, (f"{context} {name}: {over} of {err.size} pixels over {constant} = {tol:g} "
                                 f"(largest {err.max():.3g}), {allowed} allowed")


def assert_codes_agree(scene, ref, got, codes_ref, codes_got, seed, context="") -> np.ndarray:
    """The codes identical on at least AGREE_CODES of the pixels, every other one with a known cause; the causes."""
    causes = classify(scene, ref, got, codes_ref, codes_got, seed)
    share = 1.0 - causes.size / codes_ref.size
    assert share >= kernels.AGREE_CODES, \
        f"{context}: {share:.6f} of the codes identical ({causes.size} differ)"
    other = np.count_nonzero(causes == CAUSES.index("other"))
    assert other == 0, f"{context}: {other} differing codes of no known cause"
    return causes


def assert_depth_agrees(ref_u, ref_surf, got_u, got_surf, context=""):
    """Two depth buffers (1/yp and the winning surface per pixel): the surfaces the same on all but a share
    1 − AGREE_CODES of the pixels (a silhouette a rounding moved), 1/yp within AGREE_POINT where they are the same
    but on a share 1 − AGREE_GEOMETRY_SHARE of them."""
    same = np.asarray(ref_surf) == np.asarray(got_surf)
    allowed = int((1.0 - kernels.AGREE_CODES) * same.size)
    assert np.count_nonzero(~same) <= allowed, f"{context}: {np.count_nonzero(~same)} surfaces differ"
    a, b = np.asarray(ref_u, np.float64)[same], np.asarray(got_u, np.float64)[same]
    np.testing.assert_array_equal(a == 0, b == 0, err_msg=context)
    hit = a > 0
    err = np.abs(a[hit] - b[hit]) / a[hit]
    over = np.count_nonzero(err > kernels.AGREE_POINT)
    assert over <= share_of(1.0 - kernels.AGREE_GEOMETRY_SHARE, err.size), \
        f"{context}: 1/yp off by more than AGREE_POINT on {over} of {err.size} pixels (largest {err.max():.3g})"
