r"""The one LaTeX escaper: user text (titles, citations, reasons) written into LaTeX.

>>> escape("k_i at 100% & {x}")
'k\\_i at 100\\% \\& \\{x\\}'
>>> escape("{x}", balanced=True)
'\\textbraceleft{}x\\textbraceright{}'
"""

from __future__ import annotations

import re

#: Each character LaTeX treats specially in running text, and what writes it as text.
#: ``< > |`` are no commands, but the default (OT1) text font has no glyphs for them.
SPECIALS: dict[str, str] = {
    "\\": r"\textbackslash{}",
    "{": r"\{",
    "}": r"\}",
    "$": r"\$",
    "&": r"\&",
    "%": r"\%",
    "#": r"\#",
    "_": r"\_",
    "^": r"\textasciicircum{}",
    "~": r"\textasciitilde{}",
    "<": r"\textless{}",
    ">": r"\textgreater{}",
    "|": r"\textbar{}",
}

#: The same for text whose braces another reader counts (a BibTeX field, whose end
#: BibTeX finds by matching braces; the ``\text{...}`` of a notebook's LaTeX repr):
#: braces as commands, so that an escaped brace is never counted, and only LaTeX's ten
#: special characters (BibTeX styles and MathJax pass ``< > |`` through as text).
BALANCED: dict[str, str] = {
    **{char: text for char, text in SPECIALS.items() if char not in "<>|"},
    "{": r"\textbraceleft{}",
    "}": r"\textbraceright{}",
}

_PATTERNS = {
    False: re.compile("|".join(map(re.escape, SPECIALS))),
    True: re.compile("|".join(map(re.escape, BALANCED))),
}


def escape(text: str, *, balanced: bool = False) -> str:
    """``text`` with LaTeX's special characters escaped (``SPECIALS``), or with braces
    that stay balanced for a reader that counts them (``balanced``: ``BALANCED``)."""
    table = BALANCED if balanced else SPECIALS
    return _PATTERNS[balanced].sub(lambda m: table[m.group()], text)
