"""The tables of the registry database (SQLAlchemy 2.0 ORM rows) and its view.

Rows hold what the database keeps: expressions as the text their authors wrote
(and JSON lists/maps of such text), never sympy objects. No row leaves the store:
``conversions`` turns rows into domain objects and back. The schema is built and
upgraded by the Alembic revisions in ``migrations`` (whose ``env.py`` reads
``Base``); ``latest_verdicts`` is a view those revisions create.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from sqlalchemy import (
    JSON,
    Boolean,
    Column,
    DateTime,
    Float,
    ForeignKey,
    MetaData,
    Select,
    Table,
    Text,
    UniqueConstraint,
    false,
    func,
    select,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column
from sqlalchemy.types import TypeDecorator

#: Version of the table layout, kept in the ``meta`` table (the Alembic revision, as a number).
SCHEMA_VERSION = 12

#: The states of an audit run; every run starts as ``running``.
RUN_STATUSES = ("running", "complete", "failed", "interrupted")

VIEW_NAME = "latest_verdicts"


# --------------------------------------------------------------------------- types


class UTCDateTime(TypeDecorator[datetime]):
    """A timezone-aware UTC datetime, also on backends (SQLite) that store naive values."""

    impl = DateTime(timezone=True)
    cache_ok = True

    def process_bind_param(self, value: datetime | None, dialect: Any) -> datetime | None:
        if value is None:
            return None
        if value.tzinfo is None:
            raise ValueError(f"naive datetime {value!r}: use an aware (UTC) datetime")
        return value.astimezone(UTC)

    def process_result_value(self, value: datetime | None, dialect: Any) -> datetime | None:
        if value is None:
            return None
        if value.tzinfo is None:
            return value.replace(tzinfo=UTC)
        return value.astimezone(UTC)


def now() -> datetime:
    """The current time, aware, in UTC (what every time column holds)."""
    return datetime.now(UTC)


# -------------------------------------------------------------------------- tables


class Base(DeclarativeBase):
    """Declarative base of the registry tables."""


class MetaRow(Base):
    """Key/value facts about the database itself (``schema_version``)."""

    __tablename__ = "meta"

    key: Mapped[str] = mapped_column(Text, primary_key=True)
    value: Mapped[str] = mapped_column(Text)


class SourceRow(Base):
    """A publication; shared by all cases citing it the same way."""

    __tablename__ = "sources"
    __table_args__ = (UniqueConstraint("citation", "doi"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    citation: Mapped[str] = mapped_column(Text)
    doi: Mapped[str] = mapped_column(Text, default="")
    # the structured citation (case format, [source]); the first case to give a field
    # sets it, later cases fill only what is still empty
    authors: Mapped[list[str]] = mapped_column(JSON, default=list, server_default="[]")
    year: Mapped[int | None]
    title: Mapped[str] = mapped_column(Text, default="", server_default="")
    journal: Mapped[str] = mapped_column(Text, default="", server_default="")
    booktitle: Mapped[str] = mapped_column(Text, default="", server_default="")
    publisher: Mapped[str] = mapped_column(Text, default="", server_default="")
    volume: Mapped[str] = mapped_column(Text, default="", server_default="")
    issue: Mapped[str] = mapped_column(Text, default="", server_default="")
    pages: Mapped[str] = mapped_column(Text, default="", server_default="")
    url: Mapped[str] = mapped_column(Text, default="", server_default="")


class CaseRow(Base):
    """One version of one case file; old versions stay when the file changes."""

    __tablename__ = "cases"
    __table_args__ = (UniqueConstraint("case_id", "version"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    case_id: Mapped[str] = mapped_column(Text)
    version: Mapped[int]
    title: Mapped[str] = mapped_column(Text)
    source_id: Mapped[int] = mapped_column(ForeignKey("sources.id"))
    locator: Mapped[str] = mapped_column(Text, default="")
    notes: Mapped[str] = mapped_column(Text, default="")
    content_hash: Mapped[str] = mapped_column(Text)
    text: Mapped[str] = mapped_column(Text)
    path: Mapped[str | None] = mapped_column(Text)
    inertia: Mapped[list[str]] = mapped_column(JSON)
    potential: Mapped[str] = mapped_column(Text)
    torque: Mapped[list[str]] = mapped_column(JSON)
    parameters: Mapped[dict[str, str]] = mapped_column(JSON)
    functions: Mapped[dict[str, list[str]]] = mapped_column(JSON)
    added_at: Mapped[datetime] = mapped_column(UTCDateTime)
    topic: Mapped[str] = mapped_column(Text, default="", server_default="")
    #: H as the case file gives it (``system.hamiltonian``); NULL in the inertia form.
    hamiltonian: Mapped[str | None] = mapped_column(Text, nullable=True)
    #: The bracket's parameter as written (``system.kappa``): "0" is e(3).
    kappa: Mapped[str] = mapped_column(Text, default="0", server_default="0")
    #: A system on a state of its own, as written: variables, equations, bracket entries,
    #: definitions (NULL for the reference paper's forms without definitions).
    form: Mapped[dict[str, Any] | None] = mapped_column(JSON(none_as_null=True), nullable=True)


class CaseAliasRow(Base):
    """An earlier id of a case version (its ``aliases``), under which it is still found."""

    __tablename__ = "case_aliases"

    id: Mapped[int] = mapped_column(primary_key=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    alias: Mapped[str] = mapped_column(Text, index=True)


class ClaimRow(Base):
    """One claim of one case version, in file order (``position``)."""

    __tablename__ = "claims"
    __table_args__ = (UniqueConstraint("case_pk", "label"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"))
    position: Mapped[int]
    label: Mapped[str] = mapped_column(Text)
    kind: Mapped[str] = mapped_column(Text)
    expression: Mapped[str] = mapped_column(Text)
    on: Mapped[list[str]] = mapped_column(JSON)
    locator: Mapped[str] = mapped_column(Text, default="")
    notes: Mapped[str] = mapped_column(Text, default="", server_default="")
    provenance: Mapped[str] = mapped_column(Text, default="literature", server_default="literature")
    # the search that attached this claim to the case version (it is not in the text);
    # checked by `registry verify-db` (no foreign key: see migration 0004)
    search_id: Mapped[int | None]


class RunRow(Base):
    """One audit run: when, with which code, and how it ended."""

    __tablename__ = "audit_runs"

    id: Mapped[int] = mapped_column(primary_key=True)
    started_at: Mapped[datetime] = mapped_column(UTCDateTime)
    finished_at: Mapped[datetime | None] = mapped_column(UTCDateTime)
    status: Mapped[str] = mapped_column(Text)
    code_version: Mapped[str] = mapped_column(Text)
    sympy_version: Mapped[str] = mapped_column(Text)
    python_version: Mapped[str] = mapped_column(Text)
    options: Mapped[dict[str, Any]] = mapped_column(JSON)
    # the process running the audit, to tell a live run from one whose process died
    host: Mapped[str | None] = mapped_column(Text)
    pid: Mapped[int | None]
    pid_started: Mapped[str | None] = mapped_column(Text)


class ResultRow(Base):
    """One check result of one run on one case version (and claim, for claim checks)."""

    __tablename__ = "check_results"

    id: Mapped[int] = mapped_column(primary_key=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("audit_runs.id"), index=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    claim_id: Mapped[int | None] = mapped_column(ForeignKey("claims.id"))
    check: Mapped[str] = mapped_column(Text)
    verdict: Mapped[str] = mapped_column(Text)
    method: Mapped[str] = mapped_column(Text, default="")
    reason: Mapped[str] = mapped_column(Text, default="")
    residual: Mapped[str | None] = mapped_column(Text)
    witness: Mapped[dict[str, Any] | None] = mapped_column(JSON(none_as_null=True))
    seconds: Mapped[float] = mapped_column(Float, default=0.0)
    reused: Mapped[bool] = mapped_column(Boolean, default=False, server_default=false())
    #: what a verified check adds for people (a relation's cofactor)
    detail: Mapped[str] = mapped_column(Text, default="", server_default="")


class CorrectionRow(Base):
    """A derived fact about one case version in one run: the torque's ``family``, a
    re-checked correction (``casimir`` or ``torque``), or the parameter ``conditions``
    under which a failed identity holds. ``payload`` holds the whole record."""

    __tablename__ = "corrections"

    id: Mapped[int] = mapped_column(primary_key=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("audit_runs.id"), index=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    claim_id: Mapped[int | None] = mapped_column(ForeignKey("claims.id"))
    kind: Mapped[str] = mapped_column(Text)
    expression: Mapped[str | None] = mapped_column(Text)
    method: Mapped[str] = mapped_column(Text, default="")
    # a Verdict value, or NULL where none applies (a family with no Casimir, no conditions)
    verdict: Mapped[str | None] = mapped_column(Text)
    payload: Mapped[dict[str, Any]] = mapped_column(JSON)


class EvidenceRow(Base):
    """Numerical evidence for one claim in one run: drift of I, of H, runs, agreement."""

    __tablename__ = "evidence"

    id: Mapped[int] = mapped_column(primary_key=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("audit_runs.id"), index=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    claim_id: Mapped[int] = mapped_column(ForeignKey("claims.id"))
    drift: Mapped[float | None] = mapped_column(Float)
    floor: Mapped[float | None] = mapped_column(Float)
    runs: Mapped[int]
    contradicts: Mapped[bool] = mapped_column(Boolean, default=False)
    note: Mapped[str] = mapped_column(Text, default="")
    # the check whose verdict the drift was compared with (``integral``), and why the
    # trajectories stand on a smaller set than the claim's, if they do
    compared_with: Mapped[str] = mapped_column(Text, default="integral", server_default="integral")
    narrowed: Mapped[str] = mapped_column(Text, default="", server_default="")
    # on a level set: the largest relative residual of its equations where the drift was
    # measured, whether the trajectories were projected back onto it, and why the drift
    # was not compared with the verdict (the trajectories left the set), if it was not
    departure: Mapped[float | None] = mapped_column(Float)
    projected: Mapped[bool] = mapped_column(Boolean, default=False, server_default=false())
    reason: Mapped[str] = mapped_column(Text, default="", server_default="")


class DriftCurveRow(Base):
    """The trajectory an audit integrated for a refuted claim, to be drawn: the times and
    the changes of I and of H along it."""

    __tablename__ = "drift_curves"

    id: Mapped[int] = mapped_column(primary_key=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("audit_runs.id"), index=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    claim_id: Mapped[int] = mapped_column(ForeignKey("claims.id"))
    t: Mapped[list[float]] = mapped_column(JSON)
    di: Mapped[list[float]] = mapped_column(JSON)
    dh: Mapped[list[float]] = mapped_column(JSON)


class SearchRow(Base):
    """One integral search of one case version: its options (and their canonical text,
    the key of its reuse), the code that ran it, and what it established."""

    __tablename__ = "searches"

    id: Mapped[int] = mapped_column(primary_key=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    options: Mapped[dict[str, Any]] = mapped_column(JSON)
    options_key: Mapped[str] = mapped_column(Text)
    code_version: Mapped[str] = mapped_column(Text)
    started_at: Mapped[datetime] = mapped_column(UTCDateTime)
    seconds: Mapped[float] = mapped_column(Float, default=0.0)
    complete: Mapped[bool] = mapped_column(Boolean)
    coverage: Mapped[list[str]] = mapped_column(JSON)
    known: Mapped[list[str]] = mapped_column(JSON)
    dimensions: Mapped[list[list[int]]] = mapped_column(JSON)
    method: Mapped[str] = mapped_column(Text, default="")
    statement: Mapped[str] = mapped_column(Text, default="")
    # the claims proven integrals and counted as known; whether they span the ansatz's
    claims: Mapped[list[str]] = mapped_column(JSON, default=list, server_default="[]")
    claims_complete: Mapped[bool] = mapped_column(Boolean, default=False, server_default=false())


class DiscoveryRow(Base):
    """What a search found on one set of parameter values (``when`` empty: the generic
    values): how many extra integrals, a basis of them, and where they were added as
    claims (the searched case version for generic values, a derived case otherwise)."""

    __tablename__ = "discoveries"

    id: Mapped[int] = mapped_column(primary_key=True)
    search_id: Mapped[int] = mapped_column(ForeignKey("searches.id"), index=True)
    position: Mapped[int]
    when: Mapped[list[str]] = mapped_column(JSON)
    extra: Mapped[int]
    integrals: Mapped[list[str]] = mapped_column(JSON)
    casimir: Mapped[list[str]] = mapped_column(JSON)
    # per integral: {"status": "new" | "rediscovered", "equals", "modulo", "relation"}
    status: Mapped[list[dict[str, Any]]] = mapped_column(JSON, default=list, server_default="[]")
    derived_case_pk: Mapped[int | None] = mapped_column(ForeignKey("cases.id"))
    # the catalog cases it is the same system as (``model.SameSystem.as_dict``)
    same_as: Mapped[list[dict[str, Any]]] = mapped_column(JSON, default=list, server_default="[]")


class ExponentRow(Base):
    """One Kovalevskaya analysis of one case version (``registry exponents``): its options
    (and their canonical text, the key of its reuse), the code that ran it, what a query
    filters on (decided, homogeneous, integer and rational exponents, the Painlevé test,
    Yoshida's degrees, the number of balances, the statement), and the whole JSON document
    (docs/json-output.md). A new analysis is a new row: none is ever overwritten."""

    __tablename__ = "exponents"

    id: Mapped[int] = mapped_column(primary_key=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    options: Mapped[dict[str, Any]] = mapped_column(JSON)
    options_key: Mapped[str] = mapped_column(Text)
    code_version: Mapped[str] = mapped_column(Text)
    started_at: Mapped[datetime] = mapped_column(UTCDateTime)
    seconds: Mapped[float] = mapped_column(Float, default=0.0)
    decided: Mapped[bool] = mapped_column(Boolean)
    homogeneous: Mapped[bool] = mapped_column(Boolean)
    all_integer: Mapped[bool] = mapped_column(Boolean)
    all_rational: Mapped[bool] = mapped_column(Boolean)
    #: the Painlevé test: passes, fails, or NULL where it was not made
    passes: Mapped[bool | None] = mapped_column(Boolean)
    degrees: Mapped[list[int]] = mapped_column(JSON)
    balances: Mapped[int]
    statement: Mapped[str] = mapped_column(Text, default="")
    document: Mapped[dict[str, Any]] = mapped_column(JSON)


# --------------------------------------------------------------------------- views


def latest_verdicts_select() -> Select:
    """For each (case id, claim label or NULL, check) of the newest version of each case:
    the result of the newest run. Claims of older versions stay in ``check_results``.

    PARTITION BY groups NULL labels together (as GROUP BY does) on SQLite and
    PostgreSQL, so case-level checks form one partition per (case, check).
    """
    r, c, cl = ResultRow.__table__, CaseRow.__table__, ClaimRow.__table__
    newer = CaseRow.__table__.alias("newer")
    newest_version = (
        select(func.max(newer.c.version)).where(newer.c.case_id == c.c.case_id).scalar_subquery()
    )
    rank = (
        func.row_number()
        .over(
            partition_by=(c.c.case_id, cl.c.label, r.c.check),
            order_by=(r.c.run_id.desc(), r.c.id.desc()),
        )
        .label("rn")
    )
    ranked = (
        select(
            c.c.case_id.label("case"),
            c.c.version,
            cl.c.label.label("claim"),
            r.c.check,
            r.c.verdict,
            r.c.method,
            r.c.reason,
            r.c.residual,
            r.c.witness,
            r.c.run_id.label("run"),
            r.c.seconds,
            r.c.reused,
            r.c.id.label("result"),
            rank,
        )
        .select_from(r.join(c, r.c.case_pk == c.c.id).outerjoin(cl, r.c.claim_id == cl.c.id))
        .where(c.c.version == newest_version)
        .subquery("ranked")
    )
    return select(*(col for col in ranked.c if col.name != "rn")).where(ranked.c.rn == 1)


_views = MetaData()
#: The ``latest_verdicts`` view as a queryable table, typed like the select it is made of.
latest_verdicts = Table(
    VIEW_NAME,
    _views,
    *(Column(col.name, col.type) for col in latest_verdicts_select().selected_columns),
)


def newest_versions():
    """A subquery of (case_id, version) for the newest version of every case."""
    return (
        select(CaseRow.case_id, func.max(CaseRow.version).label("version"))
        .group_by(CaseRow.case_id)
        .subquery()
    )


class IdentificationRow(Base):
    """Which catalog cases one case version is the same system as (``registry
    identify``): the catalog compared with (a digest of its case versions), the code
    that ran it, the cases found (``model.SameSystem.as_dict``), those compared, skipped
    and failed, and the time. A new identification is a new row: none is overwritten."""

    __tablename__ = "identifications"

    id: Mapped[int] = mapped_column(primary_key=True)
    case_pk: Mapped[int] = mapped_column(ForeignKey("cases.id"), index=True)
    catalog: Mapped[str] = mapped_column(Text)
    code_version: Mapped[str] = mapped_column(Text)
    recorded_at: Mapped[datetime] = mapped_column(UTCDateTime)
    seconds: Mapped[float] = mapped_column(Float, default=0.0)
    same_as: Mapped[list[dict[str, Any]]] = mapped_column(JSON)
    compared: Mapped[list[str]] = mapped_column(JSON)
    skipped: Mapped[list[str]] = mapped_column(JSON)
    failed: Mapped[list[list[str]]] = mapped_column(JSON)
    # why the case was compared with none (its field has no normal form), else ""
    note: Mapped[str] = mapped_column(Text, default="")
