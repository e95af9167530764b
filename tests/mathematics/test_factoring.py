"""Factoring through FLINT gives exactly sympy.factor's form (so residuals and corrections
read the same), and leaves what is not a rational function over Q to sympy."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from registry.mathematics.factoring import coefficient_and_factors, factor, factor_element

A, B, C = sp.symbols("A B C", positive=True)
M1, M3, g1, g2, x, y = sp.symbols("M1 M3 gamma1 gamma2 x y")


def random_polynomial(rng: random.Random, names) -> sp.Expr:
    a, b, c = names
    return sum(
        sp.Rational(rng.randint(-4, 4), rng.randint(1, 3))
        * a ** rng.randint(0, 2)
        * b ** rng.randint(0, 2)
        * c ** rng.randint(0, 1)
        for _ in range(4)
    )


@pytest.mark.parametrize("names", [(x, y, A), (g1, g2, M3), (M1, g1, C)], ids=str)
def test_same_form_as_sympy_factor(names):
    rng = random.Random(str(names))
    for _ in range(60):
        numer = sp.expand(random_polynomial(rng, names) * random_polynomial(rng, names) ** 2)
        denom = sp.expand(random_polynomial(rng, names) * (B - 2))
        if denom == 0:
            continue
        expr = numer / denom
        assert factor(expr) == sp.factor(expr), expr


def test_content_and_signs():
    assert factor(-3 * B - 3) == sp.factor(-3 * B - 3)
    assert str(factor(-3 * B - 3)) == "-3*(B + 1)"
    assert str(factor(sp.Rational(2, 3) * x**2 - sp.Rational(2, 3))) == "2*(x - 1)*(x + 1)/3"
    assert factor(sp.Integer(0)) == 0
    assert factor(sp.Rational(5, 7)) == sp.Rational(5, 7)


@pytest.mark.parametrize("names", [(x, y, A), (g1, g2, M3)], ids=str)
def test_coefficient_and_factors_is_sympy_factor_list(names):
    # sympy.factor_list's coefficient and factors (in an order of their own)
    rng = random.Random(repr(names))
    for _ in range(40):
        expr = sp.expand(
            -random_polynomial(rng, names) * random_polynomial(rng, names) ** 2 * (B - 2)
        )
        c, factors = coefficient_and_factors(expr)
        c_sympy, factors_sympy = sp.factor_list(expr)
        assert c == c_sympy, expr
        assert sorted(factors, key=str) == sorted(factors_sympy, key=str), expr
        assert sp.expand(c * sp.Mul(*(f**e for f, e in factors)) - expr) == 0


def test_coefficient_and_factors_of_a_field_denominator():
    # the denominator of Gaire's Chaplygin ball: sympy's factoring drew random points and
    # took from 0.03 s to minutes on it, process by process
    I1, I2, I3, R, m = sp.symbols("I1 I2 I3 R m", positive=True)
    g3 = sp.Symbol("gamma3")
    J1, J2, J3 = (moment + R**2 * m for moment in (I1, I2, I3))
    inner = J1 * J2 * J3 - R**2 * m * (g1**2 * J2 * J3 + g2**2 * J1 * J3 + g3**2 * J1 * J2)
    c, factors = coefficient_and_factors(J1 * J3 * inner)
    assert c == -1  # sympy's sign: each factor's leading coefficient in its order is 1
    assert sorted(factors, key=str) == sorted([(J1, 1), (J3, 1), (sp.expand(-inner), 1)], key=str)
    assert coefficient_and_factors(sp.Integer(0)) == sp.factor_list(sp.Integer(0))
    assert coefficient_and_factors(sp.Rational(-4, 3)) == (sp.Rational(-4, 3), [])
    assert coefficient_and_factors(sp.sqrt(x) * (x**2 - 1)) == sp.factor_list(
        sp.sqrt(x) * (x**2 - 1)
    )


def test_factors_of_a_ring_element_are_sympys_up_to_sign():
    # FLINT's factors of an element of Q[x, y, A] are sympy's factor_list's, each
    # primitive over Z, with the same multiplicities
    from sympy.polys.rings import ring

    R, *gens = ring("x y A", sp.QQ)
    rng = random.Random(11)
    for _ in range(30):
        parts = [
            sum(
                sp.Rational(rng.randint(-4, 4), rng.randint(1, 3))
                * gens[0] ** rng.randint(0, 2)
                * gens[1] ** rng.randint(0, 2)
                * gens[2] ** rng.randint(0, 1)
                for _ in range(3)
            )
            for _ in range(2)
        ]
        p = parts[0] * parts[1] ** 2
        if p.is_ground:
            continue
        ours = factor_element(p)
        theirs = p.factor_list()[1]

        def signed(fs):
            return sorted(((f if f.LC > 0 else -f).monic(), k) for f, k in fs)

        assert signed(ours) == signed(theirs), p
        assert all(f.clear_denoms()[0] == 1 for f, _ in ours)  # integer coefficients
    assert factor_element(R(sp.Rational(3, 2))) == []


def test_what_is_not_rational_over_q_goes_to_sympy():
    f = sp.Function("f")
    for expr in (
        sp.sqrt(x) * (x**2 - 1),
        f(x) * (x**2 - 1),
        sp.Float(0.5) * (x**2 - 1),
        sp.sqrt(2) * (x**2 - 1),
    ):
        assert factor(expr) == sp.factor(expr)


def test_factors_with_coefficients_beyond_a_machine_word():
    # python-flint 0.9 raises OverflowError sorting such factors; the fallback factors them
    import flint

    from registry.mathematics.factoring import factor_mpoly

    ctx = flint.fmpz_mpoly_ctx.get(("u", "v"), "lex")
    u, v = ctx.gens()
    big = 10**30
    poly = -3 * (u + big) * (u - big) * (v + 1) ** 2 * (u * v - big * v + 7)
    content, factors = factor_mpoly(poly)
    assert content == -3
    assert sorted((str(f), e) for f, e in factors) == sorted(
        [(str(u + big), 1), (str(u - big), 1), (str(v + 1), 2), (str(u * v - big * v + 7), 1)]
    )
    product = content
    for f, e in factors:
        product *= f**e
    assert product == poly
    u_, v_ = sp.symbols("u v")
    expr = sp.expand(-3 * (u_ + big) * (u_ - big) * (v_ + 1) ** 2)
    assert factor(expr) == sp.factor(expr)  # the audit's display form, as before
