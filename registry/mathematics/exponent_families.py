"""Special parameter values of a family of fields: where every Kovalevskaya exponent of
every balance is an integer, half an integer, or rational, each value with its own exact
analysis.

*Generic part.* Over Q(p) the balances come in irreducible components; the exponents
of all the balances of one component are the roots of its *exponent polynomial*
N(lambda; p) = Res_u(g, det(lambda - K)), the product of the characteristic polynomials
of its conjugate balances, monic with coefficients in Q(p). Every exponent of every
balance is an integer exactly when every root of the product of the N's is, and that
is decided on their irreducible factors over Q(p) (``integrality``).

*Where the generic part does not hold.* N specialises correctly at p0 when no balance
escapes to infinity there and no new balance appears. So the *exceptional* values are
(a) the poles of N's coefficients and of the components' coordinates and minimal
polynomials (balances escaping or the representation failing), and (b) the parameter
values of the components that exist only there (found by solving the balance equations
with the parameters as unknowns: a component on which p is algebraic over Q, such as
Kovalevskaya's family of balances at A = B = 2C). Values where a denominator of the
field vanishes are not admissible. Every rational exceptional value is analysed on its
own; an irrational one is listed, unexamined, and the result is then not complete.

*Half-integers.* Every exponent lies in (1/2)Z exactly when every root of
N(mu/2; p) is an integer (mu = 2 lambda): the same search on the doubled polynomials
finds the values where the solutions branch at most like square roots (Goryachev and
Chaplygin's top, -1/2 and 3/2), reported apart from the integer ones.

*What is guaranteed.* For one free parameter, ``complete`` says that no admissible
value outside the lists has all exponents integer (resp. half-integer; rational, among
rational values): the candidates come from necessary conditions bounded as in
``integrality``, and each value reported is confirmed by an exact analysis at that
value. With several free parameters the conditions are reported and small rational
values are searched; nothing is claimed complete.

*Where the work runs.* The exact analyses at the candidate values are independent of
each other: ``mapper`` (``mapper(fn, items)``, the results in order) runs them where
the caller chooses (the command line's worker processes or Dask cluster).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from . import algebraic
from .balances import balance_equations
from .exponent_analysis import ExponentAnalysis, analyse
from .factoring import factor_list
from .flint_gcd import flint_gcd
from .integrality import Candidates, integer_candidates, rational_candidates
from .kovalevskaya import LAMBDA, characteristic_polynomial, kovalevskaya_matrix
from .prime_components import Component, components
from .weighted import WeightedField, polynomial_only, split_field

#: Members of an infinite family analysed to confirm it (index -MEMBERS..MEMBERS).
MEMBERS = 2
#: The small rational values tried for each parameter when there are several.
GRID = tuple(sorted({*map(sp.Integer, range(-3, 4)), *(sp.Rational(a, 2) for a in (-3, -1, 1, 3))}))
#: The kinds of special sets, strongest first.
KINDS = ("integer", "half-integer", "rational")

#: Runs ``fn`` on every item and returns the results in order (a worker pool's map).
Mapper = Callable[[Callable[[Any], Any], Sequence[Any]], list[Any]]


def kind_of(analysis: ExponentAnalysis) -> str | None:
    """The strongest kind every exponent of every balance has: "integer",
    "half-integer" (all in (1/2)Z, some not integers), "rational", or None."""
    if analysis.all_integer:
        return "integer"
    if not analysis.all_rational:
        return None
    values = [v for b in analysis.balances for v in b.exponents.values]
    return "half-integer" if all((2 * v).is_integer for v in values) else "rational"


@dataclass(frozen=True)
class SpecialSet:
    """Parameter values where every exponent is an integer (``kind`` "integer"), half an
    integer ("half-integer") or rational: one point (``values``, with its exact
    ``analysis``), or an infinite family given in terms of an ``index`` (an integer n or a
    rational t, ``ranges`` says which) with the analyses of a few members."""

    kind: str
    values: Mapping[sp.Symbol, sp.Expr]
    analysis: ExponentAnalysis | None = None
    index: sp.Symbol | None = None
    ranges: str = ""
    members: tuple[ExponentAnalysis, ...] = ()
    notes: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        found: dict = {
            "kind": self.kind,
            "values": {str(k): sp.sstr(v) for k, v in self.values.items()},
        }
        if self.index is not None:
            found["index"] = {"name": str(self.index), "ranges": self.ranges}
            found["members"] = [
                {"exponents": _exponents(a), "painleve": _painleve(a)} for a in self.members
            ]
        if self.analysis is not None:
            found["exponents"] = _exponents(self.analysis)
            found["painleve"] = _painleve(self.analysis)
        found["notes"] = list(self.notes)
        return found


@dataclass(frozen=True)
class ExponentFamily:
    """The generic analysis of a family over Q(free) (None where it was not made), its
    exponent polynomial's factors, the exceptional parameter values, and the special
    sets found."""

    free: tuple[sp.Symbol, ...]
    generic: ExponentAnalysis | None
    factors: tuple[tuple[sp.Expr, int], ...]
    exceptional: tuple[sp.Expr, ...]
    unexamined: tuple[sp.Expr, ...]
    integer: tuple[SpecialSet, ...]
    rational: tuple[SpecialSet, ...]
    complete_integer: bool
    complete_rational: bool
    coverage: tuple[str, ...] = ()
    seconds: float = field(default=0.0, compare=False)
    half_integer: tuple[SpecialSet, ...] = ()
    complete_half_integer: bool = False

    @property
    def special(self) -> tuple[SpecialSet, ...]:
        """Every special set, integer ones first, then half-integer, then rational."""
        return (*self.integer, *self.half_integer, *self.rational)

    def as_dict(self) -> dict:
        """The generic analysis's document with ``free`` and the ``special`` list."""
        document = self.generic.as_dict() if self.generic is not None else {}
        document["free"] = [str(p) for p in self.free]
        document["exponent_polynomial"] = [
            {"factor": sp.sstr(f), "multiplicity": m} for f, m in self.factors
        ]
        document["exceptional"] = [f"{sp.sstr(q)} = 0" for q in self.exceptional]
        document["special"] = [s.as_dict() for s in self.special]
        document["complete"] = {
            "integer": self.complete_integer,
            "half_integer": self.complete_half_integer,
            "rational": self.complete_rational,
        }
        document["coverage"] = list(self.coverage)
        document["seconds"] = round(self.seconds, 3)
        return document


