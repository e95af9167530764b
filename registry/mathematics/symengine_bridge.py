"""Differentiation and expansion through symengine where it is installed, sympy otherwise.

symengine (a C++ library) differentiates and expands several times faster
than sympy, conversions included. Results always come back as sympy objects
with the caller's own symbols (and their assumptions). Expressions with
arbitrary functions of a family stay with sympy, whose derivatives of
undefined functions the rest of the registry relies on. Set ``ENABLED`` to
False to use sympy alone (the tests run both ways).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from sympy.core.function import AppliedUndef

try:
    import symengine as se
except ImportError:  # optional dependency
    se = None

#: Use symengine when it is importable; tests switch it off to exercise the fallback.
ENABLED = se is not None


def _usable(expr: sp.Expr) -> bool:
    return ENABLED and not expr.has(AppliedUndef, sp.Derivative, sp.Subs, sp.Abs, sp.sign)


def _back(result, expr: sp.Expr) -> sp.Expr:
    """A symengine result as sympy, with the original symbols (assumptions included)."""
    back = sp.sympify(result)
    names = {s.name: s for s in expr.free_symbols if isinstance(s, sp.Symbol)}
    return back.xreplace({s: names[s.name] for s in back.free_symbols if s.name in names})


#: What a failed symengine conversion or derivative raises (sympy then does the work).
_FAILURES = (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError)


def diff(expr: sp.Expr, var: sp.Symbol) -> sp.Expr:
    """d expr / d var (partial derivative)."""
    return partials(expr, (var,))[0]


def partials(expr: sp.Expr, variables: Sequence[sp.Symbol]) -> tuple[sp.Expr, ...]:
    """(d expr / d var for each of ``variables``), the same as ``diff`` one by one, with
    ``expr`` converted to symengine once (the conversions cost more than the derivatives)."""
    expr = sp.sympify(expr)
    converted = None
    if _usable(expr):
        try:
            converted = se.sympify(expr)
        except _FAILURES:
            converted = None
    out = []
    for var in variables:
        if converted is not None:
            try:
                out.append(_back(converted.diff(se.Symbol(var.name)), expr))
                continue
            except _FAILURES:
                pass
        out.append(sp.diff(expr, var))
    return tuple(out)


def expand(expr: sp.Expr) -> sp.Expr:
    """The expanded form of ``expr``."""
    expr = sp.sympify(expr)
    if _usable(expr):
        try:
            return _back(se.expand(se.sympify(expr)), expr)
        except _FAILURES:
            pass
    return sp.expand(expr)
