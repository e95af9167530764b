"""Where a family with several free parameters can pass the Painlevé test: the parameter
space stratified by necessary conditions, each stratum analysed again with fewer free
parameters, down to the sets where the test passes for every member.

*Necessary conditions.* The test passes at a value p0 only if it passes at every balance.
Take a component of balances over Q(p) whose exponents are integers that do not depend
on p (the heavy top's balances with gamma = 0: -1, 1, 2, 2, 2, 3 for every top). Its
Laurent series (``painleve``) is computed once over Q(p), in k[u]/(g). Outside an
*exceptional* hypersurface E, everything in that computation specialises at p0: the
denominators of the balance's coordinates and of g's coefficients, the discriminant of
g (conjugate balances meet), the norm of a coordinate (the balance runs into the
origin) and the norms of every pivot of the series' eliminations and of the minor of
a kernel projection (where one vanishes the rank of K - k can drop) are not zero
there. So at p0 outside E:

* a resonance that lacks a free coefficient lacks it at p0 too (the rank of K - r is
  the generic one), and the test fails;
* an exponent 0 more often than the component has dimensions fails the test for the
  generic members, and at every value where the balance equations do not depend on
  the parameters; elsewhere the values where the balance joins a larger family are not
  sought, so a stratum that nothing else cuts is then left undecided;
* a compatibility condition c, reduced modulo g, holds at every conjugate balance
  exactly when each of its coefficients (in u, the free coefficients and the family's
  free coordinates) vanishes at p0: these are the equations J;
* an exponent that is a constant non-integer stays one, and the test fails; so does
  one that varies in form only: where the norm Res_u(g, H) of the part H of the
  exponent polynomial that differs between conjugate balances has rational
  coefficients, its roots are every exponent of every conjugate balance at p0;
* for a pair of complex conjugate balances (g of degree 2 whose discriminant is never
  positive: each of its factors a square, or of one sign as a sum of squares) whose
  exponents vary, integer exponents make every coefficient of their characteristic
  polynomial real at a non-real u, so its parts in u vanish: more equations in J (and
  where the discriminant vanishes, systems of their own).

Hence the values where the test passes lie in V(J) union E (in E alone when a
resonance lacks a coefficient). Balances are first taken from the coordinate
hyperplanes (the components of the balance equations with one variable set to 0),
which are small; only where those give no condition are all the balances computed.

*Recursion.* Each irreducible component of V(J) and of E over Q (``components``: those
with real points, rationally parametrised, a new parameter w1, w2, ... where needed) is
a family with fewer free parameters, analysed the same way. Real points are those at the
declared signs: a sum of terms c P m**2 (c > 0, P a product of positive parameters)
vanishes only where each m does; a real zero of a V**2 + b V + c (V = v**k, a of one
sign) whose discriminant is never positive is a double root, where the discriminant
vanishes; a positive parameter set to a value that cannot be positive leaves nothing
(``mathematics.real_zeros``). Each needs no rational parametrisation of the set it cuts
away. A stratum whose balances all have constant integer exponents and no condition
passes for its generic members; it is reported, and its own exceptional subsets are not
explored (a smaller set inside a passing one). A stratum with no free parameter left is
analysed exactly. Where the conditions cut nothing and the exponents that vary depend on
one parameter p only, or on the ratio p/q of two (``_ratio``: every coefficient of their
factors homogeneous of one degree in p and q, as the heavy top's moments enter, since
scaling the moments is a symmetry), the values of p (of p/q, with q = 0 apart) where
they can be integers (``integrality``) are the next strata: points, and infinite
families p = P(n) through an integer index n1, a parameter of its own (a family whose
resonances move with the index is left undecided: the series cannot be written for a
symbolic resonance). Where the exponents that vary involve more parameters, those of
some factors may still involve one (or a ratio): their candidates are necessary, and cut
the set (``_part``); the others are examined on the smaller sets. With one free
parameter this is ``exponent_family``, whose integer list is complete there.

*Exponents in (1/2)Z* (``half_integer_strata``). The same walk without the series:
the conditions are that a constant exponent be in (1/2)Z and the conjugate parts
(any real exponents need them); the candidates of one parameter are those of the
doubled polynomials, and an infinite family through an integer index is a set of its
own (no resonance to write). Goryachev and Chaplygin's top is found this way.

*What is guaranteed.* ``complete`` says that every admissible real parameter value
where the ARS test passes (every exponent is in (1/2)Z) lies in one of the
``passing`` sets: every stratum was
decided, none was left without a rational parametrisation, and the time sufficed.
Passing is necessary for the Painlevé property, not a proof of it.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import sympy as sp
from sympy.polys.fields import FracElement

from ..errors import WeightedFieldError
from ..execution.time_budget import BudgetExceeded, time_limit
from ..mathematics import painleve
from ..mathematics.balances import balance_equations
from ..mathematics.exponent_analysis import ExponentAnalysis, analyse
from ..mathematics.exponent_families import Mapper, doubled, exponent_family, kind_of
from ..mathematics.factoring import factor_list
from ..mathematics.flint_gcd import flint_gcd
from ..mathematics.flint_polys import discriminant, resultant_in
from ..mathematics.integrality import integer_candidates
from ..mathematics.kovalevskaya import LAMBDA, characteristic_polynomial, kovalevskaya_matrix
from ..mathematics.prime_components import Component, DecompositionLimit, components
from ..mathematics.real_zeros import MAX_REAL_STEPS, never_positive, real_system
from ..mathematics.weighted import WeightedField, polynomial_only, split_field
from .components import NEW, resolve
from .splitting import AlgebraicSet

#: The most strata one stratification visits before it stops (not complete).
MAX_STRATA = 400


@dataclass(frozen=True)
class Stratum:
    """A set of parameter values: the free parameters it fixes (``values``, in terms of
    the others and of new parameters), the ones left free, and its analysis there (the
    generic member's, or the point's)."""

    values: dict[sp.Symbol, sp.Expr]
    free: tuple[sp.Symbol, ...]
    analysis: ExponentAnalysis | None = None
    notes: tuple[str, ...] = ()

    def text(self) -> str:
        """Its equations, ``b = 1, z0 = 0`` (``every value`` for the whole space), and
        which of its free parameters run over the integers."""
        text = ", ".join(f"{k} = {sp.sstr(v)}" for k, v in self.values.items()) or "every value"
        integers = [str(p) for p in self.free if p.is_integer]
        return text + (f" ({', '.join(integers)} integer)" if integers else "")


@dataclass(frozen=True)
class Strata:
    """The outcome: the ``passing`` sets (for ``half_integer_strata``, the sets where
    every exponent is in (1/2)Z), what was left undecided (each in words), how many
    strata were analysed, and whether the list is complete (module doc)."""

    free: tuple[sp.Symbol, ...]
    passing: tuple[Stratum, ...]
    undecided: tuple[str, ...]
    visited: int
    seconds: float = field(default=0.0, compare=False)

    @property
    def complete(self) -> bool:
        return not self.undecided


@dataclass
class _Necessary:
    """What a stratum's balances impose: equations J in the parameters (``fails``: none
    can hold, V(J) is empty), the exceptional factors E, and whether every balance was
    seen with constant integer exponents (``decided``)."""

    equations: list[sp.Expr] = field(default_factory=list)
    exceptional: list[sp.Expr] = field(default_factory=list)
    fails: bool = False
    decided: bool = True
    #: factors (in lambda, over Q(p)) whose roots vary with the parameters
    varying: list[sp.Expr] = field(default_factory=list)
    #: some exponent varies along a family of balances
    undecidable: bool = False
    #: further systems whose zero sets may hold passing values (beyond V(J) and E)
    systems: list[tuple[sp.Expr, ...]] = field(default_factory=list)
    #: some exponents that vary are not among ``varying`` (a part that differs between
    #: conjugate balances)
    partial: bool = False
    #: a component's exponent 0 has a larger multiplicity than its dimension: its
    #: generic members fail, but where its balances join a larger family is not known
    deficient: bool = False

    @property
    def cuts(self) -> bool:
        """Whether the passing values lie in a smaller set: V(J) (J not zero) or E."""
        return self.fails or any(e != 0 for e in self.equations)


def painleve_strata(
    variables: Sequence[sp.Symbol],
    field_: Sequence[sp.Expr],
    weights: Sequence[int],
    free: Sequence[sp.Symbol],
    *,
    seed: int = 0,
    budget: float | None = None,
    mapper: Mapper | None = None,
) -> Strata:
    """The sets of values of ``free`` where the ARS test passes for the field
    dx/dt = ``field_`` under ``weights`` (module doc), each set once (none inside
    another). The strata of one depth are examined together, by ``mapper`` (a worker
    pool's map, in order; default: here, one after the other). Past ``budget`` seconds
    the strata not yet examined are left undecided, and the list is then not complete."""
    return _stratify(variables, field_, weights, free, seed, budget, mapper, half=False)


def half_integer_strata(
    variables: Sequence[sp.Symbol],
    field_: Sequence[sp.Expr],
    weights: Sequence[int],
    free: Sequence[sp.Symbol],
    *,
    seed: int = 0,
    budget: float | None = None,
    mapper: Mapper | None = None,
) -> Strata:
    """The sets of values of ``free`` where every exponent of every balance is in (1/2)Z
    (the weak Painlevé property's necessary condition: Goryachev-Chaplygin's top has
    exponents -1/2, 3/2), by the same stratification without the series: the
    conditions are the constant exponents' and the conjugate balances' (module doc).
    Each set's ``analysis`` (where made) says whether its exponents are all integers."""
    return _stratify(variables, field_, weights, free, seed, budget, mapper, half=True)


def _stratify(variables, field_, weights, free, seed, budget, mapper, *, half: bool) -> Strata:
    start = time.perf_counter()
    field_ = tuple(sp.sympify(f) for f in field_)
    polynomial_only(split_field(variables, field_, weights, parameters=free), "strata")
    seen: set[tuple] = set()
    passing: list[Stratum] = []
    undecided: list[str] = []
    level: list[tuple[dict, tuple]] = [({}, tuple(free))]
    visited = 0
    try:
        with time_limit(budget):
            while level:
                todo = []
                for values, left in level:
                    key = tuple(sorted((str(k), sp.srepr(v)) for k, v in values.items()))
                    if key not in seen:
                        seen.add(key)
                        todo.append((values, left))
                if visited + len(todo) > MAX_STRATA:
                    undecided.append(f"more than {MAX_STRATA} strata: the others not examined")
                    todo = todo[: MAX_STRATA - visited]
                items = [
                    (tuple(variables), field_, tuple(weights), v, f, seed, half) for v, f in todo
                ]
                results = (mapper or _in_order)(examine_stratum, items)
                visited += len(todo)
                level = []
                for (values, left), result in zip(todo, results, strict=True):
                    if result is None:
                        text = Stratum(values, left).text()
                        undecided.append(f"{text}: its examination did not come back")
                        continue
                    passing += result.passing
                    undecided += result.undecided
                    level += result.children
    except BudgetExceeded:
        undecided.append(
            f"the time ({budget:g} s) ran out after {visited} strata: the others not examined"
        )
    return Strata(
        tuple(free),
        tuple(sorted(_maximal(passing), key=lambda s: (-len(s.free), s.text()))),
        tuple(dict.fromkeys(undecided)),
        visited,
        time.perf_counter() - start,
    )


def _in_order(fn, items):
    return [fn(item) for item in items]


@dataclass
class Examined:
    """What one stratum gave: the sets found passing in it, what it left undecided, and
    the smaller strata to examine next (each its values and free parameters)."""

    passing: list[Stratum] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)
    children: list[tuple[dict[sp.Symbol, sp.Expr], tuple[sp.Symbol, ...]]] = field(
        default_factory=list
    )


