"""Frame.finish_direct(sea_rows=False), as trace_reflections calls it: the same traced frame as a full finish_direct."""

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA
from sunset.model.scene import Scene
from sunset.pipeline.frame import trace_reflections
from sunset.pipeline.frame import trace_direct

from .test_crests_numba import frame_bits


@pytest.mark.parametrize("compiled", [False, True])
@pytest.mark.parametrize("mode", [0, 2])
def test_trace_reflections_own_finish_is_the_full_one(compiled, mode):
    scene = Scene.default().with_size(120, 90)
    with kernels.use_compiled(compiled):
        base = trace_direct(scene, 1.5)
        all_sea = np.all(base.surface == SEA, axis=1)
        assert all_sea.any() and not all_sea.all()          # rows of both kinds
        for sea_bounces in (True, False):
            full = trace_reflections(scene, trace_direct(scene, 1.5).finish_direct(sea_bounces), mode,
                                     sea_bounces)
            own = trace_reflections(scene, trace_direct(scene, 1.5), mode, sea_bounces)
            assert frame_bits(own) == frame_bits(full)


def test_the_rows_with_other_pixels_are_finished():
    scene = Scene.default().with_size(120, 90)
    frame = trace_direct(scene, 0.0)
    full = trace_direct(scene, 0.0).finish_direct(False)
    frame.finish_direct(False, sea_rows=False)
    keep = ~np.all(frame.surface == SEA, axis=1)
    for name in ("ray", "final_normal"):
        assert getattr(frame, name)[keep].tobytes() == getattr(full, name)[keep].tobytes()
    for name in ("bounces", "final_surface", "final_part"):
        assert getattr(frame, name).tobytes() == getattr(full, name).tobytes()
