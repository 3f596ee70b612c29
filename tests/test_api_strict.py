"""The public API is as strict as the command line (issue 33): a wrong argument is a SunsetError, at once.

Every name of ``sunset.__all__`` that takes arguments, the series
(:mod:`sunset.model.series`, :mod:`sunset.model.pade`, the exact wave's
methods) and the player's functions (:mod:`sunset.recorder.player`) are
called with valid arguments but one, which hypothesis draws from values
that are wrong for it: text where a number goes, None where nothing is
optional, NaN, infinities, integers past float64, complex numbers, truth
values, arrays of the wrong shape, containers of the wrong things, and
objects of no use at all. The call must raise :class:`~sunset.SunsetError`,
never another exception, within hypothesis' deadline (a second: a refusal
comes before the work).
"""

from __future__ import annotations

import contextlib
import inspect
import tempfile
from dataclasses import asdict, fields

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import sunset
from sunset.errors import SunsetError
from sunset.model.pade import pade_exact
from sunset.model.series import domb_sykes, pade_coefficients
from sunset.pipeline.film import player_data, write_player
from sunset.recorder import player

#: A tiny scene and what the pipeline makes of it, the valid arguments the calls start from.
SCENE = sunset.Scene.default().with_size(8, 8)
FRAME = sunset.render(SCENE, 0.0, 2)
CODES = sunset.encode(SCENE, FRAME)
SERIES = sunset.stokes_series(6)
FLOATS = sunset.stokes_series(6, exact=False)
WAVE = sunset.solve_stokes(0.05)


def _data():
    from sunset.tape.tapefile import Tape

    _data.tape = Tape(scene=SCENE, codes=CODES[None], times=np.array([0.0]))
    return player_data(_data.tape, player.hours_grid(0.5, 0.0))


DATA = _data()
#: Where the calls that write files (they must not) would write them.
WORK = tempfile.mkdtemp(prefix="sunset-api-")


class Useless:
    """An object of no use to any argument."""

    def __repr__(self):
        raise RuntimeError("a hostile __repr__")


#: Values wrong for every argument of the API.
WRONG = [None, "0.5", "", "carlas-island\n", b"1", 1 + 2j, float("nan"), float("inf"), -float("inf"),
         10**5000, -(10**5000), Useless(), {"a": 1}, {1, 2}, [[1, 2], [3]], ["a", "b"],
         np.array([np.nan, 1.0]), np.array(["a"]), np.zeros((2, 3, 4, 5)), np.array(1 + 1j), object]
#: ... and values wrong for arguments that are not truth values (or that take text: names, paths, titles).
NOT_BOOL = [True, False, np.bool_(True)]

