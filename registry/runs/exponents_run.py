"""A Kovalevskaya analysis run: analyses that are recorded, and reused when recorded
before.

The policy of ``Registry.analyse_exponents``: a stored case version already analysed with
the same options by this code version reuses that analysis unless the run is fresh;
with ``record`` the analysis is stored with the case version (a new row each time, the
earlier ones kept). The analysis itself runs in this process, its family's candidate
values in local processes or on a Dask cluster (``discovery.exponents``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from ..discovery.every_degree import every_degree
from ..discovery.exponents import (
    analyse_case,
    analysed,
    case_field,
    exponent_options,
    refused_by,
)
from ..errors import ExponentError
from ..execution.executor import Executor
from ..language.casefile import load_case
from ..model import Case, ExponentOptions, ExponentResult, SearchOptions, Weights
from ..presentation.exponents_output import exponents_text
from ..presentation.terminal import terminal_width
from ..settings import BESIDE_SEARCH_EXPONENT_SECONDS, DEFAULT_EXPONENT_SECONDS
from ..store.database import Store, StoredCase
from ..version import code_version
from .identify_run import catalog_index
from .targets import stored_target


@dataclass(frozen=True)
class ExponentReport:
    """One Kovalevskaya analysis: its result, its number in the registry (None when it
    was not recorded), whether a stored analysis was reused, and what happened on the
    Dask cluster that ran a family's candidates (one line each)."""

    result: ExponentResult
    number: int | None = None
    reused: bool = False
    events: tuple[str, ...] = ()

    def document(self) -> dict[str, Any]:
        """The JSON document of docs/json-output.md (Kovalevskaya exponents)."""
        document = dict(self.result.document)
        if self.number is not None:
            document["analysis"] = self.number
            document["reused"] = self.reused
        if self.events:
            document["events"] = list(self.events)
        return document

    def text(self, width: int | None = None) -> str:
        """The analysis in plain text, as ``registry exponents`` prints it, wrapped to
        ``width`` (None: the terminal's, ``presentation.terminal``)."""
        return exponents_text(self.result, width or terminal_width())

    @property
    def statement(self) -> str:
        return self.result.statement


@dataclass(frozen=True)
class ExponentRequest:
    """What an analysis is asked: the weights by vector (None: the case's own), the free
    parameters, the seconds it may take; whether to store it (``record``) or analyse
    again instead of reusing a stored analysis (``fresh``)."""

    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None
    free: tuple[str, ...] = ()
    budget: float | None = DEFAULT_EXPONENT_SECONDS
    record: bool = False
    fresh: bool = False

    def options(self, case: Case) -> ExponentOptions:
        return exponent_options(case, self.weights, self.free)


def exponents_run(
    store: Store | None,
    target: str | os.PathLike | Case,
    request: ExponentRequest,
    executor: Executor,
) -> ExponentReport:
    """``Registry.analyse_exponents``: analyse a case file, a stored case or a ``Case``;
    reuse an analysis recorded before, record this one if asked. Without a store (a case
    file or a ``Case`` analysed on its own), nothing is reused or recorded, and the sets
    a family's stratifications find are not named by catalog cases; nor are they by an
    empty registry."""
    if request.record and store is not None:
        store.require_writer("record an exponent analysis")
    if store is None:
        case, stored = (target if isinstance(target, Case) else load_case(target)), None
    else:
        case, stored = stored_target(store, target)
    options = request.options(case)
    if store is not None and stored is not None and not request.fresh:
        found = store.stored_exponents(stored.pk, options, code_version())
        if found is not None and not _outgrown(found[1], request.budget):
            return ExponentReport(found[1], found[0], reused=True)
    # with several free parameters each set found is named by the stored cases it is (an
    # empty registry names none: "matches no catalog case" would then say nothing)
    catalog = catalog_index(store) if store is not None and len(options.free) > 1 else None
    if catalog is not None and not catalog.entries:
        catalog = None
    result = analyse_case(case, options, budget=request.budget, executor=executor, catalog=catalog)
    events = tuple(executor.events)
    if not request.record or store is None:
        return ExponentReport(result, events=events)
    if stored is None:
        store.add_case(case)
        (stored,) = store.case_versions([case.id])
    number = store.record_exponents(stored.pk, result, code_version())
    return replace(ExponentReport(result, number), events=events)


