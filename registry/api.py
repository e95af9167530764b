"""The Python API that notebooks and the CLI share.

>>> import registry
>>> reg = registry.open(":memory:")
>>> [r.status for r in reg.add("data/cases/borisov-mamaev-1997.toml")]
['added']
>>> run = reg.audit()
>>> reg.verdicts().query("claim == 'C' and check == 'casimir'")["verdict"].tolist()
['verified']
"""

from __future__ import annotations

import os
from collections.abc import Callable, Generator, Iterable, Sequence
from contextlib import closing
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from .audit.case_audit import DEFAULT_BUDGET, audit_case, failed_case
from .audit.outcome import CaseOutcome, outcomes
from .audit.parallel import audit_in_workers
from .discovery.search import discover, search_options
from .discovery.survey import searched, stated_options
from .distributed.audits import audit_on_cluster
from .distributed.scheduler import check_same_code, cluster_client, describe
from .distributed.searches import cluster_mapper, discover_on_cluster
from .distributed.tasks import Event
from .errors import CaseFormatError, RegistryError, UnknownCaseError
from .execution.local import default_jobs
from .execution.time_budget import TimeBudget
from .language.case_writer import corrected_case_text, derived_case_text
from .language.casefile import load_case, parse_case_text
from .model import Case, CaseAudit, Equation, Search, SearchOptions, Verdict, VerdictChange
from .presentation.audit_json import audit_document
from .presentation.search_output import search_document, statement
from .store import conversions, frames
from .store.database import Store, StoredCase
from .store.integrity import Verification, verify
from .version import code_version, source_digest  # noqa: F401 - source_digest: the API's

if TYPE_CHECKING:
    import pandas as pd
    from distributed import Client

    from .presentation.site import Catalog

#: Where the registry lives when neither --db nor REGISTRY_DB says otherwise.
DEFAULT_DB = Path("data") / "registry.sqlite"

#: Seconds an integral search may take by default (``registry discover --budget``).
DEFAULT_SEARCH_BUDGET = 300.0


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


def default_target() -> str:
    """--db default: the REGISTRY_DB environment variable, else data/registry.sqlite."""
    return os.environ.get("REGISTRY_DB") or str(DEFAULT_DB)


@dataclass(frozen=True)
class AddResult:
    """What happened to one file: added, unchanged, new version, or refused (with why)."""

    path: str
    status: str
    case: str | None = None
    version: int | None = None
    error: RegistryError | None = None


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
        """The JSON document of CASE_FORMAT.md (section Discovery) for this search."""
        document = search_document(self.search)
        if self.number is not None:
            document["search"] = self.number
            document["reused"] = self.reused
        if self.derived:
            document["derived_cases"] = list(self.derived)
        if self.events:
            document["events"] = list(self.events)
        return document


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
        """The JSON document of CASE_FORMAT.md for this run."""
        return audit_document(self.run, self.outcomes())


def case_files(paths: Iterable[str | os.PathLike]) -> list[Path]:
    """The case files named by ``paths``: files as given, folders as every *.toml file in
    them and their sub-folders (a catalog may be organised by topic)."""
    files: list[Path] = []
    for p in map(Path, paths):
        files.extend(sorted(p.rglob("*.toml")) if p.is_dir() else [p])
    return files


