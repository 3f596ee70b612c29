"""The POV-Ray exporter (sunset.model.pov), checked by reading the .pov text back, without POV-Ray.

The functions it writes are evaluated by translating POV-Ray's expression
syntax to NumPy and compared with the sea's and the islands' own code
(sunset.model.waves.Sea.elevation, sunset.model.islands.Island.height); the
camera's rays with Camera.directions; the boxes and gradient bounds with
dense samples of the surfaces.
"""

import re

import numpy as np
import pytest

from sunset.cli import main
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.pov import POV_COLOURS, pov_scene
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain
from sunset.vector.heightfield import sampling

VEC = r"<([^<>]*)>"


def vec(text):
    return np.array([float(v) for v in text.split(",")])


def blocks(text, kind):
    """The bodies of top-level ``kind { ... }`` blocks (balanced braces)."""
    out, i = [], 0
    while True:
        i = text.find(kind + " {", i)
        if i < 0:
            return out
        depth, j = 0, text.index("{", i)
        start = j
        while True:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            if depth == 0:
                break
            j += 1
        out.append(text[start + 1:j])
        i = j


def function(body):
    """A POV-Ray function body as a Python callable f(x, y, z) (NumPy)."""
    expr = re.search(r"function \{ (.*) \}\n", body).group(1)
    code = expr.replace("cos(", "np.cos(").replace("max(", "np.maximum(").replace("min(", "np.minimum(")
    return lambda x, y, z: eval(code, {"np": np, "x": x, "y": y, "z": z})


def box(body):
    lo, hi = re.search(r"contained_by \{ box \{ " + VEC + ", " + VEC, body).groups()
    return vec(lo), vec(hi)


def scenes():
    default = Scene.default().with_size(160, 120)
    stokes4 = Sea((WaveTrain(0.3, 20.0, direction=70.0, phase=0.4, stokes_order=4), WaveTrain(0.05, 5.0)))
    odd = Island(x=-40.0, y=500.0, cliff=Paraboloid(60.0, 0.002, -0.0011, 0.003),
                 beach=Paraboloid(4.0, 1e-4, 2e-5, 9e-5), cliff_top=25.0, hill_factor=0.6,
                 cosines=(Cosine(2.0, 0.05, -0.04), Cosine(1.0, -0.2, 0.1)))
    other = Scene(camera=default.camera, sun=default.sun, sea=stokes4, islands=(odd,))
    return {"default": default, "other": other}


@pytest.mark.parametrize("name", ["default", "other"])
def test_the_camera_shoots_the_packages_rays(name):
    scene = scenes()[name]
    cam = scene.camera
    text = pov_scene(scene)
    (body,) = blocks(text, "camera")
    d = vec(re.search(r"direction " + VEC, body).group(1))
    right = vec(re.search(r"right " + VEC, body).group(1))
    up = vec(re.search(r"up " + VEC, body).group(1))
    assert re.search(r"location <0, 0, 0>", body)
    # POV-Ray: pixel (i, j) -> direction + u right + v up, u = (i + 1/2)/W - 1/2, v = 1/2 - (j + 1/2)/H
    u = (np.arange(cam.width) + 0.5) / cam.width - 0.5
    v = 0.5 - (np.arange(cam.height) + 0.5) / cam.height
    ray = d + u[None, :, None] * right + v[:, None, None] * up
    ours = np.stack([ray[..., 0], ray[..., 2], ray[..., 1]], axis=-1)   # POV <x, y, z> is our (x, z, y)
    ours /= np.linalg.norm(ours, axis=-1, keepdims=True)
    np.testing.assert_allclose(ours, cam.directions(), atol=1e-12)


@pytest.mark.parametrize("name", ["default", "other"])
@pytest.mark.parametrize("t", [0.0, 1.3])
def test_the_sea_is_the_same_function(name, t):
    scene = scenes()[name]
    h = scene.camera.eye_height
    text = pov_scene(scene, t)
    sea = blocks(text, "isosurface")[0]
    f = function(sea)
    rng = np.random.default_rng(3)
    x, z = rng.uniform(-300, 300, 500), rng.uniform(1, 3000, 500)   # POV x, z = our x, y
    y = rng.uniform(-h - 1, -h + 1, 500)
    np.testing.assert_allclose(f(x, y, z), y - (scene.sea.elevation(x, z, t) - h), atol=1e-9)
    lo, hi = box(sea)
    d = scene.sea.max_elevation
    assert lo[1] <= -h - d and hi[1] >= -h + d
    assert hi[2] == pytest.approx(sampling(scene.camera, d).y_far)
    # a perfect mirror, traced to two reflections
    assert "finish { Mirror }" in sea and "max_trace_level 3" in text
    assert re.search(r"#declare Mirror = finish \{[^\n]*reflection \{ 1 \}", text)


