"""The one plain-text table printer: the verdict table, the diff of two runs, and any
other table the command line prints.

>>> print(text_table(("case", "verdict"), [("euler", "verified"), ("yehia-b", "refuted")]))
case     verdict
-------  --------
euler    verified
yehia-b  refuted
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence


def text_table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    """The rows under the header, each column as wide as its widest cell, columns two
    spaces apart, a rule of dashes under the header, no trailing spaces."""
    lines = [tuple(header), *(tuple(str(c) for c in row) for row in rows)]
    widths = [max(len(line[i]) for line in lines) for i in range(len(header))]
    out = [
        "  ".join(c.ljust(w) for c, w in zip(line, widths, strict=True)).rstrip() for line in lines
    ]
    out.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(out)
