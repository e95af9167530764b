"""Exact algebraic numbers: roots written in radicals or as CRootOf, balls that contain
them, the identification of a root among candidates, and arithmetic in k[u]/(g)."""

from __future__ import annotations

import random

import flint
import pytest
import sympy as sp

from registry.mathematics import algebraic

x, u, z, a = sp.symbols("x u z a")


def test_roots_are_radicals_where_short_and_crootof_otherwise():
    assert algebraic.exact_roots(sp.Poly(x**2 - 7, x)) == (-sp.sqrt(7), sp.sqrt(7))
    assert algebraic.exact_roots(sp.Poly(x**4 - 2, x)) == tuple(
        sorted(sp.roots(x**4 - 2, x), key=algebraic.numeric_key)
    )
    quintic = sp.Poly(x**5 - x - 1, x)
    assert algebraic.exact_roots(quintic) == tuple(sp.CRootOf(quintic, i) for i in range(5))


def test_over_a_field_of_rational_functions_only_quadratics_have_closed_forms():
    roots = algebraic.exact_roots(sp.Poly(x**2 - a, x, domain=sp.QQ.frac_field(a)))
    assert set(roots) == {sp.sqrt(a), -sp.sqrt(a)}
    cubic = sp.Poly(x**3 + a * x + 1, x, domain=sp.QQ.frac_field(a))
    assert algebraic.exact_roots(cubic) is None


def test_balls_contain_the_numbers_and_separate_the_roots():
    ball = algebraic.to_acb(sp.sqrt(2) + sp.I / 3)
    with algebraic.precision():
        assert ball.contains(flint.acb(flint.arb(2).sqrt(), flint.arb(1) / 3))
    root = sp.CRootOf(x**5 - x - 1, 0)
    value = algebraic.to_acb(root)
    assert abs(float(value.real.mid()) - 1.1673039782614187) < 1e-12
    candidates = [sp.CRootOf(x**5 - x - 1, i) for i in range(5)]
    assert algebraic.identify(value, candidates) == root
    with pytest.raises(algebraic.Unidentified):
        algebraic.identify(value, [sp.Integer(1), sp.Integer(2)])


def test_arithmetic_in_a_simple_extension():
    ext = algebraic.Extension(u, sp.Poly(u**2 - 2, u))
    inverse = ext.inverse(ext.poly(1 + u))  # 1/(1 + sqrt 2) = sqrt 2 - 1
    assert inverse.as_expr() == u - 1
    assert ext.coordinates(ext.element((u**3 + 1) / u)) == [2, sp.Rational(1, 2)]
    assert algebraic.minimal_polynomial(ext, ext.poly(u + 1), z).as_expr() == z**2 - 2 * z - 1
    with pytest.raises(ZeroDivisionError):
        ext.inverse(ext.poly(u**2 - 2))


def _same_at_random_values(a: sp.Expr, b: sp.Expr) -> bool:
    rng = random.Random(7)
    symbols = sorted(a.free_symbols | b.free_symbols, key=str)
    for _ in range(4):
        values = {s: sp.Rational(rng.randint(2, 40), rng.randint(1, 9)) for s in symbols}
        x, y = sp.N(a.xreplace(values), 40), sp.N(b.xreplace(values), 40)
        if abs(x - y) > sp.Float(10) ** -30 * (1 + abs(x)):
            return False
    return True


@pytest.mark.parametrize(
    "root",
    [
        sp.sqrt(3) + 2,
        (1 + sp.I * sp.sqrt(7)) / 2,
        sp.sqrt(sp.Symbol("B")) * sp.sqrt(-1 / (sp.Symbol("B") - sp.Symbol("C")))
        + sp.Symbol("B") * sp.sqrt(-1 / (sp.Symbol("B") ** 2 - 3 * sp.Symbol("C"))),
        sp.Symbol("a") ** sp.Rational(3, 2) - 1 / sp.sqrt(sp.Symbol("a") + 1),
        sp.Rational(5, 3),
    ],
)
def test_a_polynomial_at_a_root_in_square_roots_is_its_value(root):
    u, a, f = sp.symbols("u a f1")
    condition = (a / 3 + f**2) * u**3 - u**2 / (a + 2) + 5 * f * u - 1
    value = algebraic.value_at_root(condition, u, root)
    assert value is not None and _same_at_random_values(value, condition.subs(u, root))


def test_a_root_that_is_not_in_square_roots_is_left_to_the_caller():
    u, a = sp.symbols("u a")
    for root in (sp.cbrt(2), sp.sqrt(1 + sp.sqrt(a)), 1 / (1 + sp.sqrt(a))):
        assert algebraic.value_at_root(u**2 + a * u, u, root) is None
    assert algebraic.value_at_root(sp.sqrt(a) * u, u, sp.sqrt(2)) is None  # not over Q(a)


def test_a_root_s_own_symbols_outside_its_square_roots_stay_exact():
    u, x0 = sp.symbols("u x0")
    value = algebraic.value_at_root(u**2 - 2 * x0 * u, u, x0 + sp.sqrt(2))
    assert sp.expand(value - (2 - x0**2)) == 0
