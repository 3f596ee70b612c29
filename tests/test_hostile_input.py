"""Hostile input (issue 12): nothing lost, nothing silently wrong, every limit stated and kept.

Each test names the case of the issue it checks. Commands run in-process
through :func:`sunset.cli.main` where that suffices (pytest turns every
warning into an error, so a RuntimeWarning on a successful run fails the
test), and as subprocesses where a signal, a file descriptor or a read-only
install is involved.
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import stat
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, HealthCheck, settings, strategies as st

import sunset
from sunset import io as sio
from sunset.cli import main
from sunset.constants import (FRAME_BYTES_PER_PIXEL, MAX_COSINES, MAX_CYCLE_FRAMES, MAX_FRAME_BYTES, MAX_ISLANDS,
                              MAX_PIXELS, MAX_SCENE_BYTES, MAX_SEA_SAMPLES_PER_PIXEL)
from sunset.errors import SunsetError
from sunset.model.islands import Island, Paraboloid
from sunset.model.scene import _dump_toml, Scene
from sunset.bench.memory import measure_bytes_per_pixel
from sunset.vector.budget import check_work, predict_work

SMALL = "40x32"
ROOT = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def one_line_error(code, err, *words):
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("sunset: error:") and "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def leftovers(folder) -> list[str]:
    """Temporary files of the atomic writer left in ``folder``."""
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith(".sunset-"))


def sunset_cmd(*argv, **kw):
    env = {**os.environ, "TQDM_DISABLE": "1", **kw.pop("env", {})}
    return subprocess.run([sys.executable, "-m", "sunset", *map(str, argv)], capture_output=True, text=True,
                          env=env, **kw)


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text(Scene.default().to_toml())
    return path


@pytest.fixture(scope="module")
def tape_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tape")
    assert main(["render", "carlas-island", "--size", SMALL, "-o", str(folder / "t.png"),
                 "--tape", str(folder / "t.tape")]) == 0
    return folder / "t.tape"


def replace_in(path, old, new):
    text = path.read_text()
    assert old in text, old
    path.write_text(text.replace(old, new, 1))
    return path


# --------------------------------------------------------------------------- 1. a full disk

def _enospc(*_a, **_k):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("argv", [
    ["render", "{scene}", "--size", SMALL, "-o", "{out}/a.png"],
    ["render", "{scene}", "--size", SMALL, "-o", "{out}/a.png", "--tape", "{out}/a.tape"],
    ["expose", "{tape}", "--hours", "1", "-o", "{out}/a.png"],
])
def test_full_disk_keeps_the_old_file(capsys, tmp_path, scene_file, tape_file, monkeypatch, argv):
    """1: the disk fills while writing: one error line, the old good files untouched, no temporary left."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.png").write_bytes(b"an older good picture")
    monkeypatch.setattr(sio, "_fsync", _enospc)            # the flush to disk is where a full disk shows
    argv = [a.format(scene=scene_file, out=out, tape=tape_file) for a in argv]
    code, _, err = run(capsys, *argv)
    one_line_error(code, err, "No space left on device")
    assert (out / "a.png").read_bytes() == b"an older good picture"
    assert sorted(p.name for p in out.iterdir()) == ["a.png"]


def _fake_writer(mode):
    """An ffmpeg pipe writer that fails as a full disk makes ffmpeg fail."""
    def write_frames(path, *a, **k):
        Path(path).write_bytes(b"\0\0\0\x18ftypisom")       # a partial MP4
        n = 0
        try:
            while True:
                yield
                n += 1
                if mode == "pipe" and n > 2:
                    raise OSError(errno.EPIPE, "[Errno 32] Broken pipe\n\nFFMPEG COMMAND:\n...")
        except GeneratorExit:
            return
    return write_frames


@pytest.mark.parametrize("mode", ["pipe", "silent"])
def test_full_disk_film_keeps_the_old_film(capsys, tmp_path, monkeypatch, mode):
    """1: ffmpeg's ENOSPC (a broken pipe, or a truncated file and no error) fails the command, exit 2."""
    import imageio_ffmpeg

    film = tmp_path / "f.mp4"
    film.write_bytes(b"an older good film")
    monkeypatch.setattr(imageio_ffmpeg, "write_frames", _fake_writer(mode))
    code, _, err = run(capsys, "film", "carlas-island", "--frames", "2", "--size", "24x16", "--quiet", "-o", film,
                       "--preview", tmp_path / "p.gif", "--tape", tmp_path / "f.tape")
    one_line_error(code, err, "cannot write the film")
    assert film.read_bytes() == b"an older good film"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.mp4"]       # no preview, no tape, no temporary


