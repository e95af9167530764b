"""Terms a field can show: what rules a match out without solving."""

from __future__ import annotations

from registry.discovery.identification.supports import orders_allowed, permuted, reachable


def test_a_permutation_moves_a_term_to_its_new_axes():
    # d(L2)/dt holds gamma3: with axes 0 <-> 2 exchanged it is d(L2)/dt's gamma1
    assert permuted((1, (0, 0, 0, 0, 0, 1)), (2, 1, 0)) == (1, (0, 0, 0, 1, 0, 0))


def test_a_shift_lets_an_l_become_a_gamma():
    terms = reachable({(0, (0, 1, 1, 0, 0, 0))}, shifted=True, diagonal=True)
    assert (0, (0, 1, 0, 0, 0, 1)) in terms and (0, (0, 0, 0, 0, 1, 1)) in terms
    assert reachable({(0, (0, 1, 1, 0, 0, 0))}, shifted=False, diagonal=True) == {
        (0, (0, 1, 1, 0, 0, 0))
    }


def test_orders_that_leave_a_term_outside_are_ruled_out():
    mine = [(1, (0, 0, 0, 0, 0, 1))]
    theirs = frozenset({(1, (0, 0, 0, 0, 0, 1))})
    assert orders_allowed(mine, theirs, [(0, 1, 2), (2, 1, 0)]) == [(0, 1, 2)]
