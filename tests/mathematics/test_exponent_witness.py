"""A witness at rational parameter values that the Painlevé test fails for generic values:
found where the generic analysis fails, never where it passes, never from a balance that
is not simple, and equal there to the generic exponents evaluated."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.exponent_analysis import exponents
from registry.mathematics.exponent_witness import approximate, witness
from registry.mathematics.weighted import split_field
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, euler_top, heavy_top

a = sp.Symbol("a")
x, y, z = sp.symbols("x y z")


def test_an_exponent_that_varies_with_a_parameter_is_witnessed():
    """x' = x^2, y' = a x y: the one balance (-1, 0) has the exponents -1 and 1 - a, an
    integer at every integer a; the witness is taken at a value that is not one."""
    field = [x**2, a * x * y]
    generic = exponents([x, y], field, [1, 1])
    assert [b.exponents.values for b in generic.balances] == [(-1, 1 - a)]
    assert generic.painleve_verdict is False
    found = witness(split_field([x, y], field, [1, 1]))
    assert found is not None
    value = found.values[a]
    assert not value.is_integer
    assert sorted(found.balance.exponents.values) == sorted([-1, 1 - value])


def test_no_witness_where_every_exponent_is_an_integer_for_every_value():
    """Euler's free top with its three moments symbolic passes the test generically."""
    moments = sp.symbols("A B C")
    field = euler_top(moments)
    assert exponents(STATE[:3], field, (1, 1, 1)).painleve_verdict is True
    assert witness(split_field(STATE[:3], field, (1, 1, 1))) is None


def test_a_family_of_balances_is_no_witness():
    """x' = x^2, y' = a x y, z' = x z: the balances (-1, 0, z) form a family along z,
    with the exponents -1, 0 and 1 - a. The test fails for generic a, but a balance with
    the exponent 0 is not a simple root, so no witness is claimed from it."""
    field = [x**2, a * x * y, x * z]
    generic = exponents([x, y, z], field, [1, 1, 1])
    assert generic.painleve_verdict is False
    assert all(b.balance.dimension == 1 for b in generic.balances)
    assert witness(split_field([x, y, z], field, [1, 1, 1])) is None


def test_the_witness_has_the_generic_exponents_at_its_values():
    """The heavy top with moments (2, 2, a) and centre (1, 0, 0): the exponents of the
    witnessing balance are those of a generic balance with a put in."""
    field = heavy_top((2, 2, a), (1, 0, 0))
    generic = exponents(STATE, field, HEAVY_WEIGHTS, painleve=False)
    assert generic.painleve_verdict is False
    found = witness(split_field(STATE, field, HEAVY_WEIGHTS))
    assert found is not None
    at = found.values[a]
    specialised = [
        sorted((sp.nsimplify(sp.radsimp(v.subs(a, at))) for v in b.exponents.values), key=str)
        for b in generic.balances
    ]
    assert sorted(found.balance.exponents.values, key=str) in specialised


def test_a_parameter_value_where_a_coefficient_is_undefined_is_passed_over():
    """x' = x^2, y' = x y / (a - v) for the first value v the witness would try: that
    value is not a specialisation of the field, and the next one is used."""
    first = witness(split_field([x, y], [x**2, a * x * y], [1, 1]), tries=1)
    assert first is not None
    v = first.values[a]
    field = [x**2, x * y / (a - v)]
    found = witness(split_field([x, y], field, [1, 1]))
    assert found is not None and found.values[a] != v


def test_a_parameter_declared_integer_gets_no_witness():
    """x' = x^2, y' = n x y with n an integer: the exponents -1 and 1 - n are integers
    at every admissible n, and the solutions x = -1/(t - t0), y = C (t - t0)^(-n) are
    meromorphic; a value off the integers proves nothing about them."""
    n = sp.Symbol("n", integer=True)
    field = [x**2, n * x * y]
    assert exponents([x, y], field, [1, 1]).painleve_verdict is not False
    assert witness(split_field([x, y], field, [1, 1])) is None
    real = sp.Symbol("n")
    assert witness(split_field([x, y], [x**2, real * x * y], [1, 1])) is not None


def test_exponents_of_a_factor_over_q_that_are_not_rational_are_counted_as_such():
    """x' = x^2, y' = a x z, z' = x y: the balance (-1, 0, 0) has the exponents -1 and
    1 +- sqrt(a), the roots of a factor over Q at a value that is not a square."""
    field = [x**2, a * x * z, x * y]
    found = witness(split_field([x, y, z], field, [1, 1, 1]))
    assert found is not None
    values = found.balance.exponents.values
    assert [v for v in values if v.is_rational] == [-1]
    assert sorted(values, key=str)[1:] == sorted(
        [1 - sp.sqrt(found.values[a]), 1 + sp.sqrt(found.values[a])], key=str
    )
    root = float(sp.sqrt(found.values[a]))
    assert [round(z.real, 9) for z in approximate(found)] == [
        round(1 - root, 9),
        round(1 + root, 9),
    ]
    assert all(z.imag == 0 for z in approximate(found))


def test_the_heavy_top_s_exponents_off_the_integers_come_in_a_pair_summing_to_one():
    """Moments (2, 3, 4), centre (1, 2, a): the witnessing balance lies off gamma = 0,
    where the exponents are -1, 2, 3, 4 and rho, 1 - rho (Kovalevskaya's pairing), rho
    a root of a quadratic over the balance's field of degree 8: approximately, at one
    root theta, the two sum to 1 and are not real integers."""
    found = witness(split_field(STATE, heavy_top((2, 3, 4), (1, 2, a)), HEAVY_WEIGHTS))
    assert found is not None
    assert found.balance.exponents.values == (-1, 2, 3, 4)
    assert found.balance.balance.component.minimal.degree() == 8
    rho, other = approximate(found)
    assert abs(rho + other - 1) < 1e-9
    assert min(abs(rho - round(rho.real)), abs(other - round(other.real))) > 1e-3