def exponent_family(
    variables: Sequence[sp.Symbol],
    field: Sequence[sp.Expr],
    weights: Sequence[int],
    free: Sequence[sp.Symbol],
    *,
    seed: int = 0,
    mapper: Mapper | None = None,
    grid: Mapping[sp.Symbol, Sequence[sp.Expr]] | None = None,
    generic: bool = True,
) -> ExponentFamily:
    """The special values of the ``free`` parameters (every symbol of the field other
    than the variables) where all exponents are integers, half-integers, or rational
    (module doc). ``mapper`` runs the exact analyses at candidate values (default: here,
    one after the other); ``grid`` gives, for several free parameters, the values tried
    for each (default ``GRID``); ``generic`` False skips, for several free parameters, the
    analysis over Q(free) (costly for many parameters): every grid point is then
    analysed. sympy's gcds are FLINT's meanwhile (``flint_gcd``)."""
    with flint_gcd():
        return _exponent_family(variables, field, weights, free, seed, mapper, grid, generic)


def _exponent_family(variables, field, weights, free, seed, mapper, grid, generic):
    start = time.perf_counter()
    free = tuple(free)
    split = polynomial_only(
        split_field(variables, field, weights, parameters=free), "the special values of a family"
    )
    analyses = _Analyses(split, mapper)
    invalid = _field_denominators(split)
    if len(free) > 1:
        return _several_parameters(split, analyses, invalid, grid or {}, start, seed, generic)
    whole = analyse(split, painleve=False, seed=seed)
    matrix = kovalevskaya_matrix(split)
    factors, varying, poles = _exponent_polynomial(whole, matrix)
    special = _special_components(split, invalid, seed)
    exceptional = tuple(dict.fromkeys([*poles, *special]))
    return _one_parameter(
        split, whole, factors, exceptional, invalid, varying, start, analyses, seed
    )


