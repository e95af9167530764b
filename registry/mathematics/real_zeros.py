"""The real zeros of polynomial equations whose parameters have declared signs, without
solving them: an equation that is a sum of squares is replaced by the squares' roots, a
polynomial that is never positive is proven so factor by factor.

A sum of terms c P m**2 (c > 0 a number, P a product of parameters declared positive)
vanishes only where each m does; a real zero of a V**2 + b V + c (V = v**k, a of one
sign) whose discriminant is never positive is a double root, where the discriminant
vanishes. The Painlevé strata (``discovery.painleve_strata``) keep the real points of
each set their conditions cut, and learn that a pair of balances is complex conjugate
at every real value; neither needs a rational parametrisation of the set.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import sympy as sp

from .factoring import coefficient_and_factors, factor_list

#: How often a set's equations may be replaced by their real points before it is left.
MAX_REAL_STEPS = 8


def real_system(equations: Sequence[sp.Expr]) -> tuple[sp.Expr, ...] | None:
    """The system with each equation that is a sum of squares replaced by the squares'
    roots (the same real points), and the equations a real point needs added
    (``_double_root``), again until nothing changes; None when an equation has no real
    point."""
    system = tuple(sp.expand(e) for e in equations)
    for _ in range(MAX_REAL_STEPS):
        out: list[sp.Expr] = []
        for e in system:
            roots = _squares(e)
            if roots is None:
                roots = _squares(-e)
            if roots is None:
                roots = _double_root(e)
                if roots is not None and roots != [sp.Integer(1)]:
                    roots = [e, *roots]
            if roots == [sp.Integer(1)]:
                return None
            out += [sp.expand(r) for r in roots] if roots is not None else [e]
        found = tuple(dict.fromkeys(e for e in out if e != 0))
        if found == system:
            break
        system = found
    return system


def _squares(e: sp.Expr) -> list[sp.Expr] | None:
    """Polynomials h_i with e = sum of c_i h_i**2, c_i > 0 a number or a product of
    parameters declared positive (so e's real zeros at admissible values are the h_i's
    common zeros): a sum of such terms (``_nonnegative_terms``), a positive multiple of
    a square, e = A v**2 + B with no odd power of v and A, B such sums again, or
    a v**2 + b v + c with a > 0 a number, its square completed. [1] when e > 0
    everywhere, [] when e = 0; None when no such form was found."""
    if e.is_number:
        return [] if e == 0 else ([sp.Integer(1)] if e > 0 else None)
    terms = _nonnegative_terms(e)
    if terms is not None:
        return terms
    symbols = sorted(e.free_symbols, key=str)
    factors = factor_list(e, symbols)
    if factors and all(m % 2 == 0 for _, m in factors):
        square = sp.Mul(*(f**m for f, m in factors))
        if sp.cancel(e / square) > 0:
            return [sp.Mul(*(f for f, _ in factors))]
    for v in symbols:
        poly = sp.Poly(e, v)
        if poly.degree() != 2:
            continue
        a, b, c = (sp.sympify(poly.nth(k)) for k in (2, 1, 0))
        if b != 0 and a.is_number and a > 0:  # a (v + b/2a)**2 + (c - b**2/4a)
            shifted, rest = v + b / (2 * a), sp.expand(c - b**2 / (4 * a))
            tail = _squares(rest)
            if tail is None:
                continue
            return tail if tail == [sp.Integer(1)] else [shifted, *tail]
        if b != 0:
            continue
        head, tail = _squares(a), _squares(c)
        if head is None or tail is None:
            continue
        if tail == [sp.Integer(1)]:
            return tail  # A v**2 >= 0 plus something positive
        return [*([v] if head == [sp.Integer(1)] else [h * v for h in head]), *tail]
    return None


def _double_root(e: sp.Expr) -> list[sp.Expr] | None:
    """Where e = a V**2 + b V + c in V = v**k for a symbol v, with a of one sign and a
    discriminant b**2 - 4 a c that is never positive (minus it a sum of squares,
    ``_squares``): a real zero needs a real V, so the discriminant vanishes there, and
    the squares' roots are equations every real zero satisfies ([1]: none has one).
    None when no symbol gives such a form."""
    for v in sorted(e.free_symbols, key=str):
        poly = sp.Poly(e, v)
        k = math.gcd(*(m for (m,) in poly.monoms()))
        if k == 0 or poly.degree() != 2 * k:
            continue
        a, b, c = (sp.sympify(poly.coeff_monomial(v ** (j * k))) for j in (2, 1, 0))
        if [sp.Integer(1)] not in (_squares(a), _squares(-a)):
            continue  # a may vanish: e is not quadratic everywhere
        roots = _squares(sp.expand(4 * a * c - b**2))
        if roots:
            return roots
    return None


def _nonnegative_terms(e: sp.Expr) -> list[sp.Expr] | None:
    """Where every term of e is c P m**2 with c > 0 a number, P a product of parameters
    declared positive and m a monomial (each term >= 0 at admissible values): the m's,
    whose common zeros are e's; [1] when some term is a positive constant times P (e > 0).
    None otherwise."""
    roots: list[sp.Expr] = []
    symbols = sorted(e.free_symbols, key=str)
    try:
        terms = sp.Poly(e, *symbols).terms()
    except sp.PolynomialError:  # not a polynomial in its symbols
        return None
    for monomial, c in terms:
        if not c > 0:
            return None
        root = sp.Integer(1)
        for x, k in zip(symbols, monomial, strict=True):
            if x.is_positive:
                continue
            if k % 2:
                return None
            root *= x ** (k // 2)
        roots.append(root)
    return [sp.Integer(1)] if sp.Integer(1) in roots else roots


def never_positive(e: sp.Expr) -> list[tuple[sp.Expr, ...]] | None:
    """For a polynomial that is <= 0 at every real point, proven factor by factor (a
    factor of even multiplicity is a square; one of odd multiplicity must have a sign
    of its own, its negative or itself a sum of squares, ``_squares``): the systems
    whose real points are its real zeros, one per factor. None when no such proof was
    found."""
    if e.is_number:
        return [] if e < 0 else None
    constant, factors = coefficient_and_factors(e)
    sign = sp.sign(constant)
    systems: list[tuple[sp.Expr, ...]] = []
    for f, m in factors:
        if m % 2 == 0:
            systems.append((f,))
            continue
        roots, below = _squares(f), False
        if roots is None:
            roots, below = _squares(-f), True
        if roots is None:
            return None
        sign = -sign if below else sign
        if roots != [sp.Integer(1)]:
            systems.append(tuple(roots))
    return systems if sign < 0 else None
