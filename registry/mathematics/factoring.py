"""Factoring over Q through python-flint: sympy's multivariate factoring dominates the
cost of showing residuals and corrections; FLINT's is the same mathematics, much faster.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> factor(6*x**3*y - 12*x**2*y**2 + 6*x*y**3 + 12*x**2 - 24*x*y + 12*y**2)
6*(x - y)**2*(x*y + 2)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import sympy as sp
from sympy.core.mul import _keep_coeff
from sympy.polys.polyerrors import CoercionFailed, PolynomialError
from sympy.polys.polyutils import _sort_gens

try:
    import flint
except ImportError:  # pragma: no cover - python-flint is a dependency; sympy still works
    flint = None  # type: ignore[assignment]


def factor(expr: sp.Expr) -> sp.Expr:
    """``expr`` as one fraction with numerator and denominator factored over Q, the form
    ``sympy.factor`` gives; expressions that are not rational functions over Q of their
    symbols (radicals, functions, floats) go to ``sympy.factor`` itself."""
    if flint is None or expr.has(sp.Float):  # floats stay floats: never made rational
        return sp.factor(expr)
    numer, denom = sp.fraction(sp.together(expr))
    try:
        (cn, fn), (cd, fd) = _factor_polynomial(numer), _factor_polynomial(denom)
    except (PolynomialError, CoercionFailed):
        return sp.factor(expr)
    return _keep_coeff(cn / cd, fn / fd)  # -3*(B + 1), not -3*B - 3


def factor_mpoly(poly):
    """``poly.factor()`` of a FLINT polynomial over Z: (content, [(factor, exponent)]),
    the factors primitive with positive leading coefficient in the ring's lex order.

    python-flint 0.9 sorts the factors by a key that converts coefficients to a C long,
    so two factors with a coefficient beyond 2**63 raise OverflowError (for instance
    (u + 10**30) (u - 10**30) (v + 1)); sympy's exact factorisation over Z then does the
    same work, more slowly."""
    try:
        return poly.factor()
    except OverflowError:
        ctx = poly.context()
        gens = sp.symbols(f"x0:{ctx.nvars()}")
        terms = {tuple(int(e) for e in m): int(c) for m, c in poly.to_dict().items()}
        content, factors = sp.Poly.from_dict(terms, *gens, domain=sp.ZZ).factor_list()
        return flint.fmpz(int(content)), [
            (ctx.from_dict({m: int(c) for m, c in f.as_dict().items()}), e) for f, e in factors
        ]


def coefficient_and_factors(expr: sp.Expr) -> tuple[sp.Expr, list[tuple[sp.Expr, int]]]:
    """The coefficient and the irreducible factors (with multiplicities) that
    ``sympy.factor_list(expr)`` gives, the factors sorted by sympy's key; by FLINT where
    expr is a polynomial over Q in its symbols, else by sympy. sympy's multivariate
    factoring draws random evaluation points (Wang's method): on the same polynomial it
    took 0.03 s in one process and minutes in another.

    >>> x, a = sp.symbols("x a")
    >>> coefficient_and_factors(-2 * a * x**2 + 2 * a)
    (-2, [(a, 1), (x - 1, 1), (x + 1, 1)])
    """
    expr = sp.sympify(expr)
    if flint is None or expr.has(sp.Float):  # pragma: no cover - python-flint is a dependency
        return sp.factor_list(expr)
    try:
        content, factors = _factor_polynomial_list(expr)
    except (PolynomialError, CoercionFailed):
        return sp.factor_list(expr)
    return content, sorted(factors, key=lambda fe: sp.default_sort_key(fe[0]))


def factor_element(p) -> list[tuple[Any, int]]:
    """The irreducible factors over Q of ``p``, an element of sympy's polynomial ring
    over Q (``sympy.polys.rings``), each an element of that ring with its multiplicity,
    by FLINT: primitive over Z (the content dropped), with FLINT's signs (positive
    leading coefficient in lex order, not in the ring's). By Gauss's lemma the factors
    that involve some of the gens are the irreducible factors over the rational
    functions of the others.

    >>> from sympy.polys.rings import ring
    >>> R, x, y = ring("x y", sp.QQ)
    >>> sorted(factor_element(2 * x**2 * y - 2 * y), key=str)
    [(x + 1, 1), (x - 1, 1), (y, 1)]
    """
    ring = p.ring
    if flint is None:  # pragma: no cover - python-flint is a dependency
        return list(p.factor_list()[1])
    if p.is_ground:
        return []
    _, integral = p.clear_denoms()
    terms = {m: int(sp.QQ.numer(sp.QQ.convert(c))) for m, c in integral.items()}
    _, factors = _integer_factors(terms, ring.ngens)
    return [(ring.from_dict(f), k) for f, k in factors]


def _integer_factors(
    terms: dict[tuple[int, ...], int], nvars: int
) -> tuple[int, list[tuple[dict[tuple[int, ...], int], int]]]:
    """FLINT's factorisation over Z of the polynomial {exponents: integer} in ``nvars``
    variables: its content, and its factors (as {exponents: integer}) with their
    multiplicities."""
    ctx = flint.fmpz_mpoly_ctx.get(tuple(f"x{i}" for i in range(nvars)), "lex")
    content, factors = factor_mpoly(ctx.from_dict({m: int(c) for m, c in terms.items()}))
    return int(content), [
        ({tuple(int(e) for e in m): int(c) for m, c in f.to_dict().items()}, k) for f, k in factors
    ]


def _factor_polynomial(expr: sp.Expr) -> tuple[sp.Rational, sp.Expr]:
    """(content, product of factors) of a polynomial over Q in its symbols, factored by
    FLINT (PolynomialError if it is not one)."""
    content, factors = _factor_polynomial_list(expr)
    return content, sp.Mul(*(f**e for f, e in factors))


def _factor_polynomial_list(expr: sp.Expr) -> tuple[sp.Rational, list[tuple[sp.Expr, int]]]:
    """(content, [(factor, multiplicity)]) of a polynomial over Q in its symbols,
    factored by FLINT (PolynomialError if it is not one)."""
    if expr.is_Rational:
        return expr, []
    gens = _sort_gens(expr.free_symbols)  # sympy's order: its signs of the factors
    if not gens or not expr.is_polynomial(*gens):
        raise PolynomialError(f"not a polynomial over Q: {expr}")
    poly = sp.Poly(expr, *gens, domain=sp.QQ)
    scale, integral = poly.clear_denoms(convert=True)
    content, factors = _integer_factors(dict(integral.terms()), len(gens))
    parts = [(sp.Poly.from_dict(f, *gens).as_expr(), e) for f, e in factors]
    return sp.Integer(content) / scale, parts


def factor_list(expr: sp.Expr, gens: Sequence[sp.Symbol]) -> list[tuple[sp.Expr, int]]:
    """The irreducible factors over Q of a polynomial in ``gens`` (its numerator, for a
    rational function), each with its multiplicity, primitive with a positive leading
    coefficient in sympy's order; the content is dropped (it never vanishes).

    >>> x, a = sp.symbols("x a")
    >>> factor_list(2 * a * x**2 - 2 * a, [x, a])
    [(a, 1), (x - 1, 1), (x + 1, 1)]
    """
    numer = sp.fraction(sp.together(sp.sympify(expr)))[0]
    gens = [g for g in gens if numer.has(g)]
    if not gens:
        return []
    poly = sp.Poly(numer, *gens, domain=sp.QQ)
    if flint is None:  # pragma: no cover - python-flint is a dependency
        found = [(f.as_expr(), e) for f, e in poly.factor_list()[1]]
    else:
        _, integral = poly.clear_denoms(convert=True)
        _, factors = _integer_factors(dict(integral.terms()), len(gens))
        found = [(sp.Poly.from_dict(f, *gens), e) for f, e in factors]
        found = [((-f if f.LC() < 0 else f).as_expr(), e) for f, e in found]
    return sorted(found, key=lambda fe: sp.default_sort_key(fe[0]))