@pytest.mark.parametrize("name", ["default", "other"])
def test_each_island_is_the_same_function_inside_a_box_that_holds_it(name):
    scene = scenes()[name]
    h, d = scene.camera.eye_height, scene.sea.max_elevation
    isos = blocks(pov_scene(scene), "isosurface")[1:]
    assert len(isos) == len(scene.islands)
    for island, body in zip(scene.islands, isos):
        f = function(body)
        lo, hi = box(body)
        rng = np.random.default_rng(5)
        x = rng.uniform(lo[0], hi[0], 2000)
        z = rng.uniform(lo[2], hi[2], 2000)
        y = rng.uniform(-h, 50.0, 2000)
        np.testing.assert_allclose(f(x, y, z), y - (island.height(x, z) - h), atol=1e-9)
        # everything of the island above the lowest sea is inside the box
        gx, gz = np.meshgrid(np.linspace(2 * lo[0] - hi[0], 2 * hi[0] - lo[0], 400),
                             np.linspace(2 * lo[2] - hi[2], 2 * hi[2] - lo[2], 400))
        H = island.height(gx, gz)
        above = H > -d
        assert above.any()
        assert np.all((gx[above] >= lo[0]) & (gx[above] <= hi[0]) & (gz[above] >= lo[2]) & (gz[above] <= hi[2]))
        assert H.max() - h <= hi[1] and lo[1] <= -h - d
        # max_gradient bounds the function's gradient (finite differences over the box)
        g = float(re.search(r"max_gradient ([0-9.e-]+)", body).group(1))
        xs, zs = np.meshgrid(np.linspace(lo[0], hi[0], 300), np.linspace(lo[2], hi[2], 300))
        e = 1e-4
        hx = (island.height(xs + e, zs) - island.height(xs - e, zs)) / (2 * e)
        hz = (island.height(xs, zs + e) - island.height(xs, zs - e)) / (2 * e)
        assert np.sqrt(1 + hx * hx + hz * hz).max() <= g
        assert f"rgb <{POV_COLOURS['island'][0]}, 0, 0>" in body


def test_the_sea_gradient_bound_holds():
    scene = scenes()["other"]
    body = blocks(pov_scene(scene), "isosurface")[0]
    g = float(re.search(r"max_gradient ([0-9.e-]+)", body).group(1))
    xs, ys = np.meshgrid(np.linspace(0, 60, 400), np.linspace(0, 60, 400))
    fx, fy = scene.sea.gradient(xs, ys, 0.7)
    assert np.sqrt(1 + fx * fx + fy * fy).max() <= g


def test_export_on_the_command_line(tmp_path, capsys):
    out = tmp_path / "scene.pov"
    assert main(["export", "pov", "carlas-island", "--time", "0.5", "--size", "64x48", "-o", str(out)]) == 0
    text = out.read_text()
    assert "+W64 +H48" in text and text == pov_scene(Scene.default().with_size(64, 48), 0.5)
    # user errors: one line, exit 2, nothing written
    bad = tmp_path / "bad.txt"
    assert main(["export", "pov", "carlas-island", "-o", str(bad)]) == 2
    assert main(["export", "pov", str(tmp_path / "missing.toml"), "-o", str(tmp_path / "m.pov")]) == 2
    assert main(["export", "obj", "carlas-island", "-o", str(tmp_path / "o.pov")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3 and all(line.startswith("sunset: error: ") for line in err)
    assert not bad.exists() and not (tmp_path / "m.pov").exists() and not (tmp_path / "o.pov").exists()


def test_what_is_not_exported_is_said():
    from sunset.model.scene import load_named_scene

    assert "// not exported: clouds" in pov_scene(load_named_scene("carlas-island-clouds").with_size(16, 12))
    assert "not exported" not in pov_scene(Scene.default().with_size(16, 12))
