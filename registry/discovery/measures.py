"""Invariant measures rho = prod F_i**a_i, by the method of the Jacobi last multiplier.

A density rho keeps the measure rho dx invariant when div(rho v) = 0 (Liouville's
equation). For a rational field v = P/D (D the least common denominator of its
components in the state), rho is a density of v exactly when sigma = rho/D is one of
the polynomial field Y = D v = P (div(sigma P) = div(rho v)). For sigma = prod F_i**a_i
with distinct irreducible F_i, Liouville's equation reads

    div Y + sum_i a_i L_i = 0,        L_i = Y(F_i)/F_i,

which needs every F_i with a_i != 0 to be a Darboux polynomial of Y (F_i divides
Y(F_i), the cofactor L_i a polynomial): a linear system in the exponents a_i, solved
exactly over Q(parameters) (generic parameter values). The polynomials tried are the
irreducible factors of the field's numerators and denominator, of div Y, and of the
case's claimed relations, each kept only if it is a Darboux polynomial of Y. A
solution of the homogeneous system is a first integral prod F_i**b_i, by which any
density may be multiplied. Each density found is proven by the audit's ``measure``
check before it is reported; the statement is complete for this ansatz only.
"""

from __future__ import annotations

import math
import random
import time
from typing import Any

import sympy as sp

from ..errors import DiscoveryError
from ..language.printer import to_text
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.factoring import factor_element
from ..mathematics.normal_form import as_fraction
from ..mathematics.zero_test import decide
from ..model import Case, ClaimKind, Density, MeasureSearch, Verdict


def measure_search(case: Case) -> MeasureSearch:
    """The densities prod F_i**a_i of ``case``'s flow (module docstring)."""
    started = time.perf_counter()
    m = CaseMechanics(case)
    dyn = m.dynamics
    state = list(dyn.variables)
    field = [dyn.expanded(e) for e in m.field]
    if any(_irrational(e, state) for e in field):
        raise DiscoveryError(
            "a measure search needs a rational vector field: this one has radicals or "
            "transcendental functions of the state"
        )
    params = sorted(set().union(*(e.free_symbols for e in field)) - set(state), key=str)
    rings = _Rings(state, params)
    polynomial, common = _cleared(field, rings)
    # D's factors of the state; a factor of the parameters alone only scales the field
    factors = [(g, k) for g, k in common if any(g.degrees()[: len(state)])]
    xs = rings.big.gens[: len(state)]
    divergence = sum((y.diff(x) for y, x in zip(polynomial, xs, strict=True)), rings.big.zero)

    candidates: list = [g for g, _ in factors]
    for source in [*polynomial, divergence, *_relations(case, rings.big)]:
        for f in rings.factors(source):
            if f not in candidates:
                candidates.append(f)
    darboux = []
    rng = random.Random(0)
    for f in candidates:
        image = sum((f.diff(x) * y for x, y in zip(xs, polynomial, strict=True)), rings.big.zero)
        if _not_divisible(image, f, rings.big, rng):
            continue
        quotient, remainder = image.div(f)
        if not remainder:
            darboux.append((f, quotient))
    columns = [rings.by_state(q) for _, q in darboux]
    rhs = rings.by_state(-divergence)
    monomials = sorted(set(rhs).union(*columns))
    zero = rings.coefficients.zero
    rows = [[c.get(mono, zero) for c in columns] + [rhs.get(mono, zero)] for mono in monomials]
    solutions = _solve(rows, rings.coefficients, len(darboux))

    shown = {f: _shown(f.as_expr(), state) for f in candidates}
    denominator = sp.Mul(*(g.as_expr() ** k for g, k in common))
    darboux_text = tuple(
        (to_text(shown[f]), to_text(sp.factor_terms(q.as_expr()) / denominator)) for f, q in darboux
    )
    undecided: list[str] = []
    densities: list[Density] = []
    integrals: list[str] = []
    if solutions is not None:
        particular, homogeneous = solutions
        # rho = D sigma, sigma = prod F**a a density of the polynomial field D v
        exponents: dict = {g: sp.Integer(k) for g, k in factors}
        for (f, _), a in zip(darboux, particular, strict=True):
            exponents[f] = exponents.get(f, 0) + a
        density = _density(m, [(shown[f], a) for f, a in exponents.items() if a != 0])
        if density.verdict is Verdict.VERIFIED:
            densities.append(density)
        else:
            undecided.append(
                f"density {density.expression} found but not proven ({density.verdict})"
            )
        for direction in homogeneous:
            # integer exponents, the smallest: x*y**2 rather than sqrt(x)*y
            scale = math.lcm(*(int(sp.fraction(sp.Rational(b))[1]) for b in direction))
            whole = [sp.Rational(b) * scale for b in direction]
            common = math.gcd(*(int(b) for b in whole if b))
            powers = [(shown[f], b / common) for (f, _), b in zip(darboux, whole, strict=True)]
            integrals.append(to_text(_product(powers)))
    complete = not undecided
    statement = _statement(case, darboux_text, densities, integrals, complete)
    return MeasureSearch(
        case.id,
        darboux_text,
        tuple(densities),
        tuple(integrals),
        tuple(to_text(shown[f]) for f in candidates),
        complete,
        statement,
        tuple(undecided),
        time.perf_counter() - started,
    )