def examine_stratum(item) -> Examined:
    """One stratum (variables, field, weights, values, free, seed, half): passing, a point
    analysed, or the smaller strata its necessary conditions leave (module doc); with
    ``half``, where the exponents are in (1/2)Z instead. One call of a mapper."""
    variables, field_, weights, values, free, seed, half = item
    walk = _Walk(variables, field_, weights)
    walk.seed, walk.half = seed, half
    try:
        with flint_gcd():
            walk.visit(values, free)
    except DecompositionLimit as err:  # a system too large for the decomposition
        walk.undecided.append(f"{Stratum(values, free).text()}: not decided ({err})")
    return walk.found


class _Walk:
    def __init__(self, variables, field_, weights):
        self.variables, self.field, self.weights = variables, field_, weights
        self.seed = 0
        #: the sets sought: where the ARS test passes (False), or where every exponent is
        #: in (1/2)Z (True: no series, only the exponents)
        self.half = False
        self.found = Examined()
        self.parameters = set().union(*(f.free_symbols for f in field_)) - set(variables)

    def _merged(self, values, chosen) -> dict[sp.Symbol, sp.Expr]:
        """``values`` with ``chosen`` put in, for the family's own parameters only (a new
        parameter w1 or index n1 that a value fixes is not one of the family's)."""
        merged = {k: sp.cancel(sp.sympify(v).xreplace(chosen)) for k, v in values.items()}
        merged.update(chosen)
        return {k: v for k, v in merged.items() if k in self.parameters}

    @property
    def passing(self) -> list[Stratum]:
        return self.found.passing

    @property
    def undecided(self) -> list[str]:
        return self.found.undecided

    def visit(self, values: dict[sp.Symbol, sp.Expr], free: tuple[sp.Symbol, ...]) -> None:
        here = Stratum(values, free)
        concrete = [sp.expand(sp.sympify(f).xreplace(values)) for f in self.field]
        if any(c.has(sp.zoo, sp.nan) for c in concrete):
            return
        try:
            split = split_field(self.variables, concrete, self.weights, parameters=free)
        except WeightedFieldError as err:  # every term of lower order at these values
            self.undecided.append(f"{here.text()}: not analysed under these weights ({err})")
            return
        if not free:
            analysis = analyse(split, seed=self.seed, painleve=not self.half)
            if self._passes(analysis):
                self.passing.append(Stratum(values, free, analysis))
            return
        necessary = self._necessary(split, _hyperplane_components(split, self.seed))
        if not necessary.cuts:
            whole = _all_components(split, self.seed)
            if whole is None:
                self.undecided.append(f"{here.text()}: its balances were not found")
                return
            necessary = self._necessary(split, whole)
        if not necessary.cuts and necessary.deficient:
            self.undecided.append(
                f"{here.text()}: a balance has exponent 0 more often than its family has "
                "dimensions (the test fails for generic members); where its balances join "
                "a larger family was not sought"
            )
            return
        if not necessary.cuts:
            if necessary.decided:
                analysis = analyse(split, seed=self.seed, painleve=not self.half)
                if not self._passes(analysis):  # pragma: no cover - the same computation
                    self.undecided.append(f"{here.text()}: its two analyses disagree")
                    return
                what = "in (1/2)Z" if self.half else "passes"
                why = f"{what} for generic members; its smaller exceptional sets not explored"
                self.passing.append(Stratum(values, free, analysis, (why,)))
                return
            if len(free) == 1:
                self._one_parameter(values, free, concrete)
                return
            varying = set().union(*(f.free_symbols for f in necessary.varying)) & set(free)
            if not necessary.undecidable and len(varying) == 1:
                self._integer_values(values, free, necessary, varying.pop())
                return
            ratio = None if necessary.undecidable else _ratio(necessary.varying, varying)
            if ratio is not None:
                self._integer_values(values, free, necessary, ratio[1], scale=ratio[0])
                return
            part = None if necessary.undecidable else self._part(necessary.varying)
            if part is not None:  # some exponents alone cut the set: the others later
                factors, p, scale, found = part
                narrowed = replace(necessary, varying=factors, partial=True)
                self._integer_values(values, free, narrowed, p, scale=scale, found=found)
                return
            self.undecided.append(
                f"{here.text()}: some exponents vary with the parameters and no "
                "condition cuts the set"
            )
            return
        for equations in self._candidates(necessary):
            self._descend(values, free, equations)

    def _part(self, varying: Sequence[sp.Expr]):
        """(factors, p, q, their candidates) where some of the factors whose roots vary
        depend on one parameter p (q None), or on p/q (``_ratio``), and cut the set: their
        roots are not of the kind sought for every value. Each value where every exponent is of
        the kind makes these roots so too, so their candidates are necessary: the
        exponents of the other factors are examined on the smaller sets (two quartic
        oscillators: the balances on an axis involve one coefficient, the others two).
        None where no such part exists."""
        groups: dict[frozenset, list[sp.Expr]] = {}
        for f in dict.fromkeys(varying):
            symbols = frozenset(sp.sympify(f).free_symbols - {LAMBDA})
            if not any(x.is_integer for x in symbols):
                groups.setdefault(symbols, []).append(f)
        for symbols, factors in sorted(groups.items(), key=lambda g: sorted(map(str, g[0]))):
            if len(symbols) == 1:
                (p,), scale = tuple(symbols), None
            else:
                ratio = _ratio(factors, set(symbols))
                if ratio is None:
                    continue
                scale, p = ratio
            found = self._candidates_of(factors, p, scale)
            if found.families != ((p, p, "every value"),):
                return factors, p, scale, found
        return None

    def _candidates_of(self, factors: Sequence[sp.Expr], p: sp.Symbol, scale: sp.Symbol | None):
        """The values of p (of p/q at q = ``scale`` = 1) where the factors' roots can all be
        integers, or (``half``) in (1/2)Z: ``integer_candidates``."""
        if scale is not None:
            factors = [sp.cancel(sp.sympify(f).xreplace({scale: 1})) for f in factors]
        return integer_candidates(
            [doubled(f) for f in factors] if self.half else list(factors), p, LAMBDA
        )

    def _passes(self, analysis: ExponentAnalysis) -> bool:
        """Whether an analysis is of a set sought: the ARS test passes, or (``half``)
        every exponent is in (1/2)Z."""
        if self.half:
            return kind_of(analysis) in ("integer", "half-integer")
        return analysis.painleve_passes

    def _fits(self, factor: sp.Expr) -> bool:
        """Whether the roots of an irreducible factor over Q (in lambda) are integers, or
        (``half``) in (1/2)Z: it is linear, and its root is."""
        poly = sp.Poly(factor, LAMBDA)
        if poly.degree() != 1:
            return False  # irrational roots
        root = -poly.nth(0) / poly.nth(1)
        return bool((2 * root if self.half else root).is_integer)

    def _necessary(self, split: WeightedField, found: Sequence[Component]) -> _Necessary:
        """J and E of the components ``found`` (module doc)."""
        out = _Necessary()
        params = set(split.parameters)
        matrix = kovalevskaya_matrix(split)
        for component in found:
            _exceptional_of_component(component, params, out.exceptional)
            polynomial = characteristic_polynomial(component, matrix)
            fixed = _fixed_exponents(polynomial, component)
            if fixed is not None and not all(self._fits(f) for f in fixed):
                out.fails = True  # the same numbers at every value, one not of the kind
                continue
            if fixed is not None and self.half:
                continue  # every exponent a constant in (1/2)Z
            roots = _constant_roots(polynomial)
            if roots is None:
                out.decided = False
                if polynomial.varying:  # along a family of balances: not handled
                    out.undecidable = True
                    continue
                numbers = [f for f, _ in polynomial.common if f.free_symbols == {LAMBDA}]
                if not all(self._fits(f) for f in numbers):
                    out.fails = True  # a shared exponent the same number everywhere, unfit
                    continue
                out.partial |= bool(sp.sympify(polynomial.rest).free_symbols & params)
                conjugate = _conjugate_parts(polynomial.rest, component.symbol, params)
                nonreal = _nonreal_pair(component) if conjugate else None
                if nonreal is not None:  # integer exponents need the conjugate parts to vanish
                    out.equations += conjugate
                    out.systems += nonreal
                out.varying += [f for f, _ in polynomial.common if f.free_symbols & params]
                continue
            if any(not (2 * r if self.half else r).is_integer for r in roots):
                out.fails = True
                continue
            if self.half:
                continue  # the exponents only: no series
            if sum(1 for r in roots if r == 0) > component.dimension:
                # balances that do not depend on the parameters cannot join a larger
                # family at special values: the test fails at every one
                if any(e.free_symbols & params for e in balance_equations(split)):
                    out.deficient = True
                else:
                    out.fails = True
                    continue
            resonances: dict[int, int] = {}
            for r in roots:
                if r >= 1:
                    resonances[int(r)] = resonances.get(int(r), 0) + 1
            if not resonances:
                continue
            recursion = _Pivots(split, component, matrix, resonances)
            series = recursion.run(max(resonances))
            for pivot in recursion.pivots:
                _add_factors(_norm(component, pivot), params, out.exceptional)
            for step in series.resonances:
                if step.missing:
                    out.fails = True
                for condition in recursion.conditions[step.order - 1]:
                    for coefficient in condition.values():  # in k = Q(p, S), per u^i f^j
                        numer, denom = _fraction(recursion.algebra.field, coefficient)
                        out.equations += _coefficients(numer, params)
                        _add_factors(denom, params, out.exceptional)
        return out

    def _candidates(self, necessary: _Necessary) -> list[tuple[sp.Expr, ...]]:
        """The systems whose zero sets hold every value that may pass: V(J) (unless the
        test fails outright) and each exceptional hypersurface."""
        systems: list[tuple[sp.Expr, ...]] = []
        if not necessary.fails:
            equations = tuple(dict.fromkeys(e for e in necessary.equations if e != 0))
            if not any(e.is_number for e in equations):
                systems.append(equations)
        systems += [(q,) for q in dict.fromkeys(necessary.exceptional)]
        return systems + list(dict.fromkeys(necessary.systems))

    def _descend(self, values, free, equations: tuple[sp.Expr, ...], depth: int = 0) -> None:
        """Each real component of equations = 0 (in the free parameters), rationally
        parametrised, visited as a stratum of its own."""
        real = real_system(equations)
        if real is None:
            return  # no real point
        try:
            found = resolve(AlgebraicSet({}, real), list(free))
        except DecompositionLimit as err:  # pragma: no cover - resolve reports these
            self.undecided.append(f"{_text(real)}: its components were not found ({err})")
            return
        self.undecided.extend([f"{u}: not decided" for u in found.undecided])
        for piece in found.pieces:
            system = (
                *(sp.numer(sp.together(p - v)) for p, v in piece.values.items()),
                *piece.component.equations(),
            )
            smaller = real_system(system)
            if smaller is None:
                continue
            if smaller != system and depth < MAX_REAL_STEPS:
                self._descend(values, free, smaller, depth + 1)
                continue
            where = Stratum(values, free).text()
            self.undecided.append(
                f"{piece.text} (within {where}): no rational parametrisation, not analysed"
            )
        for chosen in found.sets:
            if NEW in set().union(*(sp.sympify(v).free_symbols for v in chosen.values())):
                fresh = _fresh(free)
                chosen = {k: sp.sympify(v).xreplace({NEW: fresh}) for k, v in chosen.items()}
            else:
                fresh = None
            merged = self._merged(values, chosen)
            if not _admissible(merged):
                continue  # where the stratum's parametrisation is not defined, or not allowed
            left = tuple(p for p in free if p not in chosen) + ((fresh,) if fresh else ())
            self.found.children.append((merged, left))

    def _integer_values(
        self,
        values,
        free,
        necessary: _Necessary,
        p: sp.Symbol,
        scale: sp.Symbol | None = None,
        found=None,
    ) -> None:
        """The exponents that vary depend on one parameter p only, or on the ratio p/q
        (``scale`` q, ``_ratio``): the values of p (of p/q) where they can all be
        integers (``found``, else ``_candidates_of``), each a stratum p = v (p = v q);
        where q may be 0, that hyperplane; and the exceptional hypersurfaces, as always."""
        unit = sp.Integer(1) if scale is None else scale
        if scale is not None and not scale.is_nonzero:
            self._descend(values, free, (scale,))
        if found is None:
            found = self._candidates_of(list(dict.fromkeys(necessary.varying)), p, scale)
        for v in found.values:
            if v.is_rational:
                self._descend(values, free, (sp.numer(sp.together(p - v * unit)),))
            else:
                text = Stratum({**values, p: v * unit}, free).text()
                self.undecided.append(f"{text}: an irrational value, not analysed")
        for expr, index, ranges in found.families:
            if expr != p:
                expr = expr * unit
            if self.half:
                self._half_integer_family(values, free, necessary, p, expr, index)
                continue
            if expr == p or ranges != "n in Z" or p.is_integer:  # resonances that move
                text = Stratum(values, free).text()
                self.undecided.append(
                    f"{text}: integer exponents that move with {p}, the test not made"
                )
                continue
            n = _fresh(free, "n", integer=True)  # the index, a parameter of its own
            chosen = {p: expr.xreplace({index: n})}
            merged = self._merged(values, chosen)
            if _admissible(merged):
                self.found.children.append((merged, (*(q for q in free if q != p), n)))
        if not found.complete:
            text = Stratum(values, free).text()
            self.undecided.append(f"{text}: the values of {p} were not all found")
        for q in dict.fromkeys(necessary.exceptional):
            self._descend(values, free, (q,))

    def _half_integer_family(self, values, free, necessary: _Necessary, p, expr, index) -> None:
        """Where the exponents that vary (in p only) are in (1/2)Z for p = expr(n), n in
        Z: the stratum itself where that is every value of p and no other exponent varies;
        else the family, with its index n1 a parameter of its own."""
        text = Stratum(values, free).text()
        whole = expr == p or (
            p.is_integer and sp.Poly(expr, index).degree() == 1 and abs(expr.coeff(index)) == 1
        )
        if whole and necessary.partial:
            self.undecided.append(f"{text}: some exponents vary with {p} and were not decided")
        elif whole:
            what = "every integer value" if p.is_integer else "every value"
            self.passing.append(Stratum(values, free, None, (f"in (1/2)Z for {what} of {p}",)))
        else:
            n = _fresh(free, "n", integer=True)
            merged = self._merged(values, {p: expr.xreplace({index: n})})
            if _admissible(merged):
                self.found.children.append((merged, (*(q for q in free if q != p), n)))

    def _one_parameter(self, values, free, concrete) -> None:
        """One free parameter whose exponents vary: ``exponent_family``'s integer sets
        (complete there), the passing ones kept; where every value has integer exponents,
        the whole set when its generic member passes."""
        family = exponent_family(self.variables, concrete, self.weights, free, seed=self.seed)
        sets = (*family.integer, *family.half_integer) if self.half else family.integer
        for s in sets:
            point = {k: sp.cancel(sp.sympify(v).xreplace(s.values)) for k, v in values.items()}
            point.update(s.values)
            if s.index is not None and not s.values:  # integer exponents for every value
                generic = family.generic
                if generic is not None and (self.half or generic.painleve_passes):
                    what = "in (1/2)Z" if self.half else "passes"
                    why = f"{what} for generic members; its exceptional values not explored"
                    self.passing.append(Stratum(values, free, generic, (why,)))
            elif s.index is not None and self.half:  # exponents only: the family is the set
                self.passing.append(Stratum(point, (s.index,), None, (f"{s.index} {s.ranges}",)))
            elif s.index is not None:
                text = f"{Stratum(point, free).text()} ({s.index} {s.ranges})"
                self.undecided.append(f"{text}: infinitely many values, not all tested")
            elif s.analysis is None:  # an irrational value: its exponents only
                if _admissible(point):
                    text = Stratum(point, free).text()
                    self.undecided.append(f"{text}: an irrational value, not analysed")
            elif self._passes(s.analysis) and _admissible(point):
                left = tuple(p for p in free if p not in s.values)
                self.passing.append(Stratum(point, left, s.analysis))
        if not family.complete_integer or (self.half and not family.complete_half_integer):
            kind = "half-integer" if self.half else "integer"
            self.undecided.append(
                f"{Stratum(values, free).text()}: the values of {free[0]} with {kind} "
                "exponents were not all found"
            )


