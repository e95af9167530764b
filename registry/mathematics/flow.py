"""The calculus of a system's flow, for any state: derivatives, time derivatives, the
bracket's action and its Jacobi identity, the divergence of the field.

Every function takes the ``Dynamics`` of a case (``registry.dynamics``), so that the
same code serves the reference paper's six variables and any other phase space.
Derivatives are total derivatives on the state space: a shorthand (``s`` for M.gamma)
is differentiated by the chain rule, so an expression may keep it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from itertools import combinations

import sympy as sp

from ..dynamics import Dynamics
from . import symengine_bridge


def total_diff(
    expr: sp.Expr, var: sp.Symbol, shorthands: Mapping[sp.Symbol, sp.Expr] | None = None
) -> sp.Expr:
    """d expr / d var on the state space, each shorthand k = value differentiated by the
    chain rule (d/dvar picks up dvalue/dvar times d/dk)."""
    return total_gradient(expr, (var,), shorthands)[0]


def total_gradient(
    expr: sp.Expr,
    variables: Sequence[sp.Symbol],
    shorthands: Mapping[sp.Symbol, sp.Expr] | None = None,
) -> tuple[sp.Expr, ...]:
    """(``total_diff(expr, x, shorthands)`` for x in ``variables``): ``expr`` converted to
    symengine once, and its derivative by each shorthand taken once for all of them."""
    expr = sp.sympify(expr)
    used = [(k, v) for k, v in (shorthands or {}).items() if expr.has(k)]
    derivatives = symengine_bridge.partials(expr, [*variables, *(k for k, _ in used)])
    by_shorthand = derivatives[len(variables) :]
    out = []
    for var, d in zip(variables, derivatives, strict=False):
        for (_, value), dk in zip(used, by_shorthand, strict=True):
            d += sp.diff(value, var) * dk
        out.append(d)
    return tuple(out)


def gradient(dynamics: Dynamics, expr: sp.Expr) -> tuple[sp.Expr, ...]:
    """(d expr / d x_i) over the state variables."""
    return total_gradient(expr, dynamics.variables, dynamics.shorthands)


def along(field: Sequence[sp.Expr], grad: Sequence[sp.Expr]) -> sp.Expr:
    """grad . X: the rate of change of a function with gradient ``grad`` along X."""
    return sp.Add(*(g * x for g, x in zip(grad, field, strict=True) if g != 0))


def time_derivative(dynamics: Dynamics, expr: sp.Expr) -> sp.Expr:
    """d expr / dt = grad expr . X along the system's flow."""
    return along(dynamics.field, gradient(dynamics, expr))


def bracket_gradient(dynamics: Dynamics, expr: sp.Expr) -> tuple[sp.Expr, ...]:
    """Pi grad f, by component: zero exactly when f is a Casimir of the bracket."""
    if dynamics.bracket is None:
        raise ValueError("the system has no bracket")
    return apply_bivector(dynamics.bracket, gradient(dynamics, expr))


def apply_bivector(pi: sp.MatrixBase, vector: Sequence[sp.Expr]) -> tuple[sp.Expr, ...]:
    """Pi v, skipping the zero entries of Pi (most of them, for the brackets of mechanics)."""
    n = pi.shape[0]
    return tuple(
        sp.Add(*(pi[i, j] * vector[j] for j in range(n) if pi[i, j] != 0 and vector[j] != 0))
        for i in range(n)
    )


def hamiltonian_field(
    pi: sp.MatrixBase, h: sp.Expr, variables: Sequence[sp.Symbol], shorthands=None
) -> tuple[sp.Expr, ...]:
    """Pi grad H: the vector field the bracket generates from H (dx_i/dt = {x_i, H})."""
    return apply_bivector(pi, total_gradient(h, variables, shorthands))


def jacobiator(
    dynamics: Dynamics, gradient_of: Callable[[sp.Expr], Sequence[sp.Expr]] | None = None
) -> dict[tuple[int, int, int], sp.Expr]:
    """The components i < j < k of the Jacobi identity of the bracket Pi:
    Pi^{li} d_l Pi^{jk} + Pi^{lj} d_l Pi^{ki} + Pi^{lk} d_l Pi^{ij}, summed over l. All
    vanish exactly when Pi is a Poisson tensor; for the six variables of e(3) this is the
    reference paper's Sec. 3 (20 components). ``gradient_of`` gives the gradient of an
    entry (default ``gradient``; a case's memo shares the gradients of equal entries)."""
    pi = dynamics.bracket
    if pi is None:
        raise ValueError("the system has no bracket")
    n = pi.shape[0]
    grad_of = gradient_of or (lambda expr: gradient(dynamics, expr))
    grads = {(a, b): grad_of(pi[a, b]) for a in range(n) for b in range(n) if pi[a, b] != 0}
    zero = (sp.Integer(0),) * n

    def term(i: int, j: int, k: int) -> sp.Expr:
        g = grads.get((j, k), zero)
        return sp.Add(*(pi[m, i] * g[m] for m in range(n) if pi[m, i] != 0 and g[m] != 0))

    return {
        (i, j, k): term(i, j, k) + term(j, k, i) + term(k, i, j)
        for i, j, k in combinations(range(n), 3)
    }


def divergence(dynamics: Dynamics, density: sp.Expr = sp.S.One) -> sp.Expr:
    """div(rho X) = sum_i d(rho X_i)/dx_i: zero exactly when rho is the density of an
    invariant measure of the flow (Liouville's equation)."""
    return sp.Add(
        *(
            total_diff(density * x, v, dynamics.shorthands)
            for v, x in zip(dynamics.variables, dynamics.field, strict=True)
        )
    )
