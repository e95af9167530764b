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
from collections.abc import Callable, Iterable, Mapping, Sequence
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Unpack

from . import settings
from .errors import CaseFormatError, RegistryError
from .execution.executor import check_options, open_executor
from .execution.time_budget import TimeBudget, default_budget
from .settings import (
    BESIDE_SEARCH_EXPONENT_SECONDS,
    DEFAULT_EXPONENT_SECONDS,
    DEFAULT_IDENTIFY_SECONDS,
    DEFAULT_SEARCH_SECONDS,
    DEFAULT_SURVEY_SECONDS,
)

# The facade is imported by ``registry --help`` and ``--version``, which must stay quick:
# sympy, SQLAlchemy and pandas are imported by the methods that use them, not here.
if TYPE_CHECKING:
    import pandas as pd
    from distributed import Client

    from .model import (
        Case,
        CaseFilter,
        CaseIdentification,
        DriftCurve,
        Equation,
        MeasureSearch,
        VerdictChange,
        Weights,
    )
    from .presentation.site import Catalog
    from .runs.audit_run import AuditReport
    from .runs.exponents_run import ExponentReport
    from .runs.search_run import SearchReport
    from .store.copying import CopyReport
    from .store.database import Store
    from .store.integrity import Verification


def __getattr__(name: str) -> Any:
    """``AuditReport`` (``registry.AuditReport``), imported on first use (PEP 562)."""
    if name == "AuditReport":
        from .runs.audit_run import AuditReport

        return AuditReport
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "AddResult",
    "AuditReport",
    "CheckInfo",
    "Registry",
    "analyse_exponents",
    "check_where",
    "checks",
    "checks_text",
    "diff_text",
    "discover_file",
    "open_registry",
    "survey_text",
    "terminal_width",
    "time_budget",
    "version",
]


@dataclass(frozen=True)
class CheckInfo:
    """A mathematical check the audit runs: its name, whether it runs once per claim, its
    cost note, and the statement it tests (its docstring's first line)."""

    name: str
    per_claim: bool
    cost: str
    statement: str


def checks() -> list[CheckInfo]:
    """Every check the audit runs, in the order it runs them (``registry list-checks``)."""
    from .audit.checks import CHECKS

    return [CheckInfo(c.name, c.per_claim, c.cost, c.statement) for c in CHECKS.values()]


def checks_text(width: int | None = None) -> str:
    """The checks as ``registry list-checks`` prints them, wrapped to ``width`` (None: the
    terminal's, ``presentation.terminal``)."""
    from .presentation.listings import checks_listing

    return checks_listing(checks(), terminal_width(width))


def terminal_width(width: int | None = None) -> int:
    """``width``, or where it is None the width of the terminal the command line prints
    to ($COLUMNS, else the terminal's, else 80): what every ``*_text`` renders to."""
    from .presentation.terminal import terminal_width as measured

    return measured() if width is None else width


def version() -> str:
    """The package's release and the digest of its code, as ``registry --version`` says."""
    from .version import code_version, release

    return f"registry {release()} (code digest {code_version().rpartition('+')[2]})"


def diff_text(
    changes: Sequence[VerdictChange], run_a: int, run_b: int, width: int | None = None
) -> str:
    """The verdicts that changed between two runs as a table (``Registry.diff``), wrapped
    to ``width`` (None: the terminal's)."""
    from .presentation.verdict_table import diff_table

    return diff_table(changes, run_a, run_b, terminal_width(width))


def survey_text(reports: Sequence[SearchReport], width: int | None = None) -> str:
    """What ``registry survey`` prints of its searches: each case (and level set) with
    the result in one sentence, wrapped to ``width`` (None: the terminal's)."""
    from .presentation.listings import survey_listing

    return survey_listing([r.search for r in reports], terminal_width(width))


def identify_text(found: Sequence[CaseIdentification], width: int | None = None) -> str:
    """What ``registry identify`` prints: each case with the cases it is the same system
    as, wrapped to ``width`` (None: the terminal's)."""
    from .presentation.listings import identify_listing

    return identify_listing(found, terminal_width(width))


def check_where(jobs: int | None, scheduler: str | None) -> None:
    """UsageError where ``jobs`` and ``scheduler`` cannot go together (both given, or a
    ``jobs`` that is no number of worker processes): what a command checks first."""
    check_options(jobs, scheduler)