class _Pivots(painleve._Recursion):
    """The ARS recursion, exporting every value it divides by or needs non-zero
    (``pivots``: pivots, minors), and the compatibility conditions of each order as
    elements of k[u, f] (``conditions[k - 1]``: their coefficients are read in k,
    without expanding expressions)."""

    def __init__(self, *args):
        super().__init__(*args)
        self.conditions: list[list] = []

    @property
    def pivots(self) -> list:
        """Every value the series divided by or needed non-zero, in k[u]."""
        return [self.algebra.exported(v) for v in self.divisors]

    def _order(self, k, rhs):
        solution, conditions, used = super()._order(k, rhs)
        exported = self.algebra.exported
        self.conditions.append([exported(c) for c in conditions if not c.is_zero])
        return solution, conditions, used


def _fraction(domain, element) -> tuple[sp.Expr, sp.Expr]:
    """Numerator and denominator of an element of k (a rational function of the
    parameters, or a rational number), as expressions."""
    if isinstance(element, FracElement):
        return element.numer.as_expr(), element.denom.as_expr()
    return sp.fraction(domain.to_sympy(element))


def _maximal(found: Sequence[Stratum]) -> list[Stratum]:
    """The passing sets that lie in no other one (a point of Euler's family, a line of
    the spherical top's), each once."""
    kept: list[Stratum] = []
    for i, s in enumerate(found):
        if not any(
            j != i and _inside(s, t) and (j < i or not _inside(t, s)) for j, t in enumerate(found)
        ):
            kept.append(s)
    return kept


