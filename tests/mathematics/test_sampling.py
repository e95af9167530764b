"""Sample points of a domain: exact, on the level set, respecting the parameters'
assumptions and the nonzero conditions; a family's functions made concrete."""

import random

import sympy as sp

from registry.mathematics.certified_evaluation import evaluate
from registry.mathematics.domain import Domain
from registry.mathematics.mechanics import AXIS, S_VALUE, gamma1, gamma2, gamma3, s
from registry.mathematics.sampling import (
    concrete_functions,
    sample_point,
    sample_points,
    substitute_functions,
)

k = sp.Symbol("k", positive=True)
SPHERE = gamma1**2 + gamma2**2 + gamma3**2 - 1


def test_sample_points_respect_nonzero_conditions_and_level_sets():
    domain = Domain(parameters=(k,), nonzero=(gamma3,), on=(SPHERE,))
    points = list(sample_points(domain, 5, seed=3))
    assert len(points) == 5
    for point in points:
        assert point[gamma3] != 0 and point[k] > 0
        assert sp.simplify(SPHERE.xreplace(point)) == 0
        assert point[s] == sp.expand(S_VALUE.xreplace(point))


def test_a_point_keeps_the_radicals_of_the_residual_exact():
    root = sp.sqrt(gamma1**2 + gamma2**2 + gamma3**2)
    point = sample_point(Domain(), random.Random(1), {}, [(root.base, 2)])
    assert evaluate(root, point).is_exact


def test_a_familys_functions_become_polynomials_and_their_derivatives_follow():
    phi = sp.Function("phi")
    functions = {"phi": (phi, AXIS)}
    concrete = concrete_functions(functions, random.Random(2))
    expr = sp.diff(phi(*AXIS), gamma1) + phi(*AXIS)
    value = substitute_functions(expr, concrete)
    instance = concrete["phi"](*AXIS)
    assert sp.expand(value - (sp.diff(instance, gamma1) + instance)) == 0
    assert sp.Poly(instance, *AXIS).total_degree() <= 2
    assert substitute_functions(S_VALUE, concrete) is S_VALUE  # nothing to replace


def test_derivatives_of_concrete_functions_are_those_of_sympy():
    f = sp.Function("f")
    expr = (
        k * sp.Derivative(f(gamma1, gamma2, gamma3), gamma1)
        + sp.Derivative(f(gamma1, gamma2, gamma3), gamma2, 2)
        + gamma3 * sp.Derivative(f(gamma1, gamma2, gamma3), gamma1, gamma3)
    )
    for seed in range(3):
        funcs = concrete_functions({"f": (f, (gamma1, gamma2, gamma3))}, random.Random(seed))
        lam = funcs["f"]
        expected = expr.subs(f(gamma1, gamma2, gamma3), lam(gamma1, gamma2, gamma3)).doit()
        assert sp.expand(substitute_functions(expr, funcs) - expected) == 0
    # a choice with a float coefficient keeps it (never made rational)
    floaty = {"f": sp.Lambda((gamma1, gamma2, gamma3), sp.Float(0.5) * gamma1**2 + k * gamma2)}
    got = substitute_functions(sp.Derivative(f(gamma1, gamma2, gamma3), gamma1), floaty)
    assert got == sp.Float(1.0) * gamma1 and got.has(sp.Float)
