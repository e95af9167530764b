"""The one plain-text table printer: the verdict table, the diff of two runs, and every
listing the command line prints.

Columns are left-aligned, two spaces apart, under a rule of dashes. A table wider than
``width`` narrows the columns it may wrap (``wrap``: long text, such as a title or an
expression) and wraps their cells onto more lines (after a space or a hyphen); the
other columns (identifiers, numbers, verdicts) keep their width. A table keyed by a
long identifier (a case id of 47 characters) is grouped: the identifier heads its rows
(``grouped_table``). Plain text only, never ANSI codes; no trailing spaces.

>>> print(text_table(("case", "verdict"), [("euler", "verified"), ("yehia-b", "refuted")]))
case     verdict
-------  --------
euler    verified
yehia-b  refuted
>>> print(text_table(("case", "title"), [("euler", "The free rigid body")], width=18, wrap={1}))
case   title
-----  -----------
euler  The free
       rigid body
"""

from __future__ import annotations

import re
import sys
import textwrap
from collections.abc import Collection, Iterable, Sequence

#: Between two columns.
GAP = "  "
#: The narrowest a wrapped column gets (its header may be wider: a header never wraps).
NARROWEST = 8
#: The indentation of a group's rows under its heading, and of a heading's next lines.
INDENT = "  "
#: An equation or inequality stays on one line: "a2 = a3", never "a2 =" then "a3".
_RELATION = re.compile(r" (=|<=|>=|!=|<|>) ")
#: What holds a relation's spaces while its text is wrapped (a private-use character).
_GLUE = "\ue000"


def text_table(
    header: Sequence[str],
    rows: Iterable[Sequence[object]],
    *,
    width: int | None = None,
    wrap: Collection[int] = (),
) -> str:
    """The rows under the header, each column as wide as its widest cell; where that is
    wider than ``width`` (None: no limit), the columns numbered in ``wrap`` are narrowed,
    the widest first, and their cells wrapped."""
    cells = [tuple(_text(c) for c in row) for row in rows]
    widths = column_widths(header, cells, width=width, wrap=wrap)
    lines = _top(header, widths) + [line for row in cells for line in _row_lines(row, widths, wrap)]
    return "\n".join(lines)


def grouped_table(
    heading: str,
    header: Sequence[str],
    groups: Iterable[tuple[str, Sequence[Sequence[object]]]],
    *,
    width: int | None = None,
    wrap: Collection[int] = (),
) -> str:
    """Rows in groups, each under its own heading line (a case id, and what holds for
    the whole case), the table's columns aligned across every group.

    ``heading`` names what the headings are (``case``); the header and the rows are
    indented under it. A heading wider than ``width`` is wrapped, its next lines
    indented twice. A group without rows is its heading alone.

    >>> print(grouped_table("case", ("claim", "verdict"), [("euler", [("T", "verified")])]))
    case
      claim  verdict
      -----  --------
    euler
      T      verified
    """
    texts = [(title, [tuple(_text(c) for c in row) for row in rows]) for title, rows in groups]
    cells = [row for _, rows in texts for row in rows]
    inner = None if width is None else max(width - len(INDENT), 1)
    widths = column_widths(header, cells, width=inner, wrap=wrap)
    lines = [heading, *(INDENT + line for line in _top(header, widths))]
    for title, rows in texts:
        lines.extend(wrapped(title, width, subsequent=INDENT * 2).splitlines())
        lines.extend(INDENT + line for row in rows for line in _row_lines(row, widths, wrap))
    return "\n".join(line.rstrip() for line in lines)


def column_widths(
    header: Sequence[str],
    cells: Sequence[Sequence[str]],
    *,
    width: int | None = None,
    wrap: Collection[int] = (),
) -> list[int]:
    """Each column's width: its widest line, unless the table is wider than ``width``;
    then the widest of the ``wrap`` columns loses a character at a time, none going
    below its header or ``NARROWEST``, until the table fits (or none can give more)."""
    widths = [
        max([len(name), *(len(line) for row in cells for line in row[i].splitlines())])
        for i, name in enumerate(header)
    ]
    if width is None:
        return widths
    floor = {i: max(len(header[i]), min(NARROWEST, widths[i])) for i in wrap}
    excess = sum(widths) + len(GAP) * (len(widths) - 1) - width
    while excess > 0:
        give = [i for i in floor if widths[i] > floor[i]]
        if not give:
            break
        widest = max(give, key=lambda i: (widths[i], -i))
        widths[widest] -= 1
        excess -= 1
    return widths


def wrapped(text: str, width: int | None, *, indent: str = "", subsequent: str = "") -> str:
    """``text`` wrapped to ``width`` (None: as it is), each line after a space or a
    hyphen; the first line starts with ``indent``, the next ones with ``subsequent``
    (a hanging indent). A word longer than the line is broken. Line breaks in the text
    are kept.

    >>> print(wrapped("note: the drift of I is flat", 18, indent="  ", subsequent="    "))
      note: the drift
        of I is flat
    """
    if width is None:
        width = sys.maxsize
    out = []
    for i, paragraph in enumerate(text.splitlines() or [""]):
        first = indent if i == 0 else subsequent
        lines = _wrap(
            paragraph,
            max(width, len(first) + 1),
            initial_indent=first,
            subsequent_indent=subsequent,
        )
        out.extend(lines or [first.rstrip()])
    return "\n".join(out)


def _wrap(
    text: str, width: int, initial_indent: str = "", subsequent_indent: str = ""
) -> list[str]:
    """textwrap.wrap, breaking after a space or a hyphen but not around a relation's
    sign (``=``, ``<=``, ...); a word longer than the line is broken."""
    glued = _RELATION.sub(lambda m: f"{_GLUE}{m[1]}{_GLUE}", text)
    lines = textwrap.wrap(
        glued, width, initial_indent=initial_indent, subsequent_indent=subsequent_indent
    )
    return [line.replace(_GLUE, " ") for line in lines]


def _text(value: object) -> str:
    return "" if value is None else str(value)


def _cell_lines(text: str, width: int, wraps: bool) -> list[str]:
    """A cell as the lines it takes in a column ``width`` wide (its own lines where
    the column does not wrap)."""
    lines = text.splitlines() or [""]
    if not wraps:
        return lines
    return [part for line in lines for part in (_wrap(line, width) or [""])]


def _joined(parts: Sequence[str], widths: Sequence[int]) -> str:
    return GAP.join(p.ljust(w) for p, w in zip(parts, widths, strict=True)).rstrip()


def _top(header: Sequence[str], widths: Sequence[int]) -> list[str]:
    """The header and the rule of dashes under it."""
    return [_joined(header, widths), GAP.join("-" * w for w in widths)]


def _row_lines(row: Sequence[str], widths: Sequence[int], wrap: Collection[int]) -> list[str]:
    """One row as the lines its tallest cell needs."""
    parts = [_cell_lines(c, w, i in wrap) for i, (c, w) in enumerate(zip(row, widths, strict=True))]
    height = max(len(p) for p in parts)
    return [_joined([p[k] if k < len(p) else "" for p in parts], widths) for k in range(height)]
