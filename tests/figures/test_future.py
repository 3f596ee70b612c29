"""Figures of the future work, II (sunset/figures/future.py): clouds.png and ripples.png."""

import numpy as np
from PIL import Image

from sunset.figures import future
from sunset.figures.future import CLOUD_HOURS, clouds_figure, cloudy, ripple_textures, ripples_figure
from sunset.model.scene import Scene, load_named_scene
from sunset.recorder.colour_tables import sun_colour
from sunset.model.eye import srgb_encode


def test_clouds_png_shows_the_sun_hidden_then_above_the_cloud(tmp_path):
    scene = Scene.default().with_size(160, 160)
    path = clouds_figure(tmp_path / "clouds.png", scene)
    with Image.open(path) as im:
        img = np.asarray(im.convert("RGB"))
        settings = im.info["sunset:settings"]
    w = scene.camera.width
    gap = img.shape[1] - 2 * w
    assert img.shape[0] == scene.camera.height and gap >= 2
    left, right = img[:, :w], img[:, w + gap:]
    sc = cloudy(scene)
    counts = []
    for half, hours in ((left, CLOUD_HOURS[0]), (right, CLOUD_HOURS[1])):
        sun = np.rint(255 * srgb_encode(sun_colour(sc.sun, hours, sc.clouds))).astype(int)
        counts.append(int(np.all(np.abs(half.astype(int) - sun) <= 1, axis=-1).sum()))
    assert counts[0] < counts[1] and counts[1] > 0       # the disk is behind the cloud, then shows
    assert "clouds" in settings


def test_ripple_textures_move_with_the_waves_and_still_water_does_not():
    scene = load_named_scene("post-in-the-swell")
    times, moving = ripple_textures(scene, times=[0.0, 0.5], cell=0.2, texels=12)
    assert times == [0.0, 0.5]
    assert not np.allclose(moving[0].above, moving[1].above)
    _, still = ripple_textures(scene.still(), times=[0.0, 0.5], cell=0.2, texels=12)
    np.testing.assert_array_equal(still[0].above, still[1].above)


def test_ripples_png_is_written(tmp_path, monkeypatch):
    monkeypatch.setattr(future, "RIPPLE_RAYS", 1 << 12)
    monkeypatch.setattr(future, "RIPPLE_CELL", 0.25)
    monkeypatch.setattr(future, "RIPPLE_TEXELS", 10)
    path = ripples_figure(tmp_path / "ripples.png")
    with Image.open(path) as img:
        assert img.size[0] > img.size[1] > 200
