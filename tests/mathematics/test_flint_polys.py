"""Elements of Q(p) cross to FLINT's polynomials over Z and back unchanged: numerators
over the lcm of the denominators, and the quotient rebuilt in sympy's field; resultants
and discriminants over Q(p) by FLINT agree with their definitions."""

from __future__ import annotations

import random

import flint
import sympy as sp
from sympy.polys.subresultants_qq_zz import sylvester

from registry.mathematics.flint_polys import (
    discriminant,
    fraction,
    integral,
    numerators,
    resultant,
    resultant_in,
    to_ring,
)

a, b = sp.symbols("a b")
K = sp.QQ.frac_field(a, b)
CTX = flint.fmpz_mpoly_ctx.get(("p0", "p1"), "lex")


def back(poly):
    return to_ring(K.field.ring, poly)


def test_numerators_over_the_lcm_rebuild_every_element():
    entries = [K.convert(e) for e in (a / 2 + b, 3 / (a * b), (a - b) / (6 * a**2), 0)]
    flat, common = numerators(CTX, entries)
    assert back(common).as_expr() == 6 * a**2 * b
    for entry, numerator in zip(entries, flat, strict=True):
        assert K.field.new(back(numerator), back(common)) == entry


def test_a_fraction_is_the_element_sympy_makes_in_lowest_terms():
    # the same numerator and denominator as K.field.new (its canonical form), signs,
    # integer contents and common factors included
    rng = random.Random(7)
    p0, p1 = CTX.gens()

    def poly():
        return sum(
            (rng.randint(-3, 3) * p0 ** rng.randint(0, 2) * p1 ** rng.randint(0, 2)
             for _ in range(3)),
            CTX.from_dict({}),
        )  # fmt: skip

    for _ in range(200):
        common, num, den = poly(), poly(), poly()
        if common.is_zero() or den.is_zero():
            continue
        made = fraction(K.field, num * common * 6, -den * common * 4)
        expected = K.field.new(back(num * common * 6), back(-den * common * 4))
        assert (made.numer, made.denom) == (expected.numer, expected.denom)
    zero = fraction(K.field, CTX.from_dict({}), -2 * p0)
    assert (zero.numer, zero.denom) == (K.field.ring.zero, K.field.ring.one)


def test_an_extra_variable_is_appended_and_left_at_degree_zero():
    ctx = flint.fmpz_mpoly_ctx.get(("p0", "p1", "u"), "lex")
    num, den = integral(ctx, K.convert(a**2 / 3).numer, K.convert(a**2 / 3).denom, extra=1)
    assert num.to_dict() == {(2, 0, 0): 1} and den.to_dict() == {(0, 0, 0): 3}


def test_a_variable_placed_before_the_parameters():
    ctx = flint.fmpz_mpoly_ctx.get(("v", "p0", "p1"), "lex")
    num, den = integral(ctx, K.convert(a * b / 5).numer, K.convert(a * b / 5).denom, before=1)
    assert num.to_dict() == {(0, 1, 1): 1} and den.to_dict() == {(0, 0, 0): 5}


x, lam = sp.symbols("x lambda")


def random_poly(rng: random.Random, degree: int) -> sp.Expr:
    """A polynomial in x with rational functions of a, b as coefficients."""
    return sum(
        sp.Rational(rng.randint(-5, 5), rng.randint(1, 3))
        * a ** rng.randint(0, 2)
        * b ** rng.randint(0, 1)
        / (1 + rng.randint(0, 1) * a)
        * x**i
        for i in range(degree + 1)
    )


def test_the_resultant_and_discriminant_are_sylvesters_over_q_of_parameters():
    """Against the Sylvester determinant (sympy's own subresultant resultant has the
    opposite sign for some degrees, e.g. Res(x, x^3 + 1) = 1 but sympy gives -1) and
    sympy's discriminant, on random polynomials with denominators."""
    rng = random.Random(7)
    checked = 0
    while checked < 6:
        f = sp.Poly(random_poly(rng, rng.randint(1, 3)), x, domain=K)
        g = sp.Poly(random_poly(rng, rng.randint(1, 3)), x, domain=K)
        if f.degree() < 1 or g.degree() < 1:
            continue
        sylvester_det = sylvester(f.as_expr(), g.as_expr(), x).det()
        assert sp.cancel(resultant(f, g) - sylvester_det) == 0
        assert sp.cancel(discriminant(f) - sp.discriminant(f.as_expr(), x)) == 0
        checked += 1
    assert resultant(sp.Poly(x, x, domain=K), sp.Poly(x**3 + 1, x, domain=K)) == 1
    # a mutated coefficient changes the value
    f, g = sp.Poly(x**2 - a, x, domain=K), sp.Poly(x - b, x, domain=K)
    assert resultant(f, g) == b**2 - a and discriminant(f) == 4 * a
    assert resultant(f, sp.Poly(x - b - 1, x, domain=K)) != b**2 - a


def test_a_resultant_of_expressions_keeps_an_extra_symbol_rational():
    value = resultant_in(x**2 - a, x - lam / b, x)
    assert sp.cancel(value - (lam**2 / b**2 - a)) == 0
    assert resultant_in(x**2 - 2, x - 1, x) == -1
    assert resultant_in(x, x**3 + 1, x) == 1  # sympy's resultant gives -1


def test_a_resultant_with_a_constant_over_q_is_its_power():
    """Res(f, c) = c^deg f: a constant over Q has one coefficient, whose denominator
    alone is the lcm (sympy's ``ilcm`` refuses a single argument)."""
    assert resultant_in(x**2 - 2, sp.Rational(3, 2), x) == sp.Rational(9, 4)
    assert resultant_in(sp.Integer(5), x**3 + x + 1, x) == 125
