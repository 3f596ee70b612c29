"""The shader's kernels: the Numba twins give the NumPy references' bytes; the response is the eye's."""

import numpy as np
import pytest

from sunset import kernels
from sunset.light import kernel
from sunset.light.geometry import Geometry
from sunset.light.lighting import Lighting
from sunset.light.shade import shade
from sunset.light.tone import display_linear, xyz_to_rgb_matrix
from sunset.model.eye import xyz_response
from sunset.model.scene import Scene
from sunset.vector.render import render


@pytest.fixture(scope="module")
def setup():
    scene = Scene.default().with_size(64, 56)
    geometry = Geometry.from_frame(render(scene, 0.3, 2))
    return scene, geometry


@pytest.mark.parametrize("hours", [4.0, 0.35, 0.02, -0.3])
def test_shading_twins_give_the_same_bytes(setup, hours):
    scene, g = setup
    light = Lighting.for_hour(scene.sun, hours)
    with kernels.use_compiled(False):
        ref = shade(g, light)
        ref_disp = display_linear(ref, light.scale)
    with kernels.use_compiled(True):
        got = shade(g, light)
        got_disp = display_linear(ref, light.scale)
    assert ref.dtype == np.float32 and got.tobytes() == ref.tobytes()
    assert got_disp.tobytes() == ref_disp.tobytes()


def test_every_kernel_has_a_twin():
    for name in ("sky_pixels", "island_pixels", "combine", "display_pixels"):
        k = getattr(kernel, name)
        assert k.compiled() is not k.reference


def test_display_is_the_eyes_response():
    rng = np.random.default_rng(8)
    xyz = np.exp(rng.normal(-3, 3, (5000, 3))).astype(np.float32)
    xyz[:10] = 0.0
    xyz[10:20] = 1e9                                    # far past full scale: bleached to white
    m = xyz_to_rgb_matrix()
    want = xyz_response(xyz.astype(float) / 0.7, lambda x: x @ m)
    for flag in (False, True):
        with kernels.use_compiled(flag):
            np.testing.assert_allclose(display_linear(xyz, 0.7), want, rtol=1e-12, atol=1e-14)
    assert np.all(display_linear(xyz[10:20], 0.7) > 0.999)
