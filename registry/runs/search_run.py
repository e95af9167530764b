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
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

from ..discovery.every_degree import bounded, every_degree, summary
from ..discovery.search import discover, search_options
from ..discovery.survey import searched, stated_options
from ..execution.executor import Executor
from ..language.case_writer import derived_case_text
from ..language.casefile import load_case, parse_case_text
from ..language.parser import Namespace, parse_equation
from ..model import Case, Equation, ExponentResult, Search, SearchOptions, Weights
from ..presentation.search_output import search_document, search_text, statement
from ..presentation.terminal import terminal_width
from ..presentation.text_table import wrapped
from ..settings import (
    BESIDE_SEARCH_EXPONENT_SECONDS,
    DEFAULT_SEARCH_SECONDS,
    DEFAULT_SURVEY_SECONDS,
)
from ..store import conversions
from ..store.database import Store, StoredCase
from ..version import code_version
from .exponents_run import beside_search, beside_searches
from .identify_run import catalog_index
from .targets import stored_target


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
    #: The Kovalevskaya analysis under the search's weights, combined with it (None for a
    #: search on a level set or of relations).
    exponents: ExponentResult | None = None

    @property
    def every_degree(self) -> str:
        """What the search and the exponents prove together at every degree
        (``discovery.every_degree``)."""
        return every_degree(self.search, self.exponents)

    @property
    def bounded(self) -> bool:
        """Whether every degree Yoshida's theorem allows lies within the complete search
        (``discovery.every_degree.bounded``)."""
        return bounded(self.search, self.exponents)

    def document(self) -> dict:
        """The JSON document of docs/json-output.md (Search output) for this search."""
        document = search_document(self.search)
        if self.exponents is not None:
            document["exponents"] = summary(self.exponents)
        document["every_degree"] = self.every_degree
        if self.number is not None:
            document["search"] = self.number
            document["reused"] = self.reused
        if self.derived:
            document["derived_cases"] = list(self.derived)
        if self.events:
            document["events"] = list(self.events)
        return document

    def text(self, width: int | None = None) -> str:
        """The search in plain text, as ``registry discover`` prints it, with what it and
        the exponents prove together at every degree, wrapped to ``width`` (None: the
        terminal's, ``presentation.terminal``)."""
        width = width or terminal_width()
        every = wrapped(f"at every degree: {self.every_degree}", width, subsequent="  ")
        return f"{search_text(self.search, width)}\n{every}"

    @property
    def statement(self) -> str:
        """The result in one sentence; with what it and the exponents prove at every degree
        where they can be combined."""
        combined = self.every_degree
        if combined.startswith("Nothing is stated"):
            return statement(self.search)
        return f"{statement(self.search)} {combined}"


@dataclass(frozen=True)
class SearchRequest:
    """What an integral search is asked to find: the ansatz (``degree``, ``weights`` by
    vector, the level set ``on``), the parameters whose special values are sought
    (``free``), Darboux polynomials instead of integrals (``relations``), the seconds
    the whole search may take; whether to store it (``record``) or search again
    instead of reusing a stored search (``fresh``); and whether to identify what it
    finds with the registry's cases (``identify``)."""

    degree: int = 4
    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None
    on: tuple[str | Equation, ...] = ()
    free: tuple[str, ...] = ()
    relations: bool = False
    budget: float | None = DEFAULT_SEARCH_SECONDS
    record: bool = False
    fresh: bool = False
    #: identify the special sets with the cases the registry holds (``same_as``)
    identify: bool = True

    def options(self, case: Case) -> SearchOptions:
        """The options for searching ``case`` (level sets parsed in its names)."""
        return search_options(
            case,
            degree=self.degree,
            weights=self.weights,
            on=self.on,
            free=self.free,
            relations=self.relations,
        )


def search_run(
    store: Store | None,
    target: str | os.PathLike | Case,
    request: SearchRequest,
    executor: Executor,
    progress: Callable[[int, int, str], None] | None = None,
) -> SearchReport:
    """``Registry.discover``: search a case file, a stored case or a ``Case``; reuse a
    search recorded before, record this one if asked. Without a store (a case file
    searched on its own), nothing is reused or recorded."""
    if request.record and store is not None:
        store.require_writer("record a search")
    if store is None:
        case, stored = (target if isinstance(target, Case) else load_case(target)), None
    else:
        case, stored = stored_target(store, target)
    options = request.options(case)
    reused = None
    if store is not None and not request.fresh:
        reused = _reused_search(store, case, stored, options, request.budget)
    if reused is not None:
        return replace(reused, exponents=beside_search(store, stored, case, options, executor))
    catalog = catalog_index(store) if store is not None and request.identify else None
    search = discover(
        case,
        options,
        budget=request.budget,
        executor=executor,
        progress=progress,
        catalog=catalog,
    )
    events = tuple(executor.events)
    if not request.record or store is None:
        found = beside_search(store, stored, case, options, executor)
        return SearchReport(search, events=events, exponents=found)
    if stored is None:
        store.add_case(case)
        (stored,) = [s for s in store.case_versions([case.id])]
    found = beside_search(store, stored, case, options, executor, record=True)
    return replace(_recorded(store, stored, case, search), events=events, exponents=found)


