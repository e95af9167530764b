"""Kovalevskaya exponents: exact eigenvalues of K = Dv(c) + diag(w) at every balance,
-1 always among them, Yoshida's degrees, and the classical heavy tops.

No printed table of heavy-top exponents could be reached for comparison (a colleague's
literature search, /work/scratch/exponents32/FINDINGS.md, found none in readable form);
the values below agree with that search's independent plain-sympy computation, and the
symmetric-top family with Kowalevski's selection of A = B = 2C (Acta Math. 12 (1889)
177-232, as reviewed in JFM 21.0935.01), tested in test_exponent_families.py.
"""

from __future__ import annotations

import pytest
import sympy as sp

from registry.mathematics import algebraic
from registry.mathematics.balances import balances
from registry.mathematics.exponent_analysis import exponents
from registry.mathematics.kovalevskaya import (
    LAMBDA,
    balance_exponents,
    characteristic_polynomial,
    kovalevskaya_matrix,
)
from registry.mathematics.weighted import split_field
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, energy, euler_top, heavy_top

x, y, z = sp.symbols("x y z")
M1, M2, M3, G1, G2, G3 = STATE
HALF = sp.Rational(1, 2)


def values(result) -> list[list[sp.Expr]]:
    return [list(b.exponents.values) for b in result.balances]


def test_a_planted_lotka_volterra_field_has_the_exponents_of_its_construction():
    """x_i' = x_i (A x)_i: on the subset I of nonzero coordinates A_II c_I = -1, and K is
    block triangular: diag(c_I) A_II on I, (A c)_j + 1 off it (weights 1)."""
    A = sp.Matrix([[-1, 2], [3, -2]])
    field = [x * (A[0, 0] * x + A[0, 1] * y), y * (A[1, 0] * x + A[1, 1] * y)]
    result = exponents([x, y], field, [1, 1])
    expected = {}
    for subset in ([0], [1], [0, 1]):
        c = sp.zeros(2, 1)
        block = A.extract(subset, subset)
        c_sub = block.solve(sp.Matrix([-1] * len(subset)))
        for i, s in enumerate(subset):
            c[s] = c_sub[i]
        outside = [(A * c)[j] + 1 for j in range(2) if j not in subset]
        inside = (sp.diag(*c_sub) * block).eigenvals()
        found = [*outside, *(e for e, m in inside.items() for _ in range(m))]
        expected[tuple(c)] = sorted(found, key=float)
    got = {
        tuple(b.balance.point[v] for v in (x, y)): list(b.exponents.values) for b in result.balances
    }
    assert got == expected


FIELDS = {
    "lotka-volterra": ([x, y], [x * (-x + 2 * y), y * (3 * x - 2 * y)], [1, 1]),
    "euler": (STATE[:3], euler_top((1, 2, 3)), [1, 1, 1]),
    "kovalevskaya": (STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS),
    "planted-3d": ([x, y, z], [-(x**2), 5 * x * y + z**2, 2 * x * z], [1, 3, 2]),
    "irrational": ([x, y], [-2 * x**2 - 2 * x * y + 2 * y**2, -2 * x**2 + x * y - y**2], [1, 1]),
}


@pytest.mark.parametrize("name", FIELDS)
def test_minus_one_is_an_exponent_with_eigenvector_w_c(name):
    variables, field, weights = FIELDS[name]
    split = split_field(variables, field, weights)
    matrix = kovalevskaya_matrix(split)
    result = exponents(variables, field, weights, painleve=False)
    assert result.balances
    for b in result.balances:
        assert -1 in b.exponents.values
        point = b.balance.point
        vector = sp.Matrix([w * point[v] for v, w in zip(variables, weights, strict=True)])
        residual = matrix.xreplace(point) * vector + vector
        assert all(sp.simplify(sp.expand(r)) == 0 for r in residual)


def test_exponents_at_conjugate_balances_are_conjugate_and_exact():
    """Balances x = (1 +- sqrt 17)/12 of a 2-d field: the second exponent is tr K + 1,
    a different irrational number at each, found through the norm over Q."""
    variables, field, weights = FIELDS["irrational"]
    split = split_field(variables, field, weights)
    matrix = kovalevskaya_matrix(split)
    found = [b for b in balances(split) if b.component.degree == 2]  # and (1/2, 1/2)
    assert len(found) == 2
    for b in found:
        other = sp.radsimp(sp.expand(matrix.xreplace(b.point).trace() + 1))
        e = balance_exponents(b, characteristic_polynomial(b.component, matrix))
        assert e.values == tuple(sorted([sp.Integer(-1), other], key=float))
        assert not e.rational
    assert {sp.expand(b.point[x]) for b in found} == {
        sp.Rational(1, 12) + sp.sqrt(17) / 12,
        sp.Rational(1, 12) - sp.sqrt(17) / 12,
    }


