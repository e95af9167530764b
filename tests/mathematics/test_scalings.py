"""The scalings of a family: parameter weights under which the field is covariant."""

from __future__ import annotations

import sympy as sp

from registry.mathematics import mechanics as mech
from registry.mathematics.scalings import covariant_weights, slicing_variables

x0, y0, z0 = sp.symbols("x0 y0 z0", real=True)
b, c = sp.symbols("b c", positive=True)


def heavy_top_field():
    return mech.vector_field(
        (1, b, c), x0 * mech.gamma1 + y0 * mech.gamma2 + z0 * mech.gamma3, (0, 0, 0)
    )


def test_the_heavy_top_scales_its_centre_of_mass_and_not_its_moments():
    weights = covariant_weights(heavy_top_field(), mech.STATE, [b, c, x0, y0, z0])
    assert weights  # gamma -> lambda gamma with r -> r / lambda, at least
    for w in weights:
        assert w[b] == 0 and w[c] == 0
        assert w[x0] == w[y0] == w[z0] != 0


def test_a_level_set_or_a_known_integral_that_is_not_homogeneous_removes_the_scaling():
    field = heavy_top_field()
    unit = mech.gamma1**2 + mech.gamma2**2 + mech.gamma3**2 - 1
    # s = 1 keeps one (M -> lambda M, gamma -> gamma / lambda, r -> lambda^3 r); with
    # |gamma| = 1 as well, none is left
    (kept,) = covariant_weights(field, mech.STATE, [b, c, x0, y0, z0], [mech.S_VALUE - 1])
    assert kept[x0] != 0
    assert covariant_weights(field, mech.STATE, [b, c, x0, y0, z0], [mech.S_VALUE - 1, unit]) == []


def test_a_term_that_is_no_product_of_powers_claims_no_scaling():
    field = list(heavy_top_field())
    field[0] += sp.sqrt(1 + x0) * mech.gamma1
    assert covariant_weights(field, mech.STATE, [b, c, x0, y0, z0]) == []


def test_slicing_takes_independent_columns_only():
    weights = [{x0: 1, z0: 1, b: 0}]
    assert slicing_variables(weights, [b, x0, z0]) == [x0]
    assert slicing_variables([{x0: 1, z0: 0}, {x0: 0, z0: 2}], [x0, z0]) == [x0, z0]
