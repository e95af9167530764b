"""Exact random points of a domain, and concrete instances of a family's functions.

The zero test probes residuals at such points (``zero_test``), the numeric evidence
starts its trajectories there (``audit.numeric_evidence``). A point is exact:
rational where the case's radicals allow it (|gamma| and one planar radius are made
rational, so square roots of |gamma|**2 evaluate exactly), placed exactly on a
claim's level set, with parameters that respect their assumptions, and inside the
domain (moments of inertia nonzero, the case's expressions defined). A family's
arbitrary functions become random quadratic polynomials.
"""

from __future__ import annotations

import itertools
import random
from collections.abc import Iterator, Mapping, Sequence
from fractions import Fraction
from functools import lru_cache

import sympy as sp
from sympy.core.function import AppliedUndef

from .certified_evaluation import At, OutsideDomain, exact_root
from .domain import Domain


def _rational(rng: random.Random, *, positive=False, nonzero=False, integer=False) -> Fraction:
    """A small random rational (or integer) respecting the assumptions."""
    while True:
        if integer:
            v = Fraction(rng.randint(1 if positive else -6, 6))
        else:
            num = rng.randint(1 if positive else -23, 23)
            v = Fraction(num, rng.randint(1, 11))
        if v != 0 or not (positive or nonzero):
            return v


def _parameter_value(sym: sp.Symbol, rng: random.Random) -> Fraction:
    return _rational(
        rng,
        positive=bool(sym.is_positive),
        nonzero=bool(sym.is_nonzero),
        integer=bool(sym.is_integer),
    )


def _pythagorean(rng: random.Random, radius: Fraction) -> tuple[Fraction, Fraction]:
    """A rational point on the circle of the given radius."""
    t = _rational(rng)
    return radius * (1 - t * t) / (1 + t * t), radius * 2 * t / (1 + t * t)


def _axis_points(rng: random.Random) -> list[list[Fraction]]:
    """Rational gamma with |gamma| and one planar radius rational, so that square roots
    of |gamma|**2 and of gamma_i**2 + gamma_j**2 evaluate exactly; the three
    arrangements make each planar radius the rational one in turn."""
    big = _rational(rng, positive=True)
    r, third = _pythagorean(rng, big)
    a, b = _pythagorean(rng, r)
    if rng.random() < 0.5:
        a, b = b, a
    return [[a, b, third], [third, a, b], [a, third, b]]


def radical_bases(exprs) -> list[tuple[sp.Expr, int]]:
    """The bases and root orders of the radicals in ``exprs``."""
    found = {
        (p.base, int(p.exp.q))
        for e in exprs
        for p in e.atoms(sp.Pow)
        if p.exp.is_Rational and not p.exp.is_Integer and p.base.free_symbols
    }
    return sorted(found, key=str)


def _exact_radicals(point: Mapping, bases: Sequence[tuple[sp.Expr, int]]) -> int:
    """How many of the radicals are rational at the point (higher is better)."""
    count = 0
    at = At(point)
    for base, q in bases:
        try:
            value = at(base)
        except (OutsideDomain, ValueError):
            continue
        exact = value.exact
        if exact is not None and exact >= 0 and exact_root(exact, q) is not None:
            count += 1
    return count


