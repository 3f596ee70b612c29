"""The benchmark harness (sunset/bench.py) on tiny pictures: what it writes, not how fast anything is.

No timing is asserted: only that every measurement the issue asks for is
there, that the stages add up to the totals they split, and that the ratios
are the ones the table says they are.
"""

import json
import statistics

import numpy as np
import pytest

from sunset import bench
from sunset.constants import CRAY1_SECONDS_FIGURE6
from sunset.model.scene import Scene


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench") / "bench.json"
    rep = bench.run_benchmark(out, repeats=1, brute_size=12, frame_sizes=((36, 30),), cycle_size=(24, 20),
                              cycle_frames=2, scaling=False, profile=True, memory_sizes=(40, 64),
                              explorer_size=(32, 24), budget=False)   # tests/test_memory_peak.py: the budget row
    return out, rep


def test_json_holds_every_measurement(report):
    out, rep = report
    data = json.loads(out.read_text())
    assert data["rows"] == json.loads(json.dumps(rep["rows"]))
    whats = {r["what"] for r in data["rows"]}
    assert any(w.startswith("brute-force") for w in whats)
    assert "Figure 6 frame 36x30" in whats
    assert "Figure 6 frame 36x30, NumPy kernels" in whats
    assert "Figure 6 frame 36x30, one thread" in whats
    assert "Figure 6 frame 36x30, NumPy's SIMD off" in whats
    assert "2-frame cycle 24x20" in whats
    explorer = {r["stage"] for r in data["rows"] if r["what"] == "explorer update 32x24"}
    assert explorer == {"time (8-bit)", "sun's azimuth (8-bit)", "hours (8-bit)", "wave amplitude (8-bit)",
                        "heading (8-bit)", "time (RGB)"}
    for r in data["rows"]:
        if r["what"] == "explorer update 32x24":         # every update's CPU seconds beside its wall clock
            assert len(r["runs_cpu_s"]) == len(r["runs_s"]) == rep["repeats"]
            assert r["median_cpu_s"] == statistics.median(r["runs_cpu_s"]) > 0
    frame = {r["stage"]: r for r in data["rows"] if r["what"] == "Figure 6 frame 36x30"}
    assert set(bench.STAGES) | {"vector stage", "total", "cpu time"} == set(frame)
    cycle = {r["stage"] for r in data["rows"] if r["what"] == "2-frame cycle 24x20"}
    assert cycle == {"coded", "filmed", "total"}
    for key in ("cpu", "cpus", "python", "numpy", "numba", "date"):
        assert key in data["machine"]
    assert data["compiled"] is True and data["kernels"] == "compiled"      # the path the frame's kernels took
    assert data["profile"] and all(0 <= p["share"] <= 1 for p in data["profile"])


def test_colour_science_is_timed_once_per_fresh_process(report):
    """The colour rows: colour-science's import and the first spectra (which include it), wall and CPU."""
    from sunset.bench.colour import STAGES

    _, rep = report
    rows = {r["stage"]: r for r in rep["rows"] if r["what"] == "colour-science, once per process"}
    assert set(rows) == set(STAGES)
    for r in rows.values():
        assert len(r["runs_s"]) == len(r["runs_cpu_s"]) == rep["repeats"]
        assert r["median_cpu_s"] == statistics.median(r["runs_cpu_s"]) and r["median_cpu_s"] > 0
    for i in range(rep["repeats"]):
        assert rows["first spectra"]["runs_s"][i] >= rows["import colour"]["runs_s"][i]
        assert rows["first spectra"]["runs_cpu_s"][i] >= rows["import colour"]["runs_cpu_s"][i]
    assert "colour-science, once per process" in bench.format_table(rep["rows"])


def test_stages_add_up_and_ratios_follow(report):
    _, rep = report
    rows = [r for r in rep["rows"] if r["what"] == "Figure 6 frame 36x30"]
    by = {r["stage"]: r for r in rows}
    runs = len(by["total"]["runs_s"])
    for i in range(runs):
        stages = sum(by[s]["runs_s"][i] for s in bench.STAGES)
        assert stages == pytest.approx(by["total"]["runs_s"][i], rel=1e-9)
        vector = sum(by[s]["runs_s"][i] for s in bench.STAGES[:-1])
        assert vector == pytest.approx(by["vector stage"]["runs_s"][i], rel=1e-9)
    per_px = rep["brute_seconds_per_pixel"]
    for r in rep["rows"]:
        assert r["median_s"] == statistics.median(r["runs_s"])
        assert r["brute_ratio"] == pytest.approx(per_px * r["pixels"] / r["median_s"])
        assert r["peak_rss_mib"] > 0
    assert by["total"]["cray1_ratio"] == pytest.approx(CRAY1_SECONDS_FIGURE6 / by["total"]["median_s"])
    assert by["codes"]["cray1_ratio"] is None