def survey_run(
    store: Store,
    case_ids: Sequence[str] | None,
    executor: Executor,
    *,
    fresh: bool = False,
    budget: float | None = DEFAULT_SURVEY_SECONDS,
    progress: Callable[[int, int, str], None] | None = None,
    exponent_budget: float = BESIDE_SEARCH_EXPONENT_SECONDS,
) -> list[SearchReport]:
    """``Registry.survey``: the stated searches of every case (or the named ones),
    reused where recorded before, each recorded as it finishes; each case's Kovalevskaya
    analysis beside them within ``exponent_budget`` seconds."""
    store.require_writer("record the survey's searches")
    planned = [
        (stored, case, options)
        for stored in store.case_versions(list(case_ids) if case_ids else None)
        for case in [stored.parse()]
        for options in stated_options(case)
    ]
    reports: dict[int, SearchReport] = {}
    for i, (stored, case, options) in enumerate(planned):
        reused = None if fresh else _reused_search(store, case, stored, options, budget)
        if reused is not None:
            reports[i] = reused
    todo = [i for i in range(len(planned)) if i not in reports]
    work = [(planned[i][1], planned[i][2]) for i in todo]
    results = searched(work, budget=budget, executor=executor)
    for done, (i, search) in enumerate(zip(todo, results, strict=True)):
        if progress is not None:
            progress(done + 1, len(todo), search.case)
        reports[i] = _recorded(store, planned[i][0], planned[i][1], search)
    found = beside_searches(store, planned, executor, exponent_budget)
    return [replace(reports[i], exponents=found[i]) for i in range(len(planned))]


def recorded_searches(store: Store, case_id: str | None = None) -> list[tuple[int, int, Search]]:
    """Every recorded search (of ``case_id``, or of every case), oldest first, as (its
    number, the case version searched, the ``Search``). A level set's equations are
    parsed in the names of the case version searched; only those versions are parsed."""
    names: dict[int, Namespace] = {}
    found = []
    for stored, row, rows in store.recorded_searches(case_id):
        texts = list(row.options.get("on") or ())
        if texts and stored.pk not in names:
            case = parse_case_text(stored.text, stored.path or stored.case_id)
            names[stored.pk] = Namespace(case.parameters, case.functions)
        on = [Equation(e, *parse_equation(e, names[stored.pk])) for e in texts]
        search = conversions.search(row, stored.case_id, stored.content_hash, rows, on)
        found.append((row.id, stored.version, search))
    return found


def _reused_search(
    store: Store,
    case: Case,
    stored: StoredCase | None,
    options: SearchOptions,
    budget: float | None,
) -> SearchReport | None:
    """The stored search of this case version with these options by this code
    version, or None; not one that ran out of time where ``budget`` gives more time than
    it had (a survey's short search does not stand in for a longer one asked for)."""
    if stored is None:
        return None
    found = store.stored_search(stored.pk, options, code_version())
    if found is None:
        return None
    number, row, rows = found
    search = conversions.search(row, case.id, case.content_hash, rows, options.on)
    if _ran_out(search) and (budget is None or budget > search.seconds):
        return None
    return SearchReport(search, number, reused=True)


def _ran_out(search: Search) -> bool:
    """Whether the search stopped at its time budget (its coverage says so)."""
    return any(part.startswith("time budget exceeded") for part in search.coverage)


def _recorded(store: Store, stored: StoredCase, case: Case, search: Search) -> SearchReport:
    """Store a search of a stored case version, with a derived case per special set."""
    derived = [
        parse_case_text(derived_case_text(case, s, search.options), f"<derived from {case.id}>")
        for s in search.special
    ]
    number = store.record_search(stored.pk, search, code_version(), statement(search), derived)
    return SearchReport(search, number, derived=tuple(c.id for c in derived))