#: (what, the callable, its valid keyword arguments, the arguments that take text, that take None).
CASES = [
    ("Camera", sunset.Camera, asdict(SCENE.camera), (), ()),
    ("Sun", sunset.Sun, asdict(SCENE.sun), (), ()),
    ("WaveTrain", sunset.WaveTrain, {f.name: getattr(SCENE.sea.trains[0], f.name)
                                     for f in fields(SCENE.sea.trains[0]) if f.init}, (), ()),
    ("Sea", sunset.Sea, {"trains": SCENE.sea.trains}, (), ("wind",)),
    ("Paraboloid", sunset.Paraboloid, asdict(SCENE.islands[0].cliff), (), ()),
    ("Cosine", sunset.Cosine, {"amplitude": 1.0, "l": 0.1, "m": 0.2, "phase": 0.0}, (), ()),
    ("Island", sunset.Island, {f.name: getattr(SCENE.islands[0], f.name) for f in fields(SCENE.islands[0])
                               if f.init}, ("name",), ()),
    ("Scene", sunset.Scene, {"camera": SCENE.camera, "sun": SCENE.sun, "sea": SCENE.sea, "islands": SCENE.islands,
                             "title": "t"}, ("title",), ("clouds",)),
    ("Frame", sunset.Frame, {f.name: getattr(FRAME, f.name) for f in fields(FRAME)}, (),
     tuple(f.name for f in fields(FRAME) if f.name not in ("t", "reflections", "surface"))),
    ("render", sunset.render, {"scene": SCENE, "t": 0.0, "reflections": 2}, ("scene",), ("islands",)),
    ("encode", sunset.encode, {"scene": SCENE, "frame": FRAME, "seed": 0}, ("scene",), ()),
    ("expose", sunset.expose, {"scene": SCENE, "codes": CODES, "hours": 0.35}, ("scene",), ()),
    ("picture", sunset.picture, {"scene": SCENE, "t": 0.0, "hours": 0.35, "size": (8, 8), "reflections": 2,
                                 "seed": 0}, ("scene",), ("size",)),
    ("make_film", sunset.make_film, {"scene": SCENE, "path_mp4": "f.mp4", "frames": 2, "progress": False,
                                     "fps": 24, "from_hours": 0.5, "to_hours": 0.0, "cycles": 1, "workers": 1,
                                     "seed": 0, "reflections": 2},
     ("scene", "path_mp4", "path_preview", "tape_path"), ("path_preview", "tape_path", "workers")),
    ("solve_stokes", sunset.solve_stokes, {"steepness": 0.05}, (), ("n_modes", "map_parameter")),
    ("stokes_series", sunset.stokes_series, {"order": 6, "exact": True}, (), ()),
    ("StokesSeries.pade", SERIES.pade, {"quantity": "speed", "x": 0.1, "parameter": "epsilon", "terms": 6},
     ("quantity", "parameter"), ("terms",)),
    ("StokesSeries(float).pade", FLOATS.pade, {"quantity": "speed", "x": 0.1, "parameter": "epsilon"},
     ("quantity", "parameter"), ("terms",)),
    ("StokesSeries.partial_sum", SERIES.partial_sum, {"quantity": "a2", "x": 0.1, "parameter": "alpha"},
     ("quantity", "parameter"), ("terms",)),
    ("StokesSeries.at_steepness", SERIES.at_steepness, {"steepness": 0.1, "n_amplitudes": 2}, (), ("terms",)),
    ("StokesSeries.coefficients", SERIES.coefficients, {"quantity": "speed", "parameter": "alpha"},
     ("quantity", "parameter"), ()),
    ("StokesSeries.amplitude", SERIES.amplitude, {"n": 2, "parameter": "alpha"}, ("parameter",), ()),
    ("StokesSeries.conformal", SERIES.conformal, {"n": 1}, (), ()),
    ("StokesSeries.highest_wave", SERIES.highest_wave, {"terms": 6}, (), ("terms",)),
    ("StokesSeries.speed_maximum", SERIES.speed_maximum, {"terms": 6}, (), ("terms",)),
    ("domb_sykes", domb_sykes, {"coefficients": SERIES.speed("epsilon"), "stride": 2, "fit_last": 2}, (), ()),
    ("pade_coefficients", pade_coefficients, {"an": [1.0, 0.5, 0.25], "m": 1, "n": 1}, (), ()),
    ("pade_exact", pade_exact, {"an": [1, 2, 3], "m": 1, "n": 1}, (), ()),
    ("StokesWave.profile", WAVE.profile, {"kx": 0.3}, (), ()),
    ("StokesWave.surface", WAVE.surface, {"n_points": 9}, (), ()),
    ("StokesWave.series_profile", WAVE.series_profile, {"kx": 0.3, "order": 3}, (), ()),
    ("player.hours_grid", player.hours_grid, {"from_hours": 0.5, "to_hours": 0.0}, (), ()),
    ("player.nearest_hour", player.nearest_hour, {"grid": player.hours_grid(0.5, 0.0), "hours": 0.2}, (), ()),
    ("player.player_size", player.player_size, {"scene": SCENE, "long_side": 64}, ("scene",), ()),
    ("player.quantise", player.quantise, {"lin": np.zeros((2, 3))}, (), ()),
    ("player.sun_geometry", player.sun_geometry, {"scene": SCENE, "hours": 0.2}, ("scene",), ()),
    ("player.code_meanings", player.code_meanings, {"sun": SCENE.sun}, (), ("clouds",)),
    ("film.player_data", player_data, {"tape": _data.tape, "grid": player.hours_grid(0.5, 0.0)}, (),
     ("start_hours",)),
    ("player.player_fragment", player.player_fragment, {"data": DATA}, (), ()),
    ("player.player_html", player.player_html, {"data": DATA}, (), ()),
    ("player.read_player_data", player.read_player_data, {"text": player.player_html(DATA)}, ("text",), ()),
    ("player.decode_codes", player.decode_codes, {"data": DATA}, (), ()),
    ("player.data_tables", player.data_tables, {"data": DATA}, (), ()),
    ("player.compose", player.compose, {"data": DATA, "frame": 0, "hour": 0}, (), ("codes",)),
    ("film.write_player", write_player, {"scene": SCENE, "path": "p.html", "frames": 2, "size": (8, 8),
                                                  "progress": False}, ("scene", "path"), ("size",)),
]

