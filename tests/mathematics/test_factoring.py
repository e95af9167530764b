"""Factoring through FLINT gives exactly sympy.factor's form (so residuals and corrections
read the same), and leaves what is not a rational function over Q to sympy."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from registry.mathematics.factoring import factor

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