def _inside(small: Stratum, big: Stratum) -> bool:
    """Whether every point of ``small`` satisfies the equations of ``big``."""
    for p, v in big.values.items():
        here = small.values.get(p, p)
        there = sp.sympify(v).xreplace(small.values)
        if sp.cancel(here - there) != 0:
            return False
    return True


def _fresh(free: Sequence[sp.Symbol], stem: str = "w", *, integer: bool = False) -> sp.Symbol:
    """A new parameter w1, w2, ... (n1, n2, ... for an integer index) that no parameter
    of the stratum is named."""
    taken = {str(p) for p in free}
    k = 1
    while f"{stem}{k}" in taken:
        k += 1
    return sp.Symbol(f"{stem}{k}", integer=True) if integer else sp.Symbol(f"{stem}{k}", real=True)


def _admissible(values: dict[sp.Symbol, sp.Expr]) -> bool:
    """Values that are defined (no division by zero) and respect the parameters'
    declared signs where they are numbers, or where the signs of the parameters left
    decide the value's (a positive parameter set to -2 p (p + 1)/(2 p + 1), p > 0)."""
    for p, v in values.items():
        if v.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
            return False
        if p.is_positive and sp.sympify(v).is_positive is False:
            return False
        if v.is_number and ((p.is_positive and not v > 0) or (p.is_nonzero and v == 0)):
            return False
        if v.is_number and p.is_integer and not v.is_integer:
            return False
    return True


