"""Translations of the parameters that leave a field unchanged, and the field with one
parameter per translation set to 0.

A constant vector v with sum_j v_j dF/dp_j = 0 for every component F keeps the field
the same under p -> p + c v for every c: a potential sum a_i gamma_i**2 / 2 enters the
equations only through the differences a_i - a_j, gamma . gamma being a Casimir.
Everything computed from the field alone (its balances, exponents, the Painlevé test)
is then the same at p and at p' = p - (p_k / v_k) v, where p'_k = 0: the analysis runs
with one parameter fewer and its results are written back with
p'_j = p_j - (p_k / v_k) v_j. Over Q(p'), generic p' are the images of generic p.

>>> a1, a2, a3, x = sp.symbols("a1 a2 a3 x")
>>> r = reduction([(a1 - a3) * x, (a2 - a3) * x**2], (a1, a2, a3))
>>> r.field, [str(p) for p in r.parameters], r.removed
((a1*x, a2*x**2), ['a1', 'a2'], (a3,))
>>> {str(k): v for k, v in r.back.items()}
{'a1': a1 - a3, 'a2': a2 - a3}
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Reduction:
    """The field with the ``removed`` parameters set to 0 (one per independent
    translation), its remaining ``parameters`` (fresh symbols of the same names, without
    sign assumptions: a1 - a3 need not be positive), and ``back``, each of them as the
    combination of the original parameters it stands for."""

    field: tuple[sp.Expr, ...]
    parameters: tuple[sp.Symbol, ...]
    removed: tuple[sp.Symbol, ...]
    back: dict[sp.Symbol, sp.Expr]
    translations: tuple[tuple[sp.Expr, ...], ...]

    def written_back(self, expr: sp.Expr) -> sp.Expr:
        """An expression of the reduced parameters in the original ones."""
        return sp.sympify(expr).xreplace(self.back)


def translations(
    field: Sequence[sp.Expr], parameters: Sequence[sp.Symbol], *, seed: int = 0
) -> list[list]:
    """A basis of the constant vectors v (rational entries) with sum_j v_j dF/dp_j = 0
    for every component F of ``field`` (rational functions of the state and the
    parameters), in reduced echelon form from the last parameter: each vector has a 1 at
    a parameter where the others have 0, the last such parameter possible. Candidates
    come from the derivatives at random rational points (one linear equation in v per
    component and point); each is kept only if the derivative along it is proven zero
    exactly (a basis where every candidate is; else none)."""
    parameters = list(parameters)
    if len(parameters) < 2:
        return []
    exprs = [sp.sympify(f) for f in field]
    symbols = sorted(set().union(*(f.free_symbols for f in exprs)), key=str)
    derivatives = [[f.diff(p) for p in parameters] for f in exprs]
    rng = random.Random(seed)
    rows: list[list] = []
    for _ in range(len(parameters) + 2):
        rows.extend(_at_random_point(derivatives, symbols, rng))
    kernel = sp.Matrix(rows).nullspace()
    if not kernel:
        return []
    # echelon form from the last parameter: the pivots are the parameters set to 0
    basis = sp.Matrix.hstack(*kernel).T[:, ::-1].rref()[0][:, ::-1]
    vectors = [list(basis.row(i)) for i in range(basis.rows) if any(basis.row(i))]
    for v in vectors:
        for row in derivatives:
            along = sum((c * d for c, d in zip(v, row, strict=True) if c != 0), sp.Integer(0))
            if sp.cancel(sp.together(along)) != 0:
                return []
    return vectors


def _at_random_point(derivatives, symbols, rng: random.Random) -> list[list]:
    """The derivatives' values at a random rational point where every one is defined."""
    for _ in range(20):
        point = {s: sp.Rational(rng.randint(-60, 60), rng.randint(1, 9)) for s in symbols}
        values = [[sp.sympify(d).xreplace(point) for d in row] for row in derivatives]
        if all(v.is_Rational for row in values for v in row):
            return values
    return []


def reduction(field: Sequence[sp.Expr], parameters: Sequence[sp.Symbol]) -> Reduction | None:
    """The field with one parameter per independent translation (``translations``) set
    to 0, or None where no translation keeps it."""
    basis = translations(field, parameters)
    if not basis:
        return None
    parameters = list(parameters)
    pivots = [max(j for j, c in enumerate(v) if c != 0) for v in basis]
    removed = [parameters[k] for k in pivots]
    kept = [p for p in parameters if p not in removed]
    fresh = {p: sp.Symbol(p.name, real=True) if p.is_real else sp.Symbol(p.name) for p in kept}
    # p'_j = p_j - sum_i p_(k_i) v_i[j]: v_i has 1 at its own pivot and 0 at the others
    back = {
        fresh[p]: p - sum((parameters[k] * v[j] for v, k in zip(basis, pivots, strict=True)), 0)
        for j, p in enumerate(parameters)
        if p in fresh
    }
    at_zero = {p: 0 for p in removed} | fresh
    reduced = tuple(sp.sympify(f).xreplace(at_zero) for f in field)
    return Reduction(
        reduced,
        tuple(fresh[p] for p in kept),
        tuple(removed),
        back,
        tuple(tuple(sp.sympify(c) for c in v) for v in basis),
    )
