"""The measurement of the two paths' agreement (sunset/bench/agreement.py): what it writes and how it names causes."""

import json

import numpy as np
import pytest

from sunset import kernels
from sunset.bench import agreement
from sunset.constants import SEA, SKY
from sunset.model.scene import as_scene, Scene
from sunset.pipeline.frame import encode, render


def test_the_command_writes_every_run(tmp_path, capsys):
    out = tmp_path / "agreement.json"
    assert agreement.main(["--out", str(out), "--size", "24", "--times", "2", "--scene", "carlas-island"]) == 0
    data = json.loads(out.read_text())
    assert data["size"] == 24 and data["times"] == 2 and data["machine"]["numpy"]
    runs = data["runs"]
    assert len(runs) == 2 * 3 * 2                              # times × modes × with and without bounces
    assert {(r["reflections"], r["sea_bounces"]) for r in runs} == {(m, b) for m in (0, 1, 2) for b in (0, 1)}
    for r in runs:
        assert r["scene"] == "carlas-island" and r["pixels"] == 24 * 24
        assert sum(r["causes"].values()) == r["differing"] and set(r["causes"]) == set(agreement.CAUSES)
        assert r["identical_share"] == 1.0 - r["differing"] / r["pixels"]
        point = r["geometry"]["point"]
        assert point["pixels"] > 0 and 0.0 <= point["median"] <= point["q9999"] <= point["max"] < 1e-5
    assert out.read_text().count("\n") < 40 + len(runs)       # one run to a line
    row = agreement.totals(data)["carlas-island"]
    assert row["pixels"] == 12 * 576 and row["differing"] == sum(r["differing"] for r in runs)


@pytest.mark.parametrize("argv", [["--size", "4"], ["--times", "0"]])
def test_bad_sizes_are_one_line_and_no_file(tmp_path, capsys, argv):
    out = tmp_path / "a.json"
    assert agreement.main(["--out", str(out), *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--size" in err[0] and not out.exists()


def test_the_cycle_times_spread_over_the_period():
    scene = as_scene("carlas-island")
    times = agreement.cycle_times(scene, 4)
    assert times == [scene.sea.period * k / 4 for k in range(4)]
    assert agreement.cycle_times(Scene.default().still(), 2) == [0.0, 4.0]     # no period: 8 s


def frames_and_codes(scene):
    frame = render(scene, 0.5, 2)
    return frame, encode(scene, frame, seed=1)


def test_the_causes_are_named_in_order():
    scene = Scene.default().with_size(64, 48)
    with kernels.use_compiled(False):
        ref, codes = frames_and_codes(scene)
    assert agreement.classify(scene, ref, ref, codes, codes, 1).size == 0           # nothing differs
    sea = np.argwhere(ref.surface == SEA)
    got = render(scene, 0.5, 2)
    got_codes = codes.copy()
    y, x = sea[0]
    got.surface[y, x] = SKY                        # a silhouette, whatever else differs there
    got_codes[y, x] ^= 1
    y2, x2 = sea[len(sea) // 2]
    got.normal[y2, x2] = got.normal[y2, x2] + np.float32(1e-3)   # a normal off by more than its tolerance
    got_codes[y2, x2] ^= 1
    y3, x3 = np.argwhere(ref.surface == SKY)[0]
    got_codes[y3, x3] ^= 8                         # the same direct sky ray, another code: no known cause
    causes = agreement.classify(scene, ref, got, codes, got_codes, 1)
    order = sorted([(y, x), (y2, x2), (y3, x3)])
    want = {(y, x): "silhouette", (y2, x2): "grazing ray", (y3, x3): "other"}
    assert [agreement.CAUSES[c] for c in causes] == [want[p] for p in order]