def _hyperplane_components(split: WeightedField, seed: int) -> list[Component]:
    """The balances on the coordinate hyperplanes: the components of the balance
    equations with one variable set to 0, each found once."""
    equations = balance_equations(split)
    found: dict[str, Component] = {}
    for x in split.variables:
        try:
            parts = components([*equations, x], split.variables, split.parameters, seed=seed)
        except DecompositionLimit:
            continue
        for c in parts:
            found.setdefault(sp.sstr((c.free, c.minimal.as_expr(), dict(c.coordinates))), c)
    return list(found.values())


def _all_components(split: WeightedField, seed: int) -> list[Component] | None:
    try:
        return list(
            components(balance_equations(split), split.variables, split.parameters, seed=seed)
        )
    except DecompositionLimit:
        return None


def _ratio(
    factors: Sequence[sp.Expr], symbols: set[sp.Symbol]
) -> tuple[sp.Symbol, sp.Symbol] | None:
    """(q, p) where the factors whose roots vary depend on two parameters p and q
    through p/q only: in each factor every coefficient in lambda is a quotient of
    homogeneous polynomials in (p, q) of one same degree, so the roots are unchanged by
    (p, q) -> (s p, s q) (a scaling of the family: the heavy top's moments). q is a
    parameter declared positive where one is. None otherwise."""
    if len(symbols) != 2 or any(x.is_integer for x in symbols):
        return None
    q, p = sorted(symbols, key=lambda x: (not x.is_positive, str(x)))
    for factor in factors:
        degrees = set()
        for c in sp.Poly(factor, LAMBDA).all_coeffs():
            if c == 0:
                continue
            numer, denom = sp.fraction(sp.cancel(sp.sympify(c)))
            parts = [sp.Poly(x, q, p) for x in (numer, denom)]
            if not all(x.is_homogeneous for x in parts):
                return None
            degrees.add(parts[0].total_degree() - parts[1].total_degree())
        if len(degrees) > 1:
            return None
    return q, p


