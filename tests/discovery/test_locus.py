"""The rank-drop locus of a parametric matrix: constant-pivot elimination keeps the
rank, maximal minors hold every component, and points and components come out exact."""

from __future__ import annotations

import random

import sympy as sp
from sympy import QQ
from sympy.polys.rings import PolyRing

from registry.discovery.locus import bareiss, drop_locus, eliminate_constants, rank_mod

RING = PolyRing(["l", "z"], QQ, "lex")
L, Z = RING.gens
ONE = PolyRing(["l"], QQ, "lex")
L1 = ONE.gens[0]


def rows_of(matrix):
    return [{j: v for j, v in enumerate(row) if v} for row in matrix]


def test_bareiss_is_the_determinant():
    m = [[L, Z, RING.one], [Z, L + 1, L], [RING.one, RING(2), Z]]
    expected = sp.Matrix([[e.as_expr() for e in row] for row in m]).det()
    assert sp.expand(bareiss(m).as_expr() - expected) == 0


def test_eliminating_constant_pivots_keeps_the_rank_at_every_point():
    matrix = [[RING(1), L, Z], [RING(2), 2 * L, L * Z], [RING(0), Z - 1, L - 2]]
    taken, rest = eliminate_constants(rows_of(matrix))
    rnd = random.Random(0)
    for _ in range(10):
        point = [rnd.randrange(1, 100), rnd.randrange(1, 100)]
        full = sp.Matrix(
            [[e.as_expr().subs({"l": point[0], "z": point[1]}) for e in row] for row in matrix]
        )
        assert taken + rank_mod(rest, point) == full.rank()


def test_one_parameter_points_are_the_rational_roots_where_the_rank_drops():
    # diag(l - 2, l - 3): rank 2 except at l = 2 and l = 3
    matrix = [{0: L1 - 2}, {1: L1 - 3}]
    locus = drop_locus(matrix, 2, 1, random.Random(1))
    assert sorted(p[sp.Symbol("l")] for p in locus.points) == [2, 3]
    assert not locus.components and not locus.undecided


def test_an_irrational_factor_where_the_rank_does_not_drop_is_dismissed():
    # rows [1 - ...] crafted: rank 1 everywhere; projections may still vanish at roots of
    # a random quadratic, which the modular check dismisses
    matrix = [{0: L1**2 - 2, 1: ONE.one}]
    locus = drop_locus(matrix, 1, 1, random.Random(2))
    assert locus.points == [] and locus.undecided == []


def test_a_line_and_an_isolated_point_in_two_parameters():
    # rank 2 generically; rank 1 on the whole line l = 1, and at the point (2, 0)
    matrix = [{0: L - 1}, {1: (L - 1) * (L - 2) + (L - 1) * Z}, {1: Z * (L - 1)}]
    locus = drop_locus(matrix, 2, 2, random.Random(3))
    assert (sp.Symbol("l"), sp.Integer(1)) in locus.components
    assert not locus.undecided


def test_isolated_points_come_from_the_gcd_of_resultants():
    # rank 2 except where l - 2 = z = 0
    matrix = [{0: RING.one}, {1: L - 2}, {1: Z}]
    locus = drop_locus(matrix, 2, 2, random.Random(4))
    assert {sp.Symbol("l"): 2, sp.Symbol("z"): 0} in [
        {k: v for k, v in p.items()} for p in locus.points
    ]
    assert locus.components == []
