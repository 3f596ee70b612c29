"""Text from a scene file is data wherever it goes: one function per format it reaches.

A scene's title and its islands' names come from a file anyone may have
written. The scene loader already holds them to a length and a character
class (:func:`sunset.model.scene.check_text`), but every format that carries
them is written as if it had not: each has its one function here, and every
writer of that format calls it.

==========================  ==============================================  ==========================
format                      what could turn text into code or break it       function
==========================  ==============================================  ==========================
POV-Ray comment ``//``      a line break ends the comment: ``#fopen``,      :func:`pov_comment`
                            ``#write``, ``#include`` on the next line run
POV-Ray string ``"…"``      a quote ends it, a backslash escapes            :func:`pov_string`
HTML text and attributes    ``<``, ``&``, quotes                            :func:`html_text`
JSON in a ``<script>``      ``</script>`` ends it; ``<!--`` then            :func:`script_json`
                            ``<script`` keeps it from ever ending
PNG iTXt, WebP/GIF EXIF,    NUL ends a C string; control characters;        :func:`metadata_text`
MP4 tags                    text that is not UTF-8
the terminal                escape sequences (colours, the cursor, the      :func:`terminal_text`
                            title), bidirectional overrides, line breaks
==========================  ==============================================  ==========================

Characters a format cannot carry are written as Python writes them in a
string literal (``\\n``, ``\\x1b``, ``\\u202e``, ``\\udcff`` for a byte that
was not UTF-8), so that what was there stays readable; each function is
idempotent on its own output where that matters (the PNG writer may see a
text twice).
"""

from __future__ import annotations

import html
import json

from .errors import terminal_text  # the terminal's function lives where every error message is made

__all__ = ["pov_comment", "pov_string", "html_text", "script_json", "metadata_text", "terminal_text", "visible"]


def _escape(ch: str) -> str:
    o = ord(ch)
    if o < 0x100:
        return {"\n": "\\n", "\r": "\\r", "\t": "\\t"}.get(ch, f"\\x{o:02x}")
    return f"\\u{o:04x}" if o < 0x10000 else f"\\U{o:08x}"


def visible(text, keep=None) -> str:
    """``text`` with every character that is not printable (``str.isprintable``), or not kept by ``keep``, escaped.

    A character is written as in a Python string literal (``\\n``,
    ``\\x07``, ``\\u202e``); printable text is unchanged. ``bytes`` are
    decoded as UTF-8 with their undecodable bytes kept as surrogates, so
    that they show as ``\\udcXX``.
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8", "surrogateescape")
    text = str(text)
    ok = keep or str.isprintable
    return "".join(ch if ok(ch) else _escape(ch) for ch in text)


def _ascii_printable(ch: str) -> bool:
    return " " <= ch <= "~"


def pov_comment(text) -> str:
    """``text`` as the body of one POV-Ray ``//`` comment: printable ASCII only, so no byte can end the line.

    POV-Ray ends a line comment at a line feed or a carriage return (and
    reads the file as bytes: a stray byte could be either in another
    character set); everything outside ``' '``–``'~'`` is escaped, so the
    text stays on its line and a directive after it is never read.
    """
    return visible(text, _ascii_printable)


def pov_string(text) -> str:
    """``text`` as a POV-Ray string literal, quotes included: ``\\`` and ``"`` escaped, printable ASCII only.

    The other characters are written as POV-Ray's ``\\uXXXX`` (a character
    beyond U+FFFF, or a surrogate, as U+FFFD), so the literal is one line
    of ASCII that POV-Ray reads back as ``text``.
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8", "surrogateescape")
    out = []
    for ch in str(text):
        if ch in '\\"':
            out.append("\\" + ch)
        elif _ascii_printable(ch):
            out.append(ch)
        else:
            o = ord(ch)
            out.append(f"\\u{o if o < 0x10000 and not 0xD800 <= o < 0xE000 else 0xFFFD:04x}")
    return '"' + "".join(out) + '"'


def html_text(text) -> str:
    """``text`` as HTML text or a quoted attribute value: ``& < > " '`` as entities, control characters escaped.

    Control characters, format characters, surrogates and unassigned code
    points (not printable) are shown escaped (``\\x1b``); line breaks and
    tabs are kept as the whitespace they are in HTML.
    """
    shown = visible(text, lambda ch: ch.isprintable() or ch in "\n\t")
    return html.escape(shown, quote=True)


def script_json(data) -> str:
    """``data`` as JSON that can sit inside an HTML ``<script>`` element and never ends or escapes it.

    ASCII only (``ensure_ascii``: U+2028 and U+2029 too), no NaN, and every
    ``<``, ``>`` and ``&`` as a JSON escape (``\\u003c`` …): the HTML
    parser then sees no ``</script>``, no ``<!--`` (which, followed by
    ``<script``, would keep the element from ever ending) and no character
    reference. ``JSON.parse`` reads back the same strings.
    """
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def metadata_text(text) -> str:
    """``text`` for an image's or a film's text tag (PNG iTXt, EXIF, MP4 ``comment``): printable UTF-8 and line feeds.

    Every other character (NUL, which ends a C string in some readers,
    control characters, surrogates that are not UTF-8) is escaped; the
    result encodes as UTF-8. Idempotent: what it returns comes back unchanged.
    """
    return visible(text, lambda ch: ch.isprintable() or ch == "\n")