def _can_mount() -> bool:
    return os.geteuid() == 0 and shutil.which("mount") is not None and sys.platform.startswith("linux")


@pytest.mark.skipif(not _can_mount(), reason="a real full tmpfs needs root (the monkeypatched cases run anyway)")
def test_full_tmpfs_film(tmp_path):
    """1, as the issue reproduced it: a 2 MB tmpfs filled to 4 KB free."""
    full = tmp_path / "full"
    full.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(full)]).returncode != 0:
        pytest.skip("mount refused")
    try:
        old = sunset_cmd("film", "carlas-island", "--frames", "2", "--size", "32x32", "--quiet", "-o", full / "f.mp4")
        assert old.returncode == 0, old.stderr
        good = (full / "f.mp4").read_bytes()
        free = os.statvfs(full).f_bavail * os.statvfs(full).f_frsize
        (full / "filler").write_bytes(bytes(free - 4096))
        proc = sunset_cmd("film", "carlas-island", "--frames", "2", "--size", "96x96", "--quiet",
                          "-o", full / "f.mp4")
        assert proc.returncode == 2, proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1 and "cannot write the film" in proc.stderr
        assert (full / "f.mp4").read_bytes() == good
        assert sorted(p.name for p in full.iterdir()) == ["f.mp4", "filler"]
    finally:
        subprocess.run(["umount", str(full)])


# --------------------------------------------------------------------------- 2. outputs that alias

