"""The registry as pandas DataFrames: cases, claims, verdicts, runs and corrections.

Named queries over the tables and the ``latest_verdicts`` view (no raw SQL), each
one database session; ``Registry.cases()`` and the other queries of the API, and
``registry export``, read the registry through them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, Unpack

from sqlalchemy import Select, func, select
from sqlalchemy import case as sql_case

from ..errors import UnknownRunError
from ..model import CaseFilter, CaseIdentification, Verdict, case_filter
from .conversions import verdict_text
from .database import Store, get_run
from .engine import guarded
from .tables import (
    CaseAliasRow,
    CaseRow,
    ClaimRow,
    CorrectionRow,
    DiscoveryRow,
    ExponentRow,
    ResultRow,
    RunRow,
    SearchRow,
    SourceRow,
    latest_verdicts,
    newest_versions,
)

if TYPE_CHECKING:
    import pandas as pd


@guarded
def cases_frame(store: Store) -> pd.DataFrame:
    """One row per case (newest version): case, version, title, citation, n_claims, ..."""
    n_claims = (
        select(ClaimRow.case_pk, func.count(ClaimRow.id).label("n"))
        .group_by(ClaimRow.case_pk)
        .subquery()
    )
    newest = newest_versions()
    stmt = (
        select(
            CaseRow.case_id.label("case"),
            CaseRow.version,
            CaseRow.title,
            SourceRow.citation,
            CaseRow.locator,
            SourceRow.doi,
            CaseRow.content_hash,
            func.coalesce(n_claims.c.n, 0).label("n_claims"),
            CaseRow.added_at,
            CaseRow.topic,
            CaseRow.inertia,
            CaseRow.potential,
            CaseRow.torque,
            CaseRow.hamiltonian,
            CaseRow.kappa,
            CaseRow.form.label("own_state"),
            SourceRow.authors,
            SourceRow.year,
            SourceRow.title.label("source_title"),
            SourceRow.journal,
            SourceRow.booktitle,
            SourceRow.publisher,
            SourceRow.volume,
            SourceRow.issue,
            SourceRow.pages,
            SourceRow.url,
            CaseRow.id.label("pk"),
        )
        .join(SourceRow, SourceRow.id == CaseRow.source_id)
        .join(
            newest,
            (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
        )
        .outerjoin(n_claims, n_claims.c.case_pk == CaseRow.id)
        .order_by(CaseRow.case_id)
    )
    frame = _select_frame(store, stmt)
    with store.read() as session:
        aliases: dict[int, list[str]] = {}
        for pk, alias in session.execute(
            select(CaseAliasRow.case_pk, CaseAliasRow.alias).order_by(CaseAliasRow.id)
        ):
            aliases.setdefault(pk, []).append(alias)
    frame["aliases"] = [aliases.get(pk, []) for pk in frame["pk"]]
    frame.insert(
        frame.columns.get_loc("hamiltonian"),
        "form",
        [
            _form_name(own, h)
            for own, h in zip(frame["own_state"], frame["hamiltonian"], strict=True)
        ],
    )
    frame.insert(
        frame.columns.get_loc("form") + 1,
        "variables",
        [list((own or {}).get("variables", [])) for own in frame["own_state"]],
    )
    return frame.drop(columns=["pk", "own_state"])


def _form_name(own: dict | None, hamiltonian: str | None) -> str:
    """The form a stored system was written in (``System.form``): "inertia" or
    "hamiltonian" on the paper's state, "equations" or "bracket" on a state of its own."""
    if own and own.get("variables"):
        return "bracket" if own.get("bracket") or not own.get("equations") else "equations"
    return "hamiltonian" if isinstance(hamiltonian, str) else "inertia"  # NULL reads as NaN


