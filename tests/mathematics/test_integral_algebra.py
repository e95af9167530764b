"""The field k[u]/(g) over Z[p]: sums, products, inverses and adjoined symbols agree
with sympy's arithmetic modulo g over Q(p) and over Q, for a g that is neither monic nor
integral; what leaves the algebra is in sympy's k[u, f] unchanged."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.mathematics.integral_algebra import IntegralAlgebra

u, a, b, f = sp.symbols("u a b f")
K = sp.QQ.frac_field(a, b)
G = sp.Poly(u**3 * (a + 1) / b - a * u + 2 / (a - b), u, domain=K)


def modulo(expr: sp.Expr, g: sp.Poly) -> sp.Expr:
    """sympy's remainder of a polynomial in u (and f) modulo g, over g's field."""
    return sp.Poly(expr, u, f, domain=g.domain).rem(sp.Poly(g.as_expr(), u, f, domain=g.domain))


def same(x: sp.Expr, y) -> bool:
    return sp.cancel(sp.together(x - y.as_expr())) == 0


def test_products_and_sums_agree_with_sympy_modulo_g_over_parameters():
    algebra = IntegralAlgebra(u, G, [f])
    p = u**2 / a + b * u - 1
    q = 3 * u**2 - u / (a + b)
    x, y = algebra.lift(sp.Poly(p, u, domain=K)), algebra.lift(sp.Poly(q, u, domain=K))
    product = algebra.reduce(x * y)
    assert same(algebra.poly(product).as_expr(), modulo(p * q, G))
    combined = algebra.reduce(x * y * algebra.variable(f) - y + 3)
    assert same(algebra.exported(combined).as_expr(), modulo(p * q * f - q + 3, G))
    # a changed coefficient is seen
    assert not same(algebra.poly(product).as_expr(), modulo((p + 1) * q, G))


def test_an_inverse_times_its_element_is_one():
    algebra = IntegralAlgebra(u, G)
    x = algebra.lift(sp.Poly(u**2 / a + b * u - 1, u, domain=K))
    inverse = algebra.inverse(x)
    assert algebra.poly(algebra.reduce(inverse * x)).as_expr() == 1
    constant = algebra.lift(sp.Poly(a / (b + 2), u, domain=K))  # an element of k
    assert algebra.poly(algebra.inverse(constant)).as_expr() == (b + 2) / a
    with pytest.raises(ZeroDivisionError):
        algebra.inverse(algebra.reduce(x - x))
    with pytest.raises(ValueError, match="adjoined"):
        IntegralAlgebra(u, G, [f]).inverse(IntegralAlgebra(u, G, [f]).variable(f))


def test_the_algebra_over_q_matches_sympys_invert():
    g = sp.Poly(2 * u**2 - 3, u, domain=sp.QQ)
    algebra = IntegralAlgebra(u, g)
    x = algebra.lift(sp.Poly(u / 3 + 1, u, domain=sp.QQ))
    expected = sp.rem(sp.invert(u / 3 + 1, 2 * u**2 - 3, u), 2 * u**2 - 3, u)
    assert sp.expand(algebra.poly(algebra.inverse(x)).as_expr() - expected) == 0
    square = algebra.poly(algebra.reduce(x * x)).as_expr()
    assert sp.expand(square - sp.rem((u / 3 + 1) ** 2, 2 * u**2 - 3, u)) == 0


def test_a_reduced_element_is_zero_exactly_when_g_divides_it():
    algebra = IntegralAlgebra(u, G)
    g_itself = algebra.lift(sp.Poly(G.as_expr() * (u + a), u, domain=K))
    assert g_itself.is_zero
    assert not algebra.lift(sp.Poly(G.as_expr() * (u + a) + 1 / b, u, domain=K)).is_zero
