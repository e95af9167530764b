"""Irreducible components of polynomial systems by Groebner bases and shape position:
families and points, the origin left out, points on families dropped, parameters."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from registry.mathematics import mechanics as mech
from registry.mathematics.balances import balance_equations
from registry.mathematics.groebner import groebner
from registry.mathematics.prime_components import (
    _Algebra,
    _Decomposition,
    _maximal,
    components,
    same_components,
)
from registry.mathematics.weighted import split_field

x, y, z, a = sp.symbols("x y z a")
B, C, B1, B2, B3 = sp.symbols("B C b1 b2 b3")
g1, g2, g3 = mech.AXIS


def points(component):
    """The component's points as sets of coordinates, from the roots of its polynomial."""
    u = component.symbol
    return {
        tuple(sp.expand(h.subs(u, r)) for h in component.coordinates.values())
        for r in sp.roots(component.minimal.as_expr(), u)
    }


def test_a_family_and_isolated_points_with_the_points_on_the_family_dropped():
    # x (x^2 - 2) = 0, x y = 0: the line x = 0 (its origin included), and x = +-sqrt 2, y = 0
    found = components([x * (x**2 - 2), x * y], [x, y])
    assert [c.dimension for c in found] == [1, 0]
    line, pair = found
    assert line.free == (y,) and line.vanishes(x) and not line.vanishes(y)
    assert points(pair) == {(sp.sqrt(2), 0), (-sp.sqrt(2), 0)}
    # (0, 0) is on the line: no separate component, although it solves the system
    assert len(components([x * (x**2 - 2), x * y, y * (y - 1)], [x, y])) == 2


def test_components_are_kept_once_and_only_those_inside_another_are_dropped():
    def one(equations):
        (component,) = components(equations, [x, y], origin=())
        return component

    pair = one([x**2 - 2, y])  # (+-sqrt 2, 0)
    shifted = one([x**2 - 2, y - 1])  # the same x, another y: same degree and form
    other = one([x**2 - 3, y])  # same degree, another minimal polynomial
    line, origin = one([x]), one([x, y])
    assert pair.element == shifted.element and pair.degree == other.degree == 2
    kept = _maximal([pair, shifted, other, one([y, x**2 - 2]), origin, line])
    assert kept[0] is line and len(kept) == 4  # the origin lies on the line
    assert {tuple(sorted(points(c))) for c in kept[1:]} == {
        tuple(sorted(points(c))) for c in (pair, shifted, other)
    }


def test_the_origin_is_left_out_and_a_prime_component_keeps_conjugate_points_together():
    found = components([x**2 - 2 * y**2, y**3 - 2 * y], [x, y])
    degrees = sorted(c.degree for c in found)
    assert degrees == [2, 2]  # (+-2, +-sqrt 2): two pairs of conjugates; (0, 0) dropped
    assert set().union(*(points(c) for c in found)) == {
        (s * 2, t * sp.sqrt(2)) for s in (1, -1) for t in (1, -1)
    }


def test_a_multiple_point_is_found_once():
    (point,) = components([x**2 - 2 * x + 1, (y - x) ** 3], [x, y])
    assert points(point) == {(1, 1)} and point.degree == 1


def test_a_point_no_coordinate_separates_is_put_in_shape_position_by_a_linear_form():
    # x^2 = 1, y^2 = 1: neither coordinate separates the four points
    found = components([x**2 - 1, y**2 - 1, z - x * y], [x, y, z])
    assert sum(c.degree for c in found) == 4
    assert set().union(*(points(c) for c in found)) == {
        (s, t, s * t) for s in (1, -1) for t in (1, -1)
    }


def test_parameters_stay_symbols_of_the_ground_field():
    (component,) = components([x**2 - a * y, y - 2], [x, y], [a])
    assert component.domain == sp.QQ.frac_field(a)
    assert component.degree == 2 and component.vanishes(x**2 - 2 * a)
    # over Q(a), x^2 = a^2 splits: two components
    assert len(components([x**2 - a * y, y - a], [x, y], [a])) == 2