def _outgrown(stored: ExponentResult, budget: float | None) -> bool:
    """Whether a stored analysis ran out of a smaller time budget than ``budget`` (None:
    none), so that it is made again rather than reused (a survey's analysis beside a
    search has ``BESIDE_SEARCH_EXPONENT_SECONDS``)."""
    spent = stored.document.get("budget")
    return not stored.decided and spent is not None and (budget is None or budget > spent)


def beside_search(
    store: Store | None,
    stored: StoredCase | None,
    case: Case,
    search: SearchOptions,
    executor: Executor,
    record: bool = False,
) -> ExponentResult | None:
    """The analysis a search is combined with (``discovery.every_degree``): under the
    search's weights, with its free parameter where it has one (else every parameter
    generic); a stored one of this case version and code version where there is one, else
    made now within ``BESIDE_SEARCH_EXPONENT_SECONDS`` (and recorded with a recorded
    search). None for a search on a level set or for relations, which it is not combined
    with; an analysis the method refuses is returned as such, with the reason."""
    if search.on or search.relations:
        return None
    options = _options(case, search)
    if options is None:
        return None
    if store is not None and stored is not None:
        found = store.stored_exponents(stored.pk, options, code_version())
        if found is not None:
            return found[1]
    try:
        result = analyse_case(
            case, options, budget=BESIDE_SEARCH_EXPONENT_SECONDS, executor=executor
        )
    except ExponentError as err:
        result = refused_by(case, options, err)
    if record and store is not None and stored is not None:
        store.record_exponents(stored.pk, result, code_version())
    return result


def beside_searches(
    store: Store,
    work: Sequence[tuple[StoredCase, Case, SearchOptions]],
    executor: Executor,
    budget: float = BESIDE_SEARCH_EXPONENT_SECONDS,
) -> list[ExponentResult | None]:
    """``beside_search`` for the survey's searches, in order: each case version analysed
    once within ``budget`` seconds (a stored analysis reused, unless it ran out of a
    smaller budget), the new ones by ``executor`` and recorded."""
    wanted: dict[tuple[int, str], tuple[StoredCase, Case, ExponentOptions]] = {}
    keys: list[tuple[int, str] | None] = []
    for stored, case, search in work:
        options = None if search.on or search.relations else _options(case, search)
        key = None if options is None else (stored.pk, repr(options.as_dict()))
        keys.append(key)
        if key is not None:
            wanted.setdefault(key, (stored, case, options))  # type: ignore[arg-type]
    found: dict[tuple[int, str], ExponentResult] = {}
    todo = []
    for key, (stored, _, options) in wanted.items():
        kept = store.stored_exponents(stored.pk, options, code_version())
        if kept is not None and not _outgrown(kept[1], budget):
            found[key] = kept[1]
        else:
            todo.append(key)
    work_items = [(wanted[k][1], wanted[k][2]) for k in todo]
    for key, result in zip(
        todo,
        analysed(work_items, budget=budget, executor=executor),
        strict=True,
    ):
        store.record_exponents(wanted[key][0].pk, result, code_version())
        found[key] = result
    return [None if k is None else found[k] for k in keys]


def _options(case: Case, search: SearchOptions) -> ExponentOptions | None:
    """The analysis options beside a search: its weights, and its one free parameter
    (several are analysed as generic parameters, and so is the one where the field has
    other parameters, which a family's analysis would need free or fixed); None where
    the weights name a vector the case does not have."""
    free = search.free if len(search.free) == 1 else ()
    try:
        options = exponent_options(case, search.weights, free)
    except ExponentError:
        return None
    if free:
        try:
            case_field(case, options)
        except ExponentError:
            return exponent_options(case, search.weights, ())
    return options


def site_exponents(store: Store) -> dict[str, Any]:
    """The newest Kovalevskaya analysis of every case that has one, with what it proves
    together with the newest search on the whole phase space of the same case version."""
    from ..presentation.site import ExponentEntry  # the site's own imports: only for it

    searches = store.newest_searches()
    found = {}
    for case_id, (number, version, result) in store.newest_exponents().items():
        searched = searches.get(case_id)
        combined = None
        if searched is not None and searched[1] == version:
            combined = every_degree(searched[2], result)
        found[case_id] = ExponentEntry(number, version, result, combined)
    return found