class Registry:
    """A registry database: add cases, audit them, query the results as DataFrames."""

    def __init__(self, store: Store):
        self.store = store

    # --- adding -----------------------------------------------------------

    def add(self, *paths: str | os.PathLike) -> list[AddResult]:
        """Load case files (or folders of them); each file is stored whole or not at all."""
        self.store.require_writer("add cases")
        results = []
        for path in case_files(paths):
            try:
                case = load_case(path)
            except CaseFormatError as err:
                results.append(AddResult(str(path), "refused", error=err))
                continue
            outcome = self.store.add_case(case)
            results.append(AddResult(str(path), outcome.status, outcome.case_id, outcome.version))
        return results

    def add_case(self, case: Case) -> AddResult:
        """Store a case built in Python (e.g. from ``parse_case_text``)."""
        self.store.require_writer("add cases")
        outcome = self.store.add_case(case)
        return AddResult(case.path or "<python>", outcome.status, outcome.case_id, outcome.version)

    # --- auditing ---------------------------------------------------------

    def case(self, case_id: str) -> Case:
        """The latest stored version of a case, parsed."""
        (stored,) = self.store.case_versions([case_id])
        return stored.parse()

    def audit(
        self,
        case_ids: Sequence[str] | None = None,
        *,
        fresh: bool = False,
        jobs: int | None = None,
        budget: TimeBudget | None = None,
        numeric: bool = False,
        progress: Callable[[str], None] | None = None,
        scheduler: str | Client | None = None,
    ) -> AuditReport:
        """Audit the latest version of every case (or the named ones) and store the run.

        Results of a case version already audited by this code version are reused
        (recorded as reused) unless ``fresh``. The others are audited in ``jobs``
        worker processes (default: one per core; 0 audits in this process), each
        check under ``budget``. With ``numeric``, each claim also gets numerical
        evidence (drift of I against that of H along integrated trajectories).
        Each case's results are committed as it finishes;
        a case that fails to load or crashes is recorded as ``error``, one that
        overruns its budget as ``inconclusive``, and the others go on.

        With ``scheduler`` (a Dask scheduler's address ``tcp://HOST:PORT``, ``local:N``
        for a LocalCluster of N worker processes started for this audit, or a
        ``distributed.Client`` already connected), the cases are audited on that Dask
        cluster instead of ``jobs`` local workers, with the same results case by
        case; only this process writes to the database. The run's options record
        the scheduler, the cluster and what happened on it (``events``: workers
        lost, cases retried elsewhere).
        """
        self.store.require_writer("record an audit run")
        if scheduler is None:
            return self._audit(case_ids, fresh, jobs, budget, numeric, progress, None, None)
        with cluster_client(scheduler) as client:
            check_same_code(client, code_version)
            given = scheduler if isinstance(scheduler, str) else client.scheduler.address
            return self._audit(case_ids, fresh, jobs, budget, numeric, progress, client, given)

    def _audit(
        self,
        case_ids: Sequence[str] | None,
        fresh: bool,
        jobs: int | None,
        budget: TimeBudget | None,
        numeric: bool,
        progress: Callable[[str], None] | None,
        client: Client | None,
        scheduler: str | None,
    ) -> AuditReport:
        """``audit``, with ``client`` the Dask client of ``scheduler`` (or both None)."""
        budget = budget or DEFAULT_BUDGET
        jobs = default_jobs() if jobs is None else jobs
        stored = self.store.case_versions(list(case_ids) if case_ids else None)
        version = code_version()
        options: dict[str, Any] = {
            "cases": list(case_ids) if case_ids else None,
            "fresh": fresh,
            "jobs": jobs,
            "budget": asdict(budget),
            "numeric": numeric,
        }
        if client is not None:
            options.update(jobs=None, scheduler=scheduler, cluster=describe(client), events=[])
        run = self.store.start_run(options, version)
        events: list[str] = []

        def happened(event: Event) -> None:  # recorded at once: a later crash keeps it
            events.append(str(event))
            self.store.update_run_options(run, events=list(events))

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
                    self.store.record_case(run, row.pk, audits[i])
                    continue
                cases[case.id] = case
                prior = None if fresh else _reusable(self.store.stored_audit(row.pk, version), case)
                if prior is not None and numeric and len(prior.evidence) < len(case.claims):
                    prior = None  # stored without numerical evidence
                if prior is not None:
                    audits[i] = prior
                    self.store.record_case(run, row.pk, prior, reused=True)
                else:
                    todo.append((i, case))
            computed = self._compute(
                [c for _, c in todo], jobs, budget, numeric, progress, client, happened
            )
            with closing(computed):  # stops the workers at once if recording fails
                for k, audit in computed:
                    i = todo[k][0]
                    audits[i] = audit
                    self.store.record_case(run, stored[i].pk, audit)
            status = "complete"
        except (KeyboardInterrupt, SystemExit):  # Ctrl-C, or SIGTERM through the CLI
            status = "interrupted"
            raise
        finally:
            self.store.finish_run(run, status)
        ordered = tuple(audits[i] for i in sorted(audits))
        versions = {row.case_id: row.version for row in stored}
        return AuditReport(run, ordered, cases, versions, tuple(events))

    @staticmethod
    def _compute(
        cases: Sequence[Case],
        jobs: int,
        budget: TimeBudget,
        numeric: bool,
        progress: Callable[[str], None] | None,
        client: Client | None = None,
        on_event: Callable[[Event], None] | None = None,
    ) -> Generator[tuple[int, CaseAudit], None, None]:
        """(index, audit) for each case: on the Dask cluster of ``client``, in workers, or
        (jobs == 0) in this process."""

        def started(case: Case) -> None:
            if progress is not None:
                progress(case.id)

        if client is not None:
            yield from audit_on_cluster(client, cases, budget, numeric, started, on_event)
        elif jobs == 0:
            for k, case in enumerate(cases):
                started(case)
                yield k, audit_case(case, budget=budget, numeric=numeric)
        else:
            yield from audit_in_workers(cases, jobs, budget, started, numeric)

    # --- discovering --------------------------------------------------------

    def discover(
        self,
        target: str | os.PathLike | Case,
        *,
        degree: int = 4,
        weights: tuple[int, int] = (1, 2),
        on: Sequence[str | Equation] = (),
        free: Sequence[str] = (),
        record: bool = False,
        fresh: bool = False,
        budget: float | None = DEFAULT_SEARCH_BUDGET,
        jobs: int = 1,
        progress: Callable[[int, int, str], None] | None = None,
        scheduler: str | Client | None = None,
    ) -> SearchReport:
        """Search a case (a case file, a stored case's id, or a ``Case``) for first
        integrals of weighted ``degree`` <= K (``weights`` of M and gamma), on the level
        set ``on`` (equations as text, like ``"s = 0"``), with the parameters ``free``
        whose special values are sought (``registry.discovery.search.discover``).

        A stored case version already searched with the same options by this code version
        reuses that search unless ``fresh``. With ``record`` the search is stored (the
        case file added first if need be): its generic integrals become claims of the
        searched version, and each special set a derived case holding its integrals as
        claims, so that the next audit decides them like any literature claim.

        With ``scheduler`` (as for ``audit``: an address, ``local:N`` or a connected
        ``distributed.Client``), the candidate parameter sets are searched on that Dask
        cluster instead of ``jobs`` local processes, with the same result; the report's
        ``events`` say what happened there. Only this process writes to the database.
        """
        if record:
            self.store.require_writer("record a search")
        case, stored = self._search_target(target)
        options = search_options(case, degree=degree, weights=weights, on=on, free=free)
        reused = None if fresh else self._reused_search(case, stored, options)
        if reused is not None:
            return reused
        search, events = _run_search(case, options, budget, jobs, progress, scheduler)
        if not record:
            return SearchReport(search, events=events)
        if stored is None:
            self.store.add_case(case)
            (stored,) = [s for s in self.store.case_versions([case.id])]
        return replace(self._recorded(stored, case, search), events=events)

    def survey(
        self,
        case_ids: Sequence[str] | None = None,
        *,
        fresh: bool = False,
        budget: float | None = DEFAULT_SEARCH_BUDGET,
        jobs: int | None = None,
        progress: Callable[[int, int, str], None] | None = None,
        scheduler: str | Client | None = None,
    ) -> list[SearchReport]:
        """Record the stated searches (``registry.discovery.survey.stated_options``) of
        the latest version of every case, or of the named ones: what each system has, and
        has not, up to the degree its claims reach. Searches already recorded by this code
        version are reused unless ``fresh``; a system the method cannot search is recorded
        as not searched, with the reason. ``jobs`` processes search (default: one per
        core), or the Dask cluster of ``scheduler`` (as for ``audit``), one task per
        search; each search is stored as it finishes, and only this process writes.
        """
        self.store.require_writer("record the survey's searches")
        planned = [
            (stored, case, options)
            for stored in self.store.case_versions(list(case_ids) if case_ids else None)
            for case in [stored.parse()]
            for options in stated_options(case)
        ]
        reports: dict[int, SearchReport] = {}
        for i, (stored, case, options) in enumerate(planned):
            reused = None if fresh else self._reused_search(case, stored, options)
            if reused is not None:
                reports[i] = reused
        todo = [i for i in range(len(planned)) if i not in reports]
        work = [(planned[i][1], planned[i][2]) for i in todo]
        jobs = default_jobs() if jobs is None else jobs

        def record(results: Iterable[Search]) -> None:
            for done, (i, search) in enumerate(zip(todo, results, strict=True)):
                if progress is not None:
                    progress(done + 1, len(todo), search.case)
                reports[i] = self._recorded(planned[i][0], planned[i][1], search)

        if scheduler is None or not work:
            record(searched(work, budget=budget, jobs=jobs))
        else:
            with cluster_client(scheduler) as client:
                check_same_code(client, code_version)
                record(searched(work, budget=budget, mapper=cluster_mapper(client)))
        return [reports[i] for i in range(len(planned))]

    def _reused_search(
        self, case: Case, stored: StoredCase | None, options: SearchOptions
    ) -> SearchReport | None:
        """The stored search of this case version with these options by this code
        version, or None."""
        if stored is None:
            return None
        found = self.store.stored_search(stored.pk, options, code_version())
        if found is None:
            return None
        number, row, rows = found
        search = conversions.search(row, case.id, case.content_hash, rows, options.on)
        return SearchReport(search, number, reused=True)

    def _recorded(self, stored: StoredCase, case: Case, search: Search) -> SearchReport:
        """Store a search of a stored case version, with a derived case per special set."""
        derived = [
            parse_case_text(derived_case_text(case, s, search.options), f"<derived from {case.id}>")
            for s in search.special
        ]
        number = self.store.record_search(
            stored.pk, search, code_version(), statement(search), derived
        )
        return SearchReport(search, number, derived=tuple(c.id for c in derived))

    def _search_target(self, target: str | os.PathLike | Case) -> tuple[Case, StoredCase | None]:
        """The case to search and its stored version (None when not stored)."""
        if isinstance(target, Case):
            case = target
        elif Path(target).is_file():
            case = load_case(target)
        else:
            (stored,) = self.store.case_versions([str(target)])
            return stored.parse(), stored
        try:
            versions = self.store.case_versions([case.id], latest_only=False)
        except UnknownCaseError:
            return case, None
        same = [s for s in versions if s.content_hash == case.content_hash]
        return case, (same[-1] if same else None)

    def searches(self) -> pd.DataFrame:
        """One row per recorded integral search: the case, the ansatz, what exists for
        generic values, how many special sets, completeness, coverage, the result in
        one sentence (negative results included), code version and time."""
        return frames.searches_frame(self.store)

    def discoveries(self) -> pd.DataFrame:
        """One row per set of parameter values a recorded search found integrals on (the
        generic values too): the equations, the integrals, their casimir verdicts, and
        the case that holds them as claims."""
        return frames.discoveries_frame(self.store)

    # --- queries ----------------------------------------------------------

    def cases(
        self,
        *,
        source: str | None = None,
        author: str | None = None,
        year: int | tuple[int, int] | None = None,
        topic: str | None = None,
        family: str | None = None,
        verdict: str | Verdict | None = None,
    ) -> pd.DataFrame:
        """One row per case (its latest version) with its citation (authors, year, title,
        journal, volume, pages, doi, ...), topic, aliases and the torque family its
        newest audit found; filtered by any of: ``source`` (text in the citation, title
        or journal), ``author`` (text in an author's name), ``year`` (a year or an
        inclusive range), ``topic``, ``family`` (exact), ``verdict`` (some claim has it).
        Text filters ignore case."""
        frame = frames.cases_frame(self.store)
        families = frames.families_frame(self.store)
        frame = frame.merge(families, on="case", how="left")
        frame["family"] = [f if isinstance(f, str) else "" for f in frame["family"]]
        keep = [True] * len(frame)

        def contains(values: Iterable[object], text: str) -> list[bool]:
            return [text.lower() in str(v).lower() for v in values]

        if source is not None:
            texts = frame["citation"] + " " + frame["source_title"] + " " + frame["journal"]
            keep = [k and c for k, c in zip(keep, contains(texts, source), strict=True)]
        if author is not None:
            names = [" ".join(a) if isinstance(a, list) else "" for a in frame["authors"]]
            keep = [k and c for k, c in zip(keep, contains(names, author), strict=True)]
        if year is not None:
            first, last = year if isinstance(year, tuple) else (year, year)
            years = [y if y == y and y is not None else None for y in frame["year"]]
            keep = [
                k and y is not None and first <= y <= last for k, y in zip(keep, years, strict=True)
            ]
        if topic is not None:
            keep = [
                k and str(t).lower() == topic.lower()
                for k, t in zip(keep, frame["topic"], strict=True)
            ]
        if family is not None:
            keep = [k and f == family for k, f in zip(keep, frame["family"], strict=True)]
        if verdict is not None:
            having = self._cases_with_verdict(Verdict(verdict))
            keep = [k and c in having for k, c in zip(keep, frame["case"], strict=True)]
        rows = [i for i, k in enumerate(keep) if k]  # a list, also when empty (no rows)
        return frame.iloc[rows].reset_index(drop=True)

    def _cases_with_verdict(self, verdict: Verdict) -> set[str]:
        """The cases some claim of which has this overall verdict (its kind's check)."""
        latest = frames.verdicts_frame(self.store)
        claims = frames.claims_frame(self.store)
        kinds = {
            (c, label): kind
            for c, label, kind in zip(claims["case"], claims["label"], claims["kind"], strict=True)
        }
        return {
            case
            for case, claim, check, found in zip(
                latest["case"], latest["claim"], latest["check"], latest["verdict"], strict=True
            )
            if kinds.get((case, claim)) == check and found == str(verdict)
        }

    def claims(self) -> pd.DataFrame:
        """One row per claim of the latest case versions."""
        return frames.claims_frame(self.store)

    def verdicts(self, run: int | None = None) -> pd.DataFrame:
        """The newest verdict of every check and claim (or those of one run)."""
        return frames.verdicts_frame(self.store, run)

    def corrections(self, run: int | None = None) -> pd.DataFrame:
        """Families, re-checked corrections and parameter conditions of a run (default: newest)."""
        return frames.corrections_frame(self.store, run)

    def export_case(self, case_id: str, claim: str | None = None, kind: str = "torque") -> str:
        """A corrected case file (TOML text) from the newest audit of ``case_id``.

        ``kind`` is ``torque`` (the claim becomes a Casimir of a repaired torque) or
        ``casimir`` (the case's own torque with its derived Casimir as the claim).
        """
        (stored,) = self.store.case_versions([case_id])
        found = self.store.stored_audit(stored.pk)
        if found is None:
            raise RegistryError(f"case {case_id!r} has not been audited yet; run 'registry audit'")
        run, audit = found
        matches = [
            c for c in audit.corrections if c.kind == kind and (claim is None or c.claim == claim)
        ]
        if not matches:
            which = f" for claim {claim!r}" if claim else ""
            raise RegistryError(
                f"the newest audit of {case_id!r} found no {kind} correction{which}"
            )
        return corrected_case_text(stored.parse(), matches[0], run)

    def run_report(self, run: int) -> AuditReport:
        """A stored audit run as an AuditReport: its audits in the order they were recorded
        and the case versions they audited, parsed (a version whose text no longer parses
        is left out: it shows as a case that could not be audited). UnknownRunError for a
        run that does not exist."""
        audits = tuple(audit for _, audit in self.store.run_results(run))
        ids = list(dict.fromkeys(a.case for a in audits))
        stored = self.store.case_versions(ids, latest_only=False) if ids else []
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

    # --- publishing ------------------------------------------------------

    def report(
        self,
        run: int | None = None,
        fmt: str = "md",
        out_dir: Path | None = None,
        plots: bool = True,
    ) -> str:
        """A report of one audit run (default: the newest) as Markdown, HTML or LaTeX
        (``presentation.report_content``); drift plots go to ``out_dir`` (md, tex) or
        into the file (html). UnknownRunError for a run that does not exist."""
        from .presentation import report_content  # pandas, matplotlib: only for reports

        row = report_content.run_row(self.runs(), run)
        outcomes = self.run_report(int(row["run"])).outcomes()
        return report_content.build_report(row, outcomes, fmt, out_dir, plots)

    def bibtex(self) -> str:
        """The sources of the cases as BibTeX (``presentation.bibtex``)."""
        from .presentation.bibtex import bibtex

        return bibtex(self.cases())

    def tables(self) -> dict[str, pd.DataFrame]:
        """The published tables by name (``data_export.TABLES``, in that order)."""
        return {
            "cases": self.cases(),
            "claims": self.claims(),
            "verdicts": self.verdicts(),
            "all_results": frames.all_results_frame(self.store),
            "corrections": self.corrections(),
            "runs": self.runs(),
        }

    def export(self, out_dir: str | os.PathLike, fmt: str) -> list[Path]:
        """Write the tables as ``fmt`` files (csv, json, parquet) into ``out_dir``; the
        paths written."""
        from .presentation import data_export

        return data_export.export_tables(self.tables(), Path(out_dir), fmt)

    def catalog(self) -> Catalog:
        """What the static site shows: every case's newest version with the newest audit
        of that version, the version history, the searches and discoveries."""
        from .presentation.site import CaseEntry, Catalog

        entries = []
        for stored in self.store.case_versions():
            case = stored.parse()
            run, audit = self.store.stored_audit(stored.pk) or (None, None)
            found = outcomes((audit,), {case.id: case}, {case.id: stored.version}) if audit else ()
            entries.append(
                CaseEntry(case, stored.version, stored.text, run, next(iter(found), None))
            )
        versions = frames.versions_frame(self.store)
        return Catalog(self.cases(), tuple(entries), versions, self.searches(), self.discoveries())

    def site(self, out_dir: str | os.PathLike, base_url: str = "") -> list[Path]:
        """Write the registry as a static web site into ``out_dir`` (``presentation.site``):
        byte-identical for the same registry; ``base_url`` is where it will be served."""
        from .presentation.site import build_site

        return build_site(self.catalog(), Path(out_dir), base_url)

    def serve(self, host: str = "127.0.0.1", port: int = 8001) -> None:
        """Browse this registry (an SQLite file) live in Datasette until interrupted
        (``presentation.live_view``; the optional extra ``serve``)."""
        from .presentation.live_view import serve

        url = self.store.engine.url
        serve(None if self.store.server else url.database, host, port)

    def diff(self, run_a: int, run_b: int) -> list[VerdictChange]:
        """The verdicts that differ between two runs, on the cases both runs audited, sorted
        by case, claim (case checks first) and check. UnknownRunError for a run that
        does not exist."""
        before, after = self._verdicts(run_a), self._verdicts(run_b)
        common = {k[0] for k in before} & {k[0] for k in after}
        keys = sorted(k for k in before.keys() | after.keys() if k[0] in common)
        changes = []
        for key in keys:
            if before.get(key) != after.get(key):
                case, claim, check = key
                change = VerdictChange(case, claim or None, check, before.get(key), after.get(key))
                changes.append(change)
        return changes

    def _verdicts(self, run: int) -> dict[tuple[str, str, str], Verdict]:
        """(case, claim or '', check) -> verdict for every result of one run."""
        return {
            (case, r.claim or "", r.check): r.verdict
            for case, audit in self.store.run_results(run)
            for r in audit.results
        }

    def runs(self) -> pd.DataFrame:
        """One row per audit run: when, status, code and sympy versions."""
        return frames.runs_frame(self.store)

    def verify_db(self) -> Verification:
        """Verify the database itself (``registry verify-db``): schema, integrity, foreign
        keys, hashes of the stored case texts, and every stored expression re-parsed."""
        return verify(self.store)

    # --- who may write (a shared server) -------------------------------------

    def grant(
        self, role: str, level: Literal["reader", "writer"] | None, *, run: bool = True
    ) -> list[str]:
        """Make a server ``role`` a reader (browse and query) or a writer (also add, audit,
        search) of this registry, or take both back (``level`` None): the SQL statements,
        run in one transaction unless ``run`` is False (to hand to an administrator).
        Only the owner of the registry's tables may run them (``store.roles``)."""
        if run:
            return self.store.grant(level, role)
        return self.store.grant_statements(level, role)

    def close(self) -> None:
        self.store.close()

    def __enter__(self) -> Registry:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def discover_file(
    path: str | os.PathLike,
    *,
    degree: int = 4,
    weights: tuple[int, int] = (1, 2),
    on: Sequence[str | Equation] = (),
    free: Sequence[str] = (),
    budget: float | None = DEFAULT_SEARCH_BUDGET,
    jobs: int = 1,
    progress: Callable[[int, int, str], None] | None = None,
    scheduler: str | Client | None = None,
) -> SearchReport:
    """Search a case file without a database (``Registry.discover`` has the options)."""
    case = load_case(path)
    options = search_options(case, degree=degree, weights=weights, on=on, free=free)
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


def open_registry(target: str | os.PathLike | None = None, *, create: bool = True) -> Registry:
    """Open the registry at a path or SQLAlchemy URL, creating it if needed (unless
    ``create`` is False: then a missing file is a DatabaseMissingError). An older
    database is upgraded to the current schema, after a backup copy."""
    where = default_target() if target is None else target
    return Registry(Store(Path(where) if isinstance(where, os.PathLike) else where, create=create))
