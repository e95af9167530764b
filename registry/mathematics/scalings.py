"""The scalings of a family: weights of the state and of the parameters under which its
vector field is weighted-homogeneous up to a scaling of time.

With weights w_x of the state variables, w_p of the parameters and a shift k, the field
is *covariant* when every term of dx_i/dt has weight w_{x_i} + k: then
x -> lambda^w_x x, p -> lambda^w_p p, t -> lambda^-k t maps solutions of the member p to
solutions of the member lambda^w_p p, for every lambda != 0, complex ones included. The
heavy top with centre of mass r has two: (M: 1, gamma: 2, r: 0) and
(M: 0, gamma: 1, r: -1). A polynomial ansatz is closed under any diagonal scaling of
the state, so its linear system at lambda^w_p p is the one at p with rows and columns
multiplied by powers of lambda: ranks, kernels and counts of integrals are the same.
Every set of parameter values an integral search finds (a rank-drop locus, a special
set, each of their irreducible components) is therefore a cone under these scalings,
and a component is decided by its slice where a parameter of non-zero weight is 1
(``discovery.algebraic_points``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import sympy as sp


def covariant_weights(
    field: Sequence[sp.Expr],
    state: Sequence[sp.Symbol],
    parameters: Sequence[sp.Symbol],
    invariant: Sequence[sp.Expr] = (),
) -> list[dict[sp.Symbol, int]]:
    """A basis of the parameters' weights of the scalings under which ``field`` (dx/dt for
    ``state``) is covariant (module docstring) and each expression of ``invariant`` (a
    level set's equations, the known integrals) is weighted-homogeneous; each basis
    vector as integer weights of ``parameters`` (a vector that leaves every parameter
    fixed is left out). Empty when a term is not a product of powers of the state and
    the parameters (a radical of a sum, a function): no scaling is claimed then."""
    state, parameters = list(state), list(parameters)
    n, m = len(state), len(parameters)
    extra = len(invariant)
    # unknowns: w_x (n), w_p (m), k, and one degree per invariant expression
    size = n + m + 1 + extra
    rows: list[list[sp.Rational]] = []

    def exponents(term: sp.Expr) -> list[sp.Rational] | None:
        row = [sp.Integer(0)] * size
        for base, e in term.as_powers_dict().items():
            if base.is_number:
                continue
            if not e.is_Rational:
                return None
            if base in state:
                row[state.index(base)] += e
            elif base in parameters:
                row[n + parameters.index(base)] += e
            else:
                return None
        return row

    for i, f in enumerate(field):
        for term in sp.Add.make_args(sp.expand(f)):
            if term == 0:
                continue
            row = exponents(term)
            if row is None:
                return []
            row[i] -= 1
            row[n + m] -= 1
            rows.append(row)
    for j, expr in enumerate(invariant):
        for term in sp.Add.make_args(sp.expand(expr)):
            if term == 0:
                continue
            row = exponents(term)
            if row is None:
                return []
            row[n + m + 1 + j] -= 1
            rows.append(row)
    if not rows:
        return []
    basis = sp.Matrix(rows).nullspace()
    out = []
    for vector in basis:
        scale = math.lcm(*(int(sp.fraction(c)[1]) for c in vector))
        weights = {p: int(vector[n + k] * scale) for k, p in enumerate(parameters)}
        if any(weights.values()):
            out.append(weights)
    return out


def slicing_variables(
    weights: Sequence[Mapping[sp.Symbol, int]], candidates: Sequence[sp.Symbol]
) -> list[sp.Symbol]:
    """The most ``candidates`` (in their order) that scalings can set to 1 at once: those
    whose columns of the weight matrix are independent."""
    chosen: list[sp.Symbol] = []
    for x in candidates:
        trial = [*chosen, x]
        matrix = sp.Matrix([[w.get(v, 0) for v in trial] for w in weights])
        if weights and matrix.rank() == len(trial):
            chosen = trial
    return chosen
