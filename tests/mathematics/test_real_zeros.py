"""The real zeros of equations with sign-declared parameters (``real_zeros``): sums of
squares replaced by their roots, double roots of quadratics in a square, polynomials
proven never positive factor by factor. Each expected system is worked out by hand in
the test's docstring or comment; mutated forms (a sign, a constant term) must not be
simplified."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.real_zeros import never_positive, real_system


def test_a_sum_of_squares_is_replaced_by_the_squares_roots():
    x, y, z, b = sp.symbols("x y z b")
    assert real_system([x**2 + y**2 / 2 - y * z + z**2 / 2]) == (x, y - z)
    assert real_system([x**2 * (b - sp.Rational(1, 2)) ** 2 + b**2 * z**2 / 2]) == (
        2 * b * x - x,
        b * z,
    )
    assert real_system([-(x**2) - (y - 1) ** 2]) == (x, y - 1)  # the negative of one


def test_an_equation_without_real_points_empties_the_system_and_others_stay():
    x, y, b = sp.symbols("x y b")
    assert real_system([x**2 + sp.Rational(9, 4)]) is None
    assert real_system([x - 1, (y - 1) ** 2 + x**2 * (b**2 + 1) + 2]) is None
    # indefinite, or with real points of their own: left as they are
    assert real_system([x**2 - y**2]) == (x**2 - y**2,)
    assert real_system([b**2 - sp.Rational(1, 2)]) == (b**2 - sp.Rational(1, 2),)
    assert real_system([x**2 + y**2 - 1]) == (x**2 + y**2 - 1,)


def test_terms_that_are_never_negative_at_positive_parameters_vanish_one_by_one():
    """p (p + 1) y^2 + (p + q) z^2 with p, q > 0 is zero exactly where y = z = 0, and
    p^2 + 2 p + 1/2 is never zero; with p and q only real, neither is known."""
    y, z = sp.symbols("y z", real=True)
    p, q = sp.symbols("p q", positive=True)
    quadric = p * (p + 1) * y**2 + (p + q) * z**2
    assert real_system([quadric]) == (y, z)
    assert real_system([p**2 + 2 * p + sp.Rational(1, 2)]) is None
    assert real_system([y - 1, -(p * q + 1) * z**2 - q]) is None  # minus the sum
    pr, qr = sp.symbols("p q", real=True)
    assert real_system([quadric.xreplace({p: pr, q: qr})]) == (
        sp.expand(quadric.xreplace({p: pr, q: qr})),
    )
    assert real_system([pr**2 + 2 * pr + sp.Rational(1, 2)]) is not None


def test_a_quadratic_in_a_square_whose_discriminant_is_never_positive_meets_it():
    """e = X^2 + 2 (y^2 - z^2) X + (y^2 + z^2)^2 in X = x^2 has discriminant -16 y^2 z^2:
    a real zero has y z = 0 (at y = 0, x^2 = z^2; at z = 0, only x = y = 0). With the
    constant term y^4 the discriminant 4 z^2 (z^2 - 2 y^2) has no sign, and nothing is
    added."""
    x, y, z = sp.symbols("x y z", real=True)
    e = sp.expand(x**4 + 2 * (y**2 - z**2) * x**2 + (y**2 + z**2) ** 2)
    assert real_system([e]) == (e, y * z)
    mutated = sp.expand(x**4 + 2 * (y**2 - z**2) * x**2 + y**4)
    assert real_system([mutated]) == (mutated,)
    # a leading coefficient that may vanish: e is not quadratic everywhere
    s = sp.Symbol("s", real=True)
    assert real_system([sp.expand(s * e)]) == (sp.expand(s * e),)


def test_a_discriminant_is_proven_never_positive_factor_by_factor():
    """-(x^2 + y^2)(x^2 + y^2 + z^2)^2: a sum of squares times a square, negated; the
    systems are its real zeros, one per factor. A factor without a sign, or the wrong
    overall sign, leaves it unproven."""
    x, y, z = sp.symbols("x y z")
    square = (x**2 + y**2 + z**2) ** 2
    assert never_positive(sp.expand(-16 * (x**2 + y**2) * square)) == [
        (x, y),
        (x**2 + y**2 + z**2,),
    ]
    assert never_positive(sp.expand(16 * (x**2 + y**2) * square)) is None  # the sign
    assert never_positive(sp.expand(-(x**2 - y**2) * square)) is None  # no sign of its own
    assert never_positive(sp.expand((x**2 + 1) * -(y**2 + 2))) == []  # never zero
    assert never_positive(sp.expand(-(x**2 + 1) * -(y**2 + 2))) is None
