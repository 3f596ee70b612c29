"""Text from a scene file is data wherever it goes (sunset.escape; issue 33).

Each format's function is tested with hostile strings (control characters,
line breaks of every kind, comment and string terminators, directives, text
that was not UTF-8) and with hypothesis over all of Unicode; then the
writers: POV-Ray itself parses an exported scene whose title and island
names carry ``#fopen``/``#write``/``#include`` after a line break (and, as a
control, the same directives unescaped, which it does run), the player with
the title ``<!--<script>``, the PNG text chunks, the terminal. The scene's
own check (length and character class) is tested against its definition.
"""

from __future__ import annotations

import json
import os
import subprocess
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sunset.constants import MAX_TEXT_CHARS
from sunset.errors import SunsetError, shown
from sunset.escape import html_text, metadata_text, pov_comment, pov_string, script_json, terminal_text, visible
from sunset.figures.povray import povray_path
from sunset.model.scene import Scene, check_text

DIRECTIVES = '#fopen F "pwned.txt" write #write(F, "owned") #fclose F #debug "RAN\\n"'

#: Strings that break a format when written raw.
HOSTILE = [
    f"title\n{DIRECTIVES}\n",
    f"title\r{DIRECTIVES}\r",
    f"title\r\n#include \"/etc/hostname\"\n",
    "*/ /* // \" ' \\ \\\" ` $ { } ; #end #declare",
    "<!--<script>", "</script><script>alert(1)</script>", "<![CDATA[ ]]> &amp; &#0; &lt;",
    "\x00\x01\x07\x08\x0b\x0c\x1a\x1b[2J\x1b]0;pwned\x07\x7f\x85\x9b",
    "\u2028\u2029\u202e\u2066\u200b\ufeff\ud800\udcff\ue000\U000e0001",
    b"\xff\xfe\n#include \"x\"\xc0\xaf".decode("utf-8", "surrogateescape"),
    "é漢字🙂 ok",
]

text = st.text(st.characters(codec=None), max_size=60) | st.sampled_from(HOSTILE)


@given(text)
@settings(max_examples=300, deadline=None)
def test_pov_comment_is_printable_ascii(t):
    out = pov_comment(t)
    assert all(" " <= ch <= "~" for ch in out), out          # no byte POV-Ray could take for a line end
    assert pov_comment(out) == out                             # idempotent on its own output


@given(text)
@settings(max_examples=300, deadline=None)
def test_pov_string_is_one_literal(t):
    out = pov_string(t)
    assert out[0] == out[-1] == '"' and all(" " <= ch <= "~" for ch in out)
    body = out[1:-1]
    i = 0
    while i < len(body):                                      # every quote and backslash is escaped
        if body[i] == "\\":
            assert body[i + 1] in '\\"u', body
            i += 6 if body[i + 1] == "u" else 2
        else:
            assert body[i] != '"'
            i += 1


@given(text)
@settings(max_examples=300, deadline=None)
def test_html_text_has_no_markup(t):
    out = html_text(t)
    assert not set(out) & set("<>\"'") and all(ch.isprintable() or ch in "\n\t" for ch in out)
    assert "&" not in out.replace("&amp;", "").replace("&lt;", "").replace("&gt;", "").replace(
        "&quot;", "").replace("&#x27;", "")


#: JSON reads two escaped surrogates back as one character: strings without them for the round trip.
json_text = st.text(st.characters(codec=None, exclude_categories=("Cs",)), max_size=40) | st.sampled_from(HOSTILE[:7])


@given(st.recursive(json_text | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.none(),
                    lambda kids: st.lists(kids, max_size=4) | st.dictionaries(json_text, kids, max_size=4),
                    max_leaves=12))
@settings(max_examples=200, deadline=None)
def test_script_json_cannot_leave_its_element(data):
    """No '<' at all: the HTML tokenizer stays in the script's data state until the real end tag."""
    out = script_json(data)
    assert not set(out) & set("<>&") and out.isascii()
    assert json.loads(out) == data


@given(text)
@settings(max_examples=300, deadline=None)
def test_metadata_and_terminal_text(t):
    out = metadata_text(t)
    assert "\x00" not in out and all(ch.isprintable() or ch == "\n" for ch in out)
    out.encode("utf-8")                                       # no surrogate left
    assert metadata_text(out) == out
    line = terminal_text(t)
    assert line.isprintable() and (line == t or line == repr(t))
    assert shown(t).isprintable()


def test_visible_shows_what_was_there():
    assert visible("a\nb\x1b\u202e\udcff🙂") == "a\\nb\\x1b\\u202e\\udcff🙂"
    assert visible(b"ok\xff") == "ok\\udcff"
    assert pov_comment("é\n") == "\\xe9\\n"


# --------------------------------------------------------------------------- the scene's text fields

@given(st.text(st.characters(codec=None), max_size=MAX_TEXT_CHARS + 20))
@settings(max_examples=300, deadline=None)
def test_scene_text_is_checked_against_its_definition(t):
    ok = len(t) <= MAX_TEXT_CHARS and all(ch.isprintable() for ch in t)
    try:
        check_text("title", t)
        accepted = True
    except SunsetError as exc:
        accepted = False
        assert "\n" not in str(exc) and str(exc).startswith("title must") and str(exc).isprintable()
    assert accepted == ok


