"""The light's table of the sun's slant columns (sunset.light.lighting)."""

import math

import numpy as np
import pytest

from sunset.constants import ATMOSPHERE_TOP
from sunset.light import lighting
from sunset.light.lighting import Lighting
from sunset.model.eye import spectrum_to_xyz
from sunset.model.scene import Scene
from sunset.model.sky import sky_radiance, slant_columns


def test_column_table_in_blocks_is_the_whole_grid_at_once():
    # built COLUMN_BLOCK rows at a time to keep its memory small: the same bytes as one call over the grid
    u = np.arange(lighting.COLUMN_ROWS) / (lighting.COLUMN_ROWS - 1)
    mu = np.linspace(-1.0, 1.0, lighting.COLUMN_MUS)
    whole = slant_columns((u * u * ATMOSPHERE_TOP)[:, None], mu[None, :])
    table = lighting._column_table()
    assert table.shape == (lighting.COLUMN_ROWS, lighting.COLUMN_MUS, 3)
    assert table.tobytes() == whole.tobytes()


def test_tabulated_columns_at_the_nodes_are_the_sky_models():
    rows = np.array([0, 17, 95])
    cols = np.array([0, 1024, 1500, 2048])
    u = rows / (lighting.COLUMN_ROWS - 1)
    h = (u * u * ATMOSPHERE_TOP)[:, None]
    mu = np.linspace(-1.0, 1.0, lighting.COLUMN_MUS)[cols][None, :]
    got = lighting.tabulated_columns(h, mu)
    np.testing.assert_allclose(got, slant_columns(h, mu), rtol=1e-12, atol=0)


@pytest.mark.parametrize("hours", [0.35, 0.05, 2.0])
def test_sky_table_in_blocks_is_the_whole_grid_at_once(hours):
    # the grid's radiance is computed SKY_BLOCK rows at a time: the same bytes as one call over the grid
    scene = Scene.default()
    light = Lighting.for_scene(scene, hours)
    p = light.sun_dir
    grid = lighting.sky_grid_directions(math.atan2(p[1], p[0]))
    whole = sky_radiance(grid.reshape(-1, 3), p, columns=lighting.tabulated_columns)
    blocks = lighting._sky_radiance_rows(grid, p)
    assert blocks.shape == whole.shape and blocks.tobytes() == whole.tobytes()
    sky = np.log(np.maximum(spectrum_to_xyz(whole), 1e-30)).reshape(grid.shape)
    assert sky.tobytes() == light.sky_table.tobytes()
