"""The notebook API: sunset.picture, scene names wherever a scene is, short reprs, typing."""

import inspect
import typing
from pathlib import Path

import numpy as np
import pytest

import sunset
from sunset.errors import SunsetError
from sunset.model.scene import as_scene, scene_names
from sunset.pipeline.frame import code_frame, encode, expose, render


def test_picture_is_the_pipeline_in_one_call():
    """picture() = expose(encode(render)) of the sized scene: computed here step by step."""
    scene = sunset.Scene.default().with_size(40, 30)
    expected = expose(scene, encode(scene, render(scene, 1.5, 1), seed=3), 2.0)
    got = sunset.picture("carlas-island", t=1.5, hours=2.0, size=(40, 30), reflections=1, seed=3)
    assert got.dtype == np.uint8 and got.shape == (30, 40, 3)
    assert np.array_equal(got, expected)


def test_picture_defaults_and_sizes(tmp_path):
    assert sunset.picture("still-lake-at-noon").shape == (400, 400, 3)
    path = tmp_path / "mine.toml"
    path.write_text(sunset.Scene.named("storm-swell").with_size(20, 10).to_toml(), encoding="utf-8")
    assert sunset.picture(path, size=None).shape == (10, 20, 3)         # the file's own camera
    assert sunset.picture(str(path), size=(8, 6)).shape == (6, 8, 3)


@pytest.mark.parametrize("kwargs, words", [
    ({"scene": "no-such-scene"}, "no scene named 'no-such-scene'"),
    ({"scene": 42}, "expected a Scene"),
    ({"scene": "carlas-island", "size": (0, 10)}, "width"),
    ({"scene": "carlas-island", "size": 400}, "size must be"),
    ({"scene": "carlas-island", "hours": float("nan")}, "hours"),
    ({"scene": "carlas-island", "reflections": 3}, "reflections"),
    ({"scene": "carlas-island", "t": float("inf")}, "finite"),
])
def test_picture_bad_input_is_one_clear_error(kwargs, words):
    kwargs = {"size": (8, 6), **kwargs}
    with pytest.raises(SunsetError, match=words):
        sunset.picture(**kwargs)


def test_a_packaged_name_works_wherever_a_scene_does():
    name = "archipelago-at-dusk"
    small = sunset.Scene.named(name)
    frame = render(name, 0.0, 0)
    assert frame.shape == (small.camera.height, small.camera.width)
    codes = encode(name, frame)
    assert np.array_equal(codes, code_frame(small, 0.0, 0))
    assert np.array_equal(expose(name, codes, 0.5), expose(small, codes, 0.5))
    assert as_scene(small) is small
    assert sorted(scene_names()) == scene_names() and "carlas-island" in scene_names()


def test_reprs_are_short_and_say_what_matters():
    scene = sunset.Scene.default()
    frame = render(scene.with_size(32, 24), 0.0, 2)
    tape = sunset.tape.tapefile.Tape(scene=scene.with_size(32, 24), codes=encode(scene.with_size(32, 24), frame)[None],
                                     times=np.zeros(1))
    for obj, words in [(scene, ["Carla's Island", "1020×1023", "4 trains", "3 islands"]),
                       (scene.sea, ["4 trains", "period 5.06 s"]),
                       (scene.still().sea, ["still"]),
                       (frame, ["t=0 s", "32×24", "reflections=2", "% sky", "% sea"]),
                       (tape, ["1 frame", "32×24"])]:
        text = repr(obj)
        assert len(text) < 160, text
        for w in words:
            assert w in text, (w, text)


def test_public_api_is_typed():
    assert (Path(sunset.__file__).parent / "py.typed").is_file()
    for name in ("picture", "render", "encode", "expose", "make_film", "solve_stokes", "scene_names"):
        fn = getattr(sunset, name)
        sig = inspect.signature(fn)
        hints = typing.get_type_hints(fn)
        assert "return" in hints, name
        for p in sig.parameters.values():
            if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                assert p.name in hints, f"{name}({p.name}) has no type hint"
