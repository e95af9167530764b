"""Where the roots of polynomials phi_j(lambda; p) over Q(p) are all integers (or all
rational), for one parameter p: the special values of a family's Kovalevskaya exponents.

*Integers.* If every root of a monic phi is an integer, so is every coefficient (they
are the elementary symmetric functions of the roots, up to sign). One coefficient
tau(p) that is not constant pins p: tau(p) = m for an integer m. When tau is a Möbius
function (numerator and denominator of degree <= 1), p = P(m) is a rational function
of m and every other coefficient becomes sigma(m) = Q(m) + R(m)/D(m), deg R < deg D.
With L the common denominator of Q's coefficients, sigma(m) in Z forces
|L R(m)| >= |D(m)| or R(m) = 0: a finite set of m, no larger in size than the largest
real root of D^2 - L^2 R^2 (isolated exactly), so the search is complete. Where every
sigma is a polynomial, sigma(m) mod 1 depends on m mod L only: the solutions are
residue classes, infinite families p = P(r + L n), n in Z. Either way the candidates
are necessary conditions; a factor of degree >= 2 must still split over Z, which the
caller checks at each candidate value (in a residue family only a bounded range can be
checked, and the answer is then not complete). A pinning tau of higher degree is
searched over a bounded range of m only.

*Rationals* (for rational p). Linear factors have rational roots at every rational p;
a quadratic factor has them exactly when its discriminant is a rational square. With
the discriminant's squarefree part D(p) of degree 1, p = (t^2 - b)/a for every
rational t; of degree 2, a conic, parametrised from one rational point found by a
small search (Legendre's theorem would decide when none is found: not implemented, so
that case is searched, not complete). Higher degrees are searched over small heights.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

#: The largest |m| enumerated when a bound is computed; beyond it the search is cut.
MAX_BOUND = 20000
#: The range of m (or of a family's index) searched where no bound exists.
SEARCH_RANGE = 12
#: The heights (|numerator|, denominator) of the rational values searched.
SEARCH_HEIGHT = 12


@dataclass(frozen=True)
class Candidates:
    """Parameter values that may be special: finitely many ``values``, and ``families``
    (p as an expression of an index, the index, and what it ranges over). ``complete``:
    no other value outside the exceptional set can be special."""

    values: tuple[sp.Expr, ...] = ()
    families: tuple[tuple[sp.Expr, sp.Symbol, str], ...] = ()
    complete: bool = True
    notes: tuple[str, ...] = ()


def integer_candidates(factors: Sequence[sp.Expr], p: sp.Symbol, lam: sp.Symbol) -> Candidates:
    """Values of p (outside the poles) where every coefficient of every monic factor is
    an integer: necessary for all roots to be integers (module doc)."""
    coefficients = _coefficients(factors, p, lam)
    constant = [c for c in coefficients if not c.has(p)]
    if any(not c.is_integer for c in constant):
        return Candidates(notes=("a constant coefficient is not an integer",))
    varying = sorted(
        (c for c in coefficients if c.has(p)), key=lambda c: (_degree(c, p), sp.default_sort_key(c))
    )
    wide = [f for f in factors if sp.degree(f, lam) > 1]
    if not varying:  # the exponents do not depend on p: integers everywhere, or nowhere
        return Candidates() if wide else Candidates(families=((p, p, "every value"),))
    tau = varying[0]
    m = sp.Symbol("m", integer=True)
    if _degree(tau, p) > 1:
        return _searched(tau, varying, p, m)
    solution = sp.solve(sp.Eq(tau, m), p)[0]
    sigmas = [sp.cancel(c.subs(p, solution)) for c in varying[1:]]
    finite = [s for s in sigmas if _fraction_part(s, m) != 0]
    if finite:
        found = None
        for s in finite:
            admissible = _integer_points(s, m)
            if admissible is None:
                return _searched(tau, varying, p, m, cut=True)
            found = admissible if found is None else found & admissible
        ms = sorted(k for k in found or () if all(_is_integer_at(s, m, k) for s in sigmas))
        values = tuple(v for v in (_at(solution, m, k) for k in ms) if v is not None)
        return Candidates(values=values)
    period = math.lcm(1, *(_denominator(s, m) for s in sigmas))
    residues = [r for r in range(period) if all(_is_integer_at(s, m, r) for s in sigmas)]
    n = sp.Symbol("n", integer=True)
    families = tuple((sp.cancel(solution.subs(m, r + period * n)), n, "n in Z") for r in residues)
    return Candidates(families=families)


def _searched(tau, varying, p, m, cut: bool = False) -> Candidates:
    """Values with tau(p) = m for |m| <= SEARCH_RANGE (real roots) and every coefficient
    an integer there: a search, not complete."""
    values = []
    for k in range(-SEARCH_RANGE, SEARCH_RANGE + 1):
        numer = sp.fraction(sp.together(tau - k))[0]
        if not numer.has(p):
            continue
        for root in sp.Poly(numer, p).real_roots():
            if all(_integer_value(c.subs(p, root)) for c in varying):
                values.append(root)
    why = "the bound on m is too large" if cut else "the pinning coefficient is not Möbius"
    return Candidates(
        values=tuple(dict.fromkeys(values)),
        complete=False,
        notes=(f"searched |m| <= {SEARCH_RANGE} only ({why})",),
    )


def _coefficients(factors, p, lam) -> list[sp.Expr]:
    found = []
    for f in factors:
        poly = sp.Poly(f, lam)
        lead = poly.LC()
        found += [sp.cancel(c / lead) for c in poly.all_coeffs()[1:]]
    return found


def _degree(expr: sp.Expr, p: sp.Symbol) -> int:
    numer, denom = sp.fraction(sp.cancel(expr))
    return max(sp.degree(numer, p), sp.degree(denom, p))


def _fraction_part(s: sp.Expr, m: sp.Symbol) -> sp.Expr:
    numer, denom = sp.fraction(sp.cancel(s))
    return sp.rem(numer, denom, m)


def _denominator(s: sp.Expr, m: sp.Symbol) -> int:
    """The common denominator of a polynomial's rational coefficients."""
    return math.lcm(1, *(int(sp.Rational(c).q) for c in sp.Poly(sp.cancel(s), m).coeffs()))