def _several_parameters(split, analyses, invalid, grid, start, seed, make_generic):
    """Several free parameters: the generic analysis over Q(free) (unless not
    ``make_generic``), and the small rational values of ``GRID`` (or ``grid``) analysed
    exactly; nothing claimed complete."""
    generic, factors = None, ()
    if make_generic:
        generic = analyse(split, painleve=False, seed=seed)
        factors, _, _ = _exponent_polynomial(generic, kovalevskaya_matrix(split))
    integer_sets, half_sets, rational_sets = _grid_search(split, factors, invalid, grid, analyses)
    sizes = sorted({len(grid.get(p, GRID)) for p in split.parameters})
    coverage = [
        "several free parameters: small rational values searched "
        f"({' or '.join(map(str, sizes))} per parameter); not complete"
    ]
    if generic is None:
        coverage.append("the generic analysis over Q(free) was not made")
    return ExponentFamily(
        split.parameters,
        generic,
        factors,
        (),
        (),
        integer_sets,
        rational_sets,
        False,
        False,
        tuple(coverage),
        time.perf_counter() - start,
        half_sets,
        False,
    )


class _Analyses:
    """The exact analyses at parameter values, each computed once: ``prefetch`` runs a
    batch through the mapper (in parallel where it is a pool's), ``at`` reads one (and
    computes it here when it was not fetched)."""

    def __init__(self, split: WeightedField, mapper: Mapper | None):
        self.split, self.mapper = split, mapper
        self.done: dict[tuple, ExponentAnalysis | None] = {}

    def _key(self, values: Mapping[sp.Symbol, sp.Expr]) -> tuple:
        return tuple(sorted((str(k), sp.srepr(v)) for k, v in values.items()))

    def prefetch(self, points: Sequence[Mapping[sp.Symbol, sp.Expr]]) -> None:
        todo = list({self._key(v): v for v in points if self._key(v) not in self.done}.values())
        if not todo:
            return
        s = self.split
        items = [(s.field, s.variables, s.weights, dict(v)) for v in todo]
        results = (self.mapper or _in_order)(analysis_at, items)
        for values, result in zip(todo, results, strict=True):
            self.done[self._key(values)] = result

    def at(self, values: Mapping[sp.Symbol, sp.Expr]) -> ExponentAnalysis | None:
        key = self._key(values)
        if key not in self.done:
            self.prefetch([values])
        return self.done[key]


def _in_order(fn, items):
    return [fn(item) for item in items]


def analysis_at(item) -> ExponentAnalysis | None:
    """The exact analysis of (field, variables, weights, values): one call of a mapper
    (None where the field is undefined, or where the call could not be made)."""
    field, variables, weights, values = item
    return _analysis_at(field, variables, weights, values)


def _one_parameter(split, generic, factors, exceptional, invalid, varying, start, analyses, seed):
    """The special sets of one free parameter p: the generic candidates (``integrality``)
    confirmed one by one, and every rational exceptional value analysed on its own.
    Where every exponent is an integer for every value, the Painlevé test is run over
    Q(p) and the values where its conditions hold are listed (``_painleve_locus``)."""
    (p,) = split.parameters
    polys = [f for f, _ in factors]
    roots = _roots(exceptional, p, invalid)
    unexamined = tuple(v for v in roots if not v.is_rational)
    integer_candidates_ = integer_candidates(polys, p, LAMBDA)
    half_candidates = integer_candidates([doubled(f) for f in polys], p, LAMBDA)
    rational_candidates_ = rational_candidates(polys, p, LAMBDA)
    analyses.prefetch(
        [
            {p: v}
            for v in (
                *integer_candidates_.values,
                *half_candidates.values,
                *rational_candidates_.values,
                *roots,
            )
            if v.is_rational
        ]
    )
    integer, int_complete = _integer_sets(
        integer_candidates_, split, p, roots, invalid, polys, analyses
    )
    half, half_complete = _integer_sets(
        half_candidates, split, p, roots, invalid, polys, analyses, "half-integer"
    )
    rational, rat_complete = _rational_sets(
        rational_candidates_, split, p, roots, invalid, analyses
    )
    note = ("an exceptional value (the generic analysis may not hold): analysed on its own",)
    found = {"integer": integer, "half-integer": half, "rational": rational}
    for v in roots:
        analysis = analyses.at({p: v}) if v.is_rational else None
        kind = None if analysis is None else kind_of(analysis)
        if kind is not None:
            found[kind] += (SpecialSet(kind, {p: v}, analysis, notes=note),)
    coverage = [*integer_candidates_.notes, *half_candidates.notes, *rational_candidates_.notes]
    if any(s.index == p for s in found["integer"]):
        generic, passing, notes = _painleve_locus(split, p, roots, invalid, analyses, seed)
        found["integer"] += passing
        coverage += notes
    if varying:
        coverage.append("some family of balances has exponents that vary along it: not handled")
    if unexamined:
        shown = ", ".join(sp.sstr(v) for v in unexamined)
        coverage.append(f"irrational exceptional values not examined: {shown}")
    examined = not unexamined and not varying
    int_complete, rat_complete = int_complete and examined, rat_complete and examined
    half_complete = half_complete and examined
    coverage.append(
        f"integer: {_complete(int_complete)}; half-integer: {_complete(half_complete)}; "
        f"rational (rational parameter values): {_complete(rat_complete)}"
    )
    return ExponentFamily(
        (p,),
        generic,
        factors,
        exceptional,
        unexamined,
        _sorted(found["integer"]),
        _sorted(found["rational"]),
        int_complete,
        rat_complete,
        tuple(dict.fromkeys(coverage)),
        time.perf_counter() - start,
        _sorted(found["half-integer"]),
        half_complete,
    )