def time_budget(check: float | None = None, corrections: float | None = None) -> TimeBudget:
    """The time budget of an audit: seconds for each check and for each case's
    corrections, where given, else from the environment or the defaults (``settings``)."""
    return default_budget(check=check, corrections=corrections)


@dataclass(frozen=True)
class AddResult:
    """What happened to one file: added, unchanged, new version, or refused (with why)."""

    path: str
    status: str
    case: str | None = None
    version: int | None = None
    error: RegistryError | None = None


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
        from .language.casefile import load_case

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
        worker processes (default: one per core; 1 audits in this process), each
        check under ``budget`` (``time_budget``). With ``numeric``, each claim also gets
        numerical evidence (drift of I against that of H along integrated trajectories).
        Each case's results are committed as it finishes (``progress`` hears its id); a
        case that fails to load or crashes is recorded as ``error``, one that overruns
        its budget as ``inconclusive``, and the others go on.

        With ``scheduler`` (a Dask scheduler's address ``tcp://HOST:PORT``, ``local:N``
        for a LocalCluster of N worker processes started for this audit, or a
        ``distributed.Client`` already connected), the cases are audited on that Dask
        cluster instead of local workers, with the same results case by case; only this
        process writes to the database. The run's options record the scheduler, the
        cluster and what happened on it (``events``: workers lost, cases retried
        elsewhere).
        """
        from .runs.audit_run import AuditRequest, audit_run

        request = AuditRequest(tuple(case_ids or ()), fresh, budget or time_budget(), numeric)
        with open_executor(jobs, scheduler) as executor:
            return audit_run(self.store, request, executor, progress)

    # --- discovering --------------------------------------------------------

    def discover(
        self,
        target: str | os.PathLike | Case,
        *,
        degree: int = 4,
        weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
        on: Sequence[str | Equation] = (),
        free: Sequence[str] = (),
        relations: bool = False,
        record: bool = False,
        fresh: bool = False,
        budget: float | None = DEFAULT_SEARCH_SECONDS,
        jobs: int | None = None,
        progress: Callable[[int, int, str], None] | None = None,
        scheduler: str | Client | None = None,
    ) -> SearchReport:
        """Search a case (a case file, a stored case's id, or a ``Case``) for first
        integrals of weighted ``degree`` <= K (``weights`` by vector of the state, such as
        ``{"M": 1, "gamma": 2}``; a vector not named keeps its default), on the level
        set ``on`` (equations as text, like ``"s = 0"``), with the parameters ``free``
        whose special values are sought (``registry.discovery.search.discover``). With
        ``relations``, Darboux polynomials (invariant relations F = 0, dF/dt = K F) are
        sought instead, the special sets being the cofactors K that carry them.

        A stored case version already searched with the same options by this code version
        reuses that search unless ``fresh``. With ``record`` the search is stored (the
        case file added first if need be): its generic integrals become claims of the
        searched version, and each special set a derived case holding its integrals as
        claims, so that the next audit decides them like any literature claim.

        The candidate parameter sets are searched in ``jobs`` worker processes (default:
        one per core; 1 in this process), or on the Dask cluster of ``scheduler`` (as for
        ``audit``), with the same result; the report's ``events`` say what happened on a
        cluster. Only this process writes to the database.
        """
        from .runs.search_run import SearchRequest, search_run

        request = SearchRequest(
            degree, weights, tuple(on), tuple(free), relations, budget, record, fresh
        )
        with open_executor(jobs, scheduler) as executor:
            return search_run(self.store, target, request, executor, progress)

    def measures(self, target: str | os.PathLike | Case) -> MeasureSearch:
        """The invariant densities prod F_i**a_i of a case (a case file, a stored case's id,
        or a ``Case``), by the method of the Jacobi last multiplier
        (``registry.discovery.measures``): each density proven by the ``measure`` check,
        the statement complete for that ansatz."""
        from .model import Case

        if isinstance(target, Case) or Path(target).is_file():
            return find_measures(target)
        return find_measures(self.case(str(target)))

    def survey(
        self,
        case_ids: Sequence[str] | None = None,
        *,
        fresh: bool = False,
        budget: float | None = DEFAULT_SURVEY_SECONDS,
        jobs: int | None = None,
        progress: Callable[[int, int, str], None] | None = None,
        scheduler: str | Client | None = None,
        exponent_budget: float = BESIDE_SEARCH_EXPONENT_SECONDS,
    ) -> list[SearchReport]:
        """Record the stated searches (``registry.discovery.survey.stated_options``) of
        the latest version of every case, or of the named ones: what each system has, and
        has not, up to the degree its claims reach. Searches already recorded by this code
        version are reused unless ``fresh``; a system the method cannot search is recorded
        as not searched, with the reason. ``jobs`` processes search (default: one per
        core), or the Dask cluster of ``scheduler`` (as for ``audit``), one task per
        search; each search is stored as it finishes, and only this process writes.
        Each case's Kovalevskaya analysis is made beside its search within
        ``exponent_budget`` seconds (recorded; one that ran out of a smaller budget is
        made again).
        """
        from .runs.search_run import survey_run

        with open_executor(jobs, scheduler) as executor:
            return survey_run(
                self.store,
                case_ids,
                executor,
                fresh=fresh,
                budget=budget,
                progress=progress,
                exponent_budget=exponent_budget,
            )

    def searches(self) -> pd.DataFrame:
        """One row per recorded integral search: the case, the ansatz, what exists for
        generic values, how many special sets, completeness, coverage, the result in
        one sentence (negative results included), code version and time."""
        from .store import frames

        return frames.searches_frame(self.store)

    def searches_text(
        self, case_id: str | None = None, *, long: bool = False, width: int | None = None
    ) -> str:
        """The recorded searches (of ``case_id``, or of every case) as ``registry
        searches`` prints them: one row each with the case, the ansatz, completeness and
        the result in short; with ``long``, each with its result in one sentence. Wrapped
        to ``width`` (None: the terminal's). UnknownCaseError for a case not held."""
        from .presentation.listings import searches_listing, searches_long
        from .runs.search_run import recorded_searches

        found = [(number, search) for number, _, search in recorded_searches(self.store, case_id)]
        render = searches_long if long else searches_listing
        return render(found, terminal_width(width))

    def search_documents(self, case_id: str | None = None) -> list[dict]:
        """The recorded searches (of ``case_id``, or of every case), oldest first, each as
        the JSON document of ``registry discover --json`` with its number (``search``)
        and the case version searched (``version``): ``registry searches --json``."""
        from .presentation.search_output import recorded_search_document
        from .runs.search_run import recorded_searches

        return [
            recorded_search_document(number, version, search)
            for number, version, search in recorded_searches(self.store, case_id)
        ]

    def discoveries(self) -> pd.DataFrame:
        """One row per set of parameter values a recorded search found integrals on (the
        generic values too): the equations, the integrals, their casimir verdicts, the
        catalog cases it is the same system as (``same_as``), and the case that holds
        them as claims."""
        from .store import frames

        return frames.discoveries_frame(self.store)

    # --- identification with the catalog ------------------------------------

    def identify(
        self,
        case_ids: Sequence[str] | None = None,
        *,
        fresh: bool = False,
        budget: float | None = DEFAULT_IDENTIFY_SECONDS,
        jobs: int | None = None,
        progress: Callable[[int, int, str], None] | None = None,
        scheduler: str | Client | None = None,
    ) -> list[CaseIdentification]:
        """Record which catalog cases each case (the latest version of every case, or of
        the named ones) is the same system as: equal vector fields at some values of the
        other's parameters, after scalings of time and of each vector, permutations and
        sign changes of the axes, rotations about a symmetry axis and shifts M -> M +
        f(gamma) (``discovery.identification``). ``budget`` seconds per case; comparisons
        in ``jobs`` processes or on the Dask cluster of ``scheduler``. A recorded
        identification against the same catalog by this code version is reused unless
        ``fresh``. Finding no case proves nothing."""
        from .runs.identify_run import identify_run

        with open_executor(jobs, scheduler) as executor:
            return identify_run(
                self.store, case_ids, executor, fresh=fresh, budget=budget, progress=progress
            )

    def identifications(self) -> pd.DataFrame:
        """One row per catalog case that a case is the same system as (the newest
        identification of its latest version): the values of the other's parameters, the
        transformation, whether the two are ``equivalent`` (each is the other)."""
        from .store import frames

        return frames.identifications_frame(self.store)

    # --- Kovalevskaya exponents ---------------------------------------------

    def analyse_exponents(
        self,
        target: str | os.PathLike | Case,
        *,
        weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
        free: Sequence[str] = (),
        record: bool = False,
        fresh: bool = False,
        budget: float | None = DEFAULT_EXPONENT_SECONDS,
        jobs: int | None = None,
        scheduler: str | Client | None = None,
    ) -> ExponentReport:
        """The Kovalevskaya exponents of a case (a case file, a stored case's id, or a
        ``Case``): every balance of its field's leading part under ``weights`` (by vector,
        default the case's own), its exponents, Yoshida's degrees and the Painlevé test
        (``registry.discovery.exponents``); with ``free``, the values of those parameters
        where every exponent is an integer, half an integer or rational, the candidates
        analysed in ``jobs`` worker processes or on the Dask cluster of ``scheduler``.
        A stored analysis of the same case version and options by this code version is
        reused unless ``fresh``; ``record`` stores this one with the case version (the
        file added first if need be), keeping the earlier ones. ``reg.exponents()`` lists
        the recorded analyses."""
        from .runs.exponents_run import ExponentRequest, exponents_run

        request = ExponentRequest(weights, tuple(free), budget, record, fresh)
        with open_executor(jobs, scheduler) as executor:
            return exponents_run(self.store, target, request, executor)

    def exponents(self) -> pd.DataFrame:
        """One row per recorded Kovalevskaya analysis, oldest first: the case version, the
        weights, the free parameters, whether it was decided, whether the field is
        weighted-homogeneous, the balances, whether every exponent is an integer
        (rational), Yoshida's degrees, the Painlevé test (``painleve``: True, False, or
        None where it was not made), a family's special sets, the statement, code version
        and time."""
        from .store import frames

        return frames.exponents_frame(self.store)

    # --- queries ----------------------------------------------------------

    def cases(self, **filters: Unpack[CaseFilter]) -> pd.DataFrame:
        """One row per case (its latest version) with its citation (authors, year, title,
        journal, volume, pages, doi, ...), topic, aliases, the torque family its newest
        audit found and the cases it was identified with; filtered by any of
        ``source`` (text in the citation, title or journal), ``author`` (text in an
        author's name), ``year`` (a year or an inclusive range), ``topic``, ``family``
        (exact), ``verdict`` (some claim has it). Text filters ignore case; a
        misspelt filter is a TypeError, never a silently unfiltered list."""
        from .store import frames

        return frames.case_table(self.store, **filters)

    def cases_text(self, width: int | None = None, **filters: Unpack[CaseFilter]) -> str:
        """The cases (filtered as ``cases``) as ``registry cases`` lists them, wrapped to
        ``width`` (None: the terminal's)."""
        from .presentation.listings import cases_listing

        return cases_listing(self.cases(**filters), terminal_width(width))

    def claims(self) -> pd.DataFrame:
        """One row per claim of the latest case versions."""
        from .store import frames

        return frames.claims_frame(self.store)

    def verdicts(self, run: int | None = None) -> pd.DataFrame:
        """The newest verdict of every check and claim (or those of one run)."""
        from .store import frames

        return frames.verdicts_frame(self.store, run)

    def verdicts_text(self, run: int | None = None, width: int | None = None) -> str:
        """The verdicts (``verdicts``) as ``registry verdicts`` lists them, under each
        case, wrapped to ``width`` (None: the terminal's)."""
        from .presentation.listings import verdicts_listing

        return verdicts_listing(self.verdicts(run), terminal_width(width))

    def corrections(self, run: int | None = None) -> pd.DataFrame:
        """Families, re-checked corrections and parameter conditions of a run (default: newest)."""
        from .store import frames

        return frames.corrections_frame(self.store, run)

    def corrections_text(self, run: int | None = None, width: int | None = None) -> str:
        """The corrections of a run (``corrections``) as ``registry corrections`` lists
        them, one row per branch of a condition, wrapped to ``width`` (None: the
        terminal's)."""
        from .presentation.listings import corrections_listing

        return corrections_listing(self.corrections(run), terminal_width(width))

    def export_case(self, case_id: str, claim: str | None = None, kind: str = "torque") -> str:
        """A corrected case file (TOML text) from the newest audit of ``case_id``.

        ``kind`` is ``torque`` (the claim becomes a Casimir of a corrected torque) or
        ``casimir`` (the case's own torque with its derived Casimir as the claim).
        """
        from .runs.audit_run import corrected_case

        return corrected_case(self.store, case_id, claim, kind)

    def run_report(self, run: int) -> AuditReport:
        """A stored audit run as an AuditReport: its audits in the order they were recorded
        and the case versions they audited, parsed (a version whose text no longer parses
        is left out: it shows as a case that could not be audited). UnknownRunError for a
        run that does not exist."""
        from .runs.audit_run import stored_run

        return stored_run(self.store, run)

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
        from .audit.numeric_evidence import drift_curves
        from .presentation import report_content  # pandas, matplotlib: only for reports

        row = report_content.run_row(self.runs(), run)
        outcomes = self.run_report(int(row["run"])).outcomes()
        curves: dict[tuple[str, str], DriftCurve | str] | None = None
        if plots:
            # the curves the audit stored; a run recorded before audits stored them
            # has its curves integrated here, once
            curves = {(c.case, c.claim): c for o in outcomes for c in o.curves}
            wanted = report_content.plotted(outcomes)
            curves |= drift_curves([(case, c) for case, c in wanted if (case.id, c) not in curves])
        return report_content.build_report(row, outcomes, fmt, out_dir, curves)

    def plot(self, case_id: str, claim: str, path: str | os.PathLike, seed: int = 0) -> Path:
        """Write a PNG of I(t) - I(0) and H(t) - H(0) of a claim along one integrated
        trajectory (the first the numerical evidence integrates with ``seed``); its path.
        UnknownClaimError for a claim the case does not make."""
        from .audit.numeric_evidence import drift_curve
        from .errors import UnknownClaimError
        from .presentation.plots import drift_plot

        case = self.case(case_id)
        if claim not in {c.label for c in case.claims}:
            raise UnknownClaimError(case_id, claim, [c.label for c in case.claims])
        return drift_plot(drift_curve(case, claim, seed), path)

    def bibtex(self) -> str:
        """The sources of the cases as BibTeX (``presentation.bibtex``)."""
        from .presentation.bibtex import bibtex

        return bibtex(self.cases())

    def tables(self) -> dict[str, pd.DataFrame]:
        """The published tables by name (``data_export.TABLES``, in that order)."""
        from .store import frames

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
        from .audit.outcome import outcomes
        from .presentation.site import CaseEntry, Catalog
        from .runs.exponents_run import site_exponents
        from .store import frames

        entries = []
        for stored in self.store.case_versions():
            case = stored.parse()
            run, audit = self.store.stored_audit(stored.pk) or (None, None)
            found = outcomes((audit,), {case.id: case}, {case.id: stored.version}) if audit else ()
            entries.append(
                CaseEntry(case, stored.version, stored.text, run, next(iter(found), None))
            )
        versions = frames.versions_frame(self.store)
        return Catalog(
            self.cases(),
            tuple(entries),
            versions,
            self.searches(),
            self.discoveries(),
            site_exponents(self.store),
            self.identifications(),
        )

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
        from .runs.audit_run import run_diff

        return run_diff(self.store, run_a, run_b)

    def runs(self) -> pd.DataFrame:
        """One row per audit run: when, status, code and sympy versions."""
        from .store import frames

        return frames.runs_frame(self.store)

    def runs_text(self, width: int | None = None) -> str:
        """The audit runs (``runs``) as ``registry runs`` lists them, wrapped to ``width``
        (None: the terminal's)."""
        from .presentation.listings import runs_listing

        return runs_listing(self.runs(), terminal_width(width))

    def verify_db(self) -> Verification:
        """Verify the database itself (``registry verify-db``): schema, integrity, foreign
        keys, hashes of the stored case texts, and every stored expression re-parsed."""
        from .store.integrity import verify

        return verify(self.store)

    def copy_to(self, target: str | os.PathLike) -> CopyReport:
        """Copy this registry whole (every table, ids and history) into ``target``: a new
        SQLite file, or an empty database or registry on a server; all or nothing, and
        verified before it is committed (``store.copying``). The way to move to a group's
        server, and to back one up (or restore it: copy from the backup into an empty
        database). CopyTargetNotEmptyError for a target that holds rows."""
        from .store.copying import copy_registry

        return copy_registry(
            self.store, Path(target) if isinstance(target, os.PathLike) else target
        )

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

    # --- the database itself ---------------------------------------------------

    @property
    def location(self) -> str:
        """Where the registry is: a file's path, or a server URL without its password."""
        return self.store.location

    @property
    def upgraded_from(self) -> str | None:
        """The schema revision the database was upgraded from on opening (None: none)."""
        return self.store.upgraded_from

    @property
    def backup(self) -> Path | None:
        """The copy of an SQLite file made before its schema was upgraded (None: none)."""
        return self.store.backup

    def count_cases(self, case_ids: Sequence[str] | None = None) -> int:
        """How many cases an audit of ``case_ids`` (default: all) covers; UnknownCaseError
        for an id the registry does not hold."""
        return len(self.store.case_versions(list(case_ids) if case_ids else None))

    def interruptible(self) -> AbstractContextManager[None]:
        """A context in which SIGTERM and SIGINT end a run as Ctrl-C does, never in the
        middle of a database session (``runs.interruption``)."""
        from .runs.interruption import interruptible

        return interruptible(self.store)

    def close(self) -> None:
        self.store.close()

    def __enter__(self) -> Registry:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def open_registry(target: str | os.PathLike | None = None, *, create: bool = True) -> Registry:
    """Open the registry at a path or SQLAlchemy URL (default: ``$REGISTRY_DB``, else
    data/registry.sqlite), creating it if needed (unless ``create`` is False: then a
    missing file is a DatabaseMissingError). An older database is upgraded to the current
    schema, after a backup copy."""
    from .store.database import Store

    where = settings.database() if target is None else target
    return Registry(Store(Path(where) if isinstance(where, os.PathLike) else where, create=create))


def find_measures(target: str | os.PathLike | Case) -> MeasureSearch:
    """The invariant densities prod F_i**a_i of a case file or a ``Case``, without a
    database (``Registry.measures``)."""
    from .discovery.measures import measure_search
    from .language.casefile import load_case
    from .model import Case

    case = target if isinstance(target, Case) else load_case(target)
    return measure_search(case)


def measure_text(search: MeasureSearch, width: int | None = None) -> str:
    """A measure search in plain text, as ``registry discover --measure`` prints it."""
    from .presentation.search_output import measure_text as render

    return render(search, terminal_width(width))


def discover_file(
    path: str | os.PathLike,
    *,
    degree: int = 4,
    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
    on: Sequence[str | Equation] = (),
    free: Sequence[str] = (),
    relations: bool = False,
    budget: float | None = DEFAULT_SEARCH_SECONDS,
    jobs: int | None = None,
    progress: Callable[[int, int, str], None] | None = None,
    scheduler: str | Client | None = None,
) -> SearchReport:
    """Search a case file without a database: nothing is reused or recorded
    (``Registry.discover`` has the options)."""
    from .runs.search_run import SearchRequest, search_run

    request = SearchRequest(degree, weights, tuple(on), tuple(free), relations, budget)
    with open_executor(jobs, scheduler) as executor:
        return search_run(None, path, request, executor, progress)


def analyse_exponents(
    target: str | os.PathLike | Case,
    *,
    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
    free: Sequence[str] = (),
    budget: float | None = DEFAULT_EXPONENT_SECONDS,
    jobs: int | None = None,
    scheduler: str | Client | None = None,
) -> ExponentReport:
    """The Kovalevskaya exponents of a case file or a ``Case`` without a database (in a
    notebook): nothing is reused or recorded (``Registry.analyse_exponents`` has the
    options).

    >>> report = analyse_exponents("data/cases/heavy-top/kovalevskaya-1889-heavy-top.toml")
    >>> report.result.all_integer, report.result.degrees
    (True, (1, 2, 3, 4))
    """
    from .runs.exponents_run import ExponentRequest, exponents_run

    request = ExponentRequest(weights, tuple(free), budget)
    with open_executor(jobs, scheduler) as executor:
        return exponents_run(None, target, request, executor)