@pytest.mark.parametrize("argv, words", [
    (["film", "{scene}", "-o", "f.mp4", "--tape", "f.mp4"], ["-o and --tape"]),
    (["film", "{scene}", "-o", "f.mp4", "--preview", "p.gif", "--tape", "p.gif"], ["--preview and --tape"]),
    (["render", "{scene}", "-o", "a.png", "--tape", "a.png"], ["-o and --tape"]),
    (["render", "{scene}", "-o", "a.png", "--tape", "{scene}"], ["the scene", "--tape"]),
    (["expose", "t.png", "--hours", "1", "-o", "t.png"], ["-o", "the tape"]),
    (["render", "{scene}", "-o", "link.png", "--tape", "a.png"], ["same file"]),          # a symbolic link
    (["render", "{scene}", "-o", "hard.png", "--tape", "a.png"], ["same file"]),          # a hard link
    (["render", "{scene}", "-o", "sub/../a.png", "--tape", "a.png"], ["same file"]),      # another spelling
    (["player", "{scene}", "-o", "scene-link.html"], ["the scene"]),                      # a link to the input
])
def test_aliased_outputs_are_refused(capsys, tmp_path, scene_file, tape_file, monkeypatch, argv, words):
    """2: two outputs, or an output and an input, that are one file: an error before any work."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    Path("a.png").write_bytes(b"old a")
    os.symlink("a.png", "link.png")
    os.link("a.png", "hard.png")
    os.symlink(scene_file, "scene-link.html")
    shutil.copy(tape_file, "t.png")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    code, _, err = run(capsys, *[a.format(scene=scene_file) for a in argv])
    one_line_error(code, err, *words)
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()} == before


def test_check_distinct_sees_new_files_through_folders(tmp_path):
    sio.check_distinct({"-o": tmp_path / "x.png", "--tape": tmp_path / "y.tape"})
    with pytest.raises(SunsetError, match="same file"):
        sio.check_distinct({"-o": tmp_path / "x.png", "--tape": tmp_path / "." / "x.png"})


# --------------------------------------------------------------------------- 3. devices and FIFOs

def test_devices_and_fifos_are_never_replaced(capsys, tmp_path, scene_file):
    """3: the rename would turn /dev/null or a FIFO into a regular file."""
    fifo = tmp_path / "pipe.tape"
    os.mkfifo(fifo)
    for target in ("/dev/null", fifo):
        code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png", "--tape", target)
        one_line_error(code, err, "not a regular file")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert not (tmp_path / "a.png").exists()


# --------------------------------------------------------------------------- 4. the island index

def _far_island(x):
    p = Paraboloid(height=5.0, e=0.01, f=0.0, g=0.01)
    return Island(x=x, y=1000.0, cliff=p, beach=Paraboloid(height=1.0, e=0.001, f=0.0, g=0.001), cliff_top=3.0)


def test_too_many_islands_is_one_error(capsys, tmp_path):
    """4: an island index past 127 would overflow its byte: a documented limit, one error line."""
    base = Scene.default()
    scene = Scene(camera=base.camera, sun=base.sun, sea=base.sea, islands=(_far_island(-1e5),) * MAX_ISLANDS)
    text = scene.to_toml()
    path = tmp_path / "many.toml"
    path.write_text(text + "\n[[islands]]" + text.rsplit("[[islands]]", 1)[1])
    code, _, err = run(capsys, "render", path, "--size", SMALL, "-o", tmp_path / "a.png")
    one_line_error(code, err, "islands", f"at most {MAX_ISLANDS}")
    with pytest.raises(SunsetError, match=f"at most {MAX_ISLANDS}"):
        Scene(islands=(_far_island(-1e5),) * (MAX_ISLANDS + 1))


def test_the_last_island_index_is_coded_right():
    """4: the island at index 127 renders as the same island at index 1 does."""
    from sunset.pipeline.frame import render

    base = Scene.default().with_size(48, 32)
    seen = base.islands[1]                                   # the middle island, in view
    alone = Scene(camera=base.camera, sun=base.sun, sea=base.sea, islands=(seen,))
    crowd = Scene(camera=base.camera, sun=base.sun, sea=base.sea,
                  islands=(_far_island(-1e5),) * (MAX_ISLANDS - 1) + (seen,))
    a, b = render(alone, 0.0, 0), render(crowd, 0.0, 0)
    mask = a.surface == 1
    assert mask.sum() > 20
    assert np.array_equal(b.surface == MAX_ISLANDS, mask)
    assert np.array_equal(a.part, b.part) and np.array_equal(a.normal, b.normal, equal_nan=True)


# --------------------------------------------------------------------------- 5. and 8. tapes

def test_flipped_header_bit_is_refused_by_expose(capsys, tmp_path, tape_file):
    """5: tilt = 40.0 becomes 50.0 with one bit: the checksum covers the header."""
    data = bytearray(tape_file.read_bytes())
    i = data.index(b"tilt = 40.0") + len(b"tilt = ")
    data[i] ^= ord("4") ^ ord("5")
    bad = tmp_path / "b.tape"
    bad.write_bytes(bytes(data))
    code, _, err = run(capsys, "expose", bad, "--hours", "1", "-o", tmp_path / "a.png")
    one_line_error(code, err, "checksum")
    assert not (tmp_path / "a.png").exists()


# --------------------------------------------------------------------------- 6. absurd numbers

DEEP = "title = " + "[" * 1000 + "]" * 1000 + "\n"


@pytest.mark.parametrize("old, new, words", [
    ("eye_height = 2.0", "eye_height = " + "9" * 400, ["camera.eye_height", "400 digits"]),
    ("eye_height = 2.0", "eye_height = " + "9" * 5000, ["more than 4300 digits"]),   # past int()'s limit
    ("width = 1020", "width = " + "9" * 4000, ["camera.width", "at most 62 bits"]),
    ("width = 1020", 'width = "1020"', ["camera.width", "integer", "(str)"]),
    ("wavelength = 40.0", "wavelength = 1e308", ["sea.trains[0].wavelength", "at most"]),
    ("amplitude = 0.5", "amplitude = 1e308", ["sea.trains[0].amplitude"]),
    ("e = 0.004", "e = 1e308", ["islands[0].cliff.e"]),
    ("g = 0.0036", "g = 9.3e18", ["islands[0].cliff.g"]),
    ("e = 0.004", "e = 1e-308", ["islands[0].cliff.e"]),
    ("cliff_top = ", "cliff_top = -1e308 #", ["islands[0].cliff_top"]),
    ("l = 0.08", "l = 1e308", ["islands[0].cosines[0].l"]),
    ("m = 0.05", "m = -1e308", ["islands[0].cosines[0].m"]),
    ("eye_height = 2.0", "eye_height = 5e-324", ["camera.eye_height", "at least"]),
    ("radius = 0.75", "radius = 1e-7", ["sun.radius", "at least"]),
    ("azimuth = 1.1", "azimuth = 1e308", ["sun.azimuth"]),
    ("direction = 260.0", "direction = -1e308", ["sea.trains[0].direction"]),
    ("phase = 1.0", "phase = 1e300", ["sea.trains[1].phase"]),
    ("x = -300.0", "x = 1e300", ["islands[0].x"]),
    ("zy_min = -0.42", "zy_min = -1e308", ["camera.zy_min"]),
    ("title = ", DEEP + "#", ["nested"]),
    ("title = ", "a." * 100_000 + "b = 1\ntitle = ", ["nested"]),
])
def test_absurd_numbers_are_one_error_line(capsys, tmp_path, scene_file, old, new, words):
    """6 and 12: numbers that parse but are absurd, and nesting, name the user's field; no traceback."""
    replace_in(scene_file, old, new)
    start = time.perf_counter()
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png")
    one_line_error(code, err, *words)
    assert time.perf_counter() - start < 20
    assert not (tmp_path / "a.png").exists()


