"""The printer of the case-file language: a sympy expression written back as text
that can be pasted into a case file.

The checks (residuals), the corrections (corrected Casimirs and torques) and the
parameter conditions write their results with ``to_text``; the parser never
needs it.

Examples
--------
>>> from registry.language.parser import parse_expression
>>> to_text(parse_expression("diff(gamma1*s, M1)"))
'gamma1**2'
"""

from __future__ import annotations

import keyword
from collections.abc import Mapping
from types import MappingProxyType

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.printing.str import StrPrinter

from ..mathematics.mechanics import AXIS, MOMENTUM, STATE, s
from .parser import CONSTANTS, FUNCTIONS, VARIABLES

#: ds/dv for each state variable v, since s = M . gamma.
_DS_DV: Mapping[sp.Symbol, sp.Symbol] = MappingProxyType(
    {**dict(zip(MOMENTUM, AXIS, strict=True)), **dict(zip(AXIS, MOMENTUM, strict=True))}
)


def to_text(expr: sp.Expr | int) -> str:
    """``expr`` written in the case-file language, ready to paste into a case file.

    Derivatives of declared functions (partial, at fixed s) are written with the
    language's total ``diff``. Raises ValueError for what the language cannot
    express (I, floats, infinities, Piecewise, functions outside the language, ...).
    """
    if isinstance(expr, int):
        expr = sp.Integer(expr)
    if not isinstance(expr, sp.Basic):
        raise TypeError(f"to_text needs a sympy expression, not {type(expr).__name__}")
    return _Printer().doprint(expr)


def _unsupported(expr: sp.Basic) -> ValueError:
    return ValueError(f"cannot write {type(expr).__name__} in the expression language: {expr}")


class _Printer(StrPrinter):
    """sympy's str printer, restricted to the language and with our ``diff``."""

    def _print(self, expr, **kwargs) -> str:
        if isinstance(expr, sp.Basic):
            _check_printable(expr)
        return super()._print(expr, **kwargs)

    def _print_Symbol(self, expr: sp.Symbol) -> str:
        return expr.name

    def _print_Abs(self, expr: sp.Abs) -> str:
        """|x| = sqrt(x**2) for real x; the parser turns it back into Abs(x)."""
        (arg,) = expr.args
        if arg.is_extended_real is not True:
            raise _unsupported(expr)
        return f"sqrt({self._print(sp.Pow(arg, 2, evaluate=False))})"

    def _print_Derivative(self, expr: sp.Derivative) -> str:
        """A partial derivative of a declared function, nested ``diff`` calls."""
        func = expr.expr
        if not isinstance(func, AppliedUndef):
            raise _unsupported(expr)
        args = func.args
        if not all(a in VARIABLES.values() for a in args) or len(set(args)) != len(args):
            raise _unsupported(expr)
        text = self._print(func)
        for var, count in expr.variable_count:
            for _ in range(int(count)):
                text = _partial_text(text, args, var)
        return text


def _partial_text(inner: str, args: tuple[sp.Symbol, ...], var: sp.Symbol) -> str:
    """The partial derivative d/var (at fixed s) of ``inner``, a function of ``args``.

    With s among the arguments, our diff(., v) is d_v + (ds/dv) d_s, and for a
    state variable w that is no argument, diff(., w) = (ds/dw) d_s. Hence
    d_s = diff(., w)/(ds/dw) and d_v = diff(., v) - (ds/dv) diff(., w)/(ds/dw).
    (diff(., s) itself is only allowed on functions of s alone.)
    """
    state_args = [a for a in args if a != s]
    if s not in args:
        return f"diff({inner}, {var})"
    if not state_args:
        return f"diff({inner}, s)"
    free = [w for w in STATE if w not in args]
    if not free:
        raise ValueError(
            "cannot write a partial derivative of a function of s and all six variables"
        )
    w = free[0]
    along_s = f"diff({inner}, {w})/{_DS_DV[w]}"
    if var == s:
        return f"({along_s})"
    return f"(diff({inner}, {var}) - {_DS_DV[var]}*{along_s})"


_PRINTABLE_FUNCTIONS = tuple(f for f in FUNCTIONS.values() if isinstance(f, sp.FunctionClass))


def _check_printable(expr: sp.Basic) -> None:
    """Raise ValueError unless the node ``expr`` (not its arguments) is in the language."""
    if isinstance(expr, sp.Symbol):
        name = expr.name
        if type(expr) is not sp.Symbol or not _is_name(name) or name in CONSTANTS:
            raise _unsupported(expr)
        return
    if expr.is_Rational or expr in (sp.pi, sp.E):
        return
    if isinstance(expr, sp.Add | sp.Mul | sp.Pow | sp.Derivative | sp.Abs | AppliedUndef):
        return
    if isinstance(expr, _PRINTABLE_FUNCTIONS):
        return
    raise _unsupported(expr)


def _is_name(name: str) -> bool:
    """Whether ``name`` can name a variable or parameter in an expression."""
    return name.isascii() and name.isidentifier() and not keyword.iskeyword(name)