#: Counts capped by the usable CPUs: any whole number >= 1 is valid, 10**5000 too.
COUNTS = ("workers",)
#: Arguments that take an array of any shape (the zeros of shape (2, 3, 4, 5) are valid there).
ARRAYS = ("kx", "x", "lin")

PAIRS = [(case, name) for case in CASES for name in case[2]]


def wrong_for(case, name):
    what, fn, kwargs, text_ok, none_ok = case
    values = [v for v in WRONG if not (v is None and name in none_ok)
              and not (isinstance(v, (str, bytes)) and name in text_ok)
              and not (isinstance(v, int) and name in COUNTS)
              and not (isinstance(v, np.ndarray) and v.dtype.kind == "f" and v.ndim == 4 and name in ARRAYS)]
    if not isinstance(kwargs[name], (bool, np.bool_)):
        values += NOT_BOOL
    return st.sampled_from(values)


@st.composite
def calls(draw):
    case, name = draw(st.sampled_from(PAIRS))
    value = draw(wrong_for(case, name))
    return case, name, value


@settings(max_examples=600, deadline=1000, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(calls())
def test_a_wrong_argument_is_a_sunset_error_at_once(call):
    (what, fn, kwargs, _, _), name, value = call
    args = {**kwargs, name: value}
    with contextlib.chdir(WORK), pytest.raises(SunsetError) as info:
        fn(**args)
    message = str(info.value)
    assert message and "\n" not in message, (what, name, message)


def test_the_valid_calls_run():
    """The baselines are valid: each call with its own arguments returns (the test above changes one)."""
    for what, fn, kwargs, _, _ in CASES:
        if what in ("make_film", "film.write_player"):
            continue                                            # they write files: valid by the CLI's tests
        fn(**kwargs)


def test_every_public_callable_is_covered():
    names = {c[0] for c in CASES}
    for name in sunset.__all__:
        obj = getattr(sunset, name)
        if name in ("SunsetError", "__version__", "default_scene", "scene_names", "explore"):
            continue
        assert callable(obj) and name in names, name
    for name in player.__all__:
        if callable(getattr(player, name)) and inspect.signature(getattr(player, name)).parameters:
            assert f"player.{name}" in names, name


#: Every public way a time t (seconds) reaches the sea's phase ω t.
TIMED = [
    ("render", lambda t: sunset.render(SCENE, t, 2)),
    ("picture", lambda t: sunset.picture(SCENE, t=t, size=(8, 8))),
    ("Frame", lambda t: sunset.Frame(**{**{f.name: getattr(FRAME, f.name) for f in fields(FRAME)}, "t": t})),
    ("Sea.elevation", lambda t: SCENE.sea.elevation(0.0, 10.0, t)),
    ("Sea.gradient", lambda t: SCENE.sea.gradient(0.0, 10.0, np.array([0.0, t]))),
    ("pov_scene", lambda t: __import__("sunset.model.pov", fromlist=["pov_scene"]).pov_scene(SCENE, t)),
    ("trace_geometry", lambda t: __import__("sunset.pipeline.rgb", fromlist=["x"]).trace_geometry(SCENE, t, 2, 1)),
    ("Tape", lambda t: __import__("sunset.tape.tapefile", fromlist=["x"]).Tape(scene=SCENE, codes=CODES[None],
                                                                               times=np.array([t]))),
]


@pytest.mark.parametrize("what, call", TIMED, ids=[w for w, _ in TIMED])
def test_a_time_is_bounded_by_the_seas_clock(what, call):
    """A time past ±MAX_TIME (1e308 made ω t infinite: a ValueError from math.remainder) is a SunsetError;
    ±MAX_TIME itself runs without a warning (the tests turn warnings into errors)."""
    from sunset.constants import MAX_TIME

    for t in (1e308, -1e308, np.nextafter(MAX_TIME, np.inf), -np.nextafter(MAX_TIME, np.inf), float("inf")):
        with pytest.raises(SunsetError, match=r"^t(imes)? must be (a time within ±1e\+09 s|a finite number)"):
            call(t)
    for t in (MAX_TIME, -MAX_TIME):
        call(t)


def test_a_sea_that_repeats_after_centuries_has_no_film():
    """Frequencies in ratios 1, 65/64, 64/63, 62/61, 60/59, 54/53 of the lowest repeat after 6e10 s (the lcm of
    the denominators, 14,511,168, cycles of the longest 80 s wave): past MAX_TIME, refused before any frame."""
    from dataclasses import replace

    from sunset.constants import MAX_TIME
    from sunset.recorder.film import cycle_times

    base = SCENE.sea.trains[0]
    trains = tuple(replace(base, wavelength=10_000.0 / r**2, amplitude=0.5)
                   for r in (1, 65 / 64, 64 / 63, 62 / 61, 60 / 59, 54 / 53))
    scene = replace(SCENE, sea=replace(SCENE.sea, trains=trains))
    longest = 2 * np.pi / min(t.omega for t in trains)
    assert scene.sea.period == pytest.approx(64 * 63 * 61 * 59 * 53 * longest, rel=1e-9) and scene.sea.period > MAX_TIME
    with pytest.raises(SunsetError, match="repeats only after 6.16e"):
        cycle_times(scene, 4)


#: Finite numbers at the ends of float64 and of int64, and denormals: wrong for most numeric arguments
#: (sizes, counts, gravity, hours, times), valid for a few (a phase, a position, kx, a hill's amplitude).
EXTREMES = [1e308, -1e308, 10**18, 2**63, 5e-324, -5e-324, 1e-300]


def test_extreme_numbers_are_refused_or_harmless():
    """Issue 33's range class: every numeric argument of every call above, set to each of EXTREMES, gives a
    SunsetError (within a second) or a result, never another exception nor a NumPy warning (errors here).
    Found so: gravity 1e308 or 5e-324 (accepted), hours 1e308 in player.sun_geometry (accepted),
    StokesWave.series_profile at k x = 1e308 (an overflow in n k x)."""
    import time
    import warnings

    bad = []
    for what, fn, kwargs, _, _ in CASES:
        if what in ("make_film", "player.write_player"):
            continue                                            # they write files: the CLI's tests
        for name, v0 in kwargs.items():
            if isinstance(v0, (bool, np.bool_, str, bytes)) or not isinstance(v0, (int, float, np.number, np.ndarray)):
                continue
            for v in EXTREMES:
                start = time.perf_counter()
                try:
                    with contextlib.chdir(WORK), warnings.catch_warnings():
                        warnings.simplefilter("error")
                        fn(**{**kwargs, name: v})
                except SunsetError as exc:
                    assert "\n" not in str(exc), (what, name, v, str(exc))
                    if time.perf_counter() - start > 1.0:       # a refusal comes before the work
                        bad.append((what, name, v, f"refused after {time.perf_counter() - start:.1f} s"))
                except Exception as exc:                        # noqa: BLE001 - the finding
                    bad.append((what, name, v, f"{type(exc).__name__}: {exc}"))
    assert bad == []


@pytest.mark.parametrize("field, value", [("gravity", 1e308), ("gravity", 5e-324), ("gravity", 0.05)])
def test_gravity_has_a_physical_range(field, value):
    """5e-324 m/s² made a wave whose cycle left float64, 1e308 one whose ω t did."""
    from dataclasses import replace

    with pytest.raises(SunsetError, match=r"^gravity must be in \[0\.1, 300\] m/s²"):
        replace(SCENE.sea.trains[0], **{field: value})
    with pytest.raises(SunsetError, match=r"^gravity must be in \[0\.1, 300\] m/s²"):
        replace(SCENE.sea, **{field: value})


def test_the_player_sun_is_within_half_a_day():
    with pytest.raises(SunsetError, match=r"^hours must be within ±12 hours"):
        player.sun_geometry(SCENE, 1e308)