@pytest.mark.parametrize("bad", [t for t in HOSTILE if not t.isprintable()] + ["x" * (MAX_TEXT_CHARS + 1), 5, None])
def test_hostile_scene_text_is_a_one_line_error(bad, tmp_path):
    base = Scene.default()
    with pytest.raises(SunsetError, match=r"^title must"):
        replace(base, title=bad)
    with pytest.raises(SunsetError, match=r"^name must"):                 # the island checks its own name
        replace(base.islands[1], name=bad)


def test_a_scene_file_with_a_line_break_in_its_title_is_refused(tmp_path):
    import sys

    text = Scene.default().to_toml().replace("title = ", 'title = "a\\n#include \\"/etc/hostname\\"" # ', 1)
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "s.pov"
    done = subprocess.run([sys.executable, "-m", "sunset", "export", "pov", str(path), "-o", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "title must hold printable" in done.stderr
    assert not out.exists()


# --------------------------------------------------------------------------- the writers

def hostile_scene(title: str, name: str) -> Scene:
    """The default scene with a title and an island name the scene's own check would refuse (set past it)."""
    scene = Scene.default().with_size(8, 8)
    island = replace(scene.islands[0])                            # a copy, its name then set past the check
    object.__setattr__(island, "name", name)
    object.__setattr__(scene, "islands", (island, *scene.islands[1:]))
    object.__setattr__(scene, "title", title)
    return scene


def run_povray(pov_text: str, folder) -> subprocess.CompletedProcess:
    (folder / "scene.pov").write_text(pov_text, encoding="utf-8", errors="surrogateescape")
    return subprocess.run([povray_path(), "+Iscene.pov", "+Oout.png", "+W8", "+H8", "-A", "+FN", "-D", "-V",
                           "+WT1"], capture_output=True, text=True, timeout=300, cwd=folder,
                          env={**os.environ, "HOME": str(folder)})


@pytest.mark.skipif(povray_path() is None, reason="povray is not installed (apt-get install povray)")
def test_povray_runs_no_directive_from_a_title_or_a_name(tmp_path):
    """POV-Ray parses and renders the exported scene; nothing is written, included or printed from the text."""
    from sunset.model.pov import pov_scene

    control = tmp_path / "control"
    control.mkdir()
    raw = run_povray(f"#version 3.7;\n// {HOSTILE[0]}", control)          # the old export: the comment ends
    assert (control / "pwned.txt").read_text() == "owned" and "RAN" in raw.stderr + raw.stdout
    for k, title in enumerate(HOSTILE):
        folder = tmp_path / f"case{k}"
        folder.mkdir()
        text = pov_scene(hostile_scene(title, HOSTILE[(k + 1) % len(HOSTILE)]))
        done = run_povray(text, folder)
        assert done.returncode == 0, done.stderr[-2000:]
        assert sorted(p.name for p in folder.iterdir()) == ["out.png", "scene.pov"]
        assert "RAN" not in done.stdout + done.stderr and "hostname" not in done.stderr


@pytest.mark.skipif(povray_path() is None, reason="povray is not installed (apt-get install povray)")
def test_povray_reads_a_string_back(tmp_path):
    """pov_string's literal is the text again in POV-Ray (characters beyond U+FFFF and surrogates as U+FFFD)."""
    cases = ["plain", 'quote " and \\ backslash', "line\nbreak\r\t", "é漢字", "*/ #include \"x\" //"]
    lines = ["#version 3.7;", "global_settings { charset utf8 assumed_gamma 1 }"]
    for k, t in enumerate(cases):
        codes = ", ".join(str(ord(ch)) for ch in t)
        lines += [f"#declare S = {pov_string(t)};", f"#declare C = array[{len(t)}] {{ {codes} }};",
                  f"#if (strlen(S) != {len(t)}) #error \"length {k}\" #end",
                  f"#for (i, 1, {len(t)}) #if (asc(substr(S, i, 1)) != C[i - 1]) #error \"char {k}\" #end #end"]
    lines.append('#debug "STRINGS OK\\n"')
    done = run_povray("\n".join(lines) + "\n", tmp_path)
    assert "STRINGS OK" in done.stdout + done.stderr, done.stderr[-2000:]


def test_the_player_starts_whatever_its_title(tmp_path):
    """The data element holds no '<' (the tokenizer cannot leave it) and reads back the title; the page's text
    and the <title> show it escaped."""
    from sunset.recorder.player import PLAYER_FORMAT, player_html, read_player_data

    for title in ["<!--<script>", "</script><script>alert(1)</script>", "a & b \" ' <b>"]:
        data = {"format": PLAYER_FORMAT, "title": title, "scene": f'title = "{title}"', "codes": []}
        page = player_html(data)
        start = page.index('<script type="application/json"')
        body = page[page.index(">", start) + 1:]
        assert "<" not in body[:body.index("</script>")]
        assert read_player_data(page) == data
        head = page[:start]
        assert title not in head and html_text(title) in head
        assert head.count("<script") == 0 and page.count("</script>") == page.count("<script") == 2


def test_png_text_chunks_carry_the_text_as_data(tmp_path):
    import io

    import numpy as np
    from PIL import Image

    from sunset.io import png_bytes

    values = {f"sunset:k{k}": t for k, t in enumerate(HOSTILE)}
    img = Image.open(io.BytesIO(png_bytes(np.zeros((2, 2, 3), np.uint8), values)))
    img.load()
    for key, t in values.items():
        assert img.text[key] == metadata_text(t) and "\x00" not in img.text[key]
