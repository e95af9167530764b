"""Mapping calls elsewhere (``registry/execution/mapping.py``): results that come in any
order are put back in order, a missing one is named, and the mapper is closed."""

from __future__ import annotations

from registry.errors import DiscoveryError
from registry.execution.mapping import in_order


def test_results_that_come_in_any_order_are_put_back_in_order_and_none_is_lost():
    closed = []

    def calls():
        try:
            yield from [(2, "c"), (0, "a"), (1, "b")]  # index 3 never comes back
        finally:
            closed.append(True)

    got = list(in_order(calls(), 4))
    assert [(i, v) for i, v in got[:3]] == [(0, "a"), (1, "b"), (2, "c")]
    assert got[3][0] == 3 and isinstance(got[3][1], DiscoveryError)
    assert closed == [True]
