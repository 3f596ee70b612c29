"""Colour-table animation (sunset/recorder/film.py): one cycle rendered once, filmed as the sun sets."""

import math
import os

import numpy as np
import pytest
from PIL import Image

from sunset.pipeline.frame import encode, expose, render
from sunset.errors import SunsetError
from sunset.pipeline.film import make_film, render_cycle, write_film
from sunset.recorder.film import cycle_times, film_frames, film_hours
from sunset.io import png_bytes
from sunset.model.scene import Scene
from sunset.tape.tapefile import read_tape, tape_bytes
from sunset.model.waves import Sea, WaveTrain

SIZE = (40, 32)


def decode_mp4(path, width, height):
    """Decode a video with ffmpeg into (frames, height, width, 3) uint8, and its duration in seconds."""
    import subprocess

    import imageio_ffmpeg

    exe = imageio_ffmpeg.get_ffmpeg_exe()
    out = subprocess.run([exe, "-v", "error", "-i", str(path), "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         capture_output=True, check=True).stdout
    assert len(out) % (width * height * 3) == 0
    return (np.frombuffer(out, np.uint8).reshape(-1, height, width, 3),
            imageio_ffmpeg.count_frames_and_secs(str(path))[1])


@pytest.fixture(scope="module")
def scene():
    return Scene.default().with_size(*SIZE)


@pytest.fixture(scope="module")
def tape(scene):
    return render_cycle(scene, 4, reflections=2, seed=3, progress=False)


def test_cycle_times_span_one_period(scene):
    T = scene.sea.period
    t = cycle_times(scene, 8)
    np.testing.assert_allclose(t, np.arange(8) * T / 8)
    assert math.isclose(t[-1] + T / 8, T)                 # the next frame would be t = T
    assert np.all(cycle_times(scene.still(), 5) == 0)


def test_a_sea_that_never_repeats_has_no_cycle(scene):
    odd = Sea((WaveTrain(0.3, 40.0), WaveTrain(0.1, 40.0 / math.pi)))
    with pytest.raises(SunsetError, match="never repeats"):
        cycle_times(Scene(camera=scene.camera, sun=scene.sun, sea=odd), 4)
    with pytest.raises(SunsetError, match="frames"):
        cycle_times(scene, 0)


@pytest.mark.parametrize("mode", [0, 1, 2])
def test_frame_at_one_period_is_frame_zero(scene, mode):
    T = scene.sea.period
    a = encode(scene, render(scene, 0.0, mode), seed=0)
    b = encode(scene, render(scene, T, mode), seed=0)
    assert a.tobytes() == b.tobytes()
    # and the cycle really moves in between
    c = encode(scene, render(scene, T / 2, mode), seed=0)
    assert not np.array_equal(a, c)


def test_render_cycle_tape(scene, tape):
    assert tape.codes.shape == (4, SIZE[1], SIZE[0])
    np.testing.assert_allclose(tape.times, cycle_times(scene, 4))
    assert tape.reflections == 2 and tape.seed == 3
    # frame i is the vector stage at t_i, coded with the frame's seed reset
    np.testing.assert_array_equal(tape.codes[2], encode(scene, render(scene, tape.times[2], 2), seed=3))
    again = render_cycle(scene, 4, reflections=2, seed=3, progress=False)
    assert tape_bytes(again) == tape_bytes(tape)


def test_film_hours():
    h = film_hours(2.0, -0.3, 24)
    assert h[0] == 2.0 and h[-1] == -0.3 and len(h) == 24
    np.testing.assert_allclose(np.diff(h), -2.3 / 23)
    assert film_hours(1.0, 0.0, 1).tolist() == [1.0]
    with pytest.raises(SunsetError, match="from_hours"):
        film_hours(float("nan"), 0.0, 4)


def test_film_frames_replay_the_tape(tape):
    frames = list(film_frames(tape, 1.0, -0.2, cycles=2))
    assert len(frames) == 8
    hours = film_hours(1.0, -0.2, 8)
    for j, (h, rgb) in enumerate(frames):
        assert h == hours[j]
        np.testing.assert_array_equal(rgb, expose(tape.scene, tape.codes[j % 4], h))


def test_write_film_is_deterministic_and_decodes(tmp_path, tape, capsys):
    files = []
    for name in ("a", "b"):
        files.append(write_film(tape, tmp_path / f"{name}.mp4", tmp_path / f"{name}.gif", from_hours=1.0,
                                to_hours=-0.2, cycles=3, fps=12, progress=False))
    assert capsys.readouterr().err == ""                  # no progress bar when asked for none
    (a_mp4, a_gif), (b_mp4, b_gif) = files
    assert a_mp4.read_bytes() == b_mp4.read_bytes()
    assert a_gif.read_bytes() == b_gif.read_bytes()
    video, seconds = decode_mp4(a_mp4, *SIZE)             # even already: no padding
    assert len(video) == 12 and math.isclose(seconds, 1.0)  # 12 frames at 12 fps
    # the decoded film is close to the exposed frames (lossy H.264, yuv420p)
    first = next(film_frames(tape, 1.0, -0.2, cycles=3))[1]
    assert np.mean(np.abs(video[0].astype(int) - first)) < 12
    with Image.open(a_gif) as gif:
        assert gif.n_frames == 12 and gif.info.get("loop") == 0
    assert sorted(os.listdir(tmp_path)) == ["a.gif", "a.mp4", "b.gif", "b.mp4"]


def test_odd_sizes_are_padded_and_progress_shows(tmp_path, capsys, monkeypatch):
    import sys

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)    # progress bars are for terminals only
    scene = Scene.default().with_size(21, 15)
    tape = render_cycle(scene, 2, reflections=0, progress=True)
    out = write_film(tape, tmp_path / "odd.mp4", None, cycles=1, progress=True)
    assert out == [tmp_path / "odd.mp4"]
    assert "filming" in capsys.readouterr().err
    video, _ = decode_mp4(out[0], 22, 16)
    assert len(video) == 2


def test_make_film_writes_everything_and_fails_cleanly(tmp_path, scene):
    files = make_film(scene, tmp_path / "f.mp4", tmp_path / "f.gif", frames=2, reflections=1, seed=0, cycles=1,
                      tape_path=tmp_path / "f.tape", progress=False)
    assert [p.name for p in files] == ["f.mp4", "f.gif", "f.tape"]
    tape = read_tape(tmp_path / "f.tape")
    assert tape.frames == 2 and tape.reflections == 1
    with pytest.raises(SunsetError, match="does not exist"):
        make_film(scene, tmp_path / "nope" / "g.mp4", None, frames=2, progress=False)
    assert sorted(os.listdir(tmp_path)) == ["f.gif", "f.mp4", "f.tape"]


def test_png_of_a_film_frame_is_deterministic(tape):
    a = png_bytes(next(film_frames(tape, 0.3, 0.3, 1))[1])
    b = png_bytes(next(film_frames(tape, 0.3, 0.3, 1))[1])
    assert a == b


def test_webp_preview_loops_and_is_deterministic(tmp_path, tape):
    outs = []
    for name in ("a", "b"):
        _, prev = write_film(tape, tmp_path / f"{name}.mp4", tmp_path / f"{name}.webp", from_hours=1.0,
                             to_hours=-0.2, cycles=2, fps=12, progress=False)
        outs.append(prev.read_bytes())
    assert outs[0] == outs[1]
    with Image.open(tmp_path / "a.webp") as im:
        assert im.format == "WEBP" and im.n_frames == 8 and im.info.get("loop") == 0
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB"))
    # the preview's last frame is the film's last frame, downscaled only if wider than the preview
    _, rgb = list(film_frames(tape, 1.0, -0.2, cycles=2))[-1]
    assert np.mean(np.abs(last.astype(int) - rgb)) < 12


@pytest.mark.parametrize("shape", [(6, 8, 3), (7, 8, 3), (6, 9, 3), (7, 9, 3), (1, 4, 3)])
def test_the_encoder_gets_the_even_pictures_bytes_in_pieces(shape):
    from sunset.recorder.film import _even, _even_parts

    rgb = np.arange(np.prod(shape), dtype=np.uint64).astype(np.uint8).reshape(shape)
    for pic in (rgb, rgb[:, ::-1]):                      # contiguous or not
        want = _even(pic)
        assert want.shape[0] % 2 == 0 and want.shape[1] % 2 == 0
        np.testing.assert_array_equal(want[:pic.shape[0], :pic.shape[1]], pic)
        np.testing.assert_array_equal(want[-1, :pic.shape[1]], pic[-1])          # the last row again
        np.testing.assert_array_equal(want[:pic.shape[0], -1], pic[:, -1])       # the last column again
        parts = _even_parts(pic)
        assert all(p.flags.c_contiguous for p in parts)
        assert b"".join(p.tobytes() for p in parts) == want.tobytes()
