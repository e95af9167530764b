"""``discover``: the integrals of a case, or of a family, up to a weighted degree, and the
free-parameter values where more appear.

1. The ansatz's system A(p, q) c = 0 (``ansatz``) and the known integrals.
2. Generic values. The kernel's dimension modulo a prime at a random point bounds the
   generic kernel from above; the products of the known integrals bound it from
   below. Where the bounds meet (the usual case) there is provably no extra integral
   for generic values, and nothing exact needs computing; otherwise the kernel is
   computed exactly over Q(p, q).
3. The special locus (``locus``): where the rank of a block drops, as sets of the
   free parameters p (some of them rational functions of the others), by case
   splitting on pivots; the others, q, stay symbolic throughout. A set inside
   another is left to the search of that one.
4. Each candidate is searched again as a case of its own with its values substituted
   (a point has no free parameter left, a larger set fewer); it is special when it
   has integrals that the known ones and those of the sets it lies in (the family's
   generic ones, restricted to it, and so on down) do not generate. A set where only
   the rank drops (the known integrals change form: the torque's Casimir s + phi
   becomes s of lower degree, nothing new) is a candidate, never a special set. A
   candidate set with no rational parametrisation is split into its components
   (``components``); those still without one are decided at their points
   (``algebraic_points``).
5. Every integral reported is proven by the audit's own zero test (the ``integral``
   check; ``casimir`` is recorded for information), and only then reported.
"""

from __future__ import annotations

import itertools
import random
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp
from sympy import QQ
from sympy.polys.rings import PolyElement, PolyRing

from ..audit.case_audit import audit_case
from ..errors import DiscoveryError
from ..execution.executor import Executor, InProcess, in_order, timed
from ..execution.serving import Failure
from ..execution.time_budget import BudgetExceeded, time_limit
from ..language import forms
from ..language.forms import equation_with_values, with_values
from ..language.parser import parse_equation, parse_expression
from ..language.printer import to_text
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.grading import grading_note, per_variable
from ..mathematics.scalings import covariant_weights
from ..model import (
    Case,
    Claim,
    ClaimKind,
    Equation,
    Expression,
    IntegralSet,
    IntegralStatus,
    SameSystem,
    Search,
    SearchOptions,
    Verdict,
    Weights,
    as_weights,
)
from .algebraic_points import decide
from .ansatz import PolynomialSystem
from .components import NEW, resolve
from .darboux import general_cofactor, proven_relations
from .identification.catalog_index import CatalogIndex
from .identification.claim_match import carried_claims
from .identification.identify import identify
from .integrals import Analysis, Generator, analyse, products
from .known import catalog_statuses, known_generators, named
from .linear import GF_PRIME, PRIME, Field
from .locus import Locus, contains, drop_locus, polynomial, same
from .simplest_form import simplest
from .splitting import AlgebraicSet, Spread

#: What a search says of how it works (stored with every recorded search).
METHOD = (
    "polynomial ansatz; generic kernel bounded modulo a prime by the known integrals' "
    "products; rank-drop locus by case splitting on the pivots of a fraction-free "
    "elimination (pivots: what the assumptions keep nonzero); exact kernels over Q(p); "
    "zero-test proofs"
)

#: Progress callback: (candidates done, candidates known so far, what is being done).
Progress = Callable[[int, int, str], None]


@dataclass
class _State:
    """What one search shares while it recurses into candidate sets."""

    options: SearchOptions
    seed: int
    undecided: list[str] = field(default_factory=list)
    found: list[IntegralSet] = field(default_factory=list)
    generic: IntegralSet | None = None
    counts: dict = field(default_factory=dict)
    known: tuple[str, ...] = ()
    claims: tuple[str, ...] = ()
    #: relations: the cofactor K' (coefficients free), and its values on candidate sets
    cofactor: sp.Expr | None = None
    coefficients: tuple[sp.Symbol, ...] = ()
    cofactors: dict = field(default_factory=dict)
    #: candidate sets searched (or being searched), as values of the free parameters
    searched: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    progress: Progress | None = None
    done: int = 0
    total: int = 0
    #: whether the ansatz is split along the field's symmetries, and what each set used
    symmetries: bool = True
    used: dict[tuple[str, ...], str] = field(default_factory=dict)
    #: components without a rational parametrisation decided at their points
    decided: list[str] = field(default_factory=list)
    #: the free parameters' values of each special set (by its equations)
    values_of: dict[tuple[str, ...], dict] = field(default_factory=dict)
    #: the executor's workers, for the splitting of a locus (None: in this process)
    spread: Spread | None = None

    def rnd(self, when: tuple[str, ...]) -> random.Random:
        """A generator seeded by the search and the set searched, so that results do not
        depend on the order (or the process) in which sets are searched."""
        return random.Random(f"{self.seed}/{'/'.join(when)}")