class _Rings:
    """The search's ring Q[state, parameters] (``big``), where products, divisions and
    FLINT's factoring are cheap, and its coefficients over Q(parameters)
    (``coefficients``). A polynomial primitive in the state over Q[parameters] divides
    another, or is irreducible, in Q(parameters)[state] exactly when it is in ``big``
    (Gauss's lemma), so Darboux polynomials are found and tested in ``big``."""

    def __init__(self, state, params):
        self.n = len(state)
        self.big = sp.polys.rings.PolyRing([*state, *params], sp.QQ, sp.grevlex)
        self.coefficients = sp.QQ.frac_field(*params) if params else sp.QQ
        self.params = params

    def coefficient(self, terms: dict):
        """{parameter exponents: rational} as an element of Q(parameters)."""
        if not self.params:
            return sum(terms.values(), sp.QQ.zero)
        field = self.coefficients.field
        return field(field.ring(terms))

    def by_state(self, p) -> dict:
        """A polynomial of ``big`` as {state exponents: coefficient in Q(parameters)}."""
        return {e: self.coefficient(terms) for e, terms in _grouped(p, self.n).items()}

    def factors(self, p) -> list:
        """The irreducible factors of ``p`` over Q(parameters) that involve the state, as
        polynomials of ``big``, primitive (no factor of the parameters alone)."""
        if not any(p.degrees()[: self.n]):
            return []
        # by Gauss's lemma, p's factors over Q that involve the state (FLINT's, in big)
        return [self.normal(f) for f, _ in factor_element(p) if any(f.degrees()[: self.n])]

    def normal(self, f):
        """``f`` up to a constant factor in one form (monic over Q, else with a positive
        leading coefficient), so that a polynomial met twice is one candidate."""
        return f.monic() if not self.params else _positive_leading(f)


def _not_divisible(p, f, ring, rng: random.Random) -> bool:
    """True when ``f`` surely does not divide ``p``: at a random rational point of every
    generator but one (x, one ``f`` has) where ``f``'s leading coefficient in x does not
    vanish, the remainder of the division in x is not zero. (A multivariate division whose
    remainder is not zero grows large: this spares it for most candidates.)"""
    x = next(g for g, d in zip(ring.gens, f.degrees(), strict=True) if d > 0)
    others = [g for g in ring.gens if g != x]
    for _ in range(3):
        point = [(g, sp.QQ(rng.randint(-97, 97), rng.randint(1, 13))) for g in others]
        fx = f.evaluate(point) if point else f
        if fx.degree() < f.degree(x):
            continue  # the leading coefficient vanished there: try another point
        px = p.evaluate(point) if point else p
        return bool(px.rem(fx))
    return False


def _grouped(p, n: int) -> dict:
    grouped: dict = {}
    for e, c in p.items():
        grouped.setdefault(e[:n], {})[e[n:]] = c
    return grouped


def _positive_leading(p):
    return -p if p.LC < 0 else p


def _cleared(field, rings: _Rings):
    """The field over its least common denominator D: the polynomial field D v in
    ``rings.big``, and D's irreducible factors with their multiplicities. The fractions
    are read in Q[state, parameters] (cheap), the denominators factored one small factor
    at a time, and the lcm taken on the factors: no gcd of large polynomials is ever
    computed. The constant a factorisation leaves out (f = u prod g**k) is divided out
    of that component, so that every component is multiplied by the same D."""
    cache: dict = {}
    irreducible: dict = {}

    def factors(f) -> tuple[list, Any]:
        if f not in irreducible:
            found = [(rings.normal(g), k) for g, k in factor_element(f)]
            # leading coefficients multiply: u = LC(f) / prod LC(g)**k
            unit = f.LC / math.prod((g.LC**k for g, k in found), start=rings.big.domain.one)
            irreducible[f] = (found, unit)
        return irreducible[f]

    parts = []
    for expr in field:
        numer, den = as_fraction(expr, rings.big, cache)
        powers: dict = {}
        for f, e in den.items():
            found, unit = factors(f)
            numer = numer.quo_ground(unit**e)
            for g, k in found:
                powers[g] = powers.get(g, 0) + k * e
        parts.append((numer, powers))
    common: dict = {}
    for _, powers in parts:
        for g, k in powers.items():
            common[g] = max(common.get(g, 0), k)
    cleared = []
    for numer, powers in parts:
        for g, k in common.items():
            numer *= g ** (k - powers.get(g, 0))
        cleared.append(numer)
    return cleared, list(common.items())


