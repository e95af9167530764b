"""An extra integral is printed in its simplest form modulo the trivial ones."""

from __future__ import annotations

from sympy import QQ

from registry.discovery.simplest_form import simplest


def test_the_representative_with_fewest_variables_then_terms_is_kept():
    # columns: x (uses variable 0), y (variable 1), z (variable 2)
    columns = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    trivial = [[QQ(0), QQ(1), QQ(1)]]  # y + z is trivial
    assert simplest([QQ(1), QQ(1), QQ(1)], trivial, columns, QQ) == [QQ(1), QQ(0), QQ(0)]
    # x + z and x - y use two variables each: the first (canonical) one is kept
    assert simplest([QQ(1), QQ(0), QQ(1)], trivial, columns, QQ) == [QQ(1), QQ(0), QQ(1)]


def test_without_a_trivial_vector_that_meets_it_the_vector_is_kept():
    columns = [(1, 0, 0), (0, 1, 0)]
    assert simplest([QQ(1), QQ(0)], [[QQ(0), QQ(1)]], columns, QQ) == [QQ(1), QQ(0)]