def test_counts_and_sizes_are_bounded(capsys, tmp_path, scene_file):
    """12: a scene with too many cosines, or larger than MAX_SCENE_BYTES, is refused before it is built."""
    text = scene_file.read_text()
    cos = "[[islands.cosines]]\namplitude = 1.0\nl = 0.1\nm = 0.1\n"
    head, tail = text.split("[[islands]]", 2)[:2]
    scene_file.write_text(head + "[[islands]]" + tail + cos * (MAX_COSINES + 1))
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png")
    one_line_error(code, err, "islands[0].cosines", f"at most {MAX_COSINES}")
    scene_file.write_text(text + cos * (MAX_SCENE_BYTES // len(cos) + 1))
    start = time.perf_counter()
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png")
    one_line_error(code, err, "KiB")
    assert time.perf_counter() - start < 5
    code, _, err = run(capsys, "film", scene_file, "--frames", MAX_CYCLE_FRAMES + 1, "-o", tmp_path / "f.mp4")
    one_line_error(code, err, "--frames", f"at most {MAX_CYCLE_FRAMES}")


# --------------------------------------------------------------------------- 7. paths

def test_long_names(capsys, tmp_path, scene_file):
    """7: a name longer than the file system allows is refused before the render; a legal long one works."""
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / ("a" * 300 + ".png"))
    one_line_error(code, err, "too long")
    legal = tmp_path / ("b" * 251 + ".png")
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", legal)
    assert code == 0, err
    assert legal.exists() and leftovers(tmp_path) == []


def test_unsearchable_folders(capsys, tmp_path, scene_file, monkeypatch):
    """7: a folder the user cannot search (PermissionError) is one error line, for inputs and outputs."""
    locked = tmp_path / "locked"
    locked.mkdir()
    if os.geteuid() != 0:
        locked.chmod(0)
    else:                                    # root searches everything: make the file system say no
        real_stat, real_open = os.stat, os.open
        import builtins
        real_bopen = builtins.open

        def guard(path):
            if str(path).startswith(str(locked) + os.sep):
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))

        monkeypatch.setattr(os, "stat", lambda p, *a, **k: (guard(p), real_stat(p, *a, **k))[1])
        monkeypatch.setattr(builtins, "open", lambda p, *a, **k: (guard(p), real_bopen(p, *a, **k))[1])
        monkeypatch.setattr(os, "open", lambda p, *a, **k: (guard(p), real_open(p, *a, **k))[1])
    try:
        for argv in (["render", locked / "s.toml", "-o", tmp_path / "a.png"],
                     ["render", scene_file, "--size", SMALL, "-o", locked / "a.png"],
                     ["render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png", "--tape", locked / "t"],
                     ["expose", locked / "t.tape", "--hours", "1", "-o", tmp_path / "a.png"]):
            code, _, err = run(capsys, *argv)
            one_line_error(code, err)
            assert "denied" in err or "not writable" in err, err
    finally:
        locked.chmod(0o755)
    assert not (tmp_path / "a.png").exists()