def discover(
    case: Case,
    options: SearchOptions | None = None,
    *,
    budget: float | None = None,
    executor: Executor | None = None,
    seed: int = 0,
    progress: Progress | None = None,
    symmetries: bool = True,
    catalog: CatalogIndex | None = None,
) -> Search:
    """Search ``case`` for first integrals (module docstring).

    ``options.free`` names the parameters whose special values are sought; the others
    stay symbolic and generic. ``budget`` bounds the whole search in seconds: when it
    runs out, what was proven so far is returned with ``complete`` false and the
    coverage saying where the search stopped. The candidate sets are searched by
    ``executor`` (default: in this process; local workers or a Dask cluster give the same
    results). A candidate set the executor could not search (its call killed, lost, or
    failed) is named in the coverage, and the search is then not complete.
    ``symmetries`` false searches the whole ansatz without splitting it along the field's
    symmetries (``symmetry``), for comparison: the results are the same.

    With a ``catalog`` (``identification.catalog_index``), each special set, and the
    family itself where it has extra integrals for generic values, is identified with
    the catalog's cases (``same_as``), and an integral is new only where it equals no
    claim of the searched case nor of any case it is the same system as.
    """
    started = time.perf_counter()
    options = options or SearchOptions()
    unknown = [f for f in options.free if f not in case.parameters]
    if unknown:
        raise DiscoveryError(
            f"--free names {', '.join(map(repr, unknown))}, which the case does not declare "
            f"(its parameters: {', '.join(case.parameters) or 'none'})"
        )
    state = _State(options, seed, progress=progress, symmetries=symmetries)
    free = [case.parameters[f] for f in options.free]
    if options.relations:
        if options.on:
            raise DiscoveryError(
                "--relations searches the whole phase space (its relations F = 0 are level "
                "sets themselves); drop --on"
            )
        m = CaseMechanics(case)
        plain = _system(options, m, free, symmetries=False)[0]
        state.cofactor, coefficients = general_cofactor(plain, options, m, state.undecided)
        state.coefficients = tuple(coefficients)
        free += coefficients
    dynamics = case.dynamics
    note = grading_note(
        dynamics.field, options.weights, dynamics.vectors, dynamics.shorthands, dynamics.variables
    )
    executor = executor or InProcess()
    state.spread = _spreader(executor, timed(budget))
    identifying = False
    try:
        with time_limit(budget):
            _, state.found = _search(state, case, free, executor, timed(budget))
            if catalog is not None and not options.relations:
                identifying = True
                for i, found in enumerate(state.found):  # each kept as soon as identified
                    state.found[i] = _identified(state, case, found, catalog)
                if state.generic is not None and state.generic.extra:
                    state.generic = _identified(state, case, state.generic, catalog)
    except BudgetExceeded:
        state.undecided.append(
            f"time budget exceeded ({budget:g} s) while identifying the sets found with "
            "the catalog: a set not identified has no same_as, and its integrals are "
            "compared only with the searched case's claims"
            if identifying
            else f"time budget exceeded ({budget:g} s) after {state.done} of the "
            f"{state.total} candidate sets found so far"
        )
    generic = state.generic or IntegralSet((), 0)
    complete = not state.undecided and state.generic is not None
    coverage = tuple(state.undecided) or (
        "every parameter value: the generic values and every point and component of the "
        "rank-drop locus",
        *(
            f"decided at its points (no rational parametrisation): {d}"
            for d in dict.fromkeys(state.decided)
        ),
    )
    return Search(
        case=case.id,
        content_hash=case.content_hash,
        options=options,
        known=state.known,
        generic=generic,
        special=tuple(_distinct(state.found)),
        complete=complete,
        coverage=coverage,
        dimensions=tuple((d, *c) for d, c in sorted(state.counts.items())),
        seconds=time.perf_counter() - started,
        method=METHOD + (f"; {note}" if note else "") + _symmetry_note(state),
        claims=state.claims,
    )


def search_options(
    case: Case,
    *,
    degree: int = 4,
    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
    on: Sequence[str | Equation] = (),
    free: Sequence[str] = (),
    relations: bool = False,
) -> SearchOptions:
    """Options for searching ``case``: level-set equations given as text (``"s = 0"``)
    are parsed in the case's own names (an ExpressionError names a bad one); ``weights``
    name vectors of the case's state (``{"M": 1, "gamma": 2}``, or the reference paper's
    two numbers), each vector not named keeping its own default weight (a DiscoveryError
    names one the state does not have)."""
    ns = forms.namespace(case)
    equations = tuple(
        e if isinstance(e, Equation) else Equation(e, *parse_equation(e, ns)) for e in on
    )
    return SearchOptions(degree, full_weights(case, weights), equations, tuple(free), relations)


