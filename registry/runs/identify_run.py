"""An identification run: which catalog cases each case the registry holds is the same
system as (``discovery.identification``), recorded per case version and reused.

The policy of ``Registry.identify``: every latest case version (or the named ones) is
compared with the latest version of every other case; a recorded identification of the
same version against the same catalog (a digest of its case versions) by this code
version is reused unless the run is fresh, or unless it ran out of time where this run
gives more. The comparisons run in this process, local processes or on a Dask cluster;
only this process writes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

from ..discovery.identification.catalog_index import CatalogIndex
from ..discovery.identification.identify import identify
from ..execution.executor import Executor, in_order
from ..execution.serving import Failure
from ..model import Case, CaseIdentification, SameSystem
from ..store.database import Store
from ..version import code_version

#: Seconds a comparison may run past an identification's budget before it is stopped:
#: the budget is looked at between cases, and one comparison can take a while.
OVERRUN = 60.0


def catalog_index(store: Store) -> CatalogIndex:
    """The identification index of the latest version of every case the registry holds
    (``discovery.identification.catalog_index``; each case's forms are computed once)."""
    return CatalogIndex.of(stored.parse() for stored in store.case_versions())


def identify_run(
    store: Store,
    case_ids: Sequence[str] | None,
    executor: Executor,
    *,
    fresh: bool = False,
    budget: float | None = None,
    progress: Callable[[int, int, str], None] | None = None,
) -> list[CaseIdentification]:
    """``Registry.identify``: each named case (default: every case) against the catalog,
    reused where recorded before, each recorded as it finishes; ``budget`` seconds per
    case (the cases left are named as skipped, never said to be other systems)."""
    store.require_writer("record identifications")
    versions = store.case_versions()
    digest = store.catalog_digest(versions)
    wanted = set(case_ids) if case_ids else None
    if wanted is not None:
        store.case_versions(sorted(wanted))  # UnknownCaseError for a case not held
    chosen = [s for s in versions if wanted is None or s.case_id in wanted]
    found: dict[int, CaseIdentification] = {}
    for i, stored in enumerate(chosen):
        reused = None if fresh else store.stored_identification(stored.pk, digest, code_version())
        if reused is not None and not (reused.skipped and _more_time(budget, reused)):
            found[i] = reused
    todo = [i for i in range(len(chosen)) if i not in found]
    if todo:
        cases = {s.pk: s.parse() for s in versions}
        index = CatalogIndex.of(cases.values())  # the versions digested
        items = [(cases[chosen[i].pk], index, budget) for i in todo]
        calls = executor.map(
            _identified,
            items,
            deadline=None if budget is None else budget + OVERRUN,
            label=lambda item: item[0].id,
            name="registry-identify",
        )
        for done, (k, outcome) in enumerate(in_order(calls, len(items))):
            stored = chosen[todo[k]]
            if isinstance(outcome, Failure):  # the call gave no result: nothing compared
                others = tuple(i for i in index.ids() if i != stored.case_id)
                why = f"no result came back: {outcome.reason}"
                outcome = CaseIdentification(stored.case_id, 0, "", skipped=others, note=why)
            result = replace(outcome, version=stored.version, catalog=digest)
            store.record_identification(stored.pk, result, code_version())
            found[todo[k]] = result
            if progress is not None:
                progress(done + 1, len(todo), stored.case_id)
    return [found[i] for i in range(len(chosen))]


def _more_time(budget: float | None, reused: CaseIdentification) -> bool:
    return budget is None or budget > reused.seconds


def _identified(item: tuple[Case, CatalogIndex, float | None]) -> CaseIdentification:
    """One case against the catalog (its own id left out), as plain data (its version and
    the catalog's digest are the caller's to fill in)."""
    case, index, budget = item
    found = identify(case.dynamics, index, exclude=(case.id,), budget=budget)
    same = tuple(
        SameSystem(
            s.case,
            tuple(sorted(s.values.items())),
            tuple(s.transformation.items()),
        )
        for s in found.same
    )
    note = "" if found.form is not None else index.unindexed().get(case.id, "")
    return CaseIdentification(
        case.id, 0, "", same, found.compared, found.skipped, found.failed, found.seconds, note=note
    )