def test_scene_to_a_full_device():
    """7: `sunset scene > /dev/full` is one error line, not an OSError traceback."""
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full on this system")
    with open("/dev/full", "w") as full:
        proc = subprocess.run([sys.executable, "-m", "sunset", "scene"], stdout=full, stderr=subprocess.PIPE,
                              text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == ["sunset: error: cannot write to standard output "
                                                "(No space left on device)"]


# --------------------------------------------------------------------------- 9. a read-only install

def _read_only_runner(tmp_path):
    """A command prefix that runs Python with the package and HOME on read-only file systems, or None."""
    pkg = tmp_path / "install"
    home = tmp_path / "home"
    home.mkdir()
    shutil.copytree(ROOT / "sunset", pkg / "sunset", ignore=shutil.ignore_patterns("__pycache__"))
    env = {"HOME": str(home), "PATH": "/usr/bin:/bin", "PYTHONPATH": str(pkg), "PYTHONDONTWRITEBYTECODE": "1",
           "TMPDIR": str(tmp_path / "tmp"), "TQDM_DISABLE": "1"}
    (tmp_path / "tmp").mkdir()
    if os.geteuid() != 0:
        for p in [home, *pkg.rglob("*"), pkg]:
            p.chmod(0o555 if p.is_dir() else 0o444)
        return [], env
    if shutil.which("unshare") is None or subprocess.run(["unshare", "-m", "true"]).returncode != 0:
        return None
    script = (f"mount --bind -o ro {pkg} {pkg} && mount --bind -o ro {home} {home} && "
              f"exec env -i {' '.join(f'{k}={v}' for k, v in env.items())} \"$@\"")
    return ["unshare", "-m", "sh", "-c", script, "sh"], env


def test_read_only_install_without_a_writable_home(tmp_path):
    """9: the package and HOME read-only: every command still runs (Numba caches elsewhere or not at all)."""
    runner = _read_only_runner(tmp_path)
    if runner is None:
        pytest.skip("cannot make a read-only file system here (not root without unshare)")
    prefix, env = runner
    out = tmp_path / "out"
    out.mkdir()
    root = Path(sunset.__file__).parent
    twins = tuple(sorted("sunset." + ".".join(p.relative_to(root).with_suffix("").parts)
                         for p in root.rglob("*_numba.py")))          # every compiled module
    assert "sunset.vector.sincos_numba" in twins and len(twins) >= 10
    load = ("import importlib, os, numba; "
            f"[importlib.import_module(m) for m in {twins!r}]; "          # each @jit decorates with a cache
            "print(numba.config.CACHE_DIR)")
    # the render runs the NumPy kernels (compiling every twin takes a minute; the
    # decoration above is where a read-only install failed)
    for argv, extra in ((["-m", "sunset", "--version"], {}), (["-c", load], {}),
                        (["-m", "sunset", "render", "carlas-island", "--size", "24x16", "-o", out / "a.png"],
                         {"SUNSET_COMPILED": "0"})):
        cmd = [*prefix[:-1], prefix[-1]] if prefix else []
        full_env = {**env, **extra}
        if prefix:                           # env -i inside the namespace: pass the extras as arguments
            cmd = [*prefix, "env", *(f"{k}={v}" for k, v in extra.items()), sys.executable, *map(str, argv)]
        else:
            cmd = [sys.executable, *map(str, argv)]
        proc = subprocess.run(cmd, capture_output=True, text=True, env=None if prefix else full_env, cwd=out)
        assert proc.returncode == 0, proc.stderr[-2000:]
        assert proc.stderr == "", proc.stderr[-2000:]
        if argv[0] == "-c":
            assert proc.stdout.strip().startswith(str(tmp_path / "tmp")), proc.stdout
    assert (out / "a.png").exists()
    assert not [p for p in (tmp_path / "install").rglob("*") if p.suffix in (".nbi", ".nbc", ".pyc")]


# --------------------------------------------------------------------------- 10–12. bounded work

def test_sliver_window_is_refused_at_once(capsys, tmp_path, scene_file):
    """10: the issue's 53-second window (s 0..1e-6, zy -0.100001..-0.1) is refused before any work."""
    for old, new in (("s_min = -0.3", "s_min = 0.0"), ("s_max = 0.3", "s_max = 1e-6"),
                     ("zy_min = -0.42", "zy_min = -0.100001"), ("zy_max = 0.18", "zy_max = -0.1")):
        replace_in(scene_file, old, new)
    start = time.perf_counter()
    code, _, err = run(capsys, "render", scene_file, "--size", "64x64", "-o", tmp_path / "a.png")
    one_line_error(code, err, "sea samples per pixel", "zy_min")
    assert time.perf_counter() - start < 10


def test_predicted_samples_are_the_renderers():
    """10: the prediction is exact for the sea and a bound for the islands (a cheap check of the budget)."""
    from sunset.pipeline.frame import trace_direct

    for scene in (Scene.default().with_size(60, 40), Scene.default().with_size(17, 90).still()):
        info = {}
        trace_direct(scene, 0.7, info=info)
        work = predict_work(scene)
        assert info["sea_samples"] == work.sea_samples_per_line
        assert info["island_samples"] <= work.island_samples_bound
        assert work.sea_samples_per_pixel <= MAX_SEA_SAMPLES_PER_PIXEL


def test_memory_per_pixel_is_within_the_budget():
    """11: render, code and expose one frame: the peak grows by at most FRAME_BYTES_PER_PIXEL per pixel.

    Measured with the NumPy reference kernels (every array they make is
    NumPy's, which tracemalloc sees), the hungrier of the two paths.
    """
    from sunset.figures.paper import render_tape
    from sunset.pipeline.frame import expose

    per_pixel = measure_bytes_per_pixel(Scene.default())
    assert 100 < per_pixel <= FRAME_BYTES_PER_PIXEL, per_pixel
    scene = Scene.default().with_size(300, 240)
    expose(scene, render_tape(scene, 0.0, 2, 0).codes[0], 0.35)
    tracemalloc.start()
    try:
        expose(scene, render_tape(scene, 0.0, 2, 0).codes[0], 0.35)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= predict_work(scene).bytes


def test_huge_sizes_are_refused_up_front(capsys, tmp_path):
    """11: 8000x8000 exceeds the memory budget: refused before anything is allocated."""
    code, _, err = run(capsys, "render", "carlas-island", "--size", "8000x8000", "-o", tmp_path / "a.png")
    one_line_error(code, err, "too large", f"{MAX_PIXELS:,}")
    assert MAX_PIXELS * FRAME_BYTES_PER_PIXEL <= MAX_FRAME_BYTES


@settings(max_examples=200, deadline=None)
@given(zy_min=st.floats(-10, 10), height=st.floats(1e-9, 20), sigma=st.floats(1 / 16, 16),
       eye=st.floats(0.001, 10_000))
def test_budget_predicts_every_window(zy_min, height, sigma, eye):
    """10: any window is either refused or predicted within MAX_SEA_SAMPLES_PER_PIXEL (cheap: no rendering)."""
    from dataclasses import replace

    base = Scene.default()
    zy_max = min(zy_min + height, 10.0)
    if not zy_max > zy_min:
        return
    try:
        cam = replace(base.camera, zy_min=zy_min, zy_max=zy_max, sigma=sigma, eye_height=eye, width=64, height=64)
        scene = Scene(camera=cam, sun=base.sun, sea=base.sea, islands=())
        work = check_work(scene)
    except SunsetError as exc:
        assert "\n" not in str(exc)
        return
    assert work.sea_samples_per_pixel <= MAX_SEA_SAMPLES_PER_PIXEL
    assert work.bytes <= MAX_FRAME_BYTES


# --------------------------------------------------------------------------- 13–15. messages and leftovers

def test_messages_are_one_line_and_short(capsys, tmp_path, scene_file):
    """13: a newline in a path, a long value: one line, the value not echoed whole."""
    odd = tmp_path / "a\nb.toml"
    odd.write_text("[camera\n")
    code, _, err = run(capsys, "render", odd, "-o", tmp_path / "a.png")
    one_line_error(code, err, "malformed TOML")
    replace_in(scene_file, "eye_height = 2.0", "eye_height = '" + "x" * 500_000 + "'")
    code, _, err = run(capsys, "render", scene_file, "-o", tmp_path / "a.png")
    assert len(one_line_error(code, err, "camera.eye_height")) < 500


def test_smallest_sun_renders_without_warnings(capsys, tmp_path, scene_file):
    """13: a tiny sun at the limit renders with no RuntimeWarning (pytest makes warnings errors)."""
    from sunset.constants import MIN_SUN_RADIUS

    replace_in(scene_file, "radius = 0.75", f"radius = {MIN_SUN_RADIUS}")
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "--hours", "0.05", "-o", tmp_path / "a.png")
    assert code == 0, err