def full_weights(
    case: Case, weights: Weights | Mapping[str, int] | tuple[int, int] | None
) -> Weights:
    """A weight for every vector of the case's state: those given, the others' defaults."""
    vectors = case.dynamics.vectors
    try:
        given = dict(as_weights(weights)) if weights is not None else {}
    except ValueError as err:
        raise DiscoveryError(f"--weights: {err}") from None
    names = [v.name for v in vectors]
    unknown = [n for n in given if n not in names]
    if unknown:
        raise DiscoveryError(
            f"--weights names {', '.join(map(repr, unknown))}, which the case's state does not "
            f"have (its vectors: {', '.join(names)})"
        )
    return tuple((v.name, given.get(v.name, v.weight)) for v in vectors)


def _search(
    state: _State,
    case: Case,
    free: list[sp.Symbol],
    executor: Executor,
    seconds: float | None,
):
    """(integrals of the family for generic values of ``free``, the special sets).

    The candidate sets are searched level by level: those of the family's locus, then
    those within them, and so on, each level's sets by ``executor`` (each call killed
    past ``seconds``). A set reached on two paths is searched once (the searched sets are
    kept here, for every level), and a set is special when it has integrals beyond those
    of the sets it lies in (``_more``)."""
    found, level, candidates = _step(state, case, free, (), {})
    queue = [(c, level) for c in _fresh(state, candidates)]
    special: list[tuple[IntegralSet, tuple]] = []
    while queue:
        state.total += len(queue)
        results = _each(state, [c for c, _ in queue], executor, seconds)
        following: list[tuple[Any, _Level]] = []
        for (candidate, reference), (g, level, inner, undecided, cofactors, used, decided) in zip(
            queue, results, strict=True
        ):
            state.undecided.extend(u for u in undecided if u not in state.undecided)
            state.cofactors.update(cofactors)
            state.used.update(used)
            state.decided.extend(decided)
            if _more(state, g, level, reference):
                special.append((g, candidate))
                state.values_of[g.when] = candidate[3]
            following.extend((c, level) for c in _fresh(state, inner))
        queue = following
    if state.options.relations:
        return found, [g for g, _ in special]
    return found, _beyond_enclosing(state, case, free, special)


def _identified(
    state: _State, case: Case, found: IntegralSet, catalog: CatalogIndex
) -> IntegralSet:
    """A set with the catalog cases it is the same system as, and each integral's
    status decided against their claims too (``identification``)."""
    values = state.values_of.get(found.when, {})
    sub = with_values(case, values) if values else case
    if sub is None:
        return found
    result = identify(sub.dynamics, catalog, exclude=(case.id,))
    if result.skipped:
        where = ", ".join(found.when) or "the generic values"
        state.undecided.append(
            f"identification of {where} stopped after {result.seconds:.0f} s: "
            f"{len(result.skipped)} catalog cases not compared (an integral there is said "
            "new only against the others)"
        )
    if result.failed:
        where = ", ".join(found.when) or "the generic values"
        names = ", ".join(f"{case_id} ({error})" for case_id, error in result.failed)
        state.undecided.append(
            f"identification of {where} could not compare {len(result.failed)} catalog "
            f"cases: {names} (an integral there is said new only against the others)"
        )
    status = list(found.status) or [IntegralStatus("new") for _ in found.integrals]
    if not result.same or result.form is None:
        return replace(found, status=tuple(status))
    carried = carried_claims(result.same, result.form, catalog) if found.integrals else []
    equal: dict[str, set[str]] = {}
    if carried and any(st.new for st in status):
        rest = [p for p in (case.parameters[f] for f in state.options.free) if p not in values]
        m = CaseMechanics(sub)
        system, params = _system(state.options, m, rest, None, values, state.symmetries)
        ns = forms.namespace(case)
        exprs = [parse_expression(text, ns).xreplace(values) for text in found.integrals]
        for source in dict.fromkeys(c for c, _, _ in carried):  # case by case
            named = catalog_statuses(
                m, system, params, exprs, [c for c in carried if c[0] == source]
            )
            for i, rediscovered in enumerate(named):
                if rediscovered is None:
                    continue
                equal.setdefault(source, set()).update(
                    label.split(":", 1)[1] for label in rediscovered.equals if ":" in label
                )
                if status[i].new:
                    status[i] = rediscovered
    same = tuple(
        SameSystem(
            s.case,
            tuple(s.values.items()),
            tuple(s.transformation.items()),
            tuple(sorted(equal.get(s.case, ()))),
        )
        for s in sorted(result.same, key=lambda s: (not equal.get(s.case), not s.identity))
    )
    return replace(found, status=tuple(status), same_as=same)


def _beyond_enclosing(state: _State, case: Case, free: list[sp.Symbol], special) -> list:
    """The special sets whose integrals the known ones and those of the special sets
    they lie in (on other paths than the one that found them: the meeting of two
    Lagrange lines, where M1 and M3 are each one's) do not generate, larger sets first.
    A count modulo a prime bounds what is new from above, so 0 proves nothing is."""
    kept: list[tuple[IntegralSet, dict, tuple]] = []
    ns = forms.namespace(case)
    for g, candidate in sorted(special, key=lambda item: len(item[1][3])):
        values, inherited = candidate[3], candidate[4]
        enclosing = [(h, v) for h, v, _ in kept if contains(v, values)]
        if enclosing:
            more = [
                sp.sympify(parse_expression(text, ns)).xreplace(values)
                for h, _ in enclosing
                for text in h.integrals
            ]
            rest = [p for p in free if p not in values]
            count = _fresh_count(
                state, candidate[0], rest, candidate[2], values, [*inherited, *more]
            )
            if not count:
                continue
        kept.append((g, values, inherited))
    return [g for g, _, _ in kept]