def sample_point(domain: Domain, rng: random.Random, funcs, bases=()) -> dict | None:
    """A random exact point of the domain (on the level set), or None.

    Parameters get values that respect their assumptions; each state vector then gets
    random rationals, except that a vector sampled with a rational norm gets three
    arrangements of a point on a sphere of rational radius (``_axis_points``), and of
    their combinations the one where most of the ``bases`` (radicals of the residuals)
    are rational is taken, so values stay exact. Shorthands (s = M.gamma) get their
    values last.
    """
    point: dict[sp.Symbol, sp.Expr] = {}
    for sym in domain.parameters:
        point[sym] = sp.Rational(_parameter_value(sym, rng))
    spheres = []
    for vector in domain.vectors:
        if vector.rational_norm and len(vector.components) == 3:
            spheres.append(vector.components)
            continue
        for sym in vector.components:
            point[sym] = sp.Rational(_rational(rng))
    arrangements = [[(c, a) for a in _axis_points(rng)] for c in spheres]
    best: dict[sp.Symbol, sp.Expr] | None = None
    best_score = -1
    for chosen in itertools.product(*arrangements):
        candidate = dict(point)
        for components, values in chosen:
            candidate.update({g: sp.Rational(v) for g, v in zip(components, values, strict=True)})
        _put_shorthands(candidate, domain)
        score = _exact_radicals(candidate, bases) if bases else 0
        if score > best_score:
            best, best_score = candidate, score
        if not bases:
            break  # without radicals every arrangement scores 0: the first one is kept
    if best is None:
        return None
    point = best
    if domain.on:
        for name in domain.shorthands:
            del point[name]
        if not _place_on_set(point, domain, rng, funcs):
            return None
        _put_shorthands(point, domain)
    at = At(point)  # the point's values converted once for every expression
    try:
        if not all(at(e).certainly_nonzero() for e in domain.nonzero):
            return None
        for expr in domain.defined:
            at(substitute_functions(expr, funcs))
    except OutsideDomain:
        return None
    return point


def _put_shorthands(point: dict, domain: Domain) -> None:
    """The value of each shorthand (s = M.gamma) at the point."""
    for name, value in domain.shorthands.items():
        point[name] = sp.expand(value.xreplace(point))


def _place_on_set(point: dict, domain: Domain, rng, funcs) -> bool:
    """Move ``point`` onto the level set, solving the equations one variable at a time.

    Each equation pins unpinned state variables: linearly, by scaling a homogeneous
    group (a vector: gamma, M), or by a real root of a quadratic. Orders are tried until
    the exact point satisfies every equation.
    """
    eqs = [domain.expanded(substitute_functions(e, funcs)) for e in domain.on]
    # vectors with a rational norm are scaled first (gamma before M on the paper's state)
    groups = [v.components for v in domain.vectors if v.rational_norm] + [
        v.components for v in domain.vectors if not v.rational_norm
    ]
    start = dict(point)
    for order in itertools.islice(itertools.permutations(eqs), 6):
        point.clear()
        point.update(start)
        pinned: set[sp.Symbol] = set()
        if all(_pin(eq, point, pinned, rng, domain.state, groups) for eq in order) and _on_set(
            point, eqs
        ):
            return True
    return False


def _pin(eq: sp.Expr, point: dict, pinned: set, rng: random.Random, state, groups) -> bool:
    free = [v for v in state if v not in pinned and eq.has(v)]
    if not free:
        return False
    known = {k: v for k, v in point.items() if k not in free}
    reduced = sp.together(eq.xreplace(known))
    numer = sp.numer(reduced)
    for v in free:  # linear in one variable: a rational solution
        fixed = {k: point[k] for k in free if k != v}
        expr = numer.xreplace(fixed)
        if not expr.is_polynomial(v):
            continue
        poly = sp.Poly(expr, v)
        if poly.degree() == 1 and poly.nth(1) != 0:
            point[v] = sp.expand(-poly.nth(0) / poly.nth(1))
            pinned.add(v)
            return True
    for group in groups:  # homogeneous in a group: scale the group
        if _scale_group(numer, group, free, point, pinned):
            return True
    for v in free:  # quadratic (or higher) in one variable: a real root
        fixed = {k: point[k] for k in free if k != v}
        expr = numer.xreplace(fixed)
        if not expr.is_polynomial(v):
            continue
        poly = sp.Poly(expr, v)
        if poly.degree() > 2:  # roots would be CRootOf, which the evaluator cannot certify
            continue
        roots = [r for r in poly.all_roots() if r.is_real]
        if roots:
            point[v] = rng.choice(roots)
            pinned.add(v)
            return True
    return False