def left_eigen_residual(integral, k, matrix, point, variables):
    """grad I(c)^T K - k grad I(c)^T at the balance (zero by Yoshida's lemma)."""
    grad = sp.Matrix([[sp.diff(integral, v) for v in variables]]).xreplace(point)
    return grad, sp.expand(grad * matrix.xreplace(point) - k * grad)


def test_yoshida_the_free_rigid_body_energy_and_momentum_have_degree_two():
    """dM/dt = M x I^-1 M, weights 1: H and |M|^2 have weighted degree 2, so 2 is an
    exponent of every balance where a gradient does not vanish (Yoshida 1983)."""
    inertia = (1, 2, 3)
    variables = STATE[:3]
    split = split_field(variables, euler_top(inertia), (1, 1, 1))
    matrix = kovalevskaya_matrix(split)
    result = exponents(variables, euler_top(inertia), (1, 1, 1))
    integrals = [energy(inertia), M1**2 + M2**2 + M3**2]
    for b in result.balances:
        assert b.exponents.values == (-1, 2, 2)
        for integral in integrals:
            grad, residual = left_eigen_residual(integral, 2, matrix, b.balance.point, variables)
            assert any(g != 0 for g in grad) and all(sp.simplify(r) == 0 for r in residual)
    assert result.degrees == (2,)


def test_the_free_rigid_body_with_symbolic_moments():
    """Over Q(A, B, C): four balances in radicals of the moments, each with -1, 2, 2."""
    A, B, C = sp.symbols("A B C", positive=True)
    result = exponents(STATE[:3], euler_top((A, B, C)), (1, 1, 1))
    assert [b.exponents.values for b in result.balances] == [(-1, 2, 2)] * 4
    assert result.all_integer and result.painleve_passes
    assert any("generic" in n for n in result.notes)


def test_yoshida_the_heavy_top_integrals_of_degree_two_three_four():
    """Kovalevskaya's top: H (2), M.gamma (3), |gamma|^2 (4) and Kovalevskaya's integral
    (4) have their degrees among the exponents of every balance."""
    inertia, r = (2, 2, 1), (1, 0, 0)
    split = split_field(STATE, heavy_top(inertia, r), HEAVY_WEIGHTS)
    matrix = kovalevskaya_matrix(split)
    result = exponents(STATE, heavy_top(inertia, r), HEAVY_WEIGHTS, painleve=False)
    kovalevskaya = ((M1**2 - M2**2) / 4 - G1) ** 2 + (M1 * M2 / 2 - G2) ** 2
    integrals = [
        (energy(inertia, r), 2),
        (M1 * G1 + M2 * G2 + M3 * G3, 3),
        (G1**2 + G2**2 + G3**2, 4),
        (kovalevskaya, 4),
    ]
    for b in result.balances:
        for integral, k in integrals:
            assert k in b.exponents.values
            _, residual = left_eigen_residual(integral, k, matrix, b.balance.point, STATE)
            assert all(sp.expand(r) == 0 for r in residual)
    assert set(result.degrees) >= {2, 3, 4}