def _fixed_exponents(polynomial, component: Component) -> list[sp.Expr] | None:
    """The irreducible factors over Q of the product of the exponent polynomials of the
    component's conjugate balances, where it does not depend on the parameters: the
    common factors times the norm Res_u(g, H) of the rest (its roots are every exponent
    of every conjugate balance). None where it depends on them, or where the exponents
    vary along a family of balances."""
    found: list[sp.Expr] = []
    for f, _ in polynomial.common:
        if f.free_symbols - {LAMBDA}:
            return None
        found.append(f)
    rest = sp.sympify(polynomial.rest)
    if sp.degree(rest, LAMBDA) > 0:
        norm = sp.cancel(_norm(component, rest))
        if norm.free_symbols - {LAMBDA}:
            return None
        found += [f for f, _ in factor_list(norm, [LAMBDA]) if f.has(LAMBDA)]
    return found


def _constant_roots(polynomial) -> list[sp.Expr] | None:
    """The exponents with multiplicity when every one is a number the same for all the
    parameter values and balances of the component, else None."""
    if sp.degree(polynomial.rest, LAMBDA) > 0:
        return None
    roots: list[sp.Expr] = []
    for f, m in polynomial.common:
        poly = sp.Poly(f, LAMBDA)
        if poly.degree() != 1 or not all(c.is_number for c in poly.all_coeffs()):
            return None
        a1, a0 = poly.all_coeffs()
        roots += [-a0 / a1] * m
    return roots