def test_a_component_over_special_parameter_values_is_found_with_the_parameter_as_unknown():
    # x (y - a) = 0, x^2 = a: generically x = +-sqrt a, y = a; at a = 0 also x = 0, y free
    generic, special = components([x * (y - a), x**2 - a], [x, y, a], origin=[x, y])
    assert generic.free == (a,) and generic.vanishes(y - a)
    assert special.free == (y,) and special.vanishes(a) and special.vanishes(x)


def test_over_parameters_a_finite_system_is_split_by_the_values_of_its_last_variable():
    # (y - 1)(y^2 - a) = 0, x^2 = y + a: y = 1 with x = +-sqrt(1 + a) (a pair over Q(a)),
    # and y = +-sqrt(a) with x^2 = y + a (four conjugate points); y's values fall into the
    # factors y - 1 and y^2 - a, and each part is decomposed on its own
    found = components([(y - 1) * (y**2 - a), x**2 - y - a], [x, y], [a])
    assert sorted(c.degree for c in found) == [2, 4]
    pair = next(c for c in found if c.degree == 2)
    assert pair.vanishes(y - 1) and pair.vanishes(x**2 - 1 - a)
    quartet = next(c for c in found if c.degree == 4)
    assert quartet.vanishes(y**2 - a) and quartet.vanishes(x**2 - y - a)
    assert not quartet.vanishes(y - 1)


def test_the_point_kept_as_polynomials_is_the_point_its_expressions_give():
    # the decomposition keeps the coordinates in u as it solved them (reading large ones
    # back from expressions cost most of an so(4) analysis): the same polynomials, for
    # isolated points and for a family over Q(a, y)
    systems = [[(y - 1) * (y**2 - a), x**2 - y - a], [x**2 - a * y, z - x - y]]
    for equations, variables in zip(systems, ([x, y], [x, y, z]), strict=True):
        for c in components(equations, variables, [a]):
            assert c.polynomials is not None
            bound = [v for v in variables if v not in c.free]
            read = [sp.Poly(c.coordinates[v], c.symbol, domain=c.domain) for v in bound]
            assert list(c.point) == read
            assert all(c.vanishes(e) for e in equations)


def test_a_split_by_values_keeps_every_point_when_one_value_is_shared():
    # y takes the value a at three points of different fields: no split by y's values
    # can separate them, and each is still found; with y = 1 two more points
    found = components(
        [(y - a) * (y - 1), (y - 1) * (x**3 - 2), (y - a) * (x**2 - a - 1)], [x, y], [a]
    )
    assert sorted(c.degree for c in found) == [2, 3]
    assert any(c.vanishes(y - 1) and c.vanishes(x**2 - a - 1) for c in found)
    assert any(c.vanishes(y - a) and c.vanishes(x**3 - 2) for c in found)


def test_over_parameters_a_system_is_split_on_a_coordinate_hyperplane():
    # x (x^2 - a) = 0, y^2 = a x + 1: on x = 0 the points y = +-1, off it four conjugate
    # points x = +-sqrt a, y^2 = 1 + a x
    system = [x * (x**2 - a), y**2 - a * x - 1]
    decomposition = _Decomposition((x, y), (a,), random.Random(0))
    basis = groebner(system, [x, y], decomposition.k)
    (on, none), (off, nothing) = decomposition._hyperplane_split(basis, x).systems
    assert none == nothing == () and set(on.exprs) == {x, y**2 - 1}
    (quartet,) = components(off.exprs, [x, y], [a])
    assert quartet.degree == 4 and quartet.vanishes(x**2 - a)
    # y vanishes at none of the six points (a unit), and x lies in I + (x): no split
    assert decomposition._hyperplane_split(basis, y) is None
    on_basis = groebner([], [x, y], decomposition.k, known=on)
    assert decomposition._hyperplane_split(on_basis, x) is None
    found = components(system, [x, y], [a])
    assert sorted(c.degree for c in found) == [1, 1, 4]
    assert same_components(found, components(system, [x, y], [a], hyperplanes=False))


