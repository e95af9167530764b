"""Whether an integral a search found is new, or one of the case's own claims again.

An extra integral F is *rediscovered* when it lies, within the ansatz, in the span of
the products of the known integrals (H, |gamma|^2, the torque's Casimir), of the claims
the audit proves, and of the new integrals found before it: F = sum c_j P_j + const
with each P_j such a product. Membership is decided exactly, by linear algebra over Q
or Q(q) on the ansatz coefficients, for the fewest claims that suffice (which names
them); the identity is then checked in the system's ring (modulo the level set) before
it is reported. Otherwise F is *new*.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations

import sympy as sp
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rings import PolyElement

from ..errors import DiscoveryError
from ..language.printer import to_text
from ..mathematics.factoring import factor
from ..model import IntegralStatus
from .ansatz import PolynomialSystem
from .integrals import vector
from .linear import Field, Span

#: Most claims tried together when naming the claims an integral equals.
MAX_CLAIMS = 4


@dataclass(frozen=True)
class Known:
    """An integral known before a search: its ``name`` (a claim's label, ``H``, or the
    expression's text), ``symbol`` (how it appears in a relation: a symbol named after
    it, or the expression), its polynomial in the system's ring, its weighted degree,
    and whether it is a claim of the case."""

    name: str
    symbol: sp.Expr
    expr: sp.Expr
    poly: PolyElement
    weight: int
    claim: bool = False
    #: the parameter polynomial ``poly`` is ``expr`` times (denominators cleared)
    scale: sp.Expr = sp.Integer(1)


def known(
    system: PolynomialSystem, name: str, expr: sp.Expr, *, claim: bool = False, symbol=None
) -> Known | None:
    """``expr`` as a known integral of the system (None where it is not in the ring, or
    is a constant there)."""
    try:
        poly = system.polynomial(expr, what="known integral")
    except DiscoveryError:
        return None
    if not system.weight(poly):
        return None
    if symbol is None:
        symbol = sp.Symbol(name if claim or name.isidentifier() else f"({name})")
    scale = _scale(system, expr)
    return Known(name, symbol, sp.sympify(expr), poly, system.weight(poly), claim, scale)


def _scale(system: PolynomialSystem, expr: sp.Expr) -> sp.Expr:
    """The parameter denominator ``PolynomialSystem.polynomial`` clears from ``expr``."""
    return sp.fraction(sp.together(sp.expand(system.expanded(expr))))[1]


def _products(system: PolynomialSystem, gens: Sequence[Known]) -> list[tuple[tuple, PolyElement]]:
    """Every product of ``gens`` (repetition allowed) of weight <= the ansatz's degree,
    reduced modulo the level set, with its exponents."""
    found: list[tuple[tuple, PolyElement]] = []

    def extend(start: int, exps: list[int], poly: PolyElement, weight: int) -> None:
        for i in range(start, len(gens)):
            g = gens[i]
            if weight + g.weight > system.degree:
                continue
            exps[i] += 1
            product = system.reduce(poly * g.poly)
            found.append((tuple(exps), product))
            extend(i, exps, product, weight + g.weight)
            exps[i] -= 1

    extend(0, [0] * len(gens), system.ring.one, 0)
    return found


def _in_span(system, fld: Field, gens: Sequence[Known], target: list) -> bool:
    span = Span(fld)
    for _, poly in _products(system, gens):
        try:
            span.add(vector(system, poly, fld))
        except ValueError:  # a product outside the ansatz (a level set's normal form)
            continue
    return not any(span.reduce(target))


def _relation(
    system, fld: Field, gens: Sequence[Known], poly: PolyElement, target: list, scale: sp.Expr
):
    """(the combination of products of ``gens`` that equals the integral ``poly``, the
    known integrals it uses), or None if there is none. The caller checks it."""
    products, columns = [], []
    for exps, p in _products(system, gens):
        try:
            columns.append(vector(system, p, fld))
        except ValueError:
            continue
        products.append(exps)
    n = len(target)
    rows = [[col[r] for col in columns] + [target[r]] for r in range(n)]
    matrix = DomainMatrix(rows, (n, len(columns) + 1), fld.domain)
    for v in matrix.nullspace().to_list():
        if v[-1]:
            coeffs = [-c / v[-1] for c in v[:-1]]
            break
    else:
        return None
    terms, parts = [], []
    used: set[int] = set()
    for exps, c in zip(products, coeffs, strict=True):
        if c:
            coefficient = fld.domain.to_sympy(c) / scale
            for g, e in zip(gens, exps, strict=True):
                coefficient *= g.scale**e
            monomial = sp.Mul(*(g.symbol**e for g, e in zip(gens, exps, strict=True)))
            coefficient = factor(coefficient)
            terms.append(coefficient * monomial)
            parts.append((coefficient, exps))
            used.update(i for i, e in enumerate(exps) if e)
    kept = sorted(used)
    parts = [(k, tuple(exps[i] for i in kept)) for k, exps in parts]
    return sp.Add(*terms), [gens[i] for i in kept], parts


def _difference(
    system: PolynomialSystem, expr: sp.Expr, parts, gens
) -> tuple[PolyElement, PolyElement]:
    """(rest, D) with expr - sum_j k_j prod_i gens_i^e_ij = rest / D in the system's ring,
    rest reduced modulo the level set and D a parameter polynomial: the identity computed
    exactly with ring arithmetic (each claim's numerator raised and multiplied there), not
    by expanding the combination as an expression."""

    def parameter(e: sp.Expr) -> PolyElement:
        return system.ring.from_expr(sp.expand(e).xreplace(system._plain))

    pieces: list[tuple[PolyElement, PolyElement]] = []
    numer, denom = system.fraction(expr)
    pieces.append((numer, parameter(denom)))
    fractions = [system.fraction(g.expr) for g in gens]
    fractions = [(n, parameter(d)) for n, d in fractions]
    for k, exps in parts:
        a, b = sp.fraction(sp.together(k))
        n, d = parameter(a), parameter(b)
        for (gn, gd), e in zip(fractions, exps, strict=True):
            if e:
                n *= gn**e
                d *= gd**e
        pieces.append((-n, d))
    common = system.ring.one
    for _, d in pieces:
        common = common.lcm(d)
    total = system.ring.zero
    for n, d in pieces:
        total += n * common.exquo(d)
    return system.reduce(total), common


def checked(
    system: PolynomialSystem, expr: sp.Expr, combination: sp.Expr, gens, parts=None
) -> sp.Expr:
    """``combination`` plus the constant that makes it equal ``expr`` on the level set,
    checked exactly in the system's ring; DiscoveryError where the two differ by more.
    With ``parts`` (combination = sum k * prod gens^exps, as (k, exps) pairs) the
    identity is computed with ring arithmetic (``_difference``); where that does not
    show it, or without ``parts``, by expanding the expressions."""
    outside = {*system.variables, *system.shorthands}
    if parts is not None and not any(k.free_symbols & outside for k, _ in parts):
        rest, common = _difference(system, expr, parts, gens)
        if not any(any(m[: system.n]) for m in rest.monoms()):
            if rest:
                constant = system.expression(rest) / system.expression(common)
                combination += factor(constant)
            return combination
    values = {g.symbol: g.expr for g in gens if g.symbol != g.expr}
    difference = sp.expand(expr - combination.xreplace(values))
    rest = system.polynomial(difference)
    if any(any(m[: system.n]) for m in rest.monoms()):
        raise DiscoveryError(
            f"the identity {to_text(expr)} = {to_text(combination)} failed its check"
        )
    if rest:
        _, denominator = sp.fraction(sp.together(sp.expand(system.expanded(difference))))
        constant = system.expression(rest) / denominator
        combination += factor(constant)
    return combination


def statuses(
    system: PolynomialSystem,
    fld: Field,
    trivial: Sequence[Known],
    claims: Sequence[Known],
    found: Sequence[sp.Expr],
) -> list[IntegralStatus]:
    """For each integral found (in the order found): new, or the fewest claims it equals
    modulo the known integrals (module docstring)."""
    base = list(trivial)
    out: list[IntegralStatus] = []
    for expr in found:
        poly = system.polynomial(expr)
        try:
            target = vector(system, poly, fld)
        except ValueError:
            out.append(IntegralStatus("new"))
            continue
        status = None
        for size in range(1, min(len(claims), MAX_CLAIMS) + 1):
            for chosen in combinations(claims, size):
                gens = [*base, *chosen]
                if not _in_span(system, fld, gens, target):
                    continue
                relation = _relation(system, fld, gens, poly, target, _scale(system, expr))
                if relation is None:
                    continue
                combination, used, parts = relation
                combination = checked(system, expr, combination, used, parts)
                status = IntegralStatus(
                    "rediscovered",
                    tuple(g.name for g in used if g.claim),
                    tuple(g.name for g in used if not g.claim),
                    sp.sstr(combination),
                )
                break
            if status is not None:
                break
        if status is None:
            status = IntegralStatus("new")
            base.append(
                Known(
                    to_text(expr),
                    expr,
                    expr,
                    poly,
                    system.weight(poly),
                    scale=_scale(system, expr),
                )
            )
        out.append(status)
    return out
