"""Mapping calls over items elsewhere, results back in the items' order.

A ``Mapper`` runs calls where it runs them (``distributed.searches.cluster_mapper``: on
a Dask cluster) and yields their results in any order; ``in_order`` puts them back in
order, and names an index that never came back instead of dropping it.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Iterator, Sequence
from typing import Any

from ..errors import DiscoveryError

#: Runs calls elsewhere (``registry.distributed.searches``: on a Dask cluster).
#: ``mapper(fn, items, seconds)`` yields ``(index, value)`` as the calls complete, in any
#: order, each index once: ``value`` is ``fn(items[index])``, or an exception saying why
#: there is none; ``seconds`` bounds each call (None: no bound). Closing the iterator
#: stops what still runs.
Mapper = Callable[
    [Callable[[Any], Any], Sequence[Any], float | None],
    Generator[tuple[int, Any], None, None],
]
#: Seconds a call given to a mapper may run past the search's budget before it is
#: killed: the budget's own alarm, here, stops the search first.
MAPPER_GRACE = 5.0


def in_order(calls: Iterator[tuple[int, Any]], count: int) -> Iterator[tuple[int, Any]]:
    """A mapper's (index, result) pairs, which come in any order, in the order of the
    indices 0..count-1, each as soon as those before it are in; an index the mapper
    never returned comes as a DiscoveryError. The mapper is closed at the end (at once,
    also when the consumer stops in the middle: the budget ran out)."""
    arrived: dict[int, Any] = {}
    following = 0
    try:
        for index, value in calls:
            arrived[index] = value
            while following in arrived:
                yield following, arrived.pop(following)
                following += 1
        for index in range(following, count):
            yield index, arrived.pop(index, DiscoveryError("no result came back"))
    finally:
        close = getattr(calls, "close", None)
        if close is not None:
            close()
