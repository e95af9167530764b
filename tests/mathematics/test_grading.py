"""The grading of a search: weights under which the vector field is homogeneous."""

from __future__ import annotations

import sympy as sp

from registry.dynamics import Vector
from registry.mathematics import mechanics as mech
from registry.mathematics.grading import grading_note, homogeneous_weights, shift

M1, M2, M3 = mech.MOMENTUM
g1, g2, g3 = mech.AXIS
kappa, c = sp.symbols("kappa c", real=True)
KOVALEVSKAYA = M1**2 + M2**2 + 2 * M3**2 + 2 * c * g1
CLEBSCH = M1**2 + 2 * M2**2 + 3 * M3**2 + g1**2 + 2 * g2**2


def field(h, k=0, mu=(0, 0, 0)):
    return mech.equations_of_motion(mu, k, h=h)


def test_e3_with_a_linear_potential_is_graded_m1_gamma2():
    assert shift(field(KOVALEVSKAYA), (1, 2)) == 1
    assert shift(field(KOVALEVSKAYA), (1, 1)) is None
    assert homogeneous_weights(field(KOVALEVSKAYA)) == (("M", 1), ("gamma", 2))


def test_quadratic_hamiltonians_are_graded_m1_gamma1_on_every_bracket():
    for k in (0, kappa, -1):
        assert homogeneous_weights(field(CLEBSCH, k)) == (("M", 1), ("gamma", 1))
        assert grading_note(field(CLEBSCH, k), (1, 1)) == ""


def test_kovalevskaya_on_so4_has_no_grading_and_the_note_says_what_the_ansatz_means():
    f = field(KOVALEVSKAYA, kappa)
    assert homogeneous_weights(f) is None
    note = grading_note(f, (1, 1))
    assert "not weighted-homogeneous for M: 1, gamma: 1" in note
    assert "degrees are coupled" in note


def test_linear_terms_in_m_break_homogeneity_and_radicals_are_not_graded():
    assert homogeneous_weights(field(CLEBSCH + M3)) is None
    assert homogeneous_weights(field(M1**2 + sp.sqrt(1 + g1**2))) is None


def test_every_weighting_reads_the_same_monomials_as_shift_one_by_one():
    """homogeneous_weights computes each component's monomials once for every candidate;
    its answer is the first candidate that ``shift`` (monomials computed afresh) accepts."""
    for f in (field(KOVALEVSKAYA), field(CLEBSCH, kappa), field(KOVALEVSKAYA, kappa)):
        first = next(
            (w for w in ((1, 2), (1, 1), (2, 1)) if shift(f, w) is not None),
            None,
        )
        found = homogeneous_weights(f)
        assert found == (None if first is None else (("M", first[0]), ("gamma", first[1])))


def test_a_field_divided_by_a_large_power_is_graded_term_by_term():
    # b gamma1^2/gamma3 (weight 4 - 2) added to Goryachev-Chaplygin's potential keeps the
    # shift under (1, 2), b/gamma3^2 (weight -4) does not; (gamma1 + gamma2 + gamma3)^400
    # in a denominator is read in its factors (one fraction: 80 000 terms multiplied out)
    b, e = sp.symbols("b e")
    goryachev = M1**2 + M2**2 + 4 * M3**2 + 2 * g1
    assert shift(field(goryachev + b * g1**2 / g3), (1, 2)) == 1
    assert shift(field(goryachev + b * g1**2 / g3), (1, 1)) is None
    assert shift(field(goryachev + b / g3**2), (1, 2)) is None
    s = g1 + g2 + g3
    assert shift(field(M1**2 + M2**2 + M3**2 + e * g1**402 / s**400), (1, 1)) == 1
    assert shift(field(M1**2 + M2**2 + M3**2 + e * g1**403 / s**400), (1, 1)) is None
    assert shift(field(M1**2 + M2**2 + M3**2 + e / s**400), (1, 2)) is None


def test_terms_that_cancel_across_denominators_are_read_as_one_fraction():
    # x^2/(y (y + 1)) + x^2/(y + 1) = x^2/y: neither term is homogeneous, their sum is
    x, y, z = sp.symbols("x y z")
    state = (Vector("v", (x, y, z), 1),)

    def graded(component):
        return shift([component, y, z], (("v", 1),), state, {}, [x, y, z])

    assert graded(x**2 / y) == graded(x**2 / (y * (y + 1)) + x**2 / (y + 1)) == 0
    assert graded(x**2 / (y * (y + 1)) + x / (y + 1)) is None