def _integer_points(s: sp.Expr, m: sp.Symbol) -> set[int] | None:
    """The integers m where sigma = Q + R/D can be an integer: the integer roots of R
    and |m| up to the largest real root of D^2 - L^2 R^2, beyond which |L R| < |D|
    (None beyond ``MAX_BOUND``)."""
    numer, denom = sp.fraction(sp.cancel(s))
    q, r = sp.div(numer, denom, m)
    scale = _denominator(q, m) if q != 0 else 1
    bound_poly = sp.Poly(sp.expand(denom**2 - scale**2 * r**2), m)
    ends = [abs(end) for interval, _ in bound_poly.intervals() for end in interval]
    bound = max(ends, default=0)
    if bound > MAX_BOUND:
        return None
    limit = int(sp.ceiling(bound))
    points = set(range(-limit, limit + 1))
    points |= {int(z) for z in sp.Poly(r, m).ground_roots() if z.is_integer} if r != 0 else set()
    return {k for k in points if _is_integer_at(s, m, k)}


def _is_integer_at(s: sp.Expr, m: sp.Symbol, k: int) -> bool:
    numer, denom = _rational_polys(s, m)
    if numer is None:  # coefficients beyond Q: sympy's arithmetic
        n, d = sp.fraction(sp.cancel(s))
        value = d.subs(m, k)
        return value != 0 and _integer_value(n.subs(m, k) / value)
    d = _horner(denom, k)
    return d != 0 and _horner(numer, k) % d == 0


@functools.lru_cache(maxsize=256)
def _rational_polys(s: sp.Expr, m: sp.Symbol):
    """Numerator and denominator of a rational function of m as integer coefficient
    lists (highest first), or (None, None) where a coefficient is not rational."""
    numer, denom = sp.fraction(sp.cancel(s))
    try:
        polys = sp.Poly(numer, m, domain="QQ"), sp.Poly(denom, m, domain="QQ")
    except (sp.PolynomialError, sp.CoercionFailed):
        return None, None
    coefficients = [poly.all_coeffs() for poly in polys]
    scale = math.lcm(*(int(c.q) for row in coefficients for c in row))
    return tuple(tuple(int(c * scale) for c in row) for row in coefficients)