@pytest.mark.parametrize("argv, words", [
    (["render", "carlas-island", "-o", "a.png", "--tape", ""], ["--tape", "empty"]),
    (["figures", "--out", ""], ["--out", "empty"]),
    (["film", "carlas-island", "-o", "f.mp4", "--preview", ""], ["--preview", "empty"]),
    (["render", "", "-o", "a.png"], ["scene", "empty"]),
    (["render", "carlas-island", "--size", "8x8", "--time", "1e308", "-o", "a.png", "--tape", "a.tape"],
     ["t must be a time within"]),                # ω t overflowed: a traceback from math.remainder before
    (["export", "pov", "carlas-island", "--time", "-1e10", "-o", "a.pov"], ["t must be a time within"]),
])
def test_empty_paths_are_errors(capsys, tmp_path, monkeypatch, argv, words):
    """14: an empty path is an error, never ignored or read as the current folder."""
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv)
    one_line_error(code, err, *words)
    assert list(tmp_path.iterdir()) == []


def test_failed_png_leaves_no_tape(capsys, tmp_path, scene_file, monkeypatch):
    """15: the PNG fails after the tape was written: neither lands."""
    import sunset.io

    def broken(*a, **k):
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(sunset.io, "png_bytes", broken)
    code, _, err = run(capsys, "render", scene_file, "--size", SMALL, "-o", tmp_path / "a.png",
                       "--tape", tmp_path / "a.tape")
    one_line_error(code, err, "Input/output error")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.toml"]


