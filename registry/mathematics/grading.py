"""The grading of a system: weights of its state's vectors under which the vector field is
weighted-homogeneous, if there are any.

With a weight w_i for each state variable, the field is homogeneous of shift d when every
monomial of dx_i/dt has weight w_i + d: then d/dt maps each weighted degree to one other,
the ansatz's system of an integral search splits into independent blocks by degree, and
an integral's homogeneous parts are integrals of their own. The reference paper's e(3)
systems with a quadratic kinetic energy and a potential linear in gamma are homogeneous
for M: 1, gamma: 2; a quadratic potential, and the bracket of so(4) and so(3,1)
(kappa != 0), need equal weights. Where no grading makes the field homogeneous (a
Hamiltonian with terms of several degrees, such as Kovalevskaya's on so(4)), an integral
search's ansatz is still every monomial of weighted degree <= K, but the degrees are
coupled: an integral found at degree K may have parts of every lower degree, none of them
conserved alone. The Kovalevskaya exponents need a grading too; there the leading part of
a field that has none is used (``weighted``).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence

import sympy as sp

from ..dynamics import Vector
from ..model import Weights, as_weights
from . import mechanics as mech
from .weighted import MAX_DIVIDED_FACTORS, by_denominator, expanded

#: The gradings of the reference paper's state tried, in order of preference (the
#: survey's usual ones first).
CANDIDATES: tuple[tuple[int, int], ...] = ((1, 2), (1, 1), (2, 1))


def per_variable(
    weights: Weights | tuple[int, int],
    vectors: Sequence[Vector],
    variables: Sequence[sp.Symbol] | None = None,
) -> tuple[int, ...]:
    """The weight of each state variable (a vector the weights do not name keeps its
    default weight), in the order of ``variables`` (default: vector by vector)."""
    given = dict(as_weights(weights))
    by_symbol = {x: given.get(v.name, v.weight) for v in vectors for x in v.components}
    order = variables if variables is not None else [x for v in vectors for x in v.components]
    return tuple(by_symbol[x] for x in order)


def shift(
    field: Sequence[sp.Expr],
    weights: Weights | tuple[int, int],
    vectors: Sequence[Vector] = mech.VECTORS,
    shorthands: Mapping[sp.Symbol, sp.Expr] = mech.SHORTHANDS,
    variables: Sequence[sp.Symbol] | None = None,
) -> int | None:
    """d such that every monomial of dx_i/dt has weight w_i + d, or None where there is
    none (a field that is not weighted-homogeneous for ``weights``, or not rational in
    the state). ``field`` lists dx/dt for ``variables`` (default: those of ``vectors``,
    vector by vector), in their order."""
    state = list(variables) if variables is not None else [x for v in vectors for x in v.components]
    return _Monomials(field, shorthands, state).shift(per_variable(weights, vectors, state))


class _Monomials:
    """The monomials in the state of each component of a field, computed once (on first
    use) for every weighting ``shift`` tries: the weights change only how the monomials
    are summed. A component is read term by term, its terms summed by denominator, each
    denominator kept in its factors (``weighted.by_denominator``): brought to one
    fraction, e/(gamma1 + gamma2 + gamma3)^400 would multiply every polynomial term by
    the expanded power (minutes and gigabytes). Where every group is weighted-homogeneous
    with one shift, so is their sum; terms whose parts cancel only across different
    denominators (x^2/(y (y + 1)) + x^2/(y + 1) = x^2/y) are read again as one fraction,
    which cancels them, unless a denominator has more than MAX_DIVIDED_FACTORS factors
    (a term the analysis refuses anyway)."""

    def __init__(
        self, field: Sequence[sp.Expr], shorthands: Mapping[sp.Symbol, sp.Expr], state: list
    ):
        self.field = list(field)
        self.shorthands = dict(shorthands)
        self.state = state
        self._groups: dict[int, list | None] = {}
        self._parts: dict[int, tuple] = {}

    def groups(self, i: int) -> list | None:
        """Component i's terms by denominator: (numerator's monomials, [(monomials of a
        factor of the denominator, its power), ...] or None) for each; None where a term
        is not a polynomial divided by one."""
        if i not in self._groups:
            x = sp.sympify(self.field[i]).subs(self.shorthands)
            grouped = by_denominator(x, self.state)
            self._groups[i] = (
                None
                if grouped is None
                else [
                    (_monoms(numer, self.state), _powers(denom, self.state))
                    for denom, numer in grouped.items()
                ]
            )
        return self._groups[i]

    def parts(self, i: int) -> tuple:
        """(numerator's monomials, denominator's) of component i brought to one fraction:
        each a list of exponent tuples, () for 0, None for no polynomial in the state."""
        if i not in self._parts:
            x = sp.sympify(self.field[i]).subs(self.shorthands)
            numer, denom = sp.fraction(sp.together(x))
            self._parts[i] = (_monoms(numer, self.state), _monoms(denom, self.state))
        return self._parts[i]

    def shift(self, w: Sequence[int]) -> int | None:
        """d such that the field is homogeneous of shift d under ``w``, or None."""
        found = self._shift_by_groups(w)
        if found is not None or not self._rereadable():
            return found
        return self._shift_whole(w)

    def _rereadable(self) -> bool:
        """Whether some component divides by the state (a polynomial field's one fraction
        is its groups again) and no denominator has more than MAX_DIVIDED_FACTORS factors,
        so that each component may be brought to one fraction."""
        sizes = [
            sum(e * _size(m) for m, e in factors)
            for i in range(len(self.field))
            for _, factors in self.groups(i) or ()
            if factors is not None
        ]
        return any(sizes) and max(sizes) <= MAX_DIVIDED_FACTORS

    def _shift_whole(self, w: Sequence[int]) -> int | None:
        shifts: set[int] = set()
        for i, wi in enumerate(w):
            numer, denom = self.parts(i)
            degree = _degree(numer, w)
            below = _degree(denom, w)
            if degree is None or not below:  # not homogeneous (a denominator is never 0)
                return None
            if degree == ():  # the component is zero
                continue
            shifts.add(degree[0] - below[0] - wi)
            if len(shifts) > 1:
                return None
        return next(iter(shifts), 0)

    def _shift_by_groups(self, w: Sequence[int]) -> int | None:
        """The shift when every group of every component is weighted-homogeneous with the
        same one, else None."""
        shifts: set[int] = set()
        for i, wi in enumerate(w):
            groups = self.groups(i)
            if groups is None:
                return None
            for numer, factors in groups:
                degree = _degree(numer, w)
                if degree == ():  # these terms sum to zero
                    continue
                if factors is None:
                    return None
                below = [(_degree(m, w), e) for m, e in factors]
                if degree is None or not all(d for d, _ in below):  # not homogeneous
                    return None
                shifts.add(degree[0] - sum(d[0] * e for d, e in below if d) - wi)
                if len(shifts) > 1:
                    return None
        return next(iter(shifts), 0)


def _powers(denom: sp.Expr, state: Sequence[sp.Symbol]) -> list | None:
    """A denominator as written, [(monomials of a base, its power), ...], None where a
    base is not a polynomial in the state to a positive integer power. Not factored
    (``weighted._factors`` does that for the split): a product is weighted-homogeneous
    exactly when each base is."""
    found = []
    for factor in sp.Mul.make_args(denom):
        base, power = factor.as_base_exp()
        if not (power.is_Integer and power > 0):
            return None
        monoms = _monoms(base, state)
        if not monoms:
            return None
        found.append((monoms, int(power)))
    return found


def _size(monoms: list) -> int:
    """The largest total degree of a polynomial's monomials."""
    return max((sum(m) for m in monoms), default=0)


