"""Exact algebraic numbers and simple algebraic extensions k[u]/(g), for balances and
Kovalevskaya exponents.

An irreducible component of the balance equations is a simple extension F = k[u]/(g)
of its ground field k (Q, or rational functions of parameters and free coordinates):
its points are the roots of g. The exponents are computed once in F, exactly, and the
roots are then written for each point: rationals, radicals where sympy writes them
briefly (degree 2, binomials, biquadratics), ``CRootOf`` over Q otherwise. Which root of
a coordinate's own minimal polynomial a point has is decided by evaluating both at 50
digits, and only where the nearest candidate is unambiguous (``identify``).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import flint
import sympy as sp

from .factoring import factor

#: Digits of the ball arithmetic that identifies a root among candidates.
DIGITS = 50
#: Root expressions longer than this (sympy operations) are replaced by CRootOf.
MAX_RADICAL_OPS = 40


@dataclass(frozen=True)
class Extension:
    """F = k[u]/(g) for a monic irreducible ``minimal`` polynomial g over the domain k."""

    symbol: sp.Symbol
    minimal: sp.Poly

    @property
    def domain(self):
        return self.minimal.domain

    @property
    def degree(self) -> int:
        return self.minimal.degree()

    def element(self, expr: sp.Expr) -> sp.Poly:
        """The element a rational function of u (and the ground field's symbols) is."""
        try:  # most are polynomials in u already
            return self.poly(sp.expand(expr))
        except (sp.PolynomialError, sp.CoercionFailed):
            pass
        numer, denom = sp.fraction(sp.together(sp.sympify(expr)))
        return self.reduce(self.poly(numer) * self.inverse(self.poly(denom)))

    def poly(self, expr: sp.Expr) -> sp.Poly:
        """A polynomial in u, reduced modulo g."""
        return self.reduce(sp.Poly(expr, self.symbol, domain=self.domain))

    def reduce(self, value: sp.Poly) -> sp.Poly:
        return value.rem(self.minimal)

    def inverse(self, value: sp.Poly) -> sp.Poly:
        """1/value in F (ZeroDivisionError for 0)."""
        value = self.reduce(value)
        if value.is_zero:
            raise ZeroDivisionError("division by zero in an algebraic extension")
        return value.invert(self.minimal)

    def evaluate(self, poly: sp.Poly, values: Sequence[sp.Poly]) -> sp.Poly:
        """poly(values) in F, for a polynomial over k in as many generators as values: by
        arithmetic on polynomials in u, without expressions (fast over Q(p))."""
        powers: dict[tuple[int, int], sp.Poly] = {}

        def power(i: int, e: int) -> sp.Poly:
            if (i, e) not in powers:
                powers[i, e] = values[i] if e == 1 else self.reduce(power(i, e - 1) * values[i])
            return powers[i, e]

        total = sp.Poly(0, self.symbol, domain=self.domain)
        for monomial, c in poly.as_dict(native=True).items():
            term = sp.Poly.from_dict({(0,): c}, self.symbol, domain=self.domain)
            for i, e in enumerate(monomial):
                if e:
                    term = self.reduce(term * power(i, e))
            total += term
        return self.reduce(total)

    def coordinates(self, value: sp.Poly) -> list:
        """The coefficients of 1, u, ..., u^(d-1): the element in the power basis."""
        coeffs = self.reduce(value).all_coeffs()[::-1]
        return coeffs + [self.domain.zero] * (self.degree - len(coeffs))


def minimal_polynomial(ext: Extension, value: sp.Poly, z: sp.Symbol) -> sp.Poly:
    """The minimal polynomial over k of an element of F: the squarefree part of its
    characteristic polynomial Res_u(g(u), z - value(u)), a power of it since g is
    irreducible."""
    charpoly = sp.resultant(ext.minimal.as_expr(), z - value.as_expr(), ext.symbol)
    return sp.Poly(charpoly, z, domain=ext.domain).sqf_part().monic()


def exact_roots(poly: sp.Poly) -> tuple[sp.Expr, ...] | None:
    """The roots of a squarefree polynomial, exactly and in a fixed order: radicals
    where sympy writes them briefly, CRootOf over Q otherwise, None where neither
    applies (degree above 2 over a field of rational functions, without short radicals).

    >>> x = sp.Symbol("x")
    >>> exact_roots(sp.Poly(x**2 + 4, x))
    (-2*I, 2*I)
    """
    if poly.degree() < 1:
        return ()
    if poly.degree() == 1:
        return (-poly.nth(0) / poly.nth(1),)
    # sympy's closed forms: quadratics, binomials, biquadratics (higher degrees: slow, long)
    short = poly.degree() <= 4 or len(poly.terms()) <= 2
    found = sp.roots(poly, cubics=False, quartics=False) if short else {}
    if sum(found.values()) == poly.degree() and all(
        sp.count_ops(r) <= MAX_RADICAL_OPS and _radical(r) for r in found
    ):
        return tuple(sorted(found, key=numeric_key))
    if poly.domain.is_QQ or poly.domain.is_ZZ:
        return tuple(sp.CRootOf(poly, i) for i in range(poly.degree()))
    return None


def value_at_root(expr: sp.Expr, symbol: sp.Symbol, root: sp.Expr) -> sp.Expr | None:
    """A polynomial in ``symbol`` (coefficients rational in the other symbols) at a root
    written in square roots: the sum over products of distinct square roots (and I) of
    factored rational coefficients, computed in Q(symbols) with s^2 = b for each square
    root s = sqrt(b) of the root (b^(k/2) = b^((k-1)/2) sqrt(b) for the principal
    branch). None where the root is not built so (nested roots, other powers, a square
    root in a denominator): the caller simplifies the substituted expression instead."""
    read = _square_roots(root, (expr.free_symbols | root.free_symbols) - {symbol})
    if read is None:
        return None
    form, k, squares, radicals = read
    try:
        coefficients = sp.Poly(expr, symbol, domain=k).as_dict(native=True)
    except (sp.PolynomialError, sp.CoercionFailed):  # not a polynomial over Q(symbols)
        return None
    total: dict[tuple[int, ...], Any] = {}
    power = {tuple(0 for _ in squares): k.one}
    for j in range(max(e for (e,) in coefficients) + 1 if coefficients else 0):
        if j:
            power = _times(power, form, k, squares)
        if (j,) in coefficients:
            for key, v in power.items():
                total[key] = total.get(key, k.zero) + coefficients[(j,)] * v
    return sp.Add(
        *(
            factor(k.to_sympy(v))
            * sp.Mul(*(r for r, bit in zip(radicals, key, strict=True) if bit))
            for key, v in total.items()
            if v
        )
    )


def _square_roots(expr: sp.Expr, symbols: set[sp.Symbol]):
    """``expr`` as {bits: coefficient}: coefficients in k = Q(symbols and the roots' own
    symbols) times products of distinct square roots sqrt(b_i) (and I = sqrt(-1)), with
    k, the squares b_i in k and the roots; None where it is not such a sum."""
    powers = [p for p in expr.atoms(sp.Pow) if p.exp.is_Rational and not p.exp.is_integer]
    if any(p.exp.q != 2 for p in powers):
        return None
    expr = sp.expand(expr)
    powers = [p for p in expr.atoms(sp.Pow) if p.exp.is_Rational and not p.exp.is_integer]
    bases = sorted({p.base for p in powers}, key=sp.default_sort_key)
    if any(b.has(sp.I) or any(not q.exp.is_integer for q in b.atoms(sp.Pow)) for b in bases):
        return None
    roots = [sp.Dummy("s") for _ in bases]
    i = sp.Dummy("i")
    named = dict(zip(bases, roots, strict=True))
    written = expr.xreplace({p: named[p.base] * p.base ** ((p.exp.p - 1) // 2) for p in powers})
    written = sp.expand(written.xreplace({sp.I: i}))
    symbols = symbols | set().union(set(), *(b.free_symbols for b in bases))
    k = sp.QQ.frac_field(*sorted(symbols, key=str)) if symbols else sp.QQ
    try:
        poly = sp.Poly(written, *roots, i, domain=k)
    except (sp.PolynomialError, sp.CoercionFailed):  # a root in a denominator
        return None
    squares = [*(k.from_sympy(b) for b in bases), -k.one]
    form: dict[tuple[int, ...], Any] = {}
    for monomial, c in poly.as_dict(native=True).items():
        for b, m in zip(squares, monomial, strict=True):
            c = c * b ** (m // 2)
        key = tuple(m % 2 for m in monomial)
        form[key] = form.get(key, k.zero) + c
    return form, k, squares, [*(sp.sqrt(b) for b in bases), sp.I]


def _times(x: dict, y: dict, k, squares: list) -> dict:
    """The product of two sums of products of square roots (``_square_roots``)."""
    out: dict[tuple[int, ...], Any] = {}
    for k1, c1 in x.items():
        for k2, c2 in y.items():
            c = c1 * c2
            for b, a1, a2 in zip(squares, k1, k2, strict=True):
                if a1 and a2:
                    c = c * b
            key = tuple(a1 ^ a2 for a1, a2 in zip(k1, k2, strict=True))
            out[key] = out.get(key, k.zero) + c
    return out


def _radical(expr: sp.Expr) -> bool:
    """Built from rationals, I and symbols by +, * and rational powers only (sympy may
    write the square root of a complex number with cos and atan)."""
    return all(
        isinstance(node, sp.Symbol | sp.Rational | sp.Add | sp.Mul | sp.Pow)
        or node is sp.I
        or node.is_Rational
        for node in sp.preorder_traversal(expr)
    )


def numeric_key(root: sp.Expr) -> tuple:
    """A fixed order of algebraic numbers: real part, then imaginary part (the balls'
    midpoints, rounded), then the text; expressions with symbols after all numbers."""
    if root.free_symbols:
        return (1, 0.0, 0.0, sp.default_sort_key(root))
    value = to_acb(root)
    re, im = float(value.real.mid()), float(value.imag.mid())
    return (0, round(re, 9), round(im, 9), sp.default_sort_key(root))


@functools.lru_cache(maxsize=4096)
def to_acb(expr: sp.Expr) -> flint.acb:
    """A closed algebraic number (rationals, I, sums, products, rational powers taken on
    the principal branch as sympy does, CRootOf) as a ball at ``DIGITS`` digits that
    provably contains it; anything else is evaluated by sympy at that precision."""
    return evaluate(expr, {})


def evaluate(expr: sp.Expr, values: Mapping[sp.Symbol, flint.acb]) -> flint.acb:
    """``expr`` (built as in ``to_acb``, and from the symbols in ``values``) as a ball."""
    with precision():
        return _acb(sp.sympify(expr), values)


def _acb(expr: sp.Expr, values: Mapping[sp.Symbol, flint.acb]) -> flint.acb:
    if expr in values:
        return values[expr]
    if expr.is_Rational:
        return flint.acb(flint.fmpq(int(expr.p), int(expr.q)))
    if expr is sp.I:
        return flint.acb(0, 1)
    if expr.is_Add:
        return sum((_acb(a, values) for a in expr.args), flint.acb(0))
    if expr.is_Mul:
        value = flint.acb(1)
        for a in expr.args:
            value *= _acb(a, values)
        return value
    if expr.is_Pow and expr.exp.is_Rational:
        base, exp = _acb(expr.base, values), expr.exp
        if exp.q == 1:
            return base ** int(exp.p)
        return base ** flint.acb(flint.fmpq(int(exp.p), int(exp.q)))
    if isinstance(expr, sp.CRootOf):
        return _crootof(expr)
    value = sp.N(expr, DIGITS + 10)  # pragma: no cover - other algebraic forms are not made
    re, im = (flint.arb(str(sp.Float(part, DIGITS + 10))) for part in value.as_real_imag())
    return flint.acb(re, im)


def _crootof(root: sp.CRootOf) -> flint.acb:
    """The ball of the FLINT root of the CRootOf's polynomial that lies in its isolating
    interval (refined until exactly one does)."""
    poly = root.poly
    candidates = flint_roots(poly)
    for _ in range(60):
        interval = root._get_interval()
        if root.is_real:
            box = flint.acb(_arb_between(interval.a, interval.b), 0)
        else:
            box = flint.acb(
                _arb_between(interval.ax, interval.bx), _arb_between(interval.ay, interval.by)
            )
        inside = [c for c in candidates if box.overlaps(c)]
        if len(inside) == 1:
            return inside[0]
        root._refine()
    raise Unidentified(f"cannot separate the roots of {poly.as_expr()}")  # pragma: no cover


@functools.lru_cache(maxsize=256)
def flint_roots(poly: sp.Poly) -> list[flint.acb]:
    """Balls around the roots of a polynomial over Q (at the working precision)."""
    coeffs = sp.Poly(poly.as_expr(), *poly.gens, domain=sp.QQ).clear_denoms(convert=True)[1]
    integral = flint.fmpz_poly([int(a) for a in coeffs.all_coeffs()[::-1]])
    found: list = integral.complex_roots()  # type: ignore[assignment]  # (ball, multiplicity)
    return [c for c, _ in found]


def _arb_between(lower: sp.Rational, upper: sp.Rational) -> flint.arb:
    lo, hi = (flint.fmpq(int(sp.Rational(q).p), int(sp.Rational(q).q)) for q in (lower, upper))
    return flint.arb((lo + hi) / 2, (hi - lo) / 2)


class precision:
    """FLINT's working precision raised to ``DIGITS`` digits, restored after."""

    def __enter__(self):
        self.saved = flint.ctx.prec
        flint.ctx.dps = DIGITS + 10

    def __exit__(self, *exc):
        flint.ctx.prec = self.saved


class Unidentified(ValueError):
    """No candidate is provably the value."""


def identify(value: flint.acb, candidates: Sequence[sp.Expr]) -> sp.Expr:
    """The candidate equal to ``value``: the only one whose ball overlaps the value's
    ball (candidates are distinct algebraic numbers, such as the roots of one squarefree
    polynomial, so at ``DIGITS`` digits exactly one does)."""
    overlapping = [c for c in candidates if to_acb(c).overlaps(value)]
    if len(overlapping) != 1:
        raise Unidentified(f"{len(overlapping)} candidates overlap {value}")
    return overlapping[0]