def _fresh_count(
    state: _State, case: Case, free: list[sp.Symbol], when, values, integrals: Sequence[sp.Expr]
) -> int:
    """How many extra integrals of ``case`` the known ones and ``integrals`` do not
    generate, counted modulo a prime at a random point (an upper bound)."""
    m = CaseMechanics(case)
    system, params = _system(state.options, m, free, None, values, state.symmetries)
    known, _ = known_generators(m, system)
    rnd = state.rnd((*when, "beyond"))
    point = {i: rnd.randrange(1, PRIME) for i in range(len(params))}
    modular = Field(GF_PRIME, params, point, system.inverses)
    return _beyond(analyse(system, [*known, *_generators(system, integrals)], modular))


def _beyond(analysis: Analysis) -> int:
    """How many integrals of weighted degree <= K the products of weight <= K of the
    generators an analysis was given do not span (none: nothing new). Counted at the top
    degree K, not degree by degree: where the field is not weighted-homogeneous, an
    integral of a lower degree may be such a product whose leading parts cancel (on the
    Lagrange body with the torque p22 gamma + (p33 gamma3 + k3) e3: (p22 - p33) I**2
    + 2 p22**2 C - p22**3 |gamma|**2, of degree 3, for I = M3 - p22 gamma3 of degree 2
    and C, |gamma|**2 of degree 4). Modulo a prime it bounds the number from above."""
    kernel, trivial, _ = analysis.counts[max(analysis.counts)]
    return kernel - trivial


@dataclass(frozen=True)
class _Level:
    """What one searched set holds at its generic point: the kernel's dimension per
    weighted degree (integrals of degree <= d, trivial ones included), its number of
    extra integrals, and how many of them the integrals of the sets it lies in do not
    generate (``fresh``; exact: counted over Q(p), or 0 modulo a prime, which bounds
    it)."""

    kernel: dict[int, int]
    extra: int
    fresh: int = 0


def _more(state: _State, g: IntegralSet, level: _Level, parent: _Level) -> bool:
    """Whether a searched set is special: some of its integrals are not generated by
    the known ones and those of the sets it lies in (restricted to it), and every extra
    integral it has is proven (one that is not is not reported, and the search is then
    not complete). A kernel that only grows because the known integrals change form
    (the rank drops, nothing new) is not more. For invariant relations every new
    Darboux polynomial counts: the kernel grows."""
    if state.options.relations:
        return any(level.kernel.get(d, 0) > k for d, k in parent.kernel.items())
    return level.fresh > 0 and g.extra == level.extra


def _symmetry_note(state: _State) -> str:
    """The symmetries each searched set's ansatz was split along (its own, found from
    its equations), as parts of the search's method."""
    if not state.symmetries:
        return "; symmetries: not used"
    parts = []
    for when, note in state.used.items():
        if not when:
            parts.append(f"symmetries: {note}")
        elif "split" in note:
            parts.append(f"symmetries where {', '.join(when)}: {note}")
    return "".join(f"; {p}" for p in parts)


def _fresh(state: _State, candidates: list) -> list:
    """The candidate sets not searched yet (none reached on another path where that
    path's parametrisation covers it everywhere), now marked as searched."""
    out = []
    for candidate in candidates:
        composed = candidate[3]
        if any(
            composed == seen or (same(composed, seen) and polynomial(seen))
            for seen in state.searched
        ):
            continue
        state.searched.append(composed)
        out.append(candidate)
    return out