def test_table_has_a_line_per_row(report):
    _, rep = report
    table = bench.format_table(rep["rows"])
    lines = table.splitlines()
    assert len(lines) == len(rep["rows"]) + 1
    assert "× Cray-1" in lines[0] and "× brute" in lines[0] and "peak MiB" in lines[0]
    assert any("film recorder" in line for line in lines)


def test_scaling_study_on_tiny_pictures(monkeypatch):
    monkeypatch.setattr(bench, "SCALING_SIZES", (24, 40))
    monkeypatch.setattr(bench, "SCALING_TRAINS", (1, 5))
    monkeypatch.setattr(bench, "SCALING_ISLANDS", (0, 4))
    monkeypatch.setattr(bench, "SCALING_SIZE", 24)
    sc = bench._measure_scaling(40, 40, 1)["scaling"]
    assert sc["size"]["n"] == [24, 40] and len(sc["size"]["seconds"]) == 2
    assert sc["size"]["sea_samples"][1] > sc["size"]["sea_samples"][0]
    assert len(sc["trains"]["seconds"]) == 2 and len(sc["islands"]["seconds"]) == 2
    assert all(s > 0 for s in sc["trains"]["seconds"] + sc["islands"]["seconds"])


def test_scaled_scenes_have_the_counts_asked_for():
    base = Scene.default()
    for n in (1, 4, 9):
        sea = bench._scaled_sea(base.sea, n)
        assert len(sea.trains) == n
        assert sea.trains[:min(n, 4)] == base.sea.trains[:min(n, 4)]
    for n in (0, 2, 7):
        isl = bench._scaled_islands(base.islands, n)
        assert len(isl) == n and len({i.name for i in isl}) == n
    # a scene with more of both still renders (no overlap errors, finite values)
    from sunset.pipeline.frame import render

    sc = Scene(camera=base.with_size(24, 20).camera, sun=base.sun, sea=bench._scaled_sea(base.sea, 6),
               islands=bench._scaled_islands(base.islands, 5))
    frame = render(sc, 0.0, 2)
    assert np.isfinite(frame.distance[frame.surface >= 0]).all()


def test_profile_names_are_readable():
    assert bench._function_name("/x/sunset/vector/heightfield.py", "sea_profile") == "heightfield.py:sea_profile"
    assert bench._function_name("~", "<method 'astype' of 'numpy.ndarray' objects>") == "numpy.ndarray.astype"
    assert bench._function_name("~", "<built-in method numpy.empty>") == "numpy.empty"