def _painleve_locus(split, p, exceptional, invalid, analyses, seed):
    """Where every exponent is an integer for every value of p: the generic analysis with
    the Painlevé test over Q(p), and the values of p where its compatibility conditions
    all hold (each condition must vanish for every value of the free coefficients, so
    each of its coefficients in them is an equation in p), each confirmed by an exact
    analysis; notes on what was not decided (a Jordan block over Q(p), an irrational
    value)."""
    generic = analyse(split, painleve=True, seed=seed)
    equations: list[sp.Expr] = []
    notes: list[str] = []
    for b in generic.balances:
        for r in b.painleve.resonances:
            if r.missing:
                notes.append(
                    f"a resonance {r.order} lacks a free coefficient for generic {p}: the "
                    "values where the Painlevé test passes were not sought"
                )
                return generic, (), tuple(notes)
            for condition in r.conditions:
                numer = sp.expand(sp.fraction(sp.together(condition))[0])
                others = sorted(numer.free_symbols - {p}, key=str)
                try:
                    parts = sp.Poly(numer, *others).coeffs() if others else [numer]
                except sp.PolynomialError:  # a radical of the free coefficients
                    notes.append(
                        f"a compatibility condition at resonance {r.order} is not "
                        f"polynomial in the free coefficients for generic {p}: the values "
                        "where the Painlevé test passes were not sought"
                    )
                    return generic, (), tuple(notes)
                equations += [sp.expand(c) for c in parts]
    if not equations:
        return generic, (), ("the Painlevé test passes for generic values of the parameter",)
    values = {
        v
        for solution in sp.solve(equations, [p], dict=True)
        if p in solution and (v := solution[p]).is_real
    }
    passing = []
    for v in sorted(values, key=sp.default_sort_key):
        if v in exceptional or _undefined(invalid, p, v):
            continue
        if not v.is_rational:
            notes.append(f"the Painlevé test's conditions hold at {p} = {v}: not analysed")
            continue
        analysis = analyses.at({p: v})
        if analysis is not None and analysis.painleve_passes:
            why = ("every compatibility condition of the generic analysis holds here",)
            passing.append(SpecialSet("integer", {p: v}, analysis, notes=why))
    return generic, tuple(passing), tuple(notes)


def _complete(flag: bool) -> str:
    return "complete" if flag else "not complete"


def doubled(f: sp.Expr) -> sp.Expr:
    """f(lambda / 2), monic in lambda: its roots are twice those of f (a half-integer
    root of f is an integer root here)."""
    poly = sp.Poly(sp.expand(f.subs(LAMBDA, LAMBDA / 2)), LAMBDA)
    return sp.expand(sp.cancel(poly.as_expr() / poly.LC()))


def _exponent_polynomial(generic: ExponentAnalysis, matrix: sp.Matrix):
    """The irreducible factors (over Q(free)) of the product of the components' exponent
    polynomials, whether some factor varies along a family, and the pole equations."""
    seen: dict[int, Component] = {}
    for b in generic.balances:
        seen.setdefault(id(b.balance.component), b.balance.component)
    total: dict[sp.Expr, int] = {}
    varying = False
    poles: list[sp.Expr] = []
    params = set(generic.parameters)
    for component in seen.values():
        polynomial = characteristic_polynomial(component, matrix)
        u, g = component.symbol, component.minimal
        norm = sp.Mul(*(f ** (e * g.degree()) for f, e in polynomial.common))
        if sp.degree(polynomial.rest, LAMBDA) > 0:
            norm *= sp.resultant(g.as_expr(), polynomial.rest, u)
        gens = [LAMBDA, *sorted(norm.free_symbols - {LAMBDA}, key=str)]
        for f, e in factor_list(norm, gens):
            if not f.has(LAMBDA):
                continue
            if f.free_symbols & set(component.free):
                varying = True
                continue
            total[f] = total.get(f, 0) + e
            poles.append(sp.Poly(f, LAMBDA).LC())
        data = [g.as_expr(), *component.coordinates.values()]
        for expr in data:
            for c in sp.Poly(sp.together(expr), u).coeffs() if expr.has(u) else [expr]:
                poles.append(sp.fraction(sp.cancel(c))[1])
    equations = []
    for q in poles:  # a family of balances' coordinate may stay in a pole: factored too
        for f, _ in factor_list(q, sorted(sp.sympify(q).free_symbols, key=str)):
            if f.free_symbols and f.free_symbols <= params and f not in equations:
                equations.append(f)
    factors = tuple(sorted(total.items(), key=lambda fe: sp.default_sort_key(fe[0])))
    return factors, varying, equations


