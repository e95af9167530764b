"""Weights under which a polynomial field has a whole leading part, found by a
mixed-integer program: the default for a state whose own weights leave a component's
leading part empty.

The leading part under weights w is made of the terms of dx_i/dt with weight w_i + 1,
every other term having a smaller one (``weighted``). A component that is not zero but
has no such term drops out of the leading part, and the balances then lose the variable
it moves: under equal weights Hénon and Heiles's dx/dt = px is of lower order than
dpx/dt = -2xy, and the leading part has no balance at all. The weights sought here
(one integer per vector, from 1 to ``LARGEST``) keep a term of weight w_i + 1 in every
component that is not zero and none above it, with as many leading terms as possible
(the dominant balances of a physicist's analysis: x, y: 2 and px, py: 3 for Hénon and
Heiles, where (1, 2, 2, 3) also qualifies but drops x² from dpy/dt), then the smallest
weights. As a program in the weights w and a 0/1 mark z_t per term t (exponents e_t in
component i):

    e_t . w - w_i <= 1                      every term at most leading,
    e_t . w - w_i >= 1 - M (1 - z_t)        a marked term is leading,
    sum of z_t over component i >= 1        every component that is not zero keeps one,

maximising the marks, then minimising the weights (scipy's ``milp``, HiGHS).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import sympy as sp

from ..dynamics import Vector, Weights

#: The largest weight a vector is given.
LARGEST = 6


def leading_weights(
    field: Sequence[sp.Expr],
    vectors: Sequence[Vector],
    variables: Sequence[sp.Symbol],
    *,
    most: bool = False,
) -> Weights | None:
    """The weights of the module doc for dx/dt = ``field`` (listed in the order of
    ``variables``), or None where none exist up to ``LARGEST`` or the field is not a
    polynomial in the state. With ``most``, where no weights keep every component, those
    that keep the most (then the most leading terms, then the smallest): Rössler's
    dx/dt = -y - z, dz/dt = b + xz - cz under x: 1, y, z: 2, where dy/dt = x + ay cannot
    lead (it would need w_x = w_y + 1 and w_x = 1)."""
    # imported here: scipy.optimize takes half a second, and most states never get here
    from scipy.optimize import Bounds, LinearConstraint, milp

    index = {x: k for k, v in enumerate(vectors) for x in v.components}
    if set(variables) != set(index):
        return None
    terms = _terms(field, variables)
    if terms is None or not any(terms):
        return None
    n = len(vectors)
    # each row: the coefficients of w in e_t . w - w_i, and the component i
    rows, owners = [], []
    for i, monomials in enumerate(terms):
        for exponents in monomials:
            row = np.zeros(n)
            for x, e in zip(variables, exponents, strict=True):
                row[index[x]] += e
            row[index[variables[i]]] -= 1
            rows.append(row)
            owners.append(i)
    m = len(rows)
    big = LARGEST * (max(sum(e) for t in terms for e in t) + 1) + 2
    w_part = np.array(rows)
    marks = np.eye(m)
    # e_t . w - w_i <= 1, and e_t . w - w_i - M z_t >= 1 - M (below)
    row_of = {i: r for r, i in enumerate(sorted(set(owners)))}  # a row per non-zero component
    c = len(row_of)
    # sum of z_t over component i >= 1 (with ``most``: >= k_i, a 0/1 mark of a kept one)
    keep = np.zeros((c, n + m + c))
    for t, owner in enumerate(owners):
        keep[row_of[owner], n + t] = 1
    if most:
        keep[:, n + m :] = -np.eye(c)
    kept = LinearConstraint(keep, 0 if most else 1, np.inf)
    one = LinearConstraint(np.concatenate([np.zeros(n + m), np.ones(c)]), 1 if most else 0, c)
    term = n * LARGEST + 1  # a leading term outweighs any weights
    cost = np.concatenate(
        [np.ones(n), -term * np.ones(m), -(m * term + n * LARGEST + 1) * np.ones(c)]
    )
    pad = np.zeros((m, c))
    upper = LinearConstraint(np.hstack([w_part, np.zeros((m, m)), pad]), -np.inf, 1)
    lower = LinearConstraint(np.hstack([w_part, -big * marks, pad]), 1 - big, np.inf)
    bounds = Bounds(np.concatenate([np.ones(n), np.zeros(m + c)]),
                    np.concatenate([LARGEST * np.ones(n), np.ones(m + c)]))  # fmt: skip
    found = milp(
        cost,
        constraints=[upper, lower, kept, one],
        integrality=np.ones(n + m + c),
        bounds=bounds,
    )
    if not found.success:
        return None
    weights = [round(v) for v in found.x[:n]]
    if not _leading(terms, variables, index, weights, every=not most):  # pragma: no cover
        return None  # the solver's rounding checked exactly
    return tuple((v.name, w) for v, w in zip(vectors, weights, strict=True))


def _terms(field: Sequence[sp.Expr], variables: Sequence[sp.Symbol]):
    """The exponent tuples of each component's monomials in the state (none for a zero
    component), or None where a component is not a polynomial in it."""
    found = []
    for f in field:
        try:
            poly = sp.Poly(sp.expand(f), *variables)
        except sp.PolynomialError:
            return None
        found.append([] if poly.is_zero else [m for m in poly.monoms()])
    return found


def _leading(terms, variables, index, weights, *, every: bool) -> bool:
    """Exactly: no term above weight w_i + 1, and one of it in every non-zero component
    (``every``), or in one at least."""
    tops = []
    for i, monomials in enumerate(terms):
        if not monomials:
            continue
        own = weights[index[variables[i]]]
        shifts = [
            sum(e * weights[index[x]] for x, e in zip(variables, m, strict=True)) - own
            for m in monomials
        ]
        if max(shifts) > 1:
            return False
        tops.append(max(shifts) == 1)
    return all(tops) if every else any(tops)