def _monoms(expr: sp.Expr, state: Sequence[sp.Symbol]) -> list | tuple | None:
    """The monomials of a polynomial in the state, () for 0, None for anything else."""
    expr = sp.expand(expr)
    if expr == 0:
        return ()
    try:
        return sp.Poly(expr, *state).monoms()
    except sp.PolynomialError:
        return None


def _degree(monoms: list | tuple | None, w: Sequence[int]) -> tuple[int, ...] | None:
    """(weighted degree,) of a weighted-homogeneous polynomial given by its monomials,
    () for 0, None for anything else."""
    if monoms is None:
        return None
    if monoms == ():
        return ()
    degrees = {sum(a * b for a, b in zip(m, w, strict=True)) for m in monoms}
    return (degrees.pop(),) if len(degrees) == 1 else None


def candidates(vectors: Sequence[Vector]) -> list[Weights]:
    """The gradings tried for a state: the reference paper's CANDIDATES for (M, gamma);
    for any other, every choice of weight 1 or 2 per vector, fewest 2s first."""
    names = [v.name for v in vectors]
    if names == [v.name for v in mech.VECTORS]:
        return [as_weights(c) for c in CANDIDATES]
    choices = sorted(itertools.product((1, 2), repeat=len(names)), key=lambda c: (sum(c), c))
    return [tuple(zip(names, c, strict=True)) for c in choices]


