"""One solution of the polynomial equations of a match, by propagation: the unknowns of a
transformation and a case's parameter values.

The equations of ``matching`` are many and mostly simple: coefficients that must vanish
(``S12 = 0``), scalings tied to moments (``tau A - 2 lam = 0``), a few products. A
Groebner basis of all of them (sympy's ``solve``) takes a minute on the catalog's large
families, because it finds every degenerate solution (tau = lam = 0) too; one solution is
all a match needs, and every solution is checked exactly afterwards (``matching``), so
the search may be greedy. In the ring K[unknowns] (K = Q or the rational functions of
the first system's parameters, generic: a polynomial in them alone is nonzero):

1. an equation linear in an unknown whose coefficient cannot vanish (an element of K
   times nonzero unknowns: scalings, signs, positive parameters) is solved for it and
   the value put everywhere (the shortest equations first);
2. an equation that factors splits the search into one branch per factor (a factor
   that cannot vanish dropped);
3. a system left in at most ``SMALL`` unknowns (a rotation's cos^2 + sin^2 = 1 with
   its angle's tangent fixed) is solved by sympy, radicals allowed;
4. where nothing else applies, an unknown takes its simplest value (a scaling 1 or
   -1, a shift 0, a sign 1 or -1), a branch each.

A sign unknown e has e**2 = 1; a nonzero unknown is never set to 0.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp
from sympy.polys.rings import PolyElement, PolyRing

from ...mathematics.factoring import factor_element

#: Branches a solve may open before it gives up.
MAX_BRANCHES = 60
#: A system in at most this many unknowns is handed to sympy's ``solve``.
SMALL = 3

Fraction = tuple[PolyElement, PolyElement]


@dataclass
class Problem:
    """The ring of the unknowns, which of its generators cannot vanish, which are signs
    (e**2 = 1), the simplest values to try for a free one (elements of the ground
    field; tried in the mapping's order), and the order in which unknowns are preferred
    for a value from a linear equation."""

    ring: PolyRing
    nonzero: frozenset[int] = frozenset()
    signs: frozenset[int] = frozenset()
    positive: frozenset[int] = frozenset()
    defaults: Mapping[int, Sequence[object]] = field(default_factory=dict)
    order: Sequence[int] = ()
    branches: int = 0
    #: whether a value may be complex (a probe at a specialisation: ``matching``)
    complex_values: bool = False

    def __post_init__(self) -> None:
        if not self.order:
            self.order = tuple(range(self.ring.ngens))


def solve(equations: Sequence[PolyElement], problem: Problem) -> dict[sp.Symbol, sp.Expr] | None:
    """One solution (module docstring) as values of the ring's symbols (those left free
    are absent), or None (none found: not a proof that there is none)."""
    found = _solve(list(equations), {}, problem)
    if found is None:
        return None
    if isinstance(found, _Expressions):
        return found.values
    return {problem.ring.symbols[u]: n.as_expr() / d.as_expr() for u, (n, d) in found.items()}


@dataclass
class _Expressions:
    """A solution finished by sympy (radicals in it): values as expressions."""

    values: dict[sp.Symbol, sp.Expr]


def _reduce(e: PolyElement, solution: Mapping[int, Fraction], problem: Problem) -> PolyElement:
    for u, (n, d) in solution.items():
        e = _put(e, u, n, d, problem)
    if problem.signs:
        e = _signs(e, problem)
    return _strip(e, problem)


def _put(e: PolyElement, u: int, n: PolyElement, d: PolyElement, problem: Problem) -> PolyElement:
    """d^k e(u = n/d), k the degree of e in u."""
    x = u  # generators by index: no lookup of the element
    k = e.degree(x)
    if k <= 0:
        return e
    one = problem.ring.one
    total = problem.ring.zero
    for j in range(k + 1):
        c = e.coeff_wrt(x, j)
        if c:
            total += c * (n**j if j else one) * (d ** (k - j) if k - j else one)
    return total


def _signs(e: PolyElement, problem: Problem) -> PolyElement:
    if not any(any(m[i] > 1 for i in problem.signs) for m in e.itermonoms()):
        return e
    out: dict = {}
    for m, c in e.iterterms():
        key = tuple(x % 2 if i in problem.signs else x for i, x in enumerate(m))
        out[key] = out.get(key, problem.ring.domain.zero) + c
    return problem.ring.from_dict({k: v for k, v in out.items() if v})


def _strip(e: PolyElement, problem: Problem) -> PolyElement:
    """e without its factors that cannot vanish: powers of nonzero unknowns common to
    every term, and its leading coefficient (an element of the ground field)."""
    if not e:
        return e
    monoms = list(e.itermonoms())
    common = [min(m[i] for m in monoms) for i in range(problem.ring.ngens)]
    if any(common) and all(not k or i in problem.nonzero for i, k in enumerate(common)):
        e = problem.ring.from_dict(
            {tuple(a - b for a, b in zip(m, common, strict=True)): c for m, c in e.iterterms()}
        )
    return e.monic()


def _unit(a: PolyElement, problem: Problem) -> bool:
    """A nonzero element of the ground field times powers of nonzero unknowns."""
    if len(a) != 1:
        return False
    ((monom, c),) = a.iterterms()
    return bool(c) and all(not k or i in problem.nonzero for i, k in enumerate(monom))


def _solve(equations: list[PolyElement], solution: dict, problem: Problem):
    problem.branches += 1
    if problem.branches > MAX_BRANCHES:
        return None
    pending = dict(solution)  # substitutions not yet put into ``equations``
    while True:
        live = []
        for e in equations:
            e = _reduce(e, pending, problem)
            if not e:
                continue
            if e.is_ground:
                return None  # a nonzero element of the ground field: no solution
            live.append(e)
        equations = list(dict.fromkeys(live))
        if not equations:
            return solution
        step = _linear_step(equations, problem)
        if step is None:
            break
        if step is _CONTRADICTION:
            return None
        u, n, d = step
        solution = {k: _fraction(v, u, n, d, problem) for k, v in solution.items()}
        solution[u] = (n, d)
        pending = {u: (n, d)}
    for e in sorted(equations, key=len):
        factors = factor_element(e) if e.ring.domain.is_QQ else e.factor_list()[1]
        kept = [f for f, _ in factors if not f.is_ground and not _unit(f, problem)]
        if len(kept) > 1 or (kept and kept[0].monic() != e.monic()):
            others = [g for g in equations if g is not e]
            for f in kept:
                found = _solve([*others, f], dict(solution), problem)
                if found is not None:
                    return found
            return None
    present = sorted({i for e in equations for i in _variables(e)})
    if len(present) <= SMALL:
        return _finish(equations, solution, present, problem)
    for u, values in problem.defaults.items():  # in the order given
        if u in solution or u not in present:
            continue
        for value in values:
            x = problem.ring.gens[u]
            found = _solve([*equations, x - value], dict(solution), problem)
            if found is not None:
                return found
    return None


def _sign(e: PolyElement, problem: Problem) -> int:
    """1 or -1 where every term of e has that sign for all allowed values (rational
    coefficients of one sign, odd powers only of positive unknowns), else 0."""
    signs = set()
    for monom, c in e.iterterms():
        if any(k % 2 and i not in problem.positive for i, k in enumerate(monom)):
            return 0
        try:
            value = problem.ring.domain.to_sympy(c)
        except (TypeError, ValueError):
            return 0
        if not value.is_Rational:
            return 0
        signs.add(1 if value > 0 else -1)
    return signs.pop() if len(signs) == 1 else 0


def _variables(e: PolyElement) -> set[int]:
    return {i for m in e.itermonoms() for i, k in enumerate(m) if k}


def _fraction(value: Fraction, u: int, n: PolyElement, d: PolyElement, problem) -> Fraction:
    """(num/den)(u = n/d) as a fraction again."""
    num, den = value
    a, b = num.degree(u), den.degree(u)
    top, bottom = _put(num, u, n, d, problem), _put(den, u, n, d, problem)
    a, b = max(a, 0), max(b, 0)
    if a > b:
        return top, bottom * d ** (a - b)
    if b > a:
        return top * d ** (b - a), bottom
    return top, bottom


#: What ``_linear_step`` returns for an equation that puts a nonzero unknown at 0, or a
#: positive one at a number that is not positive.
_CONTRADICTION = object()


def _linear_step(equations: Sequence[PolyElement], problem: Problem):
    """(unknown, numerator, denominator) from an equation linear in it with a unit
    coefficient: the shortest equations first, unknowns in the problem's order;
    ``_CONTRADICTION`` where such an equation sets a nonzero unknown to 0, or a positive
    one to a number that is not positive."""
    best = None
    rank = {u: i for i, u in enumerate(problem.order)}
    for e in sorted(equations, key=len):
        variables = _variables(e)
        for u in sorted(variables, key=lambda v: rank.get(v, len(rank))):
            if e.degree(u) != 1:
                continue
            a = e.coeff_wrt(u, 1)
            if not _unit(a, problem):
                continue
            b = e.coeff_wrt(u, 0)
            if u in problem.nonzero and not b:
                return _CONTRADICTION
            if u in problem.positive and _sign(-b, problem) * _sign(a, problem) < 0:
                return _CONTRADICTION
            if u in problem.nonzero and not _unit(b, problem):
                continue  # its value would have to be shown nonzero
            cost = (len(b), rank.get(u, len(rank)))
            if best is None or cost < best[0]:
                best = (cost, u, -b, a)
            if len(b) <= 1:
                return best[1], best[2], best[3]
    return None if best is None else best[1:]


def _finish(equations, solution, present, problem: Problem):
    """The last few unknowns by sympy's ``solve`` (radicals allowed), the solution then
    written as expressions."""
    symbols = [problem.ring.symbols[i] for i in present]
    exprs = [e.as_expr() for e in equations]
    try:
        found = sp.solve(exprs, symbols, dict=True)
    except Exception:  # noqa: BLE001 - sympy's solve fails in many ways: no match found
        return None
    nonzero = {problem.ring.symbols[i] for i in problem.nonzero}
    base = {problem.ring.symbols[u]: n.as_expr() / d.as_expr() for u, (n, d) in solution.items()}
    for values in found:
        if any(values.get(s) == 0 for s in nonzero):
            continue
        if not problem.complex_values and any(v.has(sp.I) for v in values.values()):
            continue
        done = {k: sp.cancel(v.xreplace(values)) for k, v in base.items()}
        done.update(values)
        return _Expressions(done)
    return None