def _step(
    state: _State,
    case: Case,
    free: list[sp.Symbol],
    when: tuple[str, ...],
    values: dict[sp.Symbol, sp.Expr],
    inherited: Sequence[sp.Expr] = (),
):
    """One set searched: (its integrals for generic values of ``free``, its ``_Level``,
    the candidate sets within it). ``values`` are the family's free parameters' values
    that give this case, ``inherited`` the extra integrals of the sets it lies in,
    restricted to it."""
    rnd = state.rnd(when)
    m = CaseMechanics(case)
    cofactor = state.cofactors.get(when, state.cofactor)
    try:
        system, params = _system(state.options, m, free, cofactor, values, state.symmetries)
    except DiscoveryError as err:
        if not when:
            raise
        # a set at algebraic values where the members' field is not rational
        state.undecided.append(f"{', '.join(when)} not searched: {err}")
        return IntegralSet(when, 0), _Level({}, 0), []
    state.used[when] = system.symmetry_note
    _check_invariant(system, state.options)
    known, names = known_generators(m, system)
    if cofactor is not None and cofactor != 0:  # Darboux polynomials: nothing is known
        known = []
    before = _generators(system, inherited)
    point = {i: rnd.randrange(1, PRIME) for i in range(len(params))}
    modular = Field(GF_PRIME, params, point, system.inverses)
    generic = analyse(system, known, modular)
    fresh = _beyond(analyse(system, [*known, *before], modular) if before else generic)
    integrals: list[sp.Expr] = []
    if generic.extra:  # extra integrals for generic values (or an unlucky point)
        fld = Field(QQ.frac_field(*params) if params else QQ, params, {}, system.inverses)
        generic = analyse(system, known, fld, to_poly=lambda v: _ring_poly(system, v, fld))
        if fresh and before:  # what the sets it lies in do not generate, exactly
            fresh = _beyond(analyse(system, [*known, *before], fld))
        fresh = min(fresh, generic.extra)
        columns = [e for e, _ in system.columns]
        integrals = [
            _expression(system, simplest(v, generic.trivial[d], columns, fld.domain), fld)
            for v, d in generic.extras
        ]
    if cofactor is not None and cofactor != 0:
        found = proven_relations(m, when, integrals, cofactor, state.coefficients, state.undecided)
    else:
        found = _proven(state, case, when, values, integrals)
    if not when and found.integrals:  # new, or the case's own claims again
        kept = [e for e in integrals if to_text(e) in found.integrals]
        found, state.claims = named(case, m, system, params, found, kept)
    kernel = _Level({d: c[0] for d, c in generic.counts.items()}, generic.extra, fresh)
    inside = (*inherited, *integrals)  # what the sets within are compared with
    if not when:  # the generic values are decided, whatever happens to the locus
        state.known, state.counts, state.generic = tuple(names), generic.counts, found
    divided = _divided(state, case, system, when, values, inside)
    if not free:
        return found, kernel, divided
    if system.divided_by:
        state.undecided.append(
            f"the level set's basis divides by {', '.join(map(to_text, system.divided_by))}"
            ": special values of the free parameters on it are not sought"
        )
        return found, kernel, divided
    extras = [
        Generator(system.polynomial(e), d)
        for e, (_, d) in zip(integrals, generic.extras, strict=True)
    ]
    # the paper's own e(3) form, whose known integrals never meet (``_locus``)
    general = m.dynamics.from_bracket or m.kappa != 0 or m.dynamics.torque is None
    locus = _locus(state, system, params, len(free), generic, known, extras, rnd, general)
    candidates = divided
    pieces = list(locus.pieces)
    weights = None
    while pieces:  # components with no rational parametrisation: decided at their points
        if weights is None:
            weights = _scalings(m, system, known, params, state.options)
        force = [*known, *before, *extras]  # the integrals in force on this set
        decision = decide(pieces.pop(), system, force, 0, weights, rnd)
        state.undecided.extend(u for u in decision.undecided if u not in state.undecided)
        state.decided.extend(decision.decided)
        locus.sets.extend(x for x in decision.points if x not in locus.sets)
        for smaller in decision.further:
            resolved = resolve(smaller, params[: len(free)], params[len(free) :])
            state.undecided.extend(u for u in resolved.undecided if u not in state.undecided)
            locus.sets.extend(x for x in resolved.sets if x not in locus.sets)
            pieces.extend(resolved.pieces)
    for parametrised in locus.maximal():
        assignment, introduced = _named(case, parametrised)
        sub = with_values(case, assignment)
        if sub is None:
            continue
        composed = _composed(values, assignment)
        rest = [p for p in free if p not in assignment] + introduced
        sub_when = _when(state, composed)
        candidates.append((sub, rest, sub_when, composed, _restricted(inside, assignment)))
        if cofactor is not None:
            state.cofactors[sub_when] = sp.expand(cofactor.xreplace(assignment))
    return found, kernel, candidates


def _restricted(integrals: Sequence[sp.Expr], assignment) -> tuple[sp.Expr, ...]:
    """Integrals of a set, restricted to a set within it (its parameter values put in;
    one whose coefficients have a pole there is left out)."""
    out = []
    for e in integrals:
        try:
            value = sp.cancel(sp.sympify(e).xreplace(assignment))
        except (ZeroDivisionError, sp.PolynomialError):
            continue
        if value.has(sp.zoo, sp.nan, sp.oo) or value == 0:
            continue
        out.append(value)
    return tuple(out)


def _generators(system: PolynomialSystem, integrals: Sequence[sp.Expr]) -> list[Generator]:
    """Integrals of the sets a set lies in as generators of the trivial ones there (those
    outside the system's ring, or constant there, generate nothing)."""
    out = []
    for e in integrals:
        try:
            poly = system.polynomial(e, what="integral of an enclosing set")
        except DiscoveryError:
            continue
        if poly and system.weight(poly):
            out.append(Generator(poly, system.weight(poly)))
    return out


