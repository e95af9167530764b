"""The registry as pandas DataFrames: cases, claims, verdicts, runs and repairs.

Named queries over the tables and the ``latest_verdicts`` view (no raw SQL), each
one database session; ``Registry.cases()`` and the other queries of the API, and
``registry export``, read the registry through them.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

from sqlalchemy import Select, func, select
from sqlalchemy import case as sql_case

from ..errors import UnknownRunError
from ..model import Verdict
from .conversions import verdict_text
from .database import Store, get_run
from .engine import guarded
from .tables import (
    CaseRow,
    ClaimRow,
    CorrectionRow,
    ResultRow,
    RunRow,
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
        )
        .join(SourceRow, SourceRow.id == CaseRow.source_id)
        .join(
            newest,
            (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
        )
        .outerjoin(n_claims, n_claims.c.case_pk == CaseRow.id)
        .order_by(CaseRow.case_id)
    )
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
    stmt = (
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
        .where(ResultRow.run_id == run)
        .order_by(ResultRow.id)
    )
    return _select_frame(store, stmt)


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
    """Families, repairs and conditions of one run (default: the newest run)."""
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


def _select_frame(store: Store, stmt: Select) -> pd.DataFrame:
    """Run a select and return its rows as a DataFrame named by its columns."""
    with store.connect() as conn:
        result = conn.execute(stmt)
        return _frame(result.all(), list(result.keys()))


def _frame(rows: Iterable[Sequence[Any]], columns: Sequence[str]) -> pd.DataFrame:
    """A DataFrame with these columns, also when there are no rows."""
    import pandas as pd  # imported here: adding cases should not pay for pandas

    return pd.DataFrame([tuple(r) for r in rows], columns=list(columns))