def _field_denominators(split: WeightedField) -> tuple[sp.Expr, ...]:
    """The irreducible factors of the field's denominators: where it is not defined."""
    found: list[sp.Expr] = []
    for v in split.field:
        for f, _ in factor_list(sp.fraction(sp.together(v))[1], split.parameters):
            if f not in found:
                found.append(f)
    return tuple(found)


def _special_components(split: WeightedField, invalid, seed: int) -> list[sp.Expr]:
    """Polynomials q(p) whose roots carry components of balances that exist only there:
    the balance equations solved with the parameters as unknowns (module doc, (b))."""
    equations = [sp.fraction(sp.together(e))[0] for e in balance_equations(split)]
    unknowns = [*split.variables, *split.parameters]
    found: list[sp.Expr] = []
    for c in components(equations, unknowns, origin=split.variables, seed=seed):
        if any(c.vanishes(d) for d in invalid):
            continue
        ext = algebraic.Extension(c.symbol, c.minimal)
        for p in split.parameters:
            if p in c.free:
                continue
            z = sp.Dummy("z")
            q = algebraic.minimal_polynomial(ext, ext.element(c.coordinates[p]), z)
            if not (q.as_expr().free_symbols - {z}):
                found.append(sp.expand(q.as_expr().subs(z, p)))
    return found


def _roots(equations: Sequence[sp.Expr], p: sp.Symbol, invalid) -> list[sp.Expr]:
    """The real roots of the exceptional equations (one parameter), without the values
    where the field is not defined."""
    bad = {r for d in invalid for r in sp.Poly(d, p).real_roots()} if invalid else set()
    found = []
    for q in equations:
        for r in sp.Poly(q, p).real_roots():
            if r not in bad and r not in found:
                found.append(r)
    return found


def _analysis_at(field, variables, weights, values) -> ExponentAnalysis | None:
    """The exact analysis at given parameter values (None where the field is undefined)."""
    try:
        concrete = [sp.sympify(v).subs(values) for v in field]
    except ZeroDivisionError:  # pragma: no cover - sympy gives zoo instead
        return None
    if any(c.has(sp.zoo, sp.nan) for c in concrete):
        return None
    return analyse(split_field(variables, concrete, weights))


def _integer_sets(
    cands: Candidates, split, p, exceptional, invalid, factors, analyses, kind="integer"
):
    """The candidates of ``kind`` ("integer", or "half-integer" for candidates of the
    doubled polynomials) confirmed by exact analyses; irrational values are listed as
    checked on the exponent polynomial only."""
    sets = []
    complete = cands.complete
    fits = _fits(kind)
    for v in cands.values:
        if v in exceptional or _undefined(invalid, p, v):
            continue
        if v.is_rational:
            analysis = analyses.at({p: v})
            if analysis is not None and kind_of(analysis) == kind:
                sets.append(SpecialSet(kind, {p: v}, analysis))
        else:
            sets.append(
                SpecialSet(
                    kind,
                    {p: v},
                    notes=("irrational value: checked on the exponent polynomial only",),
                )
            )
    for expr, index, ranges in cands.families:
        if expr == p:  # every value: the exponents do not depend on p
            if kind == "integer":
                sets.append(SpecialSet(kind, {}, index=p, ranges="every admissible value"))
            continue
        members = _members(split, p, expr, index, analyses)
        if all(fits(m) for m in members):
            sets.append(
                SpecialSet(kind, {p: expr}, index=index, ranges=ranges, members=tuple(members))
            )
        else:
            complete = False
            values = [expr.subs(index, k) for k in range(-MEMBERS * 3, MEMBERS * 3 + 1)]
            values = [v for v in values if v not in exceptional and not _undefined(invalid, p, v)]
            analyses.prefetch([{p: v} for v in values])
            for value in values:
                analysis = analyses.at({p: value})
                if analysis is not None and kind_of(analysis) == kind:
                    sets.append(SpecialSet(kind, {p: value}, analysis))
    return tuple(sets), complete


