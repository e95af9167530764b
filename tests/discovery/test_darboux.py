"""Darboux polynomials (``registry/discovery/darboux.py``): the general cofactor ranges
over the Newton polytope of the field, and only its top weight is searched where the
field is not weighted-homogeneous, which the search says."""

from __future__ import annotations

from pathlib import Path

import sympy as sp

from registry.discovery.ansatz import count_monomials
from registry.discovery.darboux import cofactor_monomials, general_cofactor
from registry.discovery.search import _system, search_options
from registry.language.casefile import load_case
from registry.mathematics import mechanics as mech
from registry.mathematics.case_mechanics import CaseMechanics


def cofactor_of(options, case, undecided=None):
    """The general cofactor of a case's field and its unknown coefficients."""
    m = CaseMechanics(case)
    system = _system(options, m, [], symmetries=False)[0]
    return general_cofactor(system, options, m, undecided)


def _weight(monomial) -> int:
    return sum(a * w for a, w in zip(monomial, (1, 1, 1, 2, 2, 2), strict=True))


def _polynomial_field(options, case):
    system = _system(options, CaseMechanics(case), [], symmetries=False)[0]
    return system.field, system.n, system.weights


def test_a_cofactor_ranges_over_the_newton_polytope_of_the_field():
    """Newton(K) lies in conv{exps(m) - e_i : m in X_i}: for the heavy top (homogeneous
    for M: 1, gamma: 2) that is M1, M2, M3, the cofactors' weight 1; a torque with terms
    of several degrees ((gamma3^2 + c0)(1 + s^2)) allows cofactors of several weights,
    far fewer monomials than every one of the largest weight; only that weight is
    searched, and the search says that the others are not."""
    root = Path(__file__).resolve().parents[2] / "data/cases"
    hess = load_case(root / "heavy-top/hess-1890-heavy-top.toml")
    cofactor, coefficients = cofactor_of(search_options(hess, degree=1, relations=True), hess)
    assert sp.Poly(cofactor, *mech.STATE).monoms() == [
        (1, 0, 0, 0, 0, 0),
        (0, 1, 0, 0, 0, 0),
        (0, 0, 1, 0, 0, 0),
    ]
    axis = load_case(root / "axis-torque.toml")
    options = search_options(axis, degree=2, relations=True)
    allowed = cofactor_monomials(*_polynomial_field(options, axis))
    weights = {_weight(m) for m in allowed}
    assert len(weights) > 1 and 0 in weights  # a constant part, and several weights
    assert len(allowed) < count_monomials(max(weights), (1, 1, 1, 2, 2, 2)) // 10
    undecided: list[str] = []
    cofactor, coefficients = cofactor_of(options, axis, undecided)
    top = [m for m in allowed if _weight(m) == max(weights)]
    assert len(coefficients) == len(top) < len(allowed)
    assert undecided and "are not searched" in undecided[0]
