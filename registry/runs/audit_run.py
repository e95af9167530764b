"""An audit run: the cases audited, results of unchanged cases reused, the run recorded.

The policy of ``Registry.audit``: a case version audited before by this code version
(``version.code_version``) reuses its stored audit unless the run is fresh; a reused
audit must be complete, free of crashed or killed checks and cover every claim
(``_reusable``); the others are audited here, in local workers or on a Dask cluster
(``execution``, ``distributed``), and each case is recorded as it finishes, so that an
interruption keeps what was done and marks the run interrupted.
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import closing
from dataclasses import asdict, dataclass, field
from typing import Any

from ..audit.case_audit import failed_case
from ..audit.outcome import CaseOutcome, outcomes
from ..audit.parallel import audit_cases
from ..errors import RegistryError
from ..execution.cluster_calls import Event
from ..execution.executor import Executor
from ..execution.time_budget import TimeBudget
from ..language.case_writer import corrected_case_text
from ..model import Case, CaseAudit, Verdict, VerdictChange
from ..presentation.audit_json import audit_document
from ..presentation.terminal import terminal_width
from ..presentation.verdict_table import disagreements, verdict_table
from ..store.database import Store
from ..version import code_version


@dataclass(frozen=True)
class AuditReport:
    """One audit run: its number, the audits of its cases and the cases themselves."""

    run: int
    audits: tuple[CaseAudit, ...]
    cases: dict[str, Case] = field(default_factory=dict)
    versions: dict[str, int] = field(default_factory=dict)
    #: What happened on the Dask cluster that ran the audit (workers lost, cases audited
    #: again elsewhere), one line each, as recorded in the run's options; empty without
    #: a scheduler.
    events: tuple[str, ...] = ()

    def outcomes(self) -> tuple[CaseOutcome, ...]:
        """What the run found, case by case, as typed objects (what every renderer reads)."""
        return outcomes(self.audits, self.cases, self.versions)

    def document(self) -> dict:
        """The JSON document of docs/json-output.md for this run."""
        return audit_document(self.run, self.outcomes())

    def table(self, width: int | None = None) -> str:
        """The verdict table ``registry audit`` prints, wrapped to ``width`` (None: the
        terminal's, ``presentation.terminal``)."""
        return verdict_table(self.outcomes(), self.run, width or terminal_width())

    def contradicted(self) -> list[str]:
        """The claims (case/claim) whose numerical evidence contradicts their verdict."""
        return disagreements(self.outcomes())


def _reusable(found: tuple[int, CaseAudit] | None, case: Case) -> CaseAudit | None:
    """A stored audit worth reusing: complete, with no crashed or killed check, and
    covering every claim of the case (a search may have attached claims since)."""
    if found is None:
        return None
    _, audit = found
    if any(r.verdict is Verdict.ERROR or r.check in ("audit", "load") for r in audit.results):
        return None
    if {c.label for c in case.claims} - {r.claim for r in audit.results}:
        return None
    return audit


@dataclass(frozen=True)
class AuditRequest:
    """What an audit run is asked to do: the cases (none: all), whether to recompute
    stored results (``fresh``), the time budget of each check and each case's
    corrections, and whether to add numerical evidence."""

    cases: tuple[str, ...] = ()
    fresh: bool = False
    budget: TimeBudget = field(default_factory=TimeBudget)
    numeric: bool = False

    def options(self) -> dict[str, Any]:
        """The request as the run records it."""
        return {
            "cases": list(self.cases) or None,
            "fresh": self.fresh,
            "budget": asdict(self.budget),
            "numeric": self.numeric,
        }


def audit_run(
    store: Store,
    request: AuditRequest,
    executor: Executor,
    progress: Callable[[str], None] | None = None,
) -> AuditReport:
    """``Registry.audit``: audit the latest version of every case (or the named ones),
    reusing what this code version already found, and record the run; the cases not
    reused are audited by ``executor``, and ``progress`` hears each case as it is done."""
    store.require_writer("record an audit run")
    stored = store.case_versions(list(request.cases) or None)
    version = code_version()
    options = {**request.options(), **executor.describe()}
    if not executor.local:
        options["events"] = []
    run = store.start_run(options, version)
    events: list[str] = []

    def happened(event: Event) -> None:  # recorded at once: a later crash keeps it
        events.append(str(event))
        store.update_run_options(run, events=list(events))

    audits: dict[int, CaseAudit] = {}
    cases: dict[str, Case] = {}
    todo: list[tuple[int, Case]] = []
    status = "failed"
    try:
        for i, row in enumerate(stored):
            try:
                case = row.parse()
            except Exception as exc:  # a broken case must not stop the run
                audits[i] = failed_case(row.case_id, row.content_hash, exc)
                store.record_case(run, row.pk, audits[i])
                continue
            cases[case.id] = case
            prior = None if request.fresh else _reusable(store.stored_audit(row.pk, version), case)
            if prior is not None and request.numeric and len(prior.evidence) < len(case.claims):
                prior = None  # stored without numerical evidence
            if prior is not None:
                audits[i] = prior
                store.record_case(run, row.pk, prior, reused=True)
            else:
                todo.append((i, case))
        computed = audit_cases(
            [c for _, c in todo], executor, request.budget, request.numeric, happened
        )
        with closing(computed):  # stops the workers at once if recording fails
            for k, audit in computed:
                i, case = todo[k]
                audits[i] = audit
                store.record_case(run, stored[i].pk, audit)
                if progress is not None:
                    progress(case.id)
        status = "complete"
    except (KeyboardInterrupt, SystemExit):  # Ctrl-C, or SIGTERM through the CLI
        status = "interrupted"
        raise
    finally:
        store.finish_run(run, status)
    ordered = tuple(audits[i] for i in sorted(audits))
    versions = {row.case_id: row.version for row in stored}
    return AuditReport(run, ordered, cases, versions, tuple(events))


def stored_run(store: Store, run: int) -> AuditReport:
    """A stored audit run as an AuditReport: its audits in the order they were recorded
    and the case versions they audited, parsed (a version whose text no longer parses
    is left out: it shows as a case that could not be audited). UnknownRunError for a
    run that does not exist."""
    audits = tuple(audit for _, audit in store.run_results(run))
    ids = list(dict.fromkeys(a.case for a in audits))
    stored = store.case_versions(ids, latest_only=False) if ids else []
    by_hash = {(s.case_id, s.content_hash): s for s in stored}
    cases, versions = {}, {}
    for audit in audits:
        found = by_hash.get((audit.case, audit.content_hash))
        if found is None:
            continue
        versions[audit.case] = found.version
        try:
            cases[audit.case] = found.parse()
        except RegistryError:
            pass
    return AuditReport(run, audits, cases, versions)


def run_diff(store: Store, run_a: int, run_b: int) -> list[VerdictChange]:
    """The verdicts that differ between two runs, on the cases both runs audited, sorted
    by case, claim (case checks first) and check. UnknownRunError for a run that
    does not exist."""
    before, after = _verdicts(store, run_a), _verdicts(store, run_b)
    common = {k[0] for k in before} & {k[0] for k in after}
    keys = sorted(k for k in before.keys() | after.keys() if k[0] in common)
    changes = []
    for key in keys:
        if before.get(key) != after.get(key):
            case, claim, check = key
            change = VerdictChange(case, claim or None, check, before.get(key), after.get(key))
            changes.append(change)
    return changes


def _verdicts(store: Store, run: int) -> dict[tuple[str, str, str], Verdict]:
    """(case, claim or '', check) -> verdict for every result of one run."""
    return {
        (case, r.claim or "", r.check): r.verdict
        for case, audit in store.run_results(run)
        for r in audit.results
    }


def corrected_case(store: Store, case_id: str, claim: str | None, kind: str) -> str:
    """``Registry.export_case``: a corrected case file (TOML text) from the newest audit of
    ``case_id``, with the correction of ``kind`` (for ``claim``, if given)."""
    (stored,) = store.case_versions([case_id])
    found = store.stored_audit(stored.pk)
    if found is None:
        raise RegistryError(f"case {case_id!r} has not been audited yet; run 'registry audit'")
    run, audit = found
    matches = [
        c for c in audit.corrections if c.kind == kind and (claim is None or c.claim == claim)
    ]
    if not matches:
        which = f" for claim {claim!r}" if claim else ""
        raise RegistryError(f"the newest audit of {case_id!r} found no {kind} correction{which}")
    return corrected_case_text(stored.parse(), matches[0], run)
