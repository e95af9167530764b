"""The size limits of the case-file language: what one expression, and all the
expressions of one case file together, may hold.

Each limit is checked before the work it bounds is done (on the raw text, on the
syntax tree, or before each sympy step), so a hostile text is refused in well
under a second whatever its content. ``parser`` applies them; the table of
limits in docs/case-format.md lists each one. The limits on a case file itself (bytes,
claims, nesting of the TOML) stay with ``casefile``.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ExpressionError

# Limits on one expression.

#: Longest expression text, in characters.
MAX_LENGTH = 20_000
#: Most expression nodes (names, numbers, operations, calls) in one expression.
MAX_NODES = 5_000
#: Deepest nesting (parentheses, calls, powers, unary signs); sums and products
#: of many terms do not count as nesting.
MAX_DEPTH = 100
#: Longest number literal, in characters, and largest decimal exponent in one.
MAX_DIGITS = 100
#: Largest |exponent| of ``**`` when the exponent is a number.
MAX_EXPONENT = 1000
#: Largest denominator of a rational exponent of ``**``.
MAX_DENOMINATOR = 100
#: Most digits a number built by powers and products may reach (Python prints ints
#: of at most 4300 digits, so every number a parse yields can be printed again).
MAX_RESULT_DIGITS = 4_000
#: Most digits of a number whose root is taken (sympy factors it, which takes time).
MAX_ROOT_DIGITS = 300
#: Most work that the ``diff`` calls of one expression may do together: the sum,
#: over the expressions differentiated, of their tree nodes plus the squared
#: length of each product in them (the product rule makes k terms of k factors).
MAX_DIFF_WORK = 10_000

# Limits on all the expressions of one case file together (a ``ParseBudget``), so that
# a file of many expressions, each within the limits above, is refused as fast.

#: Most expression parts (as MAX_NODES counts them) in one case file.
MAX_CASE_PARTS = 5_000
#: Most digits of the numbers whose roots the expressions of one case file take
#: (sympy factors each such number, which takes time even when it is small).
MAX_CASE_ROOT_DIGITS = 1_000
#: Most differentiation work (as MAX_DIFF_WORK counts it) in one case file.
MAX_CASE_DIFF_WORK = 10_000
#: Largest denominator q of a rational multiple p/q of pi at which sin, cos and tan
#: are evaluated (sympy writes cos(pi/120) as nested radicals, which takes time);
#: beyond it they are kept as written, with the same value.
MAX_TRIG_DENOMINATOR = 12


@dataclass
class ParseBudget:
    """What the expressions of one case file may still use together.

    Pass the same budget to every ``parse_expression`` of a case; once a limit is
    passed, ``exhausted`` holds the message and every later parse is refused.
    """

    parts: int = MAX_CASE_PARTS
    root_digits: int = MAX_CASE_ROOT_DIGITS
    diff_work: int = MAX_CASE_DIFF_WORK
    exhausted: str | None = None

    def spend(self, kind: str, amount: int, text: str) -> None:
        """Take ``amount`` of ``kind`` ('parts', 'root_digits', 'diff_work'), or refuse
        ``text`` with ExpressionError once the case's MAX_CASE_* limit is passed."""
        if self.exhausted is None:
            left = getattr(self, kind) - amount
            setattr(self, kind, left)
            if left >= 0:
                return
            self.exhausted = _CASE_LIMITS[kind]
        raise ExpressionError(self.exhausted, text)


_CASE_LIMITS = {
    "parts": f"the case's expressions are too large together "
    f"(more than {MAX_CASE_PARTS} parts in all)",
    "root_digits": f"too many roots of numbers "
    f"(more than {MAX_CASE_ROOT_DIGITS} digits under roots in all)",
    "diff_work": "the case's expressions are too large to differentiate together",
}