def homogeneous_weights(
    field: Sequence[sp.Expr],
    vectors: Sequence[Vector] = mech.VECTORS,
    shorthands: Mapping[sp.Symbol, sp.Expr] = mech.SHORTHANDS,
    variables: Sequence[sp.Symbol] | None = None,
) -> Weights | None:
    """The first of the ``candidates`` under which ``field`` is weighted-homogeneous, or
    None."""
    state = list(variables) if variables is not None else [x for v in vectors for x in v.components]
    monomials = _Monomials(field, shorthands, state)  # shared by the candidates
    return next(
        (
            w
            for w in candidates(vectors)
            if monomials.shift(per_variable(w, vectors, state)) is not None
        ),
        None,
    )


def grading_note(
    field: Sequence[sp.Expr],
    weights: Weights | tuple[int, int],
    vectors: Sequence[Vector] = mech.VECTORS,
    shorthands: Mapping[sp.Symbol, sp.Expr] = mech.SHORTHANDS,
    variables: Sequence[sp.Symbol] | None = None,
) -> str:
    """What the ansatz means for these weights: "" for a homogeneous field, else the note
    that its degrees are coupled (stored with the search and printed by discover)."""
    if shift(field, weights, vectors, shorthands, variables) is not None:
        return ""
    named = ", ".join(f"{name}: {w}" for name, w in _named(weights, vectors))
    return (
        f"the vector field is not weighted-homogeneous for {named}: the ansatz is every "
        "monomial of weighted degree <= K, its degrees are coupled, and an integral's "
        "degree is that of its leading part"
    )


def _named(weights: Weights | tuple[int, int], vectors: Sequence[Vector]) -> Weights:
    given = dict(as_weights(weights))
    return tuple((v.name, given.get(v.name, v.weight)) for v in vectors)


def ring_degree(expr: sp.Expr, weight_of: Mapping[sp.Symbol, int]) -> int | None:
    """The weighted degree of an expression in a system's ring (``discovery.ring``): of its
    terms' polynomial parts in the state (each variable weighing ``weight_of[x]``),
    inverses weighing nothing and sqrt(b) half of b; None for an expression outside such
    a ring. Shorthands such as ``s`` count as constants (a known integral wherever it is
    one)."""
    # numerators expanded, denominators kept in factors (they weigh nothing)
    expr = sp.expand_mul(expanded(expr, list(weight_of)))
    state = set(weight_of)

    def weight(e: sp.Expr) -> int | None:
        if e in weight_of:
            return weight_of[e]
        if e.is_number or not (e.free_symbols & state):
            return 0
        if isinstance(e, sp.Mul):
            parts = [weight(f) for f in e.args]
            return None if None in parts else sum(parts)  # type: ignore[arg-type]
        if isinstance(e, sp.Pow) and e.exp.is_Rational:
            if e.exp < 0:
                return 0
            inner = [weight(t) for t in sp.Add.make_args(sp.expand(e.base))]
            return None if None in inner else int(max(inner) * e.exp)  # type: ignore[type-var]
        return None

    degrees = [weight(t) for t in sp.Add.make_args(expr)]
    return None if None in degrees else max(degrees, default=0)  # type: ignore[type-var]


def weights_by_symbol(
    weights: Weights | tuple[int, int], vectors: Sequence[Vector] = mech.VECTORS
) -> dict[sp.Symbol, int]:
    """Each state variable's weight, by symbol."""
    state = [x for v in vectors for x in v.components]
    return dict(zip(state, per_variable(weights, vectors), strict=True))