def _fits(kind: str) -> Callable[[ExponentAnalysis], bool]:
    """Whether an analysis's exponents are all of ``kind`` or stronger."""
    allowed = KINDS[: KINDS.index(kind) + 1]
    return lambda analysis: kind_of(analysis) in allowed


def _rational_sets(cands: Candidates, split, p, exceptional, invalid, analyses):
    sets = []
    for v in cands.values:
        if v in exceptional or _undefined(invalid, p, v):
            continue
        analysis = analyses.at({p: v})
        if analysis is not None and kind_of(analysis) == "rational":
            sets.append(SpecialSet("rational", {p: v}, analysis))
    for expr, index, ranges in cands.families:
        members = _members(split, p, expr, index, analyses, rational=True) if expr != p else []
        values = {} if expr == p else {p: expr}
        sets.append(
            SpecialSet("rational", values, index=index, ranges=ranges, members=tuple(members))
        )
    return tuple(sets), cands.complete


def _members(split, p, expr, index, analyses, rational: bool = False) -> list[ExponentAnalysis]:
    """Exact analyses of a few members of a family (the admissible ones)."""
    picks = [sp.Rational(k, 2) if rational else k for k in range(-MEMBERS, MEMBERS + 1)]
    values = [sp.cancel(expr.subs(index, k)) for k in picks]
    values = [v for v in values if not v.has(sp.zoo, sp.nan)]
    analyses.prefetch([{p: v} for v in values])
    found = [analyses.at({p: v}) for v in values]
    return [a for a in found if a is not None]


def _undefined(invalid, p, value) -> bool:
    return any(sp.simplify(d.subs(p, value)) == 0 for d in invalid)


def _grid_search(split: WeightedField, factors, invalid, grid, analyses):
    """Several parameters: small rational values (``grid``, else ``GRID``, per parameter)
    where the exponent polynomial's roots are integers, half-integers or rational, each
    confirmed by an exact analysis."""
    params = split.parameters
    points = []
    for point in itertools.product(*(grid.get(p, GRID) for p in params)):
        values = dict(zip(params, point, strict=True))
        if any(sp.simplify(d.subs(values)) == 0 for d in invalid):
            continue
        if not factors or _root_kind([f.subs(values) for f, _ in factors]) is not None:
            points.append(values)
    analyses.prefetch(points)
    found: dict[str, list[SpecialSet]] = {k: [] for k in KINDS}
    for values in points:
        analysis = analyses.at(values)
        kind = None if analysis is None else kind_of(analysis)
        if kind is not None:
            found[kind].append(SpecialSet(kind, values, analysis))
    return tuple(found["integer"]), tuple(found["half-integer"]), tuple(found["rational"])


def _root_kind(polys: Sequence[sp.Expr]) -> str | None:
    """ "integer" or "rational" when every root of every polynomial is, else None."""
    kind = "integer"
    for f in polys:
        numer = sp.fraction(sp.together(f))[0]
        if not numer.has(LAMBDA):
            return None
        others = sorted(numer.free_symbols - {LAMBDA}, key=str)
        for g, _ in factor_list(numer, [LAMBDA, *others]):
            if not g.has(LAMBDA):
                continue
            if sp.degree(g, LAMBDA) > 1:
                return None
            a1, a0 = sp.Poly(g, LAMBDA).all_coeffs()
            if not (-a0 / a1).is_integer:
                kind = "rational"
    return kind


def _sorted(sets) -> tuple[SpecialSet, ...]:
    return tuple(
        sorted(
            sets,
            key=lambda s: (s.index is not None, sp.default_sort_key(tuple(s.values.items()))),
        )
    )


def _exponents(analysis: ExponentAnalysis) -> list[list[str]]:
    return [[sp.sstr(v) for v in b.exponents.values] for b in analysis.balances]


def _painleve(analysis: ExponentAnalysis) -> dict:
    return {
        "passes": analysis.painleve_verdict,
        "conditions": list(analysis.conditions),
    }
