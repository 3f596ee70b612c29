"""The RGB film: its frames are the single frames of their times and hours, the same bytes on any number of workers."""

import numpy as np
import pytest

from sunset.light.output import to_uint8
from sunset.light.render import frame_light, shade_display
from sunset.model.scene import load_named_scene
from sunset.pipeline.rgb import film_frames, trace_cycle, trace_geometry
from sunset.recorder.film import cycle_times, film_hours


@pytest.fixture(scope="module")
def cycle():
    scene = load_named_scene("post-in-the-swell").with_size(24, 20)
    times = cycle_times(scene, 2)
    return scene, times, trace_cycle(scene, times, 2, 1, progress=False), film_hours(0.6, 0.1, 5)


def test_a_film_frame_is_the_single_frame_of_its_time_and_hour(cycle):
    scene, times, geometries, hours = cycle
    frames = list(film_frames(scene, geometries, hours, times=times))
    assert len(frames) == len(hours)
    for j in (0, 3):
        t = times[j % len(times)]
        want = to_uint8(shade_display(trace_geometry(scene, t, 2, 1), frame_light(scene, t, hours[j])))
        assert frames[j].dtype == np.uint8 and frames[j].tobytes() == want.tobytes()
    assert frames[0].tobytes() != frames[2].tobytes()             # the same geometry, another hour


def test_the_film_is_the_same_bytes_on_two_workers(cycle):
    scene, times, geometries, hours = cycle
    one = list(film_frames(scene, geometries, hours, times=times, workers=1))
    two = list(film_frames(scene, geometries, hours, times=times, workers=2))
    assert [f.tobytes() for f in one] == [f.tobytes() for f in two]


def test_the_film_stops_cleanly_when_its_reader_does(cycle):
    scene, times, geometries, hours = cycle
    frames = film_frames(scene, geometries, hours, times=times, workers=2)
    first = next(frames)
    frames.close()                                                  # the pool is shut down, no frame is lost
    assert first.shape == (20, 24, 3)


def test_a_film_at_one_hour_computes_each_light_once(cycle, monkeypatch):
    import sunset.light.film as film

    scene, times, geometries, _ = cycle
    made = []
    real = film.frame_light
    monkeypatch.setattr(film, "frame_light", lambda *a: made.append(a) or real(*a))
    frames = list(film_frames(scene, geometries, [0.3] * 6, times=times))
    assert len(made) == len(times) == 2
    assert [f.tobytes() for f in frames[:2]] == [f.tobytes() for f in frames[2:4]]


def test_no_more_film_workers_than_the_memory_budget_allows(cycle, monkeypatch):
    import sunset.constants as constants
    from sunset.pipeline.budget import workers_within_budget

    _, _, geometries, _ = cycle
    assert workers_within_budget(2, geometries) == 2
    kept = sum(g.nbytes for g in geometries)
    monkeypatch.setattr(constants, "MAX_FRAME_BYTES", kept + constants.RGB_LIGHT_BYTES + 10**6)
    assert workers_within_budget(4, geometries) == 1


def test_a_film_of_posts_runs_past_sunset(cycle):
    scene, times, geometries, _ = cycle
    hours = [0.2, -0.25]                       # the default film ends a quarter of an hour after sunset
    frames = list(film_frames(scene, geometries, hours, times=times))
    assert len(frames) == 2 and frames[1].tobytes() != frames[0].tobytes()


def test_the_film_carries_the_ripples_of_each_cycle_frames_time(cycle):
    """Issue 30: each film frame gets the ripples of light on the post at its own cycle frame's time; without
    them (the hour's light alone) the post is darker and nothing else changes."""
    from sunset.light.lighting import Lighting

    scene, times, geometries, _ = cycle
    frames = list(film_frames(scene, geometries, [0.6, 0.6], times=times))
    gains = []
    for j, g in enumerate(geometries):
        bare = to_uint8(shade_display(g, Lighting.for_scene(scene, 0.6), 1)).astype(int)
        gain = frames[j].astype(int) - bare
        on_post = (g.final_kind == 2).reshape(g.shape)
        assert on_post.any() and not gain[~on_post].any()
        assert gain[on_post].max() >= 8 and gain.min() >= -1        # -1: the rounding of a sum in float32
        gains.append(gain[on_post].sum(axis=-1))
    assert gains[0].tolist() != gains[1].tolist()                   # the ripples move with the waves