def _scalings(m: CaseMechanics, system: PolynomialSystem, known, params, options):
    """The family's scalings (``mathematics.scalings``) that also keep the level set and
    the known integrals homogeneous: the parameters' weights."""
    field = [m.dynamics.expanded(f) for f in m.field]
    invariant = [sp.sympify(eq.expr) for eq in options.on]
    invariant += [system.expression(g.poly) for g in known]
    return covariant_weights(field, m.dynamics.variables, params, invariant)


def _named(
    case: Case, assignment: dict[sp.Symbol, sp.Expr]
) -> tuple[dict[sp.Symbol, sp.Expr], list[sp.Symbol]]:
    """A candidate set with the parameter its parametrisation introduced
    (``components.NEW``) named ``w1``, ``w2``, ... (the first name the case does not
    use), and the parameters so named: free parameters of the set's own search."""
    if not any(NEW in sp.sympify(e).free_symbols for e in assignment.values()):
        return assignment, []
    taken = {*case.parameters, *map(str, case.dynamics.variables), *case.functions}
    name = next(f"w{i}" for i in itertools.count(1) if f"w{i}" not in taken)
    named = sp.Symbol(name, real=True)
    return {s: sp.sympify(e).xreplace({NEW: named}) for s, e in assignment.items()}, [named]


def _composed(values: dict, assignment: dict) -> dict[sp.Symbol, sp.Expr]:
    """The family's free parameters' values after ``assignment`` within ``values``."""
    out = {s: sp.cancel(e.xreplace(assignment)) for s, e in values.items()}
    out.update(assignment)
    return out


def _when(state: _State, values: dict[sp.Symbol, sp.Expr]) -> tuple[str, ...]:
    """A set's equations, in the order the free parameters were named."""
    order = {name: i for i, name in enumerate(state.options.free)}
    ordered = sorted(values.items(), key=lambda item: order.get(str(item[0]), len(order)))
    return tuple(f"{to_text(s)} = {to_text(e)}" for s, e in ordered)


def _each(state: _State, candidates, executor: Executor, seconds: float | None):
    """Search each candidate set (``_step``), here or by ``executor``: (integrals,
    its ``_Level``, sets within, undecided, cofactors of the sets within), in the candidates'
    order in every case. A single set, or an executor that runs in this process, is
    searched here (with the search's state shared); sets elsewhere each get a copy."""
    if not candidates:
        return
    if executor.local and (executor.workers <= 1 or len(candidates) <= 1):
        for sub, rest, when, values, inherited in candidates:
            if state.progress is not None:
                state.progress(state.done, state.total, ", ".join(when))
            before = list(state.undecided)
            g, level, inner = _step(state, sub, rest, when, values, inherited)
            state.done += 1
            new = [u for u in state.undecided if u not in before]
            yield g, level, inner, new, {}, {}, []
        return
    yield from _each_elsewhere(state, candidates, executor, seconds)


def _each_elsewhere(state: _State, candidates, executor: Executor, seconds: float | None):
    """``_each`` by an executor, in the candidates' order; a candidate set it could not
    search is undecided."""
    bare = replace(
        state, progress=None, found=[], undecided=[], searched=[], used={}, decided=[], spread=None
    )
    work = [(bare, *candidate) for candidate in candidates]
    calls = executor.map(_step_apart, work, deadline=seconds, label=_label, name="registry-search")
    for index, value in in_order(calls, len(work)):
        when = candidates[index][2]
        if state.progress is not None:
            state.progress(state.done, state.total, ", ".join(when))
        state.done += 1
        if isinstance(value, Failure):
            where = f" on worker {value.worker}" if value.worker else ""
            why = (
                f"candidate set {', '.join(when)} not searched "
                f"({value.kind}{where}: {value.reason})"
            )
            yield IntegralSet(when, 0), _Level({}, 0), [], [why], {}, {}, []
        else:
            yield value


def _spreader(executor: Executor, seconds) -> Spread | None:
    """The splitting's ``spread`` by ``executor``'s workers (None where it has one): the
    outcomes in order, a failed call as the text of why."""
    if executor.workers <= 1:
        return None

    def spread(fn, items):
        calls = executor.map(
            fn, items, deadline=seconds, label=lambda _: "locus branches", name="registry-split"
        )
        return [
            f"{value.kind}: {value.reason}" if isinstance(value, Failure) else value
            for _, value in in_order(calls, len(items))
        ]

    return spread


def _label(work) -> str:
    """A candidate's name in a cluster's events: its equations (``lam = 1, z0 = 0``)."""
    return ", ".join(work[3])


def _step_apart(work):
    """``_step`` in a worker process, with what it could not decide and the cofactors
    of the sets within (the worker's state is a copy)."""
    state, case, free, when, values, inherited = work
    g, level, inner = _step(state, case, free, when, values, inherited)
    cofactors = {c[2]: state.cofactors[c[2]] for c in inner if c[2] in state.cofactors}
    return g, level, inner, state.undecided, cofactors, state.used, state.decided