def _relations(case: Case, ring) -> list:
    """The case's claimed relations F = 0 with a polynomial F, as polynomials of ``ring``."""
    found = []
    for claim in case.claims:
        if claim.kind is ClaimKind.RELATION and not claim.on:
            try:
                found.append(ring.from_expr(case.dynamics.expanded(claim.expression.expr)))
            except (ValueError, sp.PolynomialError, sp.CoercionFailed):
                continue  # not a polynomial: no factor of the ansatz
    return found


def _shown(expr: sp.Expr, state) -> sp.Expr:
    """A polynomial as people write it: with the sign that makes its value at the origin
    positive where the parameters' assumptions decide that sign."""
    origin = sp.sympify(expr.xreplace({x: 0 for x in state}))
    if origin.is_negative or (origin.is_positive is None and origin.could_extract_minus_sign()):
        expr = -expr
    return sp.expand(expr)


def _irrational(expr: sp.Expr, state) -> bool:
    """Whether ``expr`` has a radical or a function of the state (not a rational
    function of it)."""
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Function) and node.free_symbols & set(state):
            return True
        if node.is_Pow and not node.exp.is_Integer and node.base.free_symbols & set(state):
            return True
    return False


def _solve(rows: list[list], domain, count: int) -> tuple[list, list] | None:
    """A particular solution and a basis of the homogeneous solutions of the linear
    system (entries in ``domain``; last column: the right-hand side), exactly (the
    reduced row echelon form over the field), or None when it has none."""
    from sympy.polys.matrices import DomainMatrix

    if not rows:
        rows = [[domain.zero] * (count + 1)]
    reduced, pivots = DomainMatrix(rows, (len(rows), count + 1), domain).rref()
    if count in pivots:
        return None  # a row 0 = 1: no solution
    entries = reduced.to_Matrix()
    free = [k for k in range(count) if k not in pivots]
    particular = [sp.Integer(0)] * count
    for row, k in enumerate(pivots):
        particular[k] = entries[row, count]
    homogeneous = []
    for j in free:
        direction = [sp.Integer(0)] * count
        direction[j] = sp.Integer(1)
        for row, k in enumerate(pivots):
            direction[k] = -entries[row, j]
        homogeneous.append(direction)
    return particular, homogeneous


def _product(powers: list[tuple[sp.Expr, sp.Expr]]) -> sp.Expr:
    return sp.Mul(*(f**a for f, a in powers if a != 0))


def _density(m: CaseMechanics, powers: list[tuple[sp.Expr, sp.Expr]]) -> Density:
    """The density prod F**a, proven (or not) by the audit's measure check."""
    rho = _product(powers)
    verdict = decide(m.measure_residual(rho), m.domain, seed=m.seed("measure-search")).verdict
    singular = tuple(to_text(f) for f, a in powers if not (a.is_integer and a > 0))
    return Density(
        to_text(rho), tuple((to_text(f), to_text(a)) for f, a in powers), verdict, singular
    )


def _statement(case, darboux, densities, integrals, complete) -> str:
    if not complete:
        return (
            f"Densities prod F_i**a_i of {case.id} over the Darboux polynomials of its field: "
            "the search did not finish (see undecided)."
        )
    over = (
        f"over the {len(darboux)} Darboux polynomial(s) of its field among the factors tried"
        if darboux
        else "over the factors tried (none is a Darboux polynomial of its field)"
    )
    if not densities:
        return (
            f"{case.id} has no invariant density prod F_i**a_i {over}, for generic "
            "parameter values."
        )
    (rho,) = densities
    more = f", times any function of {', '.join(integrals)}" if integrals else ""
    where = "; it is a polynomial, defined everywhere"
    if rho.singular:
        where = (
            "; it is singular or undefined where a factor with a negative or fractional "
            "exponent vanishes"
        )
        if not integrals:
            where += ", so no density of this form is defined everywhere"
    return (
        f"Every invariant density prod F_i**a_i of {case.id} {over} is rho = {rho.expression}"
        f"{more}, for generic parameter values (proven by the measure check){where}."
    )
