"""One solution of a match's equations by propagation, radicals at the end."""

from __future__ import annotations

import sympy as sp
from sympy.polys.rings import PolyRing

from registry.discovery.identification.equation_solver import Problem, solve


def test_linear_equations_with_unit_coefficients_are_solved_in_turn():
    ring = PolyRing("A C tau lam", sp.QQ)
    a, c, tau, lam = ring.gens
    # tau/2 = lam/A, tau = lam/C (Kovalevskaya's inverse inertia as a general body's)
    problem = Problem(ring, nonzero=frozenset({0, 1, 2, 3}), defaults={2: (1,), 3: (1,)})
    found = solve([tau * a - 2 * lam, tau * c - lam], problem)
    values = {str(k): v for k, v in found.items()}
    assert sp.simplify(values["A"] - 2 * values["C"]) == 0


def test_a_positive_unknown_forced_to_zero_is_a_contradiction():
    ring = PolyRing("a b", sp.QQ)
    a, b = ring.gens
    problem = Problem(ring, nonzero=frozenset({0}), positive=frozenset({0}))
    assert solve([a + b**2 - b**2], problem) is None
    assert solve([a + 3], problem) is None


def test_a_rotation_is_finished_with_radicals():
    x = sp.Symbol("x")
    ring = PolyRing("c s r", sp.QQ.frac_field(x))
    c, s, r = ring.gens
    problem = Problem(ring, nonzero=frozenset({2}))
    found = solve([r * c - 1, r * s - ring.domain.convert(x), c**2 + s**2 - 1], problem)
    values = {str(k): v for k, v in found.items()}
    assert sp.simplify(values["r"] ** 2 - (1 + x**2)) == 0