@guarded
def case_table(store: Store, **filters: Unpack[CaseFilter]) -> pd.DataFrame:
    """``cases_frame`` with the torque family each case's newest audit found and the
    cases each was identified with, filtered as ``filters`` say (``model.CaseFilter``)."""
    import pandas as pd  # imported here: adding cases should not pay for pandas

    wanted = case_filter(filters)

    frame = cases_frame(store).merge(families_frame(store), on="case", how="left")
    frame["family"] = frame["family"].map(lambda f: f if isinstance(f, str) else "")
    identified = store.newest_identifications()
    same = identifications_frame(store, identified)

    def others(case: str, equivalent: bool) -> list[str] | None:
        if case not in identified:
            return None  # never identified: unknown, not "none"
        rows = same[(same["case"] == case) & (same["equivalent"] | (not equivalent))]
        return sorted(rows["same_as"])

    frame["same_as"] = frame["case"].map(lambda c: others(c, False))
    frame["equivalent"] = frame["case"].map(lambda c: others(c, True))
    frame["identification_note"] = frame["case"].map(
        lambda c: identified[c].note if c in identified else ""
    )
    current = store.catalog_digest()
    frame["identification_complete"] = frame["case"].map(
        lambda c: identified[c].complete if c in identified else None
    )
    frame["identification_current"] = frame["case"].map(
        lambda c: identified[c].catalog == current if c in identified else None
    )
    keep = pd.Series(True, index=frame.index)

    def contains(values: pd.Series, text: str) -> pd.Series:
        return values.astype(str).str.lower().str.contains(text.lower(), regex=False)

    if (source := wanted.get("source")) is not None:
        texts = frame["citation"] + " " + frame["source_title"] + " " + frame["journal"]
        keep &= contains(texts, source)
    if (author := wanted.get("author")) is not None:
        names = frame["authors"].map(lambda a: " ".join(a) if isinstance(a, list) else "")
        keep &= contains(names, author)
    if (year := wanted.get("year")) is not None:
        first, last = year if isinstance(year, tuple) else (year, year)
        keep &= pd.to_numeric(frame["year"], errors="coerce").between(first, last)
    if (topic := wanted.get("topic")) is not None:
        keep &= frame["topic"].astype(str).str.lower() == topic.lower()
    if (family := wanted.get("family")) is not None:
        keep &= frame["family"] == family
    if (verdict := wanted.get("verdict")) is not None:
        keep &= frame["case"].isin(_cases_with_verdict(store, str(Verdict(verdict))))
    return frame[keep.astype(bool)].reset_index(drop=True)


def identifications_frame(
    store: Store, newest: Mapping[str, CaseIdentification] | None = None
) -> pd.DataFrame:
    """One row per catalog case that a case (its latest version, its newest
    identification) is the same system as: case, version, same_as (the other case), its
    parameter ``values`` and the ``transformation`` (the other's variables and time in
    this case's), ``equivalent`` (the other is identified back with this case: one
    system written twice), ``complete`` (every case was compared)."""
    import pandas as pd  # imported here: adding cases should not pay for pandas

    newest = store.newest_identifications() if newest is None else newest
    rows = [
        {
            "case": case,
            "version": found.version,
            "same_as": same.case,
            "values": dict(same.values),
            "transformation": dict(same.transformation),
            "equivalent": same.case in newest
            and any(back.case == case for back in newest[same.case].same_as),
            "complete": found.complete,
        }
        for case, found in sorted(newest.items())
        for same in found.same_as
    ]
    columns = ["case", "version", "same_as", "values", "transformation", "equivalent", "complete"]
    return pd.DataFrame(rows, columns=columns)


def _cases_with_verdict(store: Store, verdict: str) -> set[str]:
    """The cases some claim of which has this overall verdict (its kind's check)."""
    claims = claims_frame(store)[["case", "label", "kind"]]
    found = verdicts_frame(store).merge(
        claims, left_on=["case", "claim"], right_on=["case", "label"]
    )
    return set(found.loc[(found["kind"] == found["check"]) & (found["verdict"] == verdict), "case"])