def _exceptional_of_component(component: Component, params: set, out: list) -> None:
    """Where the component's representation fails to specialise: denominators of g and of
    the coordinates, the discriminant of g, and a coordinate's norm (the origin)."""
    u, g = component.symbol, component.minimal
    for c in g.all_coeffs():
        _add_factors(sp.fraction(sp.cancel(c))[1], params, out)
    if g.degree() > 1:
        _add_factors(discriminant(g), params, out)
    shortest = None
    for x, h in component.coordinates.items():
        if x in component.free:
            continue
        poly = sp.Poly(sp.together(h), u) if h.has(u) else None
        for c in poly.all_coeffs() if poly is not None else [h]:
            _add_factors(sp.fraction(sp.cancel(c))[1], params, out)
        if not component.vanishes(x):
            size = len(sp.sstr(h))
            if shortest is None or size < shortest[0]:
                shortest = (size, x)
    if shortest is not None:
        _add_factors(_norm(component, component.evaluate(shortest[1])), params, out)


def _norm(component: Component, value) -> sp.Expr:
    """The product of an element of k[u]/(g) over the conjugate balances: Res_u(g, value)
    (the element itself where it does not involve u)."""
    u = component.symbol
    expr = value.as_expr() if hasattr(value, "as_expr") else sp.sympify(value)
    if not expr.has(u):
        return expr
    return resultant_in(component.minimal.as_expr(), expr, u)


