"""A component with no rational parametrisation, decided at its points: sliced by the
family's scalings, its extra integrals counted modulo a prime where it has a root."""

from __future__ import annotations

import random

import sympy as sp

from registry.discovery.algebraic_points import decide
from registry.discovery.components import resolve
from registry.discovery.known import known_generators
from registry.discovery.search import _scalings, _system, search_options
from registry.discovery.splitting import AlgebraicSet
from registry.mathematics.case_mechanics import CaseMechanics
from tests.helpers.samples import family


def heavy_top(degree=4):
    case = family("heavy-top-five")
    p = case.parameters
    free = [p[n] for n in ("b", "c", "x0", "y0", "z0")]
    options = search_options(case, degree=degree, free=[str(f) for f in free])
    m = CaseMechanics(case)
    system, params = _system(options, m, free)
    known, _ = known_generators(m, system)
    return p, free, system, params, known, _scalings(m, system, known, params, options)


def test_lines_over_q_sqrt_30_are_cut_to_points_and_carry_nothing_more():
    p, free, system, params, known, weights = heavy_top()
    assert weights and all(w[p["x0"]] == w[p["z0"]] != 0 for w in weights)
    values = {p["y0"]: sp.Integer(0), p["b"]: sp.Rational(19, 28)}
    found = AlgebraicSet(
        values, (p["c"] - sp.Rational(10, 7), 49 * p["x0"] ** 2 - 30 * p["z0"] ** 2)
    )
    (piece,) = resolve(found, free).pieces
    decision = decide(piece, system, known, 0, weights, random.Random(1))
    assert decision.undecided == [] and decision.points == []
    assert len(decision.decided) == 1 and "30" in decision.decided[0]
    # the part where the slicing parameter is 0 is handed back to be resolved again
    assert decision.further and all(
        p["x0"] in f.equations or p["z0"] in f.equations for f in decision.further
    )


def test_a_point_with_more_integrals_modulo_a_prime_is_handed_back_with_exact_values():
    # Kovalevskaya's point C = 1/2 is u = sqrt(2) in the u-family
    case = family("heavy-top-u-squared")
    u = case.parameters["u"]
    options = search_options(case, degree=4, free=["u"])
    m = CaseMechanics(case)
    system, params = _system(options, m, [u])
    known, _ = known_generators(m, system)
    (piece,) = resolve(AlgebraicSet({}, (u**2 - 2,)), [u]).pieces
    decision = decide(piece, system, known, 0, [], random.Random(2))
    assert decision.decided == [] and decision.undecided == []
    assert decision.points == [{u: sp.sqrt(2)}]  # the positive root only (u positive)
