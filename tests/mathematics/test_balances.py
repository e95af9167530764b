"""Balances: every nonzero c with -w_i c_i = v_i(c) for the leading part, exact, complex
ones included, families with their free coordinates, none identified by the scaling."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.mathematics.balances import balance_equations, balances
from registry.mathematics.weighted import split_field
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, energy, euler_top, heavy_top

x, y = sp.symbols("x y")


def is_zero(expr: sp.Expr) -> bool:
    """Exactly: an algebraic number is 0 when its minimal polynomial is t."""
    expr = sp.expand(expr)
    if expr == 0:
        return True
    if expr.free_symbols:
        return sp.simplify(expr) == 0
    t = sp.Dummy("t")
    return sp.minimal_polynomial(expr, t) == t


def solves(split, point) -> bool:
    return all(is_zero(e.xreplace(point)) for e in balance_equations(split))


def quotient_dimension(equations, variables) -> int:
    """dim Q[x]/I: the number of solutions with multiplicity, from the standard monomials
    of a Groebner basis (an independent count, with the origin a simple solution)."""
    basis = sp.groebner(equations, *variables, order="grevlex")
    leading = [sp.Poly(e, *variables).monoms(order="grevlex")[0] for e in basis.exprs]

    def standard(monomial):
        return not any(all(e >= m for e, m in zip(monomial, lm, strict=True)) for lm in leading)

    found, frontier = set(), [(0,) * len(variables)]
    while frontier:  # the standard monomials are closed under division: grow from 1
        monomial = frontier.pop()
        if monomial in found or not standard(monomial):
            continue
        found.add(monomial)
        for i in range(len(variables)):
            frontier.append(tuple(e + (j == i) for j, e in enumerate(monomial)))
    return len(found)


def test_a_planted_lotka_volterra_field_has_the_balances_of_its_construction():
    # x' = x (-x + 2 y), y' = y (3 x - 2 y): on each coordinate subset I the balance solves
    # A_II c_I = -1 (weights 1): (1, 0), (0, 1/2) and A c = -1 with both nonzero
    split = split_field([x, y], [x * (-x + 2 * y), y * (3 * x - 2 * y)], [1, 1])
    found = {tuple(b.point[v] for v in (x, y)) for b in balances(split)}
    both = sp.Matrix([[-1, 2], [3, -2]]).solve(sp.Matrix([-1, -1]))
    assert found == {(1, 0), (0, sp.Rational(1, 2)), tuple(both)}


def test_the_euler_top_has_four_balances_exactly_and_no_other():
    field = euler_top((1, 2, 3))
    split = split_field(STATE[:3], field, (1, 1, 1))
    found = balances(split)
    assert len(found) == 4 and all(b.dimension == 0 for b in found)
    assert all(solves(split, b.point) for b in found)
    # with the origin, a simple solution, the system has 5 solutions counted with multiplicity
    assert quotient_dimension(balance_equations(split), STATE[:3]) == 5
    assert {b.point[STATE[2]] for b in found} == {3 * sp.I, -3 * sp.I}


def test_kovalevskaya_top_two_families_of_balances_and_two_points():
    split = split_field(STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    found = balances(split)
    families = [b for b in found if b.dimension]
    assert [b.dimension for b in found] == [1, 1, 0, 0]
    m1, m2 = STATE[:2]
    assert {b.point[m1] for b in families} == {sp.I * m2, -sp.I * m2}
    assert all(b.free == (m2,) for b in families)
    assert all(solves(split, b.point) for b in found)  # the families: for every M2


def test_weighted_homogeneous_integrals_vanish_at_every_balance():
    """I(c t^(-w)) = t^(-k) I(c) is constant only if I(c) = 0: H, M.gamma and |gamma|^2
    of the heavy top vanish at each balance (families: for every value of M2)."""
    inertia, r = (2, 2, 1), (1, 0, 0)
    m, g = STATE[:3], STATE[3:]
    integrals = [
        energy(inertia, r),
        sum(a * b for a, b in zip(m, g, strict=True)),
        sum(b**2 for b in g),
    ]
    split = split_field(STATE, heavy_top(inertia, r), HEAVY_WEIGHTS)
    for b in balances(split):
        assert all(is_zero(integral.xreplace(b.point)) for integral in integrals)


def test_lagrange_top_has_a_circle_of_balances():
    c, z0 = sp.symbols("C z0", positive=True)
    split = split_field(STATE, heavy_top((1, 1, c), (0, 0, z0)), HEAVY_WEIGHTS)
    found = balances(split)
    assert [b.dimension for b in found] == [1, 1]  # the two halves of one circle
    assert all(solves(split, b.point) for b in found)
    g3 = STATE[5]
    assert {b.point[g3] for b in found} == {2 / z0}


def test_the_generic_asymmetric_top_every_balance_with_exact_coordinates():
    split = split_field(STATE, heavy_top((3, 4, 5), (1, 0, 0)), HEAVY_WEIGHTS)
    found = balances(split)
    assert len(found) == 12 and all(b.dimension == 0 for b in found)
    assert quotient_dimension(balance_equations(split), STATE) == 13
    assert all(solves(split, b.point) for b in found)
    assert len({tuple(b.point.values()) for b in found}) == 12


@pytest.mark.parametrize("scale", [2, -1, sp.I])
def test_the_weighted_scaling_maps_no_balance_to_another(scale):
    """The module's claim: a^w c solves -a w c = v(a^w c), a balance only for a = 1."""
    split = split_field(STATE, heavy_top((3, 4, 5), (1, 0, 0)), HEAVY_WEIGHTS)
    for b in balances(split):
        scaled = {v: scale**w * b.point[v] for v, w in zip(STATE, HEAVY_WEIGHTS, strict=True)}
        assert not solves(split, scaled)
        assert all(  # it solves -a w c' = v(c'): a balance of v / a, the same solution
            is_zero(f.xreplace(scaled) + scale * w * scaled[v])
            for f, v, w in zip(split.leading, STATE, HEAVY_WEIGHTS, strict=True)
        )


def test_a_balance_over_parameters_is_written_with_nothing_left_to_cancel():
    # Suslov's body with the constraint omega3 = 0 (I12 = 0): I11 w1' = -(I13 w1 + I23 w2) w2,
    # I22 w2' = (I13 w1 + I23 w2) w1. Its two balances are complex, over Q(I11, I22, I13,
    # I23) with sqrt(I11), sqrt(I22). Each coordinate is one fraction over the quadratic's
    # I11 I23**2 + I13**2 I22, its numerator no longer than when expanded (before, w1 kept
    # I13**2*I22**2 - I22*(I11*I23**2 + I13**2*I22) and a factor I23 on both sides)
    i11, i22 = sp.symbols("I11 I22", positive=True)
    i13, i23 = sp.symbols("I13 I23", real=True)
    w1, w2 = sp.symbols("w1 w2")
    axis = i13 * w1 + i23 * w2
    split = split_field(
        [w1, w2], [-axis * w2 / i11, axis * w1 / i22], [1, 1], parameters=(i11, i22, i13, i23)
    )
    found = balances(split)
    assert len(found) == 2
    for b in found:
        assert solves(split, b.point)
        for value in b.point.values():
            numerator, denominator = sp.fraction(value)
            assert denominator == i11 * i23**2 + i13**2 * i22
            assert sp.count_ops(numerator) <= sp.count_ops(sp.expand(numerator))
