"""Parameter conditions under which a failed identity holds: the coefficients of the
residual's normal form, solved for the parameters, each branch re-checked."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.domain import Domain
from registry.mathematics.mechanics import M1, gamma1, gamma2, gamma3
from registry.mathematics.parameter_conditions import equations_text, parameter_conditions

N = sp.Symbol("N", real=True)
k = sp.Symbol("k", positive=True)


def test_a_residual_proportional_to_a_parameter_holds_when_it_is_zero():
    found = parameter_conditions({"r": N * gamma1 * M1}, Domain(parameters=(N,)))
    assert found.branches == ({N: 0},)
    assert equations_text(found.branches[0], str) == ["N = 0"]


def test_branches_that_break_an_assumption_are_dropped():
    # k = 0 would make the residual vanish, but k is positive
    found = parameter_conditions({"r": k * gamma1}, Domain(parameters=(k,)))
    assert found.branches == ()
    assert "no admissible parameter values" in found.reason


def test_a_branch_that_zeroes_a_protected_expression_is_dropped():
    a = sp.Symbol("a", real=True)
    found = parameter_conditions({"r": a * gamma2}, Domain(parameters=(a,)), protected=[a])
    assert found.branches == ()


def test_several_coefficients_give_one_system():
    a, b = sp.symbols("a b", real=True)
    residual = (a - b) * gamma1 + (a - 2) * gamma2 * gamma3
    found = parameter_conditions({"r": residual}, Domain(parameters=(a, b)))
    assert found.branches == ({a: 2, b: 2},)


def test_where_no_conditions_are_sought_the_reason_says_why():
    assert "no parameters" in parameter_conditions({"r": gamma1}, Domain()).reason
    phi = sp.Function("phi")
    family = Domain(parameters=(N,), functions={"phi": (phi, (gamma1, gamma2, gamma3))})
    assert "families" in parameter_conditions({"r": N * gamma1}, family).reason
    found = parameter_conditions({"r": gamma1 + 1}, Domain(parameters=(N,)))
    assert found.branches == () and "no parameter values" in found.reason