def versions_frame(store: Store) -> pd.DataFrame:
    """One row per stored case version, oldest first for each case: case, version,
    content_hash, added_at (the version history a case's page shows)."""
    stmt = select(
        CaseRow.case_id.label("case"), CaseRow.version, CaseRow.content_hash, CaseRow.added_at
    ).order_by(CaseRow.case_id, CaseRow.version)
    return _select_frame(store, stmt)


@guarded
def claims_frame(store: Store) -> pd.DataFrame:
    """One row per claim of each newest case version, in file order."""
    newest = newest_versions()
    stmt = (
        select(
            CaseRow.case_id.label("case"),
            CaseRow.version,
            ClaimRow.label,
            ClaimRow.kind,
            ClaimRow.expression,
            ClaimRow.on,
            ClaimRow.locator,
            ClaimRow.provenance,
            ClaimRow.notes,
            ClaimRow.search_id.label("search"),
        )
        .join(CaseRow, CaseRow.id == ClaimRow.case_pk)
        .join(
            newest,
            (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
        )
        .order_by(CaseRow.case_id, ClaimRow.position)
    )
    return _select_frame(store, stmt)


@guarded
def verdicts_frame(store: Store, run: int | None = None) -> pd.DataFrame:
    """Check results: the newest per (case, claim, check) if ``run`` is None, else that run's.

    Columns: case, version, claim (None for case checks), check, verdict, method,
    reason, run, seconds, witness (a dict or None), residual, reused.
    """
    if run is None:
        v = latest_verdicts.c
        stmt = select(
            v.case, v.version, v.claim, v.check, v.verdict, v.method, v.reason, v.run,
            v.seconds, v.witness, v.residual, v.reused,
        ).order_by(v.case, v.result)  # fmt: skip
        return _select_frame(store, stmt)
    with store.read() as session:
        get_run(session, run)
    return _select_frame(store, _results().where(ResultRow.run_id == run).order_by(ResultRow.id))


@guarded
def all_results_frame(store: Store) -> pd.DataFrame:
    """Every stored check result of every run, oldest run first (the columns of
    ``verdicts_frame`` of one run)."""
    return _select_frame(store, _results().order_by(ResultRow.run_id, ResultRow.id))


def _results() -> Select:
    """The check results with their case, version and claim (no run chosen yet)."""
    return (
        select(
            CaseRow.case_id.label("case"),
            CaseRow.version,
            ClaimRow.label.label("claim"),
            ResultRow.check,
            ResultRow.verdict,
            ResultRow.method,
            ResultRow.reason,
            ResultRow.run_id.label("run"),
            ResultRow.seconds,
            ResultRow.witness,
            ResultRow.residual,
            ResultRow.reused,
        )
        .join(CaseRow, CaseRow.id == ResultRow.case_pk)
        .outerjoin(ClaimRow, ClaimRow.id == ResultRow.claim_id)
    )


@guarded
def runs_frame(store: Store) -> pd.DataFrame:
    """One row per audit run with counts of its results by verdict, newest run last."""

    def count(verdict: Verdict) -> Any:
        hit = sql_case((ResultRow.verdict == verdict_text(verdict), 1), else_=0)
        return func.coalesce(func.sum(hit), 0).label(f"n_{verdict_text(verdict)}")

    stmt = (
        select(
            RunRow.id.label("run"),
            RunRow.started_at,
            RunRow.finished_at,
            RunRow.status,
            RunRow.code_version,
            RunRow.sympy_version,
            RunRow.python_version,
            func.count(ResultRow.case_pk.distinct()).label("n_cases"),
            func.count(ResultRow.id).label("n_results"),
            *(count(v) for v in Verdict),
            func.coalesce(func.sum(sql_case((ResultRow.reused, 1), else_=0)), 0).label("n_reused"),
            RunRow.options,
        )
        .outerjoin(ResultRow, ResultRow.run_id == RunRow.id)
        .group_by(RunRow.id)
        .order_by(RunRow.id)
    )
    return _select_frame(store, stmt)


@guarded
def corrections_frame(store: Store, run: int | None = None) -> pd.DataFrame:
    """Families, corrections and conditions of one run (default: the newest run)."""
    with store.read() as session:
        if run is None:
            run = session.scalar(select(func.max(CorrectionRow.run_id)))
        elif session.get(RunRow, run) is None:
            raise UnknownRunError(run)
    stmt = (
        select(
            CorrectionRow.run_id.label("run"),
            CaseRow.case_id.label("case"),
            CaseRow.version,
            ClaimRow.label.label("claim"),
            CorrectionRow.kind,
            CorrectionRow.expression,
            CorrectionRow.method,
            CorrectionRow.verdict,
            CorrectionRow.payload,
        )
        .join(CaseRow, CaseRow.id == CorrectionRow.case_pk)
        .outerjoin(ClaimRow, ClaimRow.id == CorrectionRow.claim_id)
        .where(CorrectionRow.run_id == run)
        .order_by(CorrectionRow.id)
    )
    return _select_frame(store, stmt)


@guarded
def families_frame(store: Store) -> pd.DataFrame:
    """The torque family of every case's newest version, from the newest run that
    recorded one: case, family (``constant``, ``affine``, ``psi-gamma-grad-phi``, ...)."""
    newest = newest_versions()
    stmt = (
        select(CaseRow.case_id.label("case"), CorrectionRow.payload, CorrectionRow.run_id)
        .join(CaseRow, CaseRow.id == CorrectionRow.case_pk)
        .join(
            newest,
            (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
        )
        .where(CorrectionRow.kind == "family")
        .order_by(CaseRow.case_id, CorrectionRow.run_id.desc(), CorrectionRow.id.desc())
    )
    frame = _select_frame(store, stmt)
    frame = frame.drop_duplicates("case")
    frame["family"] = [p.get("name", "") for p in frame["payload"]]
    return frame[["case", "family"]].reset_index(drop=True)


@guarded
def searches_frame(store: Store) -> pd.DataFrame:
    """One row per integral search: the case version searched, the ansatz (degree,
    weights, level set, free parameters), how many extra integrals exist for generic
    values and how many special sets carry more, whether the search is complete, what
    it covered, the result in one sentence, and its provenance (code, time, seconds)."""
    n_special = (
        select(DiscoveryRow.search_id, func.count(DiscoveryRow.id).label("n"))
        .where(DiscoveryRow.position > 0)
        .group_by(DiscoveryRow.search_id)
        .subquery()
    )
    generic = (
        select(DiscoveryRow.search_id, DiscoveryRow.extra, DiscoveryRow.status)
        .where(DiscoveryRow.position == 0)
        .subquery()
    )
    stmt = (
        select(
            SearchRow.id.label("search"),
            CaseRow.case_id.label("case"),
            CaseRow.version,
            SearchRow.options,
            func.coalesce(generic.c.extra, 0).label("generic_extra"),
            func.coalesce(n_special.c.n, 0).label("n_special"),
            generic.c.status,
            SearchRow.complete,
            SearchRow.claims_complete,
            SearchRow.coverage,
            SearchRow.statement,
            SearchRow.known,
            SearchRow.claims,
            SearchRow.method,
            SearchRow.code_version,
            SearchRow.started_at,
            SearchRow.seconds,
        )
        .join(CaseRow, CaseRow.id == SearchRow.case_pk)
        .outerjoin(n_special, n_special.c.search_id == SearchRow.id)
        .outerjoin(generic, generic.c.search_id == SearchRow.id)
        .order_by(SearchRow.id)
    )
    frame = _select_frame(store, stmt)
    options = list(frame.pop("options"))
    for position, key in enumerate(("degree", "weights", "on", "free"), start=3):
        frame.insert(position, key, [o[key] for o in options])
    again = [sum(t["status"] != "new" for t in s or []) for s in frame.pop("status")]
    where = list(frame.columns).index("n_special")
    frame.insert(
        where, "generic_new", [n - r for n, r in zip(frame.generic_extra, again, strict=True)]
    )
    frame.insert(where + 1, "rediscovered", again)
    return frame


@guarded
def discoveries_frame(store: Store) -> pd.DataFrame:
    """One row per set of parameter values a search found integrals on (``when`` empty:
    the generic values): the search, the case, the equations, how many extra integrals,
    a basis of them, their casimir verdicts, the catalog cases it is the same system as
    (``same_as``), and the case version where they were added as claims (the searched
    case for generic values, a derived case otherwise)."""
    derived = CaseRow.__table__.alias("derived")
    stmt = (
        select(
            DiscoveryRow.search_id.label("search"),
            CaseRow.case_id.label("case"),
            DiscoveryRow.when,
            DiscoveryRow.extra,
            DiscoveryRow.integrals,
            DiscoveryRow.casimir,
            DiscoveryRow.status,
            DiscoveryRow.same_as,
            derived.c.case_id.label("derived_case"),
            derived.c.version.label("derived_version"),
        )
        .join(SearchRow, SearchRow.id == DiscoveryRow.search_id)
        .join(CaseRow, CaseRow.id == SearchRow.case_pk)
        .outerjoin(derived, derived.c.id == DiscoveryRow.derived_case_pk)
        .where((DiscoveryRow.extra > 0) | (DiscoveryRow.position == 0))
        .order_by(DiscoveryRow.search_id, DiscoveryRow.position)
    )
    return _select_frame(store, stmt)


@guarded
def exponents_frame(store: Store) -> pd.DataFrame:
    """One row per recorded Kovalevskaya analysis, oldest first: the case version, the
    weights and free parameters, whether it was decided, whether the field is
    weighted-homogeneous under the weights, the number of balances, whether every
    exponent is an integer (rational), Yoshida's degrees, the Painlevé test, how many
    special sets a family has, the statement, and its provenance (code, time, seconds)."""
    stmt = (
        select(
            ExponentRow.id.label("analysis"),
            CaseRow.case_id.label("case"),
            CaseRow.version,
            ExponentRow.options,
            ExponentRow.decided,
            ExponentRow.homogeneous,
            ExponentRow.balances,
            ExponentRow.all_integer,
            ExponentRow.all_rational,
            ExponentRow.degrees,
            ExponentRow.passes.label("painleve"),
            ExponentRow.document,
            ExponentRow.statement,
            ExponentRow.code_version,
            ExponentRow.started_at,
            ExponentRow.seconds,
        )
        .join(CaseRow, CaseRow.id == ExponentRow.case_pk)
        .order_by(ExponentRow.id)
    )
    frame = _select_frame(store, stmt)
    options = list(frame.pop("options"))
    frame.insert(3, "weights", [o["weights"] for o in options])
    frame.insert(4, "free", [o["free"] for o in options])
    documents = list(frame.pop("document"))
    where = list(frame.columns).index("painleve") + 1
    frame.insert(where, "n_special", [len(d.get("special", ())) for d in documents])
    return frame


def _select_frame(store: Store, stmt: Select) -> pd.DataFrame:
    """Run a select and return its rows as a DataFrame named by its columns."""
    with store.connect() as conn:
        result = conn.execute(stmt)
        return _frame(result.all(), list(result.keys()))


def _frame(rows: Iterable[Sequence[Any]], columns: Sequence[str]) -> pd.DataFrame:
    """A DataFrame with these columns, also when there are no rows."""
    import pandas as pd  # imported here: adding cases should not pay for pandas

    return pd.DataFrame([tuple(r) for r in rows], columns=list(columns))
