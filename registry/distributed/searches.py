"""Integral searches on a Dask cluster: a search's candidate sets through ``tasks.run_calls``.

An integral search (``discovery.search.discover``) finds the generic integrals and the
rank-drop locus of the free parameters in the client, then searches every candidate
set of the locus (a point, or a component) as a case of its own: the heavy part,
each with its exact kernels and the zero-test proofs of what it finds. Given a
``cluster_mapper``, those candidate searches run on the cluster, one task each, in
child processes of the workers (``children``), and come back in the candidates'
order: the search's result is the one the local workers give. A candidate whose
worker dies is searched again on another worker (``tasks``); one that cannot be
searched at all (its task given up, or killed past the search's budget) is named in
the search's coverage, which is then not complete. The client records the search.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Sequence
from typing import TYPE_CHECKING, Any

from ..discovery.search import discover
from ..errors import DiscoveryError
from ..execution.mapping import Mapper
from ..execution.serving import Failure
from ..model import Case, Search, SearchOptions
from .tasks import Event, run_calls

if TYPE_CHECKING:
    from distributed import Client


def _label(work: Any) -> str:
    """A candidate's name in the events: its equations (``lam = 1, z0 = 0``)."""
    when = work[-1] if isinstance(work, tuple) and work else ()
    return ", ".join(when) if isinstance(when, tuple) else str(work)


def cluster_mapper(
    client: Client,
    on_event: Callable[[Event], None] | None = None,
    label: Callable[[Any], str] = _label,
) -> Mapper:
    """A ``discovery.search.Mapper`` that runs each call as one task on the cluster of
    ``client``; a call that has no result (``children.Failure``) comes back as a
    DiscoveryError saying why."""

    def mapper(
        fn: Callable[[Any], Any], items: Sequence[Any], seconds: float | None
    ) -> Generator[tuple[int, Any], None, None]:
        calls = run_calls(
            client,
            fn,
            items,
            deadline=seconds,
            label=label,
            on_event=on_event,
            name="registry-search",
        )
        try:
            for index, outcome in calls:
                if isinstance(outcome, Failure):
                    where = f" on worker {outcome.worker}" if outcome.worker else ""
                    outcome = DiscoveryError(f"{outcome.kind}{where}: {outcome.reason}")
                yield index, outcome
        finally:
            calls.close()

    return mapper


def discover_on_cluster(
    client: Client,
    case: Case,
    options: SearchOptions | None = None,
    *,
    budget: float | None = None,
    seed: int = 0,
    progress=None,
    on_event: Callable[[Event], None] | None = None,
) -> Search:
    """``discover`` with its candidate sets searched on the cluster of ``client``; the
    same result as ``discover`` in this process or in local workers."""
    return discover(
        case,
        options,
        budget=budget,
        seed=seed,
        progress=progress,
        mapper=cluster_mapper(client, on_event),
    )
