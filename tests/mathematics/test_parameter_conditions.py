"""Parameter conditions under which a failed identity holds: the coefficients of the
residual's normal form, solved for the parameters, each branch re-checked."""

from __future__ import annotations

import itertools
import random

import pytest
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


def test_a_residual_with_two_independent_factors_gives_both_branches():
    # 2*nu*(k*M1*gamma2 + k**2*gamma3): nu = 0 saves the claim as well as k = 0
    nu, kk = sp.symbols("nu k", real=True)
    residual = 2 * nu * (kk * M1 * gamma2 + kk**2 * gamma3)
    found = parameter_conditions({"r": residual}, Domain(parameters=(nu, kk)))
    assert found.branches == ({kk: 0}, {nu: 0})


def test_a_branch_is_kept_whole_and_its_special_cases_dropped():
    # nu*k*(a - b) and nu*(k + a): nu = 0 (free a, b, k) is a component that sympy.solve
    # on the whole system misses; k = a = 0 and a = b = -k are the two others
    nu, kk, a, b = sp.symbols("nu k a b", real=True)
    residual = nu * kk * (a - b) * M1 + nu * (kk + a) * gamma2 * gamma3
    found = parameter_conditions({"r": residual}, Domain(parameters=(a, b, kk, nu)))
    assert found.branches == ({nu: 0}, {a: 0, kk: 0}, {a: -kk, b: -kk})


def test_a_factor_that_cannot_vanish_by_assumption_splits_off_nothing():
    a = sp.Symbol("a", real=True)
    found = parameter_conditions({"r": k * (a - 1) * gamma1}, Domain(parameters=(a, k)))
    assert found.branches == ({a: 1},)


def _affine_rows(equations, params):
    """The augmented matrix [A | -b] of affine equations A p + b = 0."""
    rows = []
    for eq in equations:
        poly = sp.Poly(sp.expand(eq), *params)
        assert poly.total_degree() <= 1, eq
        rows.append([poly.coeff_monomial(p) for p in params] + [poly.coeff_monomial(1)])
    return sp.Matrix(rows)


def _inside(small, big, params):
    """Whether the (non-empty) affine subspace ``small`` lies in ``big`` (linear algebra:
    every equation of ``big`` is a combination of those of ``small``)."""
    s, b = _affine_rows(small, params), _affine_rows(big, params)
    return s.rank() == s.col_join(b).rank()


def _consistent(equations, params):
    m = _affine_rows(equations, params)
    return m[:, :-1].rank() == m.rank()


@pytest.mark.parametrize("seed", range(8))
def test_planted_products_of_linear_factors_are_recovered_exactly(seed):
    # each coefficient of the residual is a product of random affine factors of the
    # parameters: the components are the affine subspaces cut by one factor of each
    # product, minus those contained in others, known here by linear algebra alone
    rng = random.Random(seed)
    params = sp.symbols("p1:5", real=True)
    monomials = [M1, gamma1 * gamma2, M1 * gamma3, gamma2**2]

    def affine():
        while True:
            coeffs = [rng.randint(-3, 3) for _ in params]
            if any(coeffs[:-1]) or coeffs[-1]:
                if any(coeffs):
                    break
        return sum(c * p for c, p in zip(coeffs, params, strict=True)) + rng.randint(-4, 4)

    products = [[affine() for _ in range(rng.randint(1, 3))] for _ in range(rng.randint(2, 3))]
    residual = sum(sp.Mul(*f) * m for f, m in zip(products, monomials, strict=False))
    choices = [list(c) for c in itertools.product(*products)]
    choices = [c for c in choices if _consistent(c, params)]
    expected = [
        c
        for c in choices
        if not any(_inside(c, o, params) and not _inside(o, c, params) for o in choices)
    ]
    found = parameter_conditions({"r": residual}, Domain(parameters=params))
    got = [[p - v for p, v in branch.items()] for branch in found.branches]
    assert all(any(_inside(g, e, params) and _inside(e, g, params) for e in expected) for g in got)
    assert all(any(_inside(g, e, params) and _inside(e, g, params) for g in got) for e in expected)
    assert len(got) == len({tuple(sorted(map(str, g))) for g in got})  # no branch twice
    for i, g in enumerate(got):  # none inside another
        assert not any(j != i and _inside(g, h, params) for j, h in enumerate(got))
