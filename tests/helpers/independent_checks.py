"""Checks of the registry's results that do not use the registry's own zero test:
evaluation at random points with 50 digits, for the tests of corrections and families."""

import random

import sympy as sp

from registry.mathematics import mechanics as mech


def random_point(case, rng):
    """A random real point (50 digits) away from the singular sets, parameters included."""
    point = {}
    for sym in case.parameters.values():
        point[sym] = sp.Float(
            rng.uniform(0.5, 2.0) * (1 if sym.is_positive else rng.choice([-1, 1])), 50
        )
    for v in mech.STATE:
        point[v] = sp.Float(rng.uniform(0.3, 1.3) * rng.choice([-1, 1]), 50)
    point[mech.s] = sum(point[m] * point[g] for m, g in zip(mech.MOMENTUM, mech.AXIS, strict=True))
    return point


def vanishes_numerically(case, exprs, points=5, seed=7):
    rng = random.Random(seed)
    for _ in range(points):
        point = random_point(case, rng)
        for e in exprs:
            value = sp.N(sp.sympify(e).xreplace(point), 50)
            if abs(value) > sp.Float("1e-30"):
                return False
    return True


def independent_of_c1(case, expr) -> bool:
    """Some d/dM_i of ``expr`` is not zero: ``expr`` is not a function of gamma alone
    (as C1 = |gamma|^2/2 is, which satisfies every Casimir system trivially)."""
    return not vanishes_numerically(case, [mech.total_diff(expr, v) for v in mech.MOMENTUM])


def casimir_residual(case, torque, expr):
    pi = mech.poisson_tensor(torque)
    return list(pi * sp.Matrix(mech.gradient(expr)))


def jacobi_residual(torque):
    return list(mech.jacobiator(mech.poisson_tensor(torque)).values())