def _system(
    options: SearchOptions,
    m: CaseMechanics,
    free: list[sp.Symbol],
    cofactor=None,
    values=None,
    symmetries: bool = True,
):
    """The polynomial system and its parameters (the free ones first, then the symbolic
    ones, then those standing for 1/c(p) where the level set's basis divides by c(p));
    with a ``cofactor``, the system of its Darboux polynomials; ``values`` are the
    parameter values of the set searched, put in the level set's equations."""
    on = [sp.sympify(eq.expr).xreplace(values or {}) for eq in options.on]
    around = [] if m.hamiltonian is None else [m.hamiltonian]
    present = set().union(*(sp.sympify(e).free_symbols for e in (*m.field, *around, *on)))
    symbolic = sorted((set(m.case.parameters.values()) - set(free)) & present, key=str)
    params = [*free, *symbolic]
    dynamics = m.dynamics
    weights = per_variable(options.weights, dynamics.vectors, dynamics.variables)
    system = PolynomialSystem(
        m.field,
        params,
        weights,
        options.degree,
        on,
        hamiltonian=m.hamiltonian,
        cofactor=cofactor,
        symmetries=symmetries,
        state=dynamics.variables,
        shorthands=dynamics.shorthands,
    )
    return system, list(system.params)


def _divided(state: _State, case: Case, system: PolynomialSystem, when, values, inside=()) -> list:
    """Where the level set's basis divides by c(p), the search above holds for c != 0;
    c = 0 is a candidate set of its own (where the assumptions allow it), searched at
    the next level and special when it has more integrals. A c that no parameter can
    be solved for rationally leaves that part undecided."""
    candidates = []
    for c in system.divided_by:
        solved = None
        for p in sorted(c.free_symbols, key=str):
            poly = sp.Poly(sp.numer(sp.together(c)), p)
            if poly.degree() == 1:
                solved = {p: sp.cancel(-poly.nth(0) / poly.nth(1))}
                break
        if solved is None:
            state.undecided.append(
                f"the level set's basis divides by {to_text(c)}; where it vanishes is not searched"
            )
            continue
        sub = with_values(case, solved)
        if sub is None:  # the assumptions exclude c = 0
            continue
        composed = _composed(values or {}, solved)
        sub_when = _when(state, composed)
        if state.cofactor is not None:
            base = state.cofactors.get(when, state.cofactor)
            state.cofactors[sub_when] = sp.expand(base.xreplace(solved))
        free = [f for f in _free_symbols(state, case) if f not in solved]
        candidates.append((sub, free, sub_when, composed, _restricted(inside, solved)))
    return candidates


def _free_symbols(state: _State, case: Case) -> list[sp.Symbol]:
    """The free parameters of the search that ``case`` still declares."""
    return [case.parameters[f] for f in state.options.free if f in case.parameters]


def _locus(
    state, system, params, free, generic: Analysis, known, extras, rnd, general=False
) -> Locus:
    """Candidate sets of the free parameters (the first ``free`` of ``params``).

    Extra integrals appear where some block's kernel grows (block by block, cut off at
    each weight, since integrals are counted by degree) or where the trivial
    integrals become dependent. On e(3) with H = M.I^-1 M/2 + U the known integrals
    never do (H is quadratic in M with finite moments, |gamma|^2 free of M, the torque's
    Casimir linear in M through s); products with extra integrals of generic values may,
    and so may a ``general`` H or a deformed bracket (H can meet the Casimirs at special
    values), so that their rank is added then.
    """
    ring = PolyRing([str(p) for p in params], QQ, "lex")
    locus = Locus()

    def rows_of(entries) -> list[dict[int, PolyElement]]:
        rows: dict[int, dict[int, PolyElement]] = {}
        for (r, c), v in entries:
            poly = ring(dict(v))
            if poly:
                rows.setdefault(r, {})[c] = poly
        return list(rows.values())

    positive = frozenset(i for i, p in enumerate(params) if p.is_positive)
    nonzero = frozenset(i for i, p in enumerate(params) if p.is_nonzero)

    def drops(rows, rho) -> None:
        if rows and rho > 0:
            found = drop_locus(
                rows, rho, free, rnd, positive=positive, nonzero=nonzero, spread=state.spread
            )
            locus.merge(found)

    for b, block in enumerate(system.blocks):
        weights = block.weights
        for cutoff in sorted(set(weights)):
            keep = {c: i for i, c in enumerate(c for c, w in enumerate(weights) if w <= cutoff)}
            rows = rows_of(((r, keep[c]), v) for (r, c), v in block.entries.items() if c in keep)
            drops(rows, len(keep) - generic.nullities[(b, cutoff)])
    if extras or general:
        trivial = products(system, [*known, *extras], system.degree)
        rows = rows_of(
            ((i, j), coeffs)
            for i, p in enumerate(trivial)
            for j, coeffs in system.coordinates(p).items()
        )
        drops(rows, generic.counts[system.degree][1])
    back = dict(zip(ring.symbols, params, strict=True))
    locus.sets = [{back[s]: e.xreplace(back) for s, e in p.items()} for p in locus.sets]
    for found in locus.algebraic:  # its components: rational ones, and pieces to decide
        mapped = AlgebraicSet(
            {back[s]: e.xreplace(back) for s, e in found.values.items()},
            tuple(e.xreplace(back) for e in found.equations),
            tuple(e.xreplace(back) for e in found.units),
        )
        resolved = resolve(mapped, params[:free], params[free:])
        locus.undecided.extend(u for u in resolved.undecided if u not in locus.undecided)
        locus.sets.extend(x for x in resolved.sets if x not in locus.sets)
        locus.pieces.extend(resolved.pieces)
    state.undecided.extend(u for u in locus.undecided if u not in state.undecided)
    return locus


