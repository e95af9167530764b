"""Balances: the leading terms x = c t^(-w) of Laurent solutions of a weighted field.

A balance is a nonzero c with -w_i c_i = v_i(c) for the leading part v of the field
(``weighted``). All of them are found, complex ones included, as the points (and
families) of the irreducible components of these equations other than the origin
(``prime_components``); the coordinates are exact algebraic numbers.

*The scaling symmetry.* The weighted scaling c -> a^w c maps the leading part to
v(a^w c) = a^(w + 1) v(c), so it maps a balance c to a point c' with
-a w_i c'_i = v_i(c'): a balance only for a = 1, whatever the weights. The equations
fix the normalisation: the solutions x = c (t - t0)^(-w) and a^w c (a (t - t0))^(-w)
are the same, so each orbit of the scaling, a line of "weighted Darboux points"
d with v(d) = mu w d (mu != 0), meets the balances exactly once, at a = -1/mu.
Listing every balance therefore lists each orbit once; nothing is identified. What
does map balances to other balances, with the same exponents, are the symmetries of
the field itself (sign changes, rotations): those balances are different solutions
and are listed separately, and a continuous symmetry makes a family of balances.

*Families.* A component of dimension d > 0 is a family: its free coordinates S stay
symbols and the other coordinates are functions of them (``Balance.free``). Where the
component's minimal polynomial has constant coefficients, each of its roots is one
family, written out; otherwise the family is given through a root u of that polynomial.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from . import algebraic
from .groebner import groebner
from .prime_components import Component, components
from .weighted import WeightedField


@dataclass(frozen=True)
class Balance:
    """One balance (a point c, or a family of them), with its exact coordinates.

    ``root`` is the value at this balance of the component's primitive element u
    (``component.symbol``); where the roots of its minimal polynomial have no closed
    form (over rational functions of parameters), ``root`` is None and ``point`` is
    written in terms of u itself."""

    point: Mapping[sp.Symbol, sp.Expr]
    component: Component
    root: sp.Expr | None

    @property
    def free(self) -> tuple[sp.Symbol, ...]:
        """The coordinates left free along a family (none for an isolated balance)."""
        return self.component.free

    @property
    def dimension(self) -> int:
        return self.component.dimension


def balance_equations(split: WeightedField) -> list[sp.Expr]:
    """v_i(c) + w_i c_i for the leading part v, times its denominator in the state where
    it has one: zero at the balances (and at 0, and where a denominator vanishes)."""
    equations = []
    for v, w, x in zip(split.leading, split.weights, split.variables, strict=True):
        e = v + w * x
        if split.denominators:
            e = sp.fraction(sp.together(e))[0]
        equations.append(sp.expand(e))
    return equations


def balances(split: WeightedField, *, seed: int = 0) -> tuple[Balance, ...]:
    """Every balance of the leading part, complex ones included, isolated ones after the
    families, each component's balances in the order of their roots. For a field with
    denominators, the components on which one of them vanishes are not balances (the
    equations were multiplied by it): those left are the closures of the balances where
    the field is defined."""
    found: list[Balance] = []
    equations = balance_equations(split)
    for component in components(equations, split.variables, split.parameters, seed=seed):
        if any(component.vanishes(d) for d, _ in split.denominators):
            continue
        found.extend(component_balances(component))
    return tuple(found)


def component_balances(component: Component) -> list[Balance]:
    """The balances of one irreducible component: one per root of its minimal polynomial
    when the roots have a closed form, else one given through the root u."""
    g, u = component.minimal, component.symbol
    coords = component.coordinates
    # levels of degree <= 2 multiply to a power of 2: only then can the triangular
    # solve succeed, and its lexicographic basis over Q(p) is not spent in vain
    power_of_two = g.degree() & (g.degree() - 1) == 0
    if g.degree() > 2 and power_of_two and not component.free and not g.domain.is_QQ:
        triangular = _triangular_points(component)
        if triangular is not None:
            return [Balance(p, component, _tidy(component.element.xreplace(p))) for p in triangular]
    constant = g.domain.is_QQ or not (set(g.free_symbols) - {u})
    roots = algebraic.exact_roots(_over_q(g) if constant else g)
    if roots is None:
        return [Balance(dict(coords), component, None)]
    if len(roots) > 2 and constant and not component.free:
        points = _identified_points(component, roots)
    else:
        points = [{x: _tidy(h.subs(u, r)) for x, h in coords.items()} for r in roots]
    return [Balance(p, component, r) for p, r in zip(points, roots, strict=True)]


def _triangular_points(component: Component) -> list[dict[sp.Symbol, sp.Expr]] | None:
    """The points of a zero-dimensional component solved level by level from its
    lexicographic basis (last variable first), when that basis is triangular and every
    level has degree <= 2: short radicals over Q(parameters), where no root can be told
    apart numerically. None otherwise."""
    variables = component.variables
    domain = component.domain
    basis = groebner(component.ideal, variables, domain, order="lex").exprs
    levels = {}
    for e in basis:
        leading = next(x for x in variables if e.has(x))
        if leading in levels or sp.degree(e, leading) > 2:
            return None
        levels[leading] = e
    if set(levels) != set(variables):
        return None
    points: list[dict[sp.Symbol, sp.Expr]] = [{}]
    for x in reversed(variables):
        extended = []
        for point in points:
            poly = sp.Poly(sp.expand(levels[x].xreplace(point)), x)
            if poly.degree() == 1:  # most levels: x = -b/a, no need for sympy's roots
                extended.append({**point, x: _tidy(-poly.nth(0) / poly.nth(1))})
                continue
            roots = sp.roots(poly)
            if sum(roots.values()) != poly.degree() or any(m > 1 for m in roots.values()):
                return None
            extended += [{**point, x: _tidy(r)} for r in roots]
        points = extended
    if len(points) != component.degree:
        return None
    return [{x: p[x] for x in variables} for p in points]


def _over_q(g: sp.Poly) -> sp.Poly:
    return sp.Poly(g.as_expr(), *g.gens, domain=sp.QQ)


def _tidy(expr: sp.Expr) -> sp.Expr:
    """A coordinate in a short form: expanded, radicals out of denominators; over
    Q(parameters) one fraction whose numerator is expanded, so that terms that cancel
    (Suslov's I13**2*I22**2 - I22*(... + I13**2*I22)) are gone."""
    expr = sp.expand(expr)
    if expr.free_symbols:
        numerator, denominator = sp.fraction(sp.together(expr))
        return sp.factor_terms(sp.expand(numerator)) / denominator
    return sp.radsimp(expr)


def _identified_points(component: Component, roots) -> list[dict[sp.Symbol, sp.Expr]]:
    """The points of a zero-dimensional component over Q with each coordinate written
    as a root of its own minimal polynomial (radicals where short), chosen by ``identify``;
    a coordinate that cannot be identified keeps the form h(root)."""
    ext = algebraic.Extension(component.symbol, _over_q(component.minimal))
    z = sp.Dummy("z")
    candidates: dict[sp.Symbol, tuple[sp.Expr, ...]] = {}
    for x, h in component.coordinates.items():
        minimal = algebraic.minimal_polynomial(ext, ext.poly(h), z)
        candidates[x] = algebraic.exact_roots(minimal) or ()  # over Q: never None
    points = []
    for root in roots:
        point = {}
        for x, h in component.coordinates.items():
            value = algebraic.to_acb(h.subs(component.symbol, root))
            try:
                point[x] = algebraic.identify(value, candidates[x])
            except algebraic.Unidentified:  # pragma: no cover - the balls separate them
                point[x] = h.subs(component.symbol, root)
        points.append(point)
    return points