def test_failed_preview_leaves_no_film(capsys, tmp_path, monkeypatch):
    """15: a failed preview leaves no MP4 (and no tape)."""
    from PIL import Image

    def broken(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", broken)
    code, _, err = run(capsys, "film", "carlas-island", "--frames", "2", "--size", "24x16", "--quiet",
                       "-o", tmp_path / "f.mp4", "--preview", tmp_path / "p.gif", "--tape", tmp_path / "f.tape")
    assert code == 2, err
    assert list(tmp_path.iterdir()) == []


def test_stale_temporaries_of_killed_runs_are_removed(tmp_path, scene_file):
    """15: SIGKILL leaves `.sunset-<pid>-….part.mp4`; the next write into the folder removes it."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".sunset-{dead.pid}-abcd.part.mp4"
    stale.write_bytes(b"half a film")
    old = time.time() - 3600
    os.utime(stale, (old, old))
    mine = tmp_path / f".sunset-{os.getpid()}-efgh.part.png"             # a live process's: kept
    mine.write_bytes(b"in progress")
    os.utime(mine, (old, old))
    assert main(["render", str(scene_file), "--size", SMALL, "-o", str(tmp_path / "a.png")]) == 0
    assert not stale.exists() and mine.exists()


# --------------------------------------------------------------------------- 15–16. signals

def _start_film(tmp_path, *extra):
    # long enough (400 frames) that even a fast, idle machine is still rendering when the signal comes
    return subprocess.Popen([sys.executable, "-m", "sunset", "film", "carlas-island", "--frames", "400",
                             "--size", "200x150", "--quiet", "-o", str(tmp_path / "f.mp4"), *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env={**os.environ, "SUNSET_WORKERS": "2"})


@pytest.mark.parametrize("sig, code, line", [
    (signal.SIGINT, 130, "sunset: interrupted"),
    (signal.SIGTERM, 143, "sunset: stopped by SIGTERM"),
])
def test_signals_give_one_line_and_no_files(tmp_path, sig, code, line):
    """15–16: Ctrl-C (to the whole process group, workers included) or SIGTERM mid-film: one line, no files."""
    proc = _start_film(tmp_path, "--tape", str(tmp_path / "f.tape"))
    try:
        time.sleep(6)                                    # the import and the first frames
        assert proc.poll() is None, proc.communicate()
        os.killpg(proc.pid, sig)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == code, err
    assert err.strip().splitlines() == [line]
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- fuzzing scene files

def _toml(value) -> str:
    """Any JSON-like value as TOML (inline tables and arrays), so that a fuzzed scene is always valid TOML."""
    import json
    import math as _m

    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if _m.isnan(value) else ("inf" if value > 0 else "-inf") if _m.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in value.items()) + "}"


HOSTILE_NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 5e-324, 1e-308, 1e308, -1e308, 9.3e18, 1e-7, 1e7, 0.5, -1.0, 2.0]),
    st.integers(-10**30, 10**30),
    st.just(10**400),
)
HOSTILE_VALUES = st.one_of(HOSTILE_NUMBERS, st.text(max_size=20), st.booleans(),
                           st.lists(st.integers(-3, 3), max_size=3), st.just({}), st.just({"x": 1}))


def _paths(node, prefix=()):
    """Every (path, value) of the scene's tables, for choosing which field to spoil."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list) and node and isinstance(node[0], dict):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))
    else:
        yield prefix, node


@st.composite
def spoiled_scenes(draw):
    """The default scene at a small size with a few fields replaced, removed, added or scaled."""
    def clean(node):                          # optional parts left out (None) are not written
        if isinstance(node, dict):
            return {k: clean(v) for k, v in node.items() if v is not None}
        return [clean(v) for v in node] if isinstance(node, list) else node

    data = clean(Scene.default().with_size(24, 16).to_dict())
    leaves = [p for p, _ in _paths(data)]
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(leaves))
        parent = data
        for key in path[:-1]:
            parent = parent[key]
        action = draw(st.sampled_from(["value", "scale", "nudge", "nudge", "nudge", "nudge", "drop", "unknown"]))
        old = parent.get(path[-1]) if isinstance(parent, dict) else None
        if action == "value":
            parent[path[-1]] = draw(HOSTILE_VALUES)
        elif action == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            parent[path[-1]] = type(old)(old * draw(st.sampled_from([-1, 0, 10, 1000, 10**6, 10**-6])))
        elif action == "nudge" and isinstance(old, float):           # mostly valid, unusual scenes
            parent[path[-1]] = old * draw(st.floats(0.25, 4)) + draw(st.floats(-1, 1))
        elif action == "drop" and path[-1] not in ("width", "height"):
            parent.pop(path[-1], None)
        elif action == "unknown":
            parent["zz_" + str(path[-1])] = 1.0
    return "\n".join(f"{json_key} = {_toml(v)}" for json_key, v in data.items()) + "\n"


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=spoiled_scenes())
def test_fuzzed_scene_files_exit_0_or_2(tmp_path_factory, text):
    """Proof: a spoiled scene file renders (exit 0) or is one error line (exit 2), never a traceback,
    never a partial output, within the predicted budget."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("fuzz")
    scene_path = folder / "s.toml"
    scene_path.write_text(text)
    out, tape = folder / "a.png", folder / "a.tape"
    err = io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stderr(err):
        code = main(["render", str(scene_path), "-o", str(out), "--tape", str(tape), "--reflections", "2"])
    assert code in (0, 2), err.getvalue()
    if code == 2:
        lines = err.getvalue().strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("sunset: error:"), err.getvalue()
        assert not out.exists() and not tape.exists()
    else:
        assert out.exists() and tape.exists()
        scene = Scene.from_toml(scene_path)
        assert predict_work(scene).sea_samples_per_pixel <= MAX_SEA_SAMPLES_PER_PIXEL
    assert leftovers(folder) == []
    assert time.perf_counter() - start < 60


def test_export_refuses_to_overwrite_its_scene(capsys, tmp_path):
    """2 (a sibling): `export pov x.pov -o x.pov`, also through a symbolic link, would replace the scene it reads."""
    scene = tmp_path / "scene.pov"                      # a scene file may have any name
    scene.write_text(Scene.default().to_toml())
    before = scene.read_bytes()
    code, _, err = run(capsys, "export", "pov", scene, "-o", scene)
    one_line_error(code, err, "the scene", "same file")
    (tmp_path / "link.pov").symlink_to(scene)
    code, _, err = run(capsys, "export", "pov", scene, "-o", tmp_path / "link.pov")
    one_line_error(code, err, "same file")
    assert scene.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.pov", "scene.pov"]
    assert run(capsys, "export", "pov", scene, "-o", tmp_path / "out.pov")[0] == 0


# ---------------------------------------------------------------- hours before sunset: ±12 h everywhere
@pytest.mark.parametrize("argv, option", [
    (["render", "carlas-island", "--hours", "13", "--size", SMALL], "--hours"),
    (["render", "carlas-island", "--hours", "-1e300", "--shading", "rgb", "--size", SMALL], "--hours"),
    (["film", "carlas-island", "--from-hours", "100000", "--frames", "2", "--size", SMALL], "--from-hours"),
    (["film", "carlas-island", "--to-hours", "-12.5", "--frames", "2", "--size", SMALL], "--to-hours"),
    (["film", "carlas-island", "--to-hours", "12.01", "--shading", "rgb", "--frames", "2", "--size", SMALL],
     "--to-hours"),
    (["player", "carlas-island", "--from-hours", "13", "--frames", "2", "--size", SMALL], "--from-hours"),
])
def test_hours_beyond_half_a_day_of_sunset_are_refused_before_any_work(capsys, tmp_path, monkeypatch, argv,
                                                                         option):
    # the sun goes round its circle in 24 h: every position is within ±12 h of sunset; tracing must not start
    import sunset.pipeline.frame as frame

    # every traced frame's depth buffer: no frame is traced before the hours are checked
    monkeypatch.setattr(frame, "depth_buffer", lambda *a, **k: pytest.fail("rendered before the hours were checked"))
    monkeypatch.setattr(frame, "island_pass", lambda *a, **k: pytest.fail("rendered before the hours were checked"))
    suffix = {"render": ".png", "film": ".mp4", "player": ".html"}[argv[0]]
    out = tmp_path / ("out" + suffix)
    code, _, err = run(capsys, *argv, "-o", out)
    one_line_error(code, err, option, "±12 hours")
    assert not out.exists() and not leftovers(tmp_path)


def test_expose_refuses_hours_beyond_half_a_day_before_reading_the_tape(capsys, tmp_path):
    # the tape does not exist: the hours are checked first
    code, _, err = run(capsys, "expose", tmp_path / "no.tape", "--hours", "-40", "-o", tmp_path / "e.png")
    one_line_error(code, err, "--hours", "±12 hours")


@pytest.mark.parametrize("hours", [12.0, -12.0, 0.0])
def test_hours_at_the_ends_of_the_half_day_are_pictures(capsys, tmp_path, hours):
    out = tmp_path / "r.png"
    code, _, err = run(capsys, "render", "carlas-island", "--hours", hours, "--size", SMALL, "-o", out, "--quiet")
    assert code == 0, err
    assert out.stat().st_size > 0