def _ring_poly(system: PolynomialSystem, vec, fld: Field) -> PolyElement:
    """A kernel vector as a ring polynomial with its parameter denominators cleared."""
    return system.polynomial(_expression(system, vec, fld))


def _expression(system: PolynomialSystem, vec, fld: Field) -> sp.Expr:
    """A kernel vector as an expression: integer coefficients with no common factor
    (polynomial in the symbolic parameters), the first one positive."""
    terms = [
        fld.domain.to_sympy(c)
        * sp.Mul(*(x**e for x, e in zip(system.variables, system.columns[j][0], strict=True)))
        for j, c in enumerate(vec)
        if c
    ]
    numer = sp.numer(sp.together(sp.Add(*terms)))
    _, primitive = sp.Poly(numer, *system.variables).primitive()
    if primitive.LC().could_extract_minus_sign():
        primitive = -primitive
    return system.space.lower(primitive.as_expr())


def _proven(
    state: _State, case: Case, when, values: dict, integrals: Sequence[sp.Expr]
) -> IntegralSet:
    """The integrals, each proven by the audit's ``integral`` check (``casimir`` recorded
    for information) on the level set at the set's parameter ``values``. One that is not
    proven is not reported, and the search is then not complete. The checks run under
    the search's own budget."""
    if not integrals:
        return IntegralSet(when, 0)
    on = tuple(equation_with_values(eq, values) for eq in state.options.on)
    claims = tuple(
        Claim(f"F{i + 1}", ClaimKind.INTEGRAL, Expression(to_text(e), e), on=on)
        for i, e in enumerate(integrals)
    )
    audit = audit_case(
        replace(case, claims=claims), checks=["integral", "casimir"], corrections=False, budget=None
    )
    kept: list[str] = []
    casimirs: list[Verdict] = []
    for claim in claims:
        result = audit.result("integral", claim.label)
        if result.verdict is not Verdict.VERIFIED:
            where = f" where {', '.join(when)}" if when else ""
            state.undecided.append(
                f"integral {claim.expression.text}{where} found but not proven "
                f"({result.verdict}: {result.reason or result.method})"
            )
            continue
        kept.append(claim.expression.text)
        casimirs.extend(
            r.verdict for r in audit.results if (r.check, r.claim) == ("casimir", claim.label)
        )
    # a system given by its equations has no bracket, hence no Casimir verdicts
    return IntegralSet(when, len(kept), tuple(kept), tuple(casimirs))


def _check_invariant(system: PolynomialSystem, options: SearchOptions) -> None:
    """The level set must be kept by the flow, or an integral on it means nothing. (The
    ring's own relations, such as u d = 1 for an inverse u of d, are kept by
    construction: u' = -u**2 d' makes (u d - 1)' = u d' (1 - u d); nothing to check
    without a level set.)"""
    if not options.on:
        return
    inverse = {sp.Symbol(str(i)): 1 / c for i, c in system.divisors.items()}
    for g in system.ideal:
        rate = system.reduce(
            sum(
                (g.diff(system.ring.gens[i]) * system.field[i] for i in range(system.n)),
                system.ring.zero,
            )
        )
        if rate and inverse:  # 1/c(p) put back for the parameter iota that stands for it
            rest = sp.numer(sp.together(system.expression(rate).xreplace(inverse)))
            rate = system.polynomial(rest) if sp.expand(rest) != 0 else system.ring.zero
        if rate:
            equations = ", ".join(eq.text for eq in options.on)
            raise DiscoveryError(
                f"the flow does not keep the level set {equations} invariant (the time "
                "derivative of its equations does not vanish on it); an integral there "
                "would mean nothing"
            )


def _distinct(sets: list[IntegralSet]) -> list[IntegralSet]:
    """One entry per set, fewest equations first."""
    out: dict[tuple[str, ...], IntegralSet] = {}
    for s in sets:
        out.setdefault(tuple(sorted(s.when)), s)
    return sorted(out.values(), key=lambda s: (len(s.when), s.when))
