"""The rank-drop locus of a parametric matrix: every set where the rank falls comes out
as an exact rational assignment, contained sets are left to the search of the larger
one, and what cannot be solved rationally is said."""

from __future__ import annotations

import random

import sympy as sp
from sympy import QQ
from sympy.polys.rings import PolyRing

from registry.discovery.locus import Locus, contains, drop_locus, rank_mod

RING = PolyRing(["l", "z"], QQ, "lex")
L, Z = RING.gens
ONE = PolyRing(["l"], QQ, "lex")
L1 = ONE.gens[0]
lam, z = sp.symbols("l z")


def rows_of(matrix):
    return [{j: v for j, v in enumerate(row) if v} for row in matrix]


def test_the_modular_rank_at_a_point_is_the_rank_there():
    matrix = [[RING(1), L, Z], [RING(2), 2 * L, L * Z], [RING(0), Z - 1, L - 2]]
    rnd = random.Random(0)
    for _ in range(10):
        point = [rnd.randrange(1, 100), rnd.randrange(1, 100)]
        full = sp.Matrix(
            [[e.as_expr().subs({"l": point[0], "z": point[1]}) for e in row] for row in matrix]
        )
        assert rank_mod(rows_of(matrix), point) == full.rank()


def test_one_parameter_points_are_the_rational_roots_where_the_rank_drops():
    # diag(lam - 2, lam - 3): rank 2 except at lam = 2 and lam = 3
    locus = drop_locus([{0: L1 - 2}, {1: L1 - 3}], 2, 1, random.Random(1))
    assert sorted(s[lam] for s in locus.sets) == [2, 3]
    assert not locus.undecided


def test_a_root_that_breaks_a_positivity_assumption_is_not_a_candidate():
    locus = drop_locus([{0: L1 + 2}, {1: L1 - 3}], 2, 1, random.Random(1), positive={0})
    assert locus.sets == [{lam: 3}]


def test_an_entry_that_cannot_vanish_under_the_assumptions_is_a_pivot():
    # lam**2 + 1 never vanishes; lam + z cannot for lam, z positive
    matrix = [{0: L**2 + 1, 1: Z}, {1: L + Z}]
    assert drop_locus(matrix, 2, 2, random.Random(2), positive={0, 1}).sets == []
    assert drop_locus(matrix, 2, 2, random.Random(2), positive={0}).sets == [{z: -lam}]


def test_a_line_and_an_isolated_point_in_two_parameters():
    # rank 2 generically; rank 1 on the whole line lam = 1, and at the point (2, 0)
    matrix = [{0: L - 1}, {1: (L - 1) * (L - 2) + (L - 1) * Z}, {1: Z * (L - 1)}]
    locus = drop_locus(matrix, 2, 2, random.Random(3))
    assert {lam: 1} in locus.sets
    matrix = [{0: RING.one}, {1: L - 2}, {1: Z}]
    assert drop_locus(matrix, 2, 2, random.Random(4)).sets == [{lam: 2, z: 0}]


def test_a_component_solved_for_a_parameter_it_is_linear_in():
    # rank 1 exactly where z*lam = 1; with a second row lam, also on lam = 0 (z free)
    (one,) = drop_locus([{0: L * Z - 1}], 1, 2, random.Random(5)).sets
    assert len(one) == 1 and sp.cancel((lam * z - 1).xreplace(one)) == 0
    sets = drop_locus([{0: L * Z - 1}, {1: L}], 2, 2, random.Random(5)).sets
    assert one in sets and {lam: 0} in sets and len(sets) == 2


def test_a_nonlinear_component_is_returned_as_an_algebraic_set():
    locus = drop_locus([{0: L**2 + Z**2 - 2}], 1, 2, random.Random(6))
    assert locus.sets == [] and locus.undecided == []
    (found,) = locus.algebraic
    assert found.text() == "l**2 + z**2 - 2 = 0"
    # one that has no real point is no special set at all
    none = drop_locus([{0: L1**2 + 2}], 1, 1, random.Random(6))
    assert none.undecided == [] and none.algebraic == []


def test_isolated_irrational_points_where_the_rank_holds_are_decided_exactly():
    # the first two entries vanish together at four points (lam**2 = 2, z**2 = lam z + 1),
    # where the third does not: rank 1 everywhere
    matrix = [{0: L**2 - 2}, {0: Z**2 - L * Z - 1}, {0: L**2 + Z**2 + 7}]
    locus = drop_locus(matrix, 1, 2, random.Random(7))
    assert locus.sets == [] and locus.undecided == [] and locus.algebraic == []
    # where it does vanish there too, the points are an algebraic set (decided by the
    # search at its points, over their number field)
    matrix[2] = {0: (L**2 - 2) * Z}
    locus = drop_locus(matrix, 1, 2, random.Random(7))
    assert locus.sets == [] and locus.undecided == []
    (found,) = locus.algebraic
    assert found.text() == "l = (z**2 - 1)/z, z**4 - 4*z**2 + 1 = 0" and found.units == (z,)


def test_a_set_inside_another_is_left_to_its_search():
    locus = Locus([{lam: 1}, {lam: 1, z: 0}, {z: lam}, {z: 1, lam: 1}])
    assert contains({z: lam}, {z: 1, lam: 1}) and not contains({lam: 1}, {lam: 1})
    assert locus.maximal() == [{lam: 1}, {z: lam}]


def test_a_set_where_another_parametrisation_is_undefined_stays():
    # z (lam - 1) = x: the parametrisation z = x/(lam - 1) misses its part lam = 1, x = 0
    x = sp.Symbol("x")
    big, small = {z: x / (lam - 1)}, {lam: 1, x: 0}
    assert not contains(big, small)
    assert contains(big, {lam: 2, x: 0, z: 0})  # inside, where it is defined
    assert not contains(big, {lam: 2, x: 0})  # z free there: not inside
    assert Locus([big, small]).maximal() == [small, big]  # polynomial ones first
    # two parametrisations of one set: the one without denominators is searched
    assert Locus([{x: z * (lam - 1)}, big]).maximal() == [{x: z * (lam - 1)}]