def test_kovalevskaya_top_every_exponent_an_integer():
    result = exponents(STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    assert result.all_integer
    assert values(result) == [[-1, 0, 1, 2, 3, 4]] * 2 + [[-1, -1, 2, 2, 3, 4]] * 2


def test_lagrange_top_every_exponent_an_integer_for_every_moment_and_height():
    A, C, z0 = sp.symbols("A C z0", positive=True)
    result = exponents(STATE, heavy_top((A, A, C), (0, 0, z0)), HEAVY_WEIGHTS)
    assert result.all_integer and result.homogeneous
    assert values(result) == [[-1, 0, 1, 2, 3, 4]] * 2


def test_goryachev_chaplygin_has_half_integer_exponents():
    """A = B = 4, C = 1, r = (1, 0, 0): -1/2 and 3/2 at two balances (algebraic branching,
    the weak Painlevé property), -2 at the others (not principal)."""
    result = exponents(STATE, heavy_top((4, 4, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    assert not result.all_integer and result.all_rational
    assert sorted(map(tuple, values(result))) == [
        (-2, -1, 2, 3, 3, 4),
        (-2, -1, 2, 3, 3, 4),
        (-1, -HALF, 3 * HALF, 2, 3, 4),
        (-1, -HALF, 3 * HALF, 2, 3, 4),
    ]
    weak = [b for b in result.balances if -HALF in b.exponents.values]
    assert all(any("weak Painlevé" in n for n in b.notes) for b in weak)
    assert not result.painleve_passes


def test_a_generic_asymmetric_top_has_irrational_exponents():
    result = exponents(STATE, heavy_top((3, 4, 5), (1, 0, 0)), HEAVY_WEIGHTS, painleve=False)
    assert not result.all_rational and len(result.balances) == 12
    assert any(
        set(b.exponents.values) >= {HALF - sp.sqrt(2), HALF + sp.sqrt(2)} for b in result.balances
    )
    assert "irrational or complex exponent" in result.statement


@pytest.mark.slow
def test_exponents_over_a_number_field_of_degree_eight():
    """A = 1, B = 2, C = 3, r = (1, 1, 1): eight balances form one component of degree 8;
    their shared exponents -1 and 2 are exact, the others roots of the norm."""
    field = heavy_top((1, 2, 3), (1, 1, 1))
    matrix = kovalevskaya_matrix(split_field(STATE, field, HEAVY_WEIGHTS))
    result = exponents(STATE, field, HEAVY_WEIGHTS, painleve=False)
    octet = [b for b in result.balances if b.balance.component.degree == 8]
    assert len(octet) == 8
    for b in octet:
        assert {-1, 2} <= set(b.exponents.values) and len(b.exponents.values) == 6
        total = algebraic.to_acb(sp.Add(*b.exponents.values))
        trace = algebraic.to_acb(matrix.xreplace(b.balance.point).trace())
        assert (total - trace).contains(0)


def test_the_characteristic_polynomial_splits_into_a_common_and_a_varying_part():
    variables, field, weights = FIELDS["irrational"]
    split = split_field(variables, field, weights)
    component = next(b.component for b in balances(split) if b.component.degree == 2)
    polynomial = characteristic_polynomial(component, kovalevskaya_matrix(split))
    assert polynomial.common == ((LAMBDA + 1, 1),)
    assert sp.degree(polynomial.rest, LAMBDA) == 1 and polynomial.norm


def test_exponents_among_radicals_of_the_parameters_by_the_quadratic_formula():
    """Moments (1, 1, c), centre (x0, y0, z0): the balances off the axis have coordinates
    with I and sqrt(x0**2 + y0**2), and two exponents that vary, the roots of a quadratic
    written by the formula (sympy's roots factored it over the extension for a minute).
    They are the eigenvalues: with the four shared ones (-1, 2, 3, 4) they sum to the
    trace of the Kovalevskaya matrix and multiply to its determinant, at a sample point;
    they are never rational (a rational root would be shared by the conjugate balances)."""
    c = sp.Symbol("c", positive=True)
    x0, y0, z0 = sp.symbols("x0 y0 z0", real=True)
    field = heavy_top((1, 1, c), (x0, y0, z0))
    split = split_field(STATE, field, HEAVY_WEIGHTS)
    result = exponents(STATE, field, HEAVY_WEIGHTS, parameters=(c, x0, y0, z0), painleve=False)
    matrix = kovalevskaya_matrix(split)
    at = {c: sp.Rational(3, 7), x0: sp.Rational(2, 3), y0: sp.Rational(-5, 4), z0: 3}
    varying = [b for b in result.balances if b.balance.point[STATE[5]].has(sp.I)]
    assert len(varying) == 2
    for b in varying:
        values = b.exponents.values
        assert {-1, 2, 3, 4} <= set(values) and len(values) == 6
        assert not b.exponents.rational and any(v.has(sp.sqrt(x0**2 + y0**2)) for v in values)
        k = matrix.xreplace(b.balance.point).xreplace(at)
        total, product = sp.Add(*values).xreplace(at), sp.Mul(*values).xreplace(at)
        assert abs(sp.N(total - k.trace(), 30)) < 1e-25
        assert abs(sp.N(product - k.det(), 30)) < 1e-25
