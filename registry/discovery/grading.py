"""The grading of a search: weights of M and gamma under which the vector field is
weighted-homogeneous, if there are any.

With weights (w_M, w_gamma), the field is homogeneous of shift d when every monomial of
dx_i/dt has weight w_i + d: then d/dt maps each weighted degree to one other, the
ansatz's system splits into independent blocks by degree, and an integral's homogeneous
parts are integrals of their own. The reference paper's e(3) systems with a quadratic
kinetic energy and a potential linear in gamma are homogeneous for M: 1, gamma: 2; a
quadratic potential, and the bracket of so(4) and so(3,1) (kappa != 0), need equal
weights. Where no grading makes the field homogeneous (a Hamiltonian with terms of
several degrees, such as Kovalevskaya's on so(4)), the ansatz is still every monomial of
weighted degree <= K, but the degrees are coupled: an integral found at degree K may
have parts of every lower degree, none of them conserved alone, and the blocks of the
system are no longer separated by degree. The search decides in the same way; only the
meaning of "degree" is that of the integral's leading part.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from ..mathematics import mechanics as mech

#: The gradings tried, in order of preference (the survey's usual ones first).
CANDIDATES: tuple[tuple[int, int], ...] = ((1, 2), (1, 1), (2, 1))


def shift(field: Sequence[sp.Expr], weights: tuple[int, int]) -> int | None:
    """d such that every monomial of dx_i/dt has weight w_i + d, or None where there is
    none (a field that is not weighted-homogeneous for ``weights``, or not rational in
    the state)."""
    w = (weights[0],) * 3 + (weights[1],) * 3
    shifts: set[int] = set()
    for wi, x in zip(w, field, strict=True):
        numer, denom = sp.fraction(sp.together(sp.sympify(x).subs(mech.s, mech.S_VALUE)))
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


def _degree(expr: sp.Expr, w: Sequence[int]) -> tuple[int, ...] | None:
    """(weighted degree,) of a weighted-homogeneous polynomial in the state, () for 0,
    None for anything else."""
    expr = sp.expand(expr)
    if expr == 0:
        return ()
    try:
        poly = sp.Poly(expr, *mech.STATE)
    except sp.PolynomialError:
        return None
    degrees = {sum(a * b for a, b in zip(m, w, strict=True)) for m in poly.monoms()}
    return (degrees.pop(),) if len(degrees) == 1 else None


def homogeneous_weights(field: Sequence[sp.Expr]) -> tuple[int, int] | None:
    """The first of CANDIDATES under which ``field`` is weighted-homogeneous, or None."""
    return next((w for w in CANDIDATES if shift(field, w) is not None), None)


def grading_note(field: Sequence[sp.Expr], weights: tuple[int, int]) -> str:
    """What the ansatz means for these weights: "" for a homogeneous field, else the note
    that its degrees are coupled (stored with the search and printed by discover)."""
    if shift(field, weights) is not None:
        return ""
    return (
        f"the vector field is not weighted-homogeneous for M: {weights[0]}, gamma: "
        f"{weights[1]}: the ansatz is every monomial of weighted degree <= K, its degrees "
        "are coupled, and an integral's degree is that of its leading part"
    )