def _scale_group(numer, group, free, point, pinned) -> bool:
    if not all(g in free for g in group):
        return False
    lam = sp.Dummy("lam", positive=True)
    others = {k: point[k] for k in free if k not in group}
    scaled = sp.expand(numer.xreplace(others).xreplace({g: lam * point[g] for g in group}))
    if not scaled.is_polynomial(lam):
        return False
    poly = sp.Poly(scaled, lam)
    terms = [(m[0], c) for m, c in poly.terms() if c != 0]
    if len(terms) != 2 or min(d for d, _ in terms) != 0:
        return False
    (d, a), (_, c) = sorted(terms, reverse=True)
    ratio = -c / a
    if not (ratio.is_positive):
        return False
    factor = ratio ** sp.Rational(1, d)
    for g in group:
        point[g] = point[g] * factor
        pinned.add(g)
    return True


def _on_set(point: dict, eqs: Sequence[sp.Expr]) -> bool:
    """Exact check that the point satisfies the equations."""
    for eq in eqs:
        value = eq.xreplace(point)
        if sp.simplify(value) != 0:
            return False
    return True


# --- arbitrary functions: concrete choices for probes -----------------------


def concrete_functions(functions, rng: random.Random) -> dict[str, sp.Lambda]:
    """A random quadratic polynomial for each declared function (a family's instance)."""
    chosen = {}
    for name, (_, args) in functions.items():
        terms = [sp.Rational(_rational(rng, nonzero=True))]
        terms += [sp.Rational(_rational(rng)) * a for a in args]
        terms += [
            sp.Rational(_rational(rng)) / 2 * a * b
            for a, b in itertools.combinations_with_replacement(args, 2)
        ]
        chosen[name] = sp.Lambda(args, sp.Add(*terms))
    return chosen


def substitute_functions(expr: sp.Expr, funcs: Mapping[str, sp.Lambda]) -> sp.Expr:
    """Replace each declared function by its concrete choice and its derivatives by the
    derivatives of that choice (one substitution; ``replace`` + ``doit`` where other
    structures such as Subs appear)."""
    if not funcs or not expr.has(AppliedUndef):
        return expr
    if expr.has(sp.Subs):

        def concrete(e) -> bool:
            return isinstance(e, AppliedUndef) and e.func.__name__ in funcs

        return expr.replace(concrete, lambda e: funcs[e.func.__name__](*e.args)).doit()
    mapping: dict[sp.Expr, sp.Expr] = {}
    for f in expr.atoms(AppliedUndef):
        if f.func.__name__ in funcs:
            mapping[f] = funcs[f.func.__name__](*f.args)
    for d in expr.atoms(sp.Derivative):
        if d.expr in mapping:
            mapping[d] = _derivative(mapping[d.expr], d.variable_count)
    return expr.xreplace(mapping)


@lru_cache(maxsize=4096)  # one probe differentiates the same choice in many residuals
def _derivative(value: sp.Expr, variable_count) -> sp.Expr:
    """A derivative of a concrete function (a polynomial): through Poly, which skips the
    assumption queries of ``sp.diff`` (most of the cost of probing a family)."""
    variables = [v for v, _ in variable_count]
    if all(isinstance(v, sp.Symbol) for v in variables) and value.is_polynomial(*variables):
        order = [(v, int(n)) for v, n in variable_count]
        gens = [*variables, *sorted(value.free_symbols - set(variables), key=str)]
        if not value.has(sp.Float):  # floats are never made rational
            try:  # over Q in all its symbols: no coefficient domain to construct
                return sp.Poly(value, *gens, domain=sp.QQ).diff(*order).as_expr()
            except (sp.PolynomialError, sp.polys.polyerrors.CoercionFailed):
                pass
        return sp.Poly(value, *variables).diff(*order).as_expr()
    return sp.diff(value, *variable_count)


def sample_points(domain: Domain, count: int, seed: int = 0) -> Iterator[dict]:
    """Exact random points of the domain (used by tests and numeric evidence)."""
    rng = random.Random(seed)
    funcs = concrete_functions(domain.functions, rng)
    produced = 0
    while produced < count:
        point = sample_point(domain, rng, funcs)
        if point is not None:
            produced += 1
            yield point
