"""Numbers in ×10ⁿ notation for the sunset book (no dependencies).

``scientific("6.7e-06")`` is ``"6.7 × 10⁻⁶"``. Used by ``sunset_book.py``
(the Sphinx side) on every page's prose, and tested in tests/test_book.py.
"""

from __future__ import annotations

import re

_SUPERSCRIPT = str.maketrans("0123456789+-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻")

#: A number in e-notation standing alone in running text: a mantissa with an
#: optional sign and fraction, "e" or "E", and a signed exponent (Python's
#: format always writes the exponent's sign).
E_NUMBER = re.compile(r"(?<![\w.])([+\-−]?\d+(?:\.\d+)?)[eE]([+\-]\d+)(?![\w.])")


def scientific(text: str) -> str:
    """Rewrite every e-notation number in ``text`` as ``m × 10ⁿ``.

    ``"6.7e-06"`` becomes ``"6.7 × 10⁻⁶"``, ``"1e+03"`` becomes ``"10³"``
    (a mantissa of exactly 1 is dropped), ``"-2.50e+00"`` becomes ``"-2.50"``
    (a zero exponent is dropped) and leading zeros of the exponent go. Text
    without such a number is returned unchanged.
    """

    def one(match: re.Match) -> str:
        mantissa, exponent = match.group(1), int(match.group(2))
        if exponent == 0:
            return mantissa
        power = "10" + str(exponent).translate(_SUPERSCRIPT)
        if mantissa.lstrip("+") == "1":
            return power
        if mantissa.lstrip("+-−") == "1":
            return mantissa[0] + power
        return f"{mantissa} × {power}"

    return E_NUMBER.sub(one, text)