def _horner(coefficients: tuple[int, ...], k: int) -> int:
    total = 0
    for c in coefficients:
        total = total * k + c
    return total


def _integer_value(value: sp.Expr) -> bool:
    return bool(sp.radsimp(sp.expand(value)).is_integer)


def _at(solution: sp.Expr, m: sp.Symbol, k: int) -> sp.Expr | None:
    numer, denom = sp.fraction(sp.cancel(solution))
    d = denom.subs(m, k)
    return None if d == 0 else numer.subs(m, k) / d


def rational_candidates(factors: Sequence[sp.Expr], p: sp.Symbol, lam: sp.Symbol) -> Candidates:
    """Rational values of p where every factor has only rational roots (module doc)."""
    wide = [f for f in factors if sp.degree(f, lam) > 1]
    if not wide:
        return Candidates(families=((p, p, "every rational value"),))
    t = sp.Symbol("t", rational=True)
    if len(wide) == 1 and sp.degree(wide[0], lam) == 2:
        family = _square_discriminant(wide[0], p, lam, t)
        if family is not None:
            return Candidates(families=(family,)) if family[0] is not None else Candidates()
    values = [
        v for v in _small_rationals() if all(_rational_roots(f.subs(p, v), lam) for f in wide)
    ]
    return Candidates(
        values=tuple(values),
        complete=False,
        notes=(f"searched rational p of height <= {SEARCH_HEIGHT} only",),
    )


def _square_discriminant(factor, p, lam, t):
    """The rational p where a quadratic's discriminant is a rational square, as a family
    p(t), t rational; (None, t, ...) when there is provably none; None when undecided."""
    a2, a1, a0 = sp.Poly(factor, lam).all_coeffs()
    disc = sp.cancel((a1**2 - 4 * a0 * a2) / a2**2)
    numer, denom = sp.fraction(disc)
    squarefree = _squarefree_part(sp.expand(numer * denom), p)
    degree = sp.degree(squarefree, p)
    if degree == 0:
        value = sp.Rational(squarefree)
        is_square = value >= 0 and sp.sqrt(value).is_rational
        return (p, t, "every rational value") if is_square else (None, t, "none")
    if degree == 1:
        b, a = sp.Poly(squarefree, p).all_coeffs()[::-1]
        return (sp.cancel((t**2 - b) / a), t, "t in Q")
    if degree == 2:
        c, b, a = sp.Poly(squarefree, p).all_coeffs()[::-1]
        for v in _small_rationals():
            value = a * v**2 + b * v + c
            if value >= 0 and sp.sqrt(value).is_rational:
                y0 = sp.sqrt(value)
                s = (2 * a * v + b - 2 * y0 * t) / (t**2 - a)
                return (sp.cancel(v + s), t, "t in Q (and the point found)")
        return None
    return None


def _squarefree_part(expr: sp.Expr, p: sp.Symbol) -> sp.Expr:
    """expr divided by its largest square factor over Q (a rational constant kept only
    up to rational squares)."""
    content, factors = sp.factor_list(expr, p)
    content = sp.Rational(content)
    square_free_content = sp.Integer(content.p * content.q)
    for prime, e in sp.factorint(abs(square_free_content)).items():
        square_free_content /= prime ** (e - e % 2)
    rest = sp.Mul(*(f ** (e % 2) for f, e in factors))
    return sp.expand(square_free_content * rest)


def _rational_roots(poly_expr: sp.Expr, lam: sp.Symbol) -> bool:
    poly = sp.Poly(sp.cancel(poly_expr), lam)
    return all(sp.degree(f, lam) <= 1 for f, _ in sp.factor_list(poly.as_expr(), lam)[1])


def _small_rationals():
    seen = set()
    for q, a in itertools.product(range(1, SEARCH_HEIGHT + 1), range(0, SEARCH_HEIGHT + 1)):
        for v in {sp.Rational(a, q), sp.Rational(-a, q)}:
            if v not in seen:
                seen.add(v)
                yield v
