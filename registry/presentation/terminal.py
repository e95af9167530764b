"""The width of the terminal the command line prints to.

Every renderer of plain text takes the width it may use and computes nothing from the
environment; the facade asks here when no width is given.
"""

from __future__ import annotations

import shutil

#: Where standard output is no terminal (a pipe, a file, the tests) and $COLUMNS is not
#: set: the width of a normal terminal.
DEFAULT_WIDTH = 80
#: Below this a table cannot hold its columns: a narrower terminal gets this width.
NARROWEST = 40


def terminal_width() -> int:
    """``$COLUMNS`` if set, else the width of the terminal when standard output is one,
    else 80; never below 40."""
    return max(NARROWEST, shutil.get_terminal_size((DEFAULT_WIDTH, 24)).columns)
