"""Certified evaluation of an expression at an exact point.

A probe of the zero test must never mistake rounding noise for a value, nor a
tiny value for zero. This evaluator walks the sympy tree with exact rationals
(``fractions.Fraction``) as long as it can, and switches to mpmath interval
arithmetic only where a value is irrational (a root that is not a perfect
power, a transcendental function). The result is either an exact rational or
an interval guaranteed to contain the true value, so "nonzero" is a proof:
exact ``!= 0`` or an interval that excludes 0.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from math import isqrt
from typing import Any

import mpmath
import sympy as sp

#: Working precision of the interval fallback, in decimal digits.
INTERVAL_DPS = 60

_iv = mpmath.iv


class OutsideDomain(ArithmeticError):
    """The expression is undefined (or not real) at the point: pick another point."""


@dataclass(frozen=True)
class Value:
    """An exact rational, or an interval that certainly contains the value."""

    exact: Fraction | None = None
    interval: Any = None  # mpmath.iv.mpf, when not exact

    @property
    def is_exact(self) -> bool:
        return self.exact is not None

    def certainly_nonzero(self) -> bool:
        """True only when the value is proven different from 0."""
        if self.exact is not None:
            return self.exact != 0
        return not (self.interval.a <= 0 <= self.interval.b)

    def text(self) -> str:
        """The value for a witness: the exact rational, or the certified enclosure."""
        if self.exact is not None:
            return str(self.exact)
        with mpmath.workdps(INTERVAL_DPS):
            lo, hi = _lo(self.interval), _hi(self.interval)
            return f"[{mpmath.nstr(lo, 20)}, {mpmath.nstr(hi, 20)}]"

    def approx(self) -> str:
        """A short decimal approximation, for people."""
        if self.exact is not None:
            return mpmath.nstr(mpmath.mpf(self.exact.numerator) / self.exact.denominator, 15)
        with mpmath.workdps(INTERVAL_DPS):
            return mpmath.nstr((_lo(self.interval) + _hi(self.interval)) / 2, 15)


def evaluate(expr: sp.Expr, point: Mapping[sp.Symbol, sp.Expr]) -> Value:
    """Evaluate ``expr`` at ``point`` (exact sympy numbers), exactly where possible.

    Raises OutsideDomain where the expression is undefined or not real there.
    """
    return At(point)(expr)


class At:
    """Evaluation of several expressions at one exact point: ``At(point)(expr)`` is
    ``evaluate(expr, point)``, with the point's values converted once and the values of
    common subexpressions (a radical shared by the components of a residual) computed
    once for all the expressions evaluated there."""

    def __init__(self, point: Mapping[sp.Symbol, sp.Expr]) -> None:
        self.point = point
        self._env: dict | None = None
        self._cache: dict = {}

    def __call__(self, expr: sp.Expr) -> Value:
        """The value of ``expr`` at the point; OutsideDomain as ``evaluate``."""
        with mpmath.workdps(INTERVAL_DPS):
            _iv.dps = INTERVAL_DPS
            if self._env is None:
                self._env = {sym: _number(val, {}) for sym, val in self.point.items()}
            return _as_value(_eval(expr, self._env, self._cache))


# --- internals: values are Fraction (exact) or mpmath.iv.mpf (enclosure) ---


def _as_value(v) -> Value:
    return Value(exact=v) if isinstance(v, Fraction) else Value(interval=v)


def _lo(v) -> mpmath.mpf:
    """Lower endpoint of an interval as a plain mpf (call at the working precision)."""
    return mpmath.mpf(v._mpi_[0])


def _hi(v) -> mpmath.mpf:
    return mpmath.mpf(v._mpi_[1])


def _to_iv(v):
    if isinstance(v, Fraction):
        return _iv.mpf(v.numerator) / v.denominator
    return v


def _number(expr: sp.Expr, cache: dict):
    """An exact sympy number (possibly with radicals, pi, ...) as a Fraction or interval."""
    return _eval(sp.sympify(expr), {}, cache)


def _eval(expr, env, cache):
    if expr in env:
        return env[expr]
    hit = cache.get(expr)
    if hit is not None:
        return hit
    value = _eval_node(expr, env, cache)
    cache[expr] = value
    return value


def _eval_node(expr, env, cache):
    if expr.is_Rational:
        return Fraction(int(expr.p), int(expr.q))
    if expr is sp.pi:
        return _iv.pi
    if expr is sp.E:
        return _iv.e
    if expr.is_Symbol:
        raise ValueError(f"no value for {expr} at the point")
    if expr.is_Add:
        total = Fraction(0)
        for arg in expr.args:
            total = _add(total, _eval(arg, env, cache))
        return total
    if expr.is_Mul:
        prod = Fraction(1)
        for arg in expr.args:
            prod = _mul(prod, _eval(arg, env, cache))
        return prod
    if expr.is_Pow:
        return _pow(_eval(expr.base, env, cache), expr.exp, env, cache)
    if isinstance(expr, sp.Function) and type(expr) in _FUNCTIONS:
        return _FUNCTIONS[type(expr)](_eval(expr.args[0], env, cache))
    raise ValueError(f"cannot evaluate {type(expr).__name__} at a point")


def _add(a, b):
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a + b
    return _to_iv(a) + _to_iv(b)


def _mul(a, b):
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a * b
    if isinstance(a, Fraction) and a == 0 or isinstance(b, Fraction) and b == 0:
        return Fraction(0)
    return _to_iv(a) * _to_iv(b)


def _contains_zero(v) -> bool:
    return v == 0 if isinstance(v, Fraction) else bool(v.a <= 0 <= v.b)


def _positive(v) -> bool:
    return v > 0 if isinstance(v, Fraction) else bool(v.a > 0)


def _pow(base, exp: sp.Expr, env, cache):
    if exp.is_Integer:
        n = int(exp)
        if n < 0 and _contains_zero(base):
            raise OutsideDomain("division by zero")
        if isinstance(base, Fraction):
            return base**n
        return _iv_int_pow(base, n)
    if exp.is_Rational:
        p, q = int(exp.p), int(exp.q)
        if p < 0 and _contains_zero(base):
            raise OutsideDomain("division by zero")
        if isinstance(base, Fraction):
            if base < 0:
                raise OutsideDomain("root of a negative number")
            root = exact_root(base, q)
            if root is not None:
                return root**p
        if not _positive(base):
            if isinstance(base, Fraction) and base == 0:
                return Fraction(0)
            raise OutsideDomain("root of a number that may be negative")
        root = _iv.sqrt(_to_iv(base)) if q == 2 else _monotone(lambda x: mpmath.root(x, q))(base)
        return _iv_int_pow(root, p)
    # a symbolic exponent: b**e = exp(e log b), defined for b > 0
    if not _positive(base):
        raise OutsideDomain("power with a non-positive base")
    e = _to_iv(_eval(exp, env, cache))
    return _iv.exp(e * _iv.log(_to_iv(base)))


def _iv_int_pow(v, n: int):
    if n < 0:
        return 1 / _iv_int_pow(v, -n)
    result = _iv.mpf(1)
    for _ in range(n):
        result = result * v
    if n % 2 == 0 and n > 0:  # even powers are non-negative; tighten the naive product
        lo, hi = abs(_lo(v)), abs(_hi(v))
        lower = 0 if _lo(v) <= 0 <= _hi(v) else min(lo, hi) ** n
        if lower > _lo(result):
            lower = mpmath.mpf(lower) * (1 - mpmath.mpf(2) ** (-mpmath.mp.prec + 8))
            result = _iv.mpf([max(lower, _lo(result)), _hi(result)])
    return result


def exact_root(x: Fraction, q: int) -> Fraction | None:
    """The exact q-th root of a non-negative rational, if it is rational."""
    num = _int_root(x.numerator, q)
    den = _int_root(x.denominator, q)
    return None if num is None or den is None else Fraction(num, den)


def _int_root(n: int, q: int) -> int | None:
    if q == 2:
        r = isqrt(n)
    else:
        r = int(round(n ** (1.0 / q))) if n < 2**900 else int(mpmath.root(n, q))
        for cand in (r - 1, r, r + 1):
            if cand >= 0 and cand**q == n:
                return cand
        return None
    return r if r * r == n else None


def _monotone(fn, lower=None, upper=None, decreasing=False):
    """Enclosure of a monotone function: evaluate at both ends, widen by a few ulps.

    mpmath evaluates elementary functions to within an ulp or two; the widening
    of 2**-(prec-8) relative keeps the enclosure safe.
    """

    def apply(v):
        v = _to_iv(v)
        a, b = _lo(v), _hi(v)
        if lower is not None and a < lower or upper is not None and b > upper:
            raise OutsideDomain("argument outside the function's domain")
        eps = mpmath.mpf(2) ** (-mpmath.mp.prec + 8)
        lo, hi = fn(a), fn(b)
        if decreasing:
            lo, hi = hi, lo
        return _iv.mpf([lo - eps * (1 + abs(lo)), hi + eps * (1 + abs(hi))])

    return apply


def _log(v):
    if not _positive(v):
        raise OutsideDomain("logarithm of a number that may be non-positive")
    if v == 1:
        return Fraction(0)
    return _iv.log(_to_iv(v))


def _exact_zero(fn, at_zero):
    def apply(v):
        if isinstance(v, Fraction) and v == 0:
            return at_zero
        return fn(v)

    return apply


def _sinh(v):
    e = _iv.exp(_to_iv(v))
    return (e - 1 / e) / 2


def _cosh(v):
    e = _iv.exp(_to_iv(v))
    return (e + 1 / e) / 2


def _tanh(v):
    e2 = _iv.exp(2 * _to_iv(v))
    return (e2 - 1) / (e2 + 1)


def _tan(v):
    c = _iv.cos(_to_iv(v))
    if c.a <= 0 <= c.b:
        raise OutsideDomain("tangent at a pole")
    return _iv.sin(_to_iv(v)) / c


def _abs(v):
    if isinstance(v, Fraction):
        return abs(v)
    lo, hi = _lo(v), _hi(v)
    if lo >= 0:
        return v
    if hi <= 0:
        return -v
    return _iv.mpf([0, max(-lo, hi)])


def _sign(v):
    if isinstance(v, Fraction):
        return Fraction((v > 0) - (v < 0))
    if _lo(v) > 0:
        return Fraction(1)
    if _hi(v) < 0:
        return Fraction(-1)
    raise OutsideDomain("the sign of a value that may be zero")


_FUNCTIONS = {
    sp.Abs: _abs,
    sp.sign: _sign,
    sp.exp: _exact_zero(lambda v: _iv.exp(_to_iv(v)), Fraction(1)),
    sp.log: _log,
    sp.sin: _exact_zero(lambda v: _iv.sin(_to_iv(v)), Fraction(0)),
    sp.cos: _exact_zero(lambda v: _iv.cos(_to_iv(v)), Fraction(1)),
    sp.tan: _exact_zero(_tan, Fraction(0)),
    sp.atan: _exact_zero(_monotone(mpmath.atan), Fraction(0)),
    sp.asin: _exact_zero(_monotone(mpmath.asin, -1, 1), Fraction(0)),
    sp.acos: _monotone(mpmath.acos, -1, 1, decreasing=True),
    sp.sinh: _exact_zero(_sinh, Fraction(0)),
    sp.cosh: _exact_zero(_cosh, Fraction(1)),
    sp.tanh: _exact_zero(_tanh, Fraction(0)),
}
