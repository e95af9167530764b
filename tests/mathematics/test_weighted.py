"""The weighted split: a field's parts by shift, the leading part for x = c t^(-w), and
every problem with the field or the weights reported at once."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.errors import RegistryError, WeightedFieldError
from registry.mathematics import mechanics as mech
from registry.mathematics.weighted import split_field, weighted_degrees
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, heavy_top

x, y, a = sp.symbols("x y a")


def test_the_heavy_top_is_weighted_homogeneous_for_m_1_gamma_2():
    field = heavy_top((2, 2, 1), (1, 0, 0))
    split = split_field(STATE, field, HEAVY_WEIGHTS)
    assert split.homogeneous and split.shifts == (1,)
    assert split.leading == field
    assert split.parameters == ()


def test_the_euler_top_with_symbolic_moments_keeps_them_as_parameters():
    A, B, C = sp.symbols("A B C", positive=True)
    field = heavy_top((A, B, C), (0, 0, 0))[:3]
    split = split_field(mech.MOMENTUM, field, (1, 1, 1))
    assert split.homogeneous and set(split.parameters) == {A, B, C}


def test_a_zero_component_adds_no_part():
    A, C = sp.symbols("A C", positive=True)
    field = heavy_top((A, A, C), (0, 0, 1))  # dM3/dt = 0 for a symmetric top
    split = split_field(STATE, field, HEAVY_WEIGHTS)
    assert split.homogeneous and split.leading[2] == 0


def test_a_field_that_is_not_homogeneous_is_split_by_shift_with_its_leading_part_first():
    # x' = y + x^2 + a x (shifts 1, 1, 0), y' = x y + 1 (shifts 1, -2) for weights (1, 2)
    split = split_field([x, y], [y + x**2 + a * x, x * y + 1], [1, 2])
    assert not split.homogeneous
    assert split.shifts == (1, 0, -2)
    assert split.leading == (x**2 + y, x * y)
    assert split.parts[0] == (a * x, 0) and split.parts[-2] == (0, 1)


def test_every_problem_is_listed_with_the_component_or_weight_it_concerns():
    with pytest.raises(WeightedFieldError) as caught:
        split_field([x, y], [sp.sqrt(x) + y, sp.Float(0.5) * y * x], [1, 0])
    assert str(caught.value).splitlines() == [
        "weights[1]: not a positive integer: '0'",
        "field[0]: not a polynomial in the variables, nor a polynomial divided by one: "
        "'sqrt(x) + y'",
        "field[1]: a coefficient is not a rational function over Q of the parameters: "
        "'0.500000000000000'",
    ]
    assert isinstance(caught.value, ValueError) and isinstance(caught.value, RegistryError)
    assert len(caught.value.problems) == 3
    with pytest.raises(WeightedFieldError, match=r"^field: 1 components for 2 variables$"):
        split_field([x, y], [x], [1, 1])


def test_terms_that_dominate_the_derivative_are_named():
    with pytest.raises(WeightedFieldError) as caught:
        split_field([x, y], [x**3, y], [1, 1])
    assert str(caught.value) == (
        "field: terms of shift 2 > 1 dominate dx/dt under these weights, so no solution "
        "behaves like c t^(-w): 'x**3'"
    )
    with pytest.raises(WeightedFieldError, match="no term of shift 1"):
        split_field([x, y], [x, y], [1, 1])


def test_undeclared_names_are_refused_when_the_parameters_are_given():
    with pytest.raises(WeightedFieldError, match="names neither a variable nor a parameter: 'a'"):
        split_field([x, y], [a * x**2, y**2], [1, 1], parameters=())


def test_weighted_degrees_of_the_heavy_top_integrals():
    m1, m2, m3 = mech.MOMENTUM
    g1, g2, g3 = mech.AXIS
    energy = (m1**2 + m2**2) / 4 + m3**2 / 2 + g1
    assert weighted_degrees(energy, STATE, HEAVY_WEIGHTS) == (2,)
    assert weighted_degrees(m1 * g1 + m2 * g2 + m3 * g3, STATE, HEAVY_WEIGHTS) == (3,)
    assert weighted_degrees(g1**2 + m1, STATE, HEAVY_WEIGHTS) == (4, 1)
    assert weighted_degrees(0, STATE, HEAVY_WEIGHTS) == ()


def test_a_field_divided_by_weighted_homogeneous_polynomials_keeps_one_shift_per_term():
    # under weights (1, 2): y^2/x^2 has degree 4 - 2 = 2 (shift 1 in x'), a x shift 0;
    # x y^3/(x^2 + y)^2 has degree 7 - 4 = 3 (shift 1 in y')
    field = [y**2 / x**2 + a * x, x * y**3 / (x**2 + y) ** 2]
    split = split_field([x, y], field, [1, 2])
    assert split.denominators == ((x, 1), (x**2 + y, 2))
    assert split.shifts == (1, 0) and not split.homogeneous
    assert split.leading == (y**2 / x**2, x * y**3 / (x**2 + y) ** 2)
    assert split.parts[0] == (a * x, 0)
    assert {(t.component, t.monomial, t.powers, t.shift) for t in split.terms} == {
        (0, (0, 2), (2, 0), 1),
        (0, (1, 0), (0, 0), 0),  # a x stays a polynomial term
        (1, (1, 3), (0, 2), 1),
    }


def test_a_denominator_that_is_not_weighted_homogeneous_is_refused():
    with pytest.raises(WeightedFieldError) as caught:
        split_field([x, y], [x**2 / (1 + y), x * y], [1, 1])
    assert str(caught.value).splitlines() == [
        "field[0]: divides by a polynomial that is not weighted-homogeneous under these "
        "weights, so the terms have no single shift: 'y + 1'"
    ]


def test_a_power_in_a_denominator_stays_a_power():
    """Terms are not brought to one fraction: x^2 stays a polynomial term beside
    a y / (x + y)^60, whose denominator is the factor x + y to the power 60 (one
    fraction would multiply x^2 by the expanded (x + y)^60, 61 terms of degree 62)."""
    split = split_field([x, y], [x**2 + a * y / (x + y) ** 60, x * y], [1, 1])
    assert split.denominators == ((x + y, 1),)
    assert {(t.component, t.monomial, t.powers, t.shift) for t in split.terms} == {
        (0, (2, 0), (0,), 1),
        (0, (0, 1), (60,), -60),
        (1, (1, 1), (0,), 1),
    }


def test_a_divided_term_of_too_many_factors_is_refused():
    # x^101 / y^100 has shift 1 under weights (1, 1), but its series would multiply
    # 201 factors
    with pytest.raises(WeightedFieldError) as caught:
        split_field([x, y], [x**101 / y**100, x * y], [1, 1])
    assert str(caught.value) == (
        "field[0]: a divided term of more than 100 factors (numerator and denominator): "
        "beyond what the Laurent series multiplies out: 'x**101/y**100'"
    )