def test_a_unit_of_the_algebra_is_shown_by_its_determinant_at_a_value():
    """x (x^2 - a) = 0, y^2 = a x + 1 over Q(a): y vanishes at none of the six points
    (its multiplication matrix has a non-zero determinant), x at two of them (a zero
    determinant: no value shows a unit); with x shifted by 1 - a, at none again."""
    k = sp.QQ.frac_field(a)
    basis = groebner([x * (x**2 - a), y**2 - a * x - 1], [x, y], k)
    algebra = _Algebra(basis, (x, y), k)
    assert algebra.size == 6
    assert algebra.is_unit(y) and not algebra.is_unit(x)
    shifted = groebner([(x - 1 + a) * ((x - 1 + a) ** 2 - a), y**2 - a * x - 1], [x, y], k)
    assert _Algebra(shifted, (x, y), k).is_unit(x)


def test_values_shown_irreducible_at_one_value_of_the_parameters_split_nothing():
    """x^3 = a + 1, y = x^2 over Q(a): the values of x are the roots of u^3 - a - 1,
    irreducible at integer values of a, hence over Q(a) (no split, no determinant over
    Q(a)[u]); the values of y - x too. x (x^2 - a) splits into x and x^2 - a."""
    k = sp.QQ.frac_field(a)
    algebra = _Algebra(groebner([x**3 - a - 1, y - x**2], [x, y], k), (x, y), k)
    assert algebra.value_split(x) is None and algebra.value_split(y - x) is None
    split = _Algebra(groebner([x * (x**2 - a), y - 1], [x, y], k), (x, y), k).value_split(x)
    assert split is not None and set(split) in ({x, x**2 - a}, {x, a - x**2})  # up to sign


def kirchhoff_balances(potential, parameters, inertia=(1, B, C)):
    """The balance equations of Kirchhoff's equations (M and gamma both of weight 1)."""
    field = [sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0))]
    split = split_field(mech.STATE, field, (1,) * 6, parameters=parameters)
    return balance_equations(split)


def test_the_diagonal_kirchhoff_balances_over_five_parameters_are_all_found():
    # moments (1, B, C), potential (b1 g1^2 + b2 g2^2 + b3 g3^2)/2: over Q(B, C, b) the
    # decomposition splits on the hyperplanes first (without the splits it did not end
    # in ten minutes); at a sample value its points are every balance there
    equations = kirchhoff_balances((B1 * g1**2 + B2 * g2**2 + B3 * g3**2) / 2, (B, C, B1, B2, B3))
    found = components(equations, mech.STATE, (B, C, B1, B2, B3))
    assert all(c.dimension == 0 for c in found)
    assert all(all(c.vanishes(e) for e in equations) for c in found)
    sample = {B: 2, C: 3, B1: 1, B2: 5, B3: 7}
    there = components([e.subs(sample) for e in equations], mech.STATE)
    assert all(c.dimension == 0 for c in there)
    assert sum(c.degree for c in found) == sum(c.degree for c in there) == 16


@pytest.mark.slow
def test_clebschs_family_of_balances_is_put_in_shape_position_over_two_parameters():
    # on Clebsch's condition b2 = (B - 1)/(C - 1) (b1 = 0, b3 = 1) the balances form a
    # curve: eight points over Q(B, C, gamma3), one prime component; the linear algebra of
    # a small algebra finds its shape position (each form's lexicographic basis stalls)
    clebsch = (B - 1) / (C - 1)
    equations = kirchhoff_balances((clebsch * g2**2 + g3**2) / 2, (B, C))
    found = components(equations, mech.STATE, (B, C))
    (curve,) = [c for c in found if c.dimension == 1]
    assert curve.degree == 8
    assert all(curve.vanishes(e) for e in equations)
    assert not curve.vanishes(g1) and not curve.vanishes(mech.STATE[0])