def test_bad_arguments_are_one_line_errors(capsys):
    assert bench.main(["--repeats", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "repeats" in err
    for row, field, value in (("paths", "--width", "-5"), ("cycle", "--height", "0"), ("frame", "--width", "1000000000")):
        assert bench.main(["--measure", row, field, value]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and field.strip("-") in err and "Traceback" not in err, err


def test_a_row_timed_alone_is_listed_in_the_help(capsys):
    with pytest.raises(SystemExit):
        bench.main(["--help"])
    out = capsys.readouterr().out
    assert "--measure ROW" in out and "paths" in out and "cycle" in out


def test_memory_film_look_povray_and_load_are_reported(report):
    from sunset.bench.extra import BYTES_PER_PIXEL_BOUND
    from sunset.figures.povray import povray_path

    _, rep = report
    mem = rep["memory"]
    assert mem["bound_bytes_per_pixel"] == BYTES_PER_PIXEL_BOUND
    assert [(m["width"], m["height"]) for m in mem["sizes"]] == [(40, 40), (64, 64)]
    for m in mem["sizes"]:
        assert m["bytes_per_pixel"] == pytest.approx(m["added_mib"] * 2**20 / (m["width"] * m["height"]))
    assert mem["ok"] == all(m["bytes_per_pixel"] <= BYTES_PER_PIXEL_BOUND for m in mem["sizes"])
    look = rep["film_look"]
    assert look["before"]["preset"] == "medium" and look["now"]["preset"] == "ultrafast"
    for v in look.values():
        assert v["frames"] == 24 and v["bytes"] > 0 and 10 < v["psnr_db"] < 100 and v["cpu_s"] > 0
    assert len(rep["machine"]["load_before"]) == 3 and len(rep["machine"]["load_after"]) == 3
    lim = rep["limits"]
    assert lim["memory_s"] == pytest.approx(lim["bytes_written"] / (lim["copy_bandwidth_gbs"] * 1e9 * lim["cores"]))
    assert lim["bytes_per_pixel_written"] == pytest.approx(73.0)   # the frame's 69 bytes, a code, RGB
    assert lim["cosine_s"] > 0 and lim["trains"] == 4
    if povray_path() is None:
        assert rep["povray"] is None
    else:
        p = rep["povray"]
        assert (p["width"], p["height"]) == (36, 30) and p["seconds"] > 0
        assert p["ratio"] == pytest.approx(p["seconds"] / p["ours_s"])
        assert 0.9 < p["direct_agree"] <= 1.0


def test_rgb_rows_split_the_four_sample_frame(report):
    _, rep = report
    rgb = {r["stage"]: r for r in rep["rows"] if r["what"] == "RGB 36x30"}
    assert set(rgb) == {"shade stored frame", "light of one hour", "4-sample frame", "4-sample vector",
                        "4-sample back end"}
    whole, vector, back = (rgb[k]["runs_s"] for k in ("4-sample frame", "4-sample vector", "4-sample back end"))
    assert len(whole) == len(vector) == len(back) == 1
    for a, b, c in zip(whole, vector, back):
        assert b > 0 and c > 0 and a == pytest.approx(b + c)


def test_figures_are_timed_in_fresh_processes_outside_the_users_folder(tmp_path, monkeypatch):
    from sunset.bench import extra

    monkeypatch.chdir(tmp_path)
    res = extra.measure_figures(runs=2, args=["--only", "1,2"])
    assert res["files"] == 2                                 # fig1.png and fig2.png, in a temporary folder
    assert not (tmp_path / "figures").exists()
    assert len(res["runs_s"]) == len(res["cpu_s"]) == 2      # the warm-up run is not counted
    assert res["median_s"] == statistics.median(res["runs_s"])
    assert all(c > 0 for c in res["cpu_s"]) and res["cores"] >= 1


def test_the_wind_sea_rows():
    """The tile's rows (sunset/bench/ocean.py): every size and count measured, and the direct sum is the FFT's sea."""
    from sunset.bench import ocean

    res = ocean.measure_ocean(0, 0, 2, sizes=(64,), components=(4, 64), direct=(4,), samples=1000)
    assert set(res) == {"build N=64", "instant N=64", "components 4, FFT", "components 4, direct sum",
                        "components 64, FFT", "sample 1000 points"}
    assert all(len(v) == 2 and min(v) > 0 for v in res.values())
    rows = ocean.rows({"times": res, "peak_rss_mib": 1.0})
    assert rows[0]["what"] == "wind-sea tile, build N=64" and rows[0]["median_s"] == statistics.median(res["build N=64"])
    sea = ocean._sea(256)
    from sunset.model.ocean import OceanTile

    tile = OceanTile(ocean._keep(sea.amplitudes, 64), sea.tile_size, sea.cycle)
    assert np.count_nonzero(tile.h0) == 64
    xs = np.arange(256) * tile.spacing
    np.testing.assert_allclose(ocean._direct(tile, xs, 1.5), tile.fields(1.5)["z"], atol=1e-12)


def test_the_wind_sea_frame_rows():
    """A frame against the tile's components and Max's trains: every one timed, the packaged scene's tile put back."""
    from sunset.bench import ocean
    from sunset.model.scene import Scene

    res = ocean.measure_wind_frames(24, 16, 1, components=(4, 64), trains=(4, 8))
    assert list(res) == ["24x16 frame, wind sea of 4 components", "24x16 frame, wind sea of 64 components",
                         "24x16 frame, 4 wave trains (Max's)", "24x16 frame, 8 wave trains (Max's)"]
    assert all(len(v) == 1 and v[0] > 0 for v in res.values())
    assert np.count_nonzero(Scene.named(ocean.WIND_FRAME_SCENE).sea.wind.tile.h0) > 10000
    assert ocean.rows({"times": res, "peak_rss_mib": 1.0}, "frame")[0]["what"] == "frame, " + list(res)[0]


def test_the_ripples_rows_and_the_convergence_measure(monkeypatch):
    """sunset/bench/ripples.py: its rows carry the medians and the counts; the convergence measure (shrunk here
    to 16 × 4096 photons and two cells) reports a difference per cell and the photons' own noise."""
    from sunset.bench import ripples

    assert bench.MEASUREMENTS["ripples"] is ripples.measure_ripples
    assert bench.MEASUREMENTS["ripples-convergence"] is ripples.measure_convergence
    rows = ripples.rows({"times": {"post texture, beams": [0.3, 0.1, 0.2], "bytes": {"post texture": 2048}},
                         "peak_rss_mib": 12.0})
    assert rows == [{"what": "ripples: post texture, beams", "median_cpu_s": 0.2, "runs_cpu_s": [0.3, 0.1, 0.2],
                     "peak_rss_mib": 12.0}, {"what": "ripples: post texture", "count": 2048}]
    text = ripples.format_rows(rows).splitlines()
    assert len(text) == 2 and text[0].endswith("0.200") and text[1].endswith("2,048")
    monkeypatch.setattr(ripples, "CONVERGENCE_PHOTONS", 16 * 4096)
    monkeypatch.setattr(ripples, "CONVERGENCE_CELLS", (0.2, 0.1))
    monkeypatch.setattr(ripples, "CONVERGENCE_TEXELS", 8)
    monkeypatch.setattr(ripples, "NEAR_CELLS", (0.2, 0.1))
    res = ripples.measure_convergence()
    assert res["photons"] == 16 * 4096 and res["cells"] == [0.2, 0.1] and res["near_cells"] == [0.2, 0.1]
    for key in ("difference", "difference_refined", "beam_seconds", "beam_seconds_refined",
                "beam_seconds_everywhere"):
        assert len(res[key]) == 2 and all(v > 0 for v in res[key])
    for kind in ("", "_refined", "_everywhere", "_near"):
        for norm in ("", "_l1"):
            assert len(res[f"self_reflected{kind}{norm}"]) == 1 and res[f"self_refracted{kind}{norm}"][0] > 0
    for key in ("self_reflected", "self_refracted", "self_reflected_refined", "self_refracted_refined"):
        assert len(res[key]) == 1 and 0 < res[key][0] < 2
    # the everywhere-refined differences split between the columns by the silhouettes and the rest, in squares
    for name in ("reflected", "refracted"):
        on, off = (res[f"self_{name}_everywhere_{key}_silhouettes"] for key in ("on", "off"))
        assert len(on) == len(off) == 1
        assert on[0] ** 2 + off[0] ** 2 == pytest.approx(res[f"self_{name}_everywhere"][0] ** 2, rel=1e-9)
    # 4096 photons a part over 8 x ~60 texels: their noise is several per cent of the texture, and the beams
    # differ from them by at least about that
    assert 0.01 < res["photon_noise"] < 1.0 and min(res["difference"]) > 0.3 * res["photon_noise"]


def test_the_columns_by_a_posts_silhouettes_are_the_lit_ones_within_two_of_a_dark_one():
    from sunset.bench.ripples import SILHOUETTE_REACH, silhouette_columns

    lit = np.zeros((3, 12))
    lit[1, [0, 1, 2, 3, 4, 5, 11]] = 1.0                   # lit from column 11 round to column 5
    assert SILHOUETTE_REACH == 2
    assert np.flatnonzero(silhouette_columns(lit)).tolist() == [0, 4, 5, 11]
    assert not silhouette_columns(np.ones((3, 12))).any()


def test_the_ripples_book_data_command_refuses_bad_repeats(tmp_path, capsys):
    from sunset.bench import ripples_book

    assert ripples_book.main(["--out", str(tmp_path / "d"), "--repeats", "0"]) == 2
    err = capsys.readouterr().err
    assert "repeats" in err and err.count("\n") == 1 and not (tmp_path / "d").exists()


def test_the_self_orders_of_textures_whose_differences_fall_by_four():
    """sunset.bench.ripples.self_orders: textures base + 4^-k bump differ from the next by a quarter as much each
    time, order 2 in either norm (to the change of the finer texture's own norm, under 1e-3 here)."""
    from sunset.bench.ripples import self_orders

    rng = np.random.default_rng(4)
    base, bump = 1.0 + rng.random((6, 5)), 1e-3 * rng.standard_normal((6, 5))
    textures = [(base + 4.0 ** -k * bump, base - 2.0 ** -k * bump) for k in range(4)]
    for which, order in ((0, 2.0), (1, 1.0)):
        res = self_orders(textures, which)
        assert len(res["L2"]) == 3 and res["L2_order"] == pytest.approx([order] * 2, abs=1e-2)
        assert res["L1_order"] == pytest.approx([order] * 2, abs=1e-2)