def _add_factors(expr: sp.Expr, params: set, out: list) -> None:
    """The irreducible factors of numerator and denominator that involve only the
    parameters (at least one), each added once."""
    numer, denom = sp.fraction(sp.together(sp.sympify(expr)))
    for part in (numer, denom):
        symbols = sorted(part.free_symbols, key=str)
        if not symbols or not set(symbols) <= params:
            continue
        for f, _ in factor_list(part, symbols):
            f = sp.expand(f)
            if f.free_symbols and f not in out:
                out.append(f)


def _coefficients(condition: sp.Expr, params: set) -> list[sp.Expr]:
    """A condition's numerator as polynomials in the parameters: its coefficients in every
    other symbol (u, the free coefficients, a family's free coordinates)."""
    numer = sp.expand(sp.fraction(sp.together(condition))[0])
    others = sorted(numer.free_symbols - params, key=str)
    if not others:
        return [numer]
    return [sp.expand(c) for c in sp.Poly(numer, *others).coeffs()]


def _conjugate_parts(rest: sp.Expr, u: sp.Symbol, params: set) -> list[sp.Expr]:
    """The parts in u, u**2, ... (in k[u]/(g)) of the coefficients of the factor of the
    characteristic polynomial that differs between conjugate balances, as equations in
    the parameters: where the two balances are complex conjugate (``_nonreal_pair``),
    integer exponents make each coefficient a real number at a non-real u, so these
    parts vanish."""
    found = []
    for c in sp.Poly(sp.expand(rest), LAMBDA).all_coeffs():
        if not c.has(u):
            continue
        for (j,), a in sp.Poly(sp.together(c), u).terms():
            if j:
                found += _coefficients(a, params)
    return found


def _nonreal_pair(component: Component) -> list[tuple[sp.Expr, ...]] | None:
    """For a component of two balances (g of degree 2) whose discriminant is never
    positive at real parameter values (``never_positive``): the systems where it may
    vanish (the two balances real and equal), none when it never does. None otherwise:
    the balances may be real, and then their exponents' conjugate parts may differ
    without any condition."""
    g = component.minimal
    if g.degree() != 2 or component.free:
        return None
    numer, denom = sp.fraction(sp.together(discriminant(g)))
    return never_positive(sp.expand(numer * denom))


def _text(equations: Sequence[sp.Expr]) -> str:
    return ", ".join(f"{sp.sstr(e)} = 0" for e in equations)
