"""A search run: integral searches that are recorded, and reused when recorded before.

The policy of ``Registry.discover`` and ``Registry.survey``: a stored case version
already searched with the same options by this code version reuses that search unless
the run is fresh; a recorded search's generic integrals become claims of the searched
version and each special set a derived case (``language.case_writer``), so that the
next audit decides them like any literature claim. The searches themselves run in this
process, in local processes or on a Dask cluster (``discovery``, ``distributed``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from ..discovery.search import discover, search_options
from ..discovery.survey import searched, stated_options
from ..distributed.scheduler import check_same_code, cluster_client
from ..distributed.searches import cluster_mapper, discover_on_cluster
from ..errors import UnknownCaseError
from ..execution.local import default_jobs
from ..language.case_writer import derived_case_text
from ..language.casefile import load_case, parse_case_text
from ..model import Case, Equation, Search, SearchOptions
from ..presentation.search_output import search_document, statement
from ..store import conversions
from ..store.database import Store, StoredCase
from ..version import code_version
from . import DEFAULT_SEARCH_BUDGET

if TYPE_CHECKING:
    from distributed import Client


@dataclass(frozen=True)
class SearchReport:
    """One integral search: its outcome, its number in the registry (None when it was
    not recorded), whether a stored search was reused, and the ids of the derived cases
    that hold the integrals of its special sets as claims."""

    search: Search
    number: int | None = None
    reused: bool = False
    derived: tuple[str, ...] = ()
    #: What happened on the Dask cluster that ran the search (workers lost, candidate
    #: sets searched again elsewhere), one line each; empty without a scheduler.
    events: tuple[str, ...] = ()

    def document(self) -> dict:
        """The JSON document of docs/json-output.md (Search output) for this search."""
        document = search_document(self.search)
        if self.number is not None:
            document["search"] = self.number
            document["reused"] = self.reused
        if self.derived:
            document["derived_cases"] = list(self.derived)
        if self.events:
            document["events"] = list(self.events)
        return document


def search_run(
    store: Store,
    target: str | os.PathLike | Case,
    *,
    degree: int = 4,
    weights: tuple[int, int] = (1, 2),
    on: Sequence[str | Equation] = (),
    free: Sequence[str] = (),
    relations: bool = False,
    record: bool = False,
    fresh: bool = False,
    budget: float | None = DEFAULT_SEARCH_BUDGET,
    jobs: int = 1,
    progress: Callable[[int, int, str], None] | None = None,
    scheduler: str | Client | None = None,
) -> SearchReport:
    """``Registry.discover``: search a case file, a stored case or a ``Case``; reuse a
    search recorded before, record this one if asked."""
    if record:
        store.require_writer("record a search")
    case, stored = _search_target(store, target)
    options = search_options(
        case, degree=degree, weights=weights, on=on, free=free, relations=relations
    )
    reused = None if fresh else _reused_search(store, case, stored, options)
    if reused is not None:
        return reused
    search, events = _run_search(case, options, budget, jobs, progress, scheduler)
    if not record:
        return SearchReport(search, events=events)
    if stored is None:
        store.add_case(case)
        (stored,) = [s for s in store.case_versions([case.id])]
    return replace(_recorded(store, stored, case, search), events=events)


def survey_run(
    store: Store,
    case_ids: Sequence[str] | None = None,
    *,
    fresh: bool = False,
    budget: float | None = DEFAULT_SEARCH_BUDGET,
    jobs: int | None = None,
    progress: Callable[[int, int, str], None] | None = None,
    scheduler: str | Client | None = None,
) -> list[SearchReport]:
    """``Registry.survey``: the stated searches of every case (or the named ones),
    reused where recorded before, each recorded as it finishes."""
    store.require_writer("record the survey's searches")
    planned = [
        (stored, case, options)
        for stored in store.case_versions(list(case_ids) if case_ids else None)
        for case in [stored.parse()]
        for options in stated_options(case)
    ]
    reports: dict[int, SearchReport] = {}
    for i, (stored, case, options) in enumerate(planned):
        reused = None if fresh else _reused_search(store, case, stored, options)
        if reused is not None:
            reports[i] = reused
    todo = [i for i in range(len(planned)) if i not in reports]
    work = [(planned[i][1], planned[i][2]) for i in todo]
    jobs = default_jobs() if jobs is None else jobs

    def record(results: Iterable[Search]) -> None:
        for done, (i, search) in enumerate(zip(todo, results, strict=True)):
            if progress is not None:
                progress(done + 1, len(todo), search.case)
            reports[i] = _recorded(store, planned[i][0], planned[i][1], search)

    if scheduler is None or not work:
        record(searched(work, budget=budget, jobs=jobs))
    else:
        with cluster_client(scheduler) as client:
            check_same_code(client, code_version)
            record(searched(work, budget=budget, mapper=cluster_mapper(client)))
    return [reports[i] for i in range(len(planned))]


def _reused_search(
    store: Store, case: Case, stored: StoredCase | None, options: SearchOptions
) -> SearchReport | None:
    """The stored search of this case version with these options by this code
    version, or None."""
    if stored is None:
        return None
    found = store.stored_search(stored.pk, options, code_version())
    if found is None:
        return None
    number, row, rows = found
    search = conversions.search(row, case.id, case.content_hash, rows, options.on)
    return SearchReport(search, number, reused=True)


def _recorded(store: Store, stored: StoredCase, case: Case, search: Search) -> SearchReport:
    """Store a search of a stored case version, with a derived case per special set."""
    derived = [
        parse_case_text(derived_case_text(case, s, search.options), f"<derived from {case.id}>")
        for s in search.special
    ]
    number = store.record_search(stored.pk, search, code_version(), statement(search), derived)
    return SearchReport(search, number, derived=tuple(c.id for c in derived))


def _search_target(
    store: Store, target: str | os.PathLike | Case
) -> tuple[Case, StoredCase | None]:
    """The case to search and its stored version (None when not stored)."""
    if isinstance(target, Case):
        case = target
    elif Path(target).is_file():
        case = load_case(target)
    else:
        (stored,) = store.case_versions([str(target)])
        return stored.parse(), stored
    try:
        versions = store.case_versions([case.id], latest_only=False)
    except UnknownCaseError:
        return case, None
    same = [s for s in versions if s.content_hash == case.content_hash]
    return case, (same[-1] if same else None)


def discover_file(
    path: str | os.PathLike,
    *,
    degree: int = 4,
    weights: tuple[int, int] = (1, 2),
    on: Sequence[str | Equation] = (),
    free: Sequence[str] = (),
    relations: bool = False,
    budget: float | None = DEFAULT_SEARCH_BUDGET,
    jobs: int = 1,
    progress: Callable[[int, int, str], None] | None = None,
    scheduler: str | Client | None = None,
) -> SearchReport:
    """Search a case file without a database (``Registry.discover`` has the options)."""
    case = load_case(path)
    options = search_options(
        case, degree=degree, weights=weights, on=on, free=free, relations=relations
    )
    search, events = _run_search(case, options, budget, jobs, progress, scheduler)
    return SearchReport(search, events=events)


def _run_search(
    case: Case,
    options: SearchOptions,
    budget: float | None,
    jobs: int,
    progress: Callable[[int, int, str], None] | None,
    scheduler: str | Client | None,
) -> tuple[Search, tuple[str, ...]]:
    """A search in this process, in ``jobs`` processes, or on the Dask cluster of
    ``scheduler``; and what happened on the cluster, one line each."""
    if scheduler is None:
        return discover(case, options, budget=budget, jobs=jobs, progress=progress), ()
    events: list[str] = []
    with cluster_client(scheduler) as client:
        check_same_code(client, code_version)
        search = discover_on_cluster(
            client,
            case,
            options,
            budget=budget,
            progress=progress,
            on_event=lambda event: events.append(str(event)),
        )
    return search, tuple(events)
