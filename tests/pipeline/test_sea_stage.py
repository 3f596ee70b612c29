"""The sea's kind picks its strip kernels in one place (sunset/pipeline/frame.py: sea_stage).

A wind sea's frames go through the wind sea's own kernels (sunset/vector/windsea_scan.py, windsea_crests.py and
their Numba twins) on both paths, and never through the trains' compiled kernels, which refuse it; which path ran
is recorded as for every kernel (sunset.kernels.path). The two paths' wind frames agree within the tolerances of
sunset.kernels (tests/test_kernels.py holds every packaged scene, the two wind scenes among them, to them).
"""

import math
import re
from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA
from sunset.errors import SunsetError
from sunset.model.scene import Scene
from sunset.model.waves import Sea
from sunset.model.windsea import WindSea
from sunset.pipeline.cycle import cycle_pass
from sunset.pipeline.frame import TRAINS, WIND, code_frame, depth_buffer, render, sea_stage
from sunset.pipeline.rgb import render_rgb
from sunset.vector.direct import sea_strip
from sunset.vector.heightfield import WIND_REFUSED

from ..agree import assert_geometry_agrees

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="the compiled kernels need Numba")

#: The trains' compiled kernels of the rows: (module, name). A wind sea must reach none of them.
TRAINS_TWINS = [("sunset.vector.reflect_numba", "trace_sea_rays"), ("sunset.vector.direct_numba", "sea_geometry"),
                ("sunset.vector.slopes_numba", "put_sea_normals"), ("sunset.pipeline.fused_numba", "code_strip"),
                ("sunset.vector.heightfield_numba", "sea_columns")]


def wind_scene(width=40, height=30):
    ws = WindSea(speed=9.0, direction=260.0, fetch=math.inf, seed=2, tile_points=64, tile_size=160.0, cycle=64.0)
    base = Scene.default().with_size(width, height)
    return replace(base, sea=Sea(wind=ws), camera=replace(base.camera, eye_height=3.0))


def every_frame(scene):
    """The frames the package makes of ``scene`` on the compiled path: render, the 8-bit strips with and without
    a cycle's still part, the RGB back end; with 0, 1 and 2 reflections. Also a cycle's strip of sea pixels with
    the sea's geometry kernel, as the 8-bit strips that do not run fused make it."""
    with kernels.use_compiled(True):
        still = cycle_pass(scene)
        for reflections in (0, 1, 2):
            render(scene, 2.0, reflections, sea_bounces=True)
            code_frame(scene, 2.0, reflections)
            code_frame(scene, 2.0, reflections, islands=still)
        render_rgb(scene, 2.0, 0.35, reflections=2)
        depth = depth_buffer(scene, 2.0, islands=still.islands)
        sea_strip(scene, 2.0, depth, still.direction, 0, scene.camera.height, sea_stage(scene.sea).geometry)


@pytest.fixture
def spies(monkeypatch):
    """Each of the trains' compiled kernels replaced by one that records its call and goes on."""
    import importlib

    called = []
    for module, name in TRAINS_TWINS:
        mod = importlib.import_module(module)
        real = getattr(mod, name)

        def spy(*args, _real=real, _name=f"{module}.{name}", **kwargs):
            called.append(_name)
            return _real(*args, **kwargs)

        monkeypatch.setattr(mod, name, spy)
    return called


def test_a_wind_sea_never_reaches_the_trains_compiled_kernels(spies):
    every_frame(wind_scene())
    assert spies == []
    every_frame(Scene.default().with_size(40, 30))      # the spies see the trains: the check above can fail
    assert {name.rsplit(".", 1)[1] for name in spies} == {name for _, name in TRAINS_TWINS}


def test_the_trains_kernels_refuse_a_wind_sea_on_both_paths():
    from sunset.vector.direct import put_sea_normals
    from sunset.vector.frame import Frame
    from sunset.vector.reflect import trace_sea_rays

    scene = wind_scene(8, 6)
    frame = Frame(t=0.0, reflections=1, direction=np.zeros((1, 1, 3), np.float32),
                  surface=np.full((1, 1), SEA, np.int8), part=None, distance=None,
                  point=np.zeros((1, 1, 3), np.float32), normal=np.zeros((1, 1, 3), np.float32))
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            for reflections in (0, 1, 2):
                with pytest.raises(SunsetError, match=re.escape(WIND_REFUSED)):
                    trace_sea_rays(scene, frame, reflections)
            with pytest.raises(SunsetError, match=re.escape(WIND_REFUSED)):
                put_sea_normals(scene.sea, 0.0, np.zeros((1, 1, 3), np.float32), np.array([0]), np.array([0.1]),
                                np.array([50.0]))


def test_the_sea_picks_its_kernels_and_each_is_a_twin_of_its_own_kind():
    assert sea_stage(wind_scene(8, 6).sea) is WIND and sea_stage(Scene.default().sea) is TRAINS
    assert WIND.fused is False and TRAINS.fused is True
    for kernel in (WIND.columns, WIND.normals, WIND.geometry, WIND.rays):
        twin = kernel.compiled()
        assert kernel.__module__.startswith("sunset.vector.windsea_"), kernel.__module__
        assert twin.__module__ == kernel.__module__ + "_numba" and twin.__name__ == kernel.__name__
    for kernel in (TRAINS.normals, TRAINS.geometry, TRAINS.rays):
        assert "windsea" not in kernel.__module__ and "windsea" not in kernel.compiled().__module__


@pytest.mark.parametrize("reflections", [1, 2])
def test_the_wind_frames_agree_on_both_paths_with_the_bounces(reflections):
    """The full frame with every sea bounce recorded, held to sunset.kernels' tolerances field by field."""
    scene = wind_scene(64, 48)
    frames = []
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            frames.append(render(scene, 5.0, reflections, sea_bounces=True))
    ref, got = frames
    assert (ref.bounces == 2).any() == (reflections == 2)
    assert_geometry_agrees(ref, got, f"wind, {reflections} reflections")


def test_no_compiled_twin_of_the_vector_stage_imports_inside_a_function():
    """The sea's kernel is chosen by sunset.pipeline.frame.sea_stage and sunset.kernels, never by a twin handing
    work back to a reference through an import inside a function (the vector stage's and the fused pass's twins)."""
    import ast
    from pathlib import Path

    import sunset

    root = Path(sunset.__file__).parent
    found = []
    for path in sorted([*root.glob("vector/*_numba.py"), *root.glob("pipeline/*_numba.py")]):
        for fn in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found += [f"{path.relative_to(root)}:{node.lineno}" for node in ast.walk(fn)
                          if isinstance(node, (ast.Import, ast.ImportFrom))]
    assert found == []
