"""The rigid-body fields of the exponent tests: the heavy top (Euler-Poisson) and the
free rigid body (Euler), from the package's own equations of motion."""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from registry.mathematics import mechanics as mech

STATE = mech.STATE
#: M: 1, gamma: 2, under which the heavy top is weighted-homogeneous.
HEAVY_WEIGHTS = (1, 1, 1, 2, 2, 2)


def heavy_top(inertia: Sequence[sp.Expr], r: Sequence[sp.Expr]) -> tuple[sp.Expr, ...]:
    """dM/dt = M x I^-1 M + gamma x r, dgamma/dt = gamma x I^-1 M (r: centre of mass)."""
    potential = sum(ri * g for ri, g in zip(r, mech.AXIS, strict=True))
    return tuple(sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0)))


def euler_top(inertia: Sequence[sp.Expr]) -> tuple[sp.Expr, ...]:
    """dM/dt = M x I^-1 M, the free rigid body."""
    return heavy_top(inertia, (0, 0, 0))[:3]


def energy(inertia: Sequence[sp.Expr], r: Sequence[sp.Expr] = (0, 0, 0)) -> sp.Expr:
    """H = M . I^-1 M / 2 + r . gamma."""
    potential = sum(ri * g for ri, g in zip(r, mech.AXIS, strict=True))
    return mech.hamiltonian(inertia, potential)
