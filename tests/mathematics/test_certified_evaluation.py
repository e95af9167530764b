"""Certified evaluation: exact where rational, enclosures that never lie elsewhere."""

from fractions import Fraction

import pytest
import sympy as sp

from registry.mathematics.certified_evaluation import At, OutsideDomain, evaluate

x, y = sp.symbols("x y", real=True)


def test_rational_values_are_exact():
    v = evaluate(x**2 / 3 - y, {x: sp.Rational(1, 2), y: sp.Rational(1, 12)})
    assert v.exact == Fraction(0) and not v.certainly_nonzero()


def test_perfect_powers_stay_exact():
    v = evaluate(sp.sqrt(x**2 + y**2) + sp.cbrt(x + 4), {x: 4, y: 3})
    assert v.exact == Fraction(7)


def test_irrational_values_are_enclosed():
    v = evaluate(sp.sqrt(x) - sp.Rational(14142, 10000), {x: 2})
    assert v.exact is None and v.certainly_nonzero()
    assert abs(float(v.approx()) - 1.35623730950488e-5) < 1e-18


def test_an_irrational_zero_is_never_called_nonzero():
    v = evaluate((x - sp.sqrt(2)) ** 3 + sp.atan(x) - sp.atan(sp.sqrt(2)), {x: sp.sqrt(2)})
    assert not v.certainly_nonzero()


@pytest.mark.parametrize(
    "expr, value",
    [
        (sp.atan(x), sp.atan(sp.Rational(1, 3))),
        (sp.asin(x), sp.asin(sp.Rational(1, 3))),
        (sp.acos(x), sp.acos(sp.Rational(1, 3))),
        (
            sp.sinh(x) * sp.cosh(x) + sp.tanh(x),
            sp.sinh(sp.Rational(1, 3)) * sp.cosh(sp.Rational(1, 3)) + sp.tanh(sp.Rational(1, 3)),
        ),
        (sp.exp(x) * sp.log(x + 1) + sp.tan(x) * sp.sin(x) * sp.cos(x), None),
        (sp.pi * x + sp.E, None),
    ],
)
def test_enclosures_contain_the_true_value(expr, value):
    third = sp.Rational(1, 3)
    v = evaluate(expr, {x: third})
    truth = sp.N(value if value is not None else expr.subs(x, third), 50)
    lo, hi = (float(t) for t in v.text().strip("[]").split(","))
    assert lo <= float(truth) <= hi
    assert hi - lo < 1e-15


@pytest.mark.parametrize(
    "expr, point",
    [
        (1 / x, {x: 0}),
        (sp.sqrt(x), {x: -1}),
        (sp.log(x), {x: 0}),
        (sp.asin(x), {x: 2}),
        (x ** sp.Rational(-1, 2), {x: 0}),
    ],
)
def test_undefined_points_are_reported(expr, point):
    with pytest.raises(OutsideDomain):
        evaluate(expr, point)


def test_one_point_many_expressions_gives_what_evaluate_gives():
    point = {x: sp.Rational(3, 2), y: sp.sqrt(2)}
    at = At(point)
    exprs = [
        sp.sqrt(x**2 + y**2) * x,  # a radical shared with the next expression
        sp.sqrt(x**2 + y**2) - y,
        x**2 / 3 - sp.Rational(3, 4),
        sp.atan(y) + x,
    ]
    for expr in exprs:
        mine, theirs = at(expr), evaluate(expr, point)
        assert mine.exact == theirs.exact
        assert mine.text() == theirs.text()
    assert at(x**2 / 3 - sp.Rational(3, 4)).exact == 0


def test_one_point_reports_each_undefined_expression_and_goes_on():
    at = At({x: sp.Integer(0), y: sp.Integer(2)})
    with pytest.raises(OutsideDomain):
        at(1 / x)
    with pytest.raises(OutsideDomain):
        at(sp.sqrt(x - y))
    assert at(y**2 + x).exact == Fraction(4)
