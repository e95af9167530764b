"""The registry database: cases, audit runs and check results (SQLAlchemy 2.0).

The database never does algebra: it keeps expressions as the text their
authors wrote (and JSON lists/maps of such text), so a stored case is parsed
again from its ``text`` when it is needed. Rows are converted to and from the
domain objects of ``model`` here and nowhere else; no ORM row leaves this module.

SQLite is the default (foreign keys on, WAL journal, 30 s busy timeout); any
SQLAlchemy URL works. On SQLite, write transactions start with
``BEGIN IMMEDIATE`` so that reading the next version number and inserting it
happen under one write lock, even with several processes on one file.
"""

from __future__ import annotations

import functools
import os
import platform
import socket
import sqlite3
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from importlib import metadata as importlib_metadata
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, ParamSpec, TypeVar

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
    create_engine,
    event,
    false,
    func,
    select,
)
from sqlalchemy import case as sql_case
from sqlalchemy.engine import URL, Connection, Engine, make_url
from sqlalchemy.exc import (
    ArgumentError,
    DBAPIError,
    IntegrityError,
    NoSuchModuleError,
    OperationalError,
    ProgrammingError,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, Session, mapped_column
from sqlalchemy.pool import StaticPool
from sqlalchemy.types import TypeDecorator

from ..errors import (
    DatabaseFullError,
    DatabaseLockedError,
    DatabaseMissingError,
    DatabaseReadOnlyError,
    NotADatabaseError,
    StorageError,
    UnknownCaseError,
    UnknownRunError,
)
from ..model import (
    Case,
    CaseAudit,
    CheckResult,
    Claim,
    Conditions,
    Correction,
    Evidence,
    FamilyRecord,
    Verdict,
    Witness,
)
from . import migrate

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "SCHEMA_VERSION",
    "RUN_STATUSES",
    "AddOutcome",
    "StoredCase",
    "StoredText",
    "Store",
    "Base",
]

#: Version of the table layout, kept in the ``meta`` table (the Alembic revision, as a number).
SCHEMA_VERSION = 3

#: How long one attempt waits for another process's write lock (SQLite busy timeout).
BUSY_TIMEOUT = 10.0

#: Attempts of a transaction that found the database locked, before giving up.
LOCK_ATTEMPTS = 3

#: The states of an audit run; every run starts as ``running``.
RUN_STATUSES = ("running", "complete", "failed", "interrupted")

#: Execution option that makes a SQLite transaction start with BEGIN IMMEDIATE.
_WRITE_OPTION = "registry_write"

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


def _now() -> datetime:
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


class CorrectionRow(Base):
    """A derived fact about one case version in one run: the torque's ``family``, a
    re-checked repair (``casimir`` or ``torque``), or the parameter ``conditions``
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


# --------------------------------------------------------------------------- views


def _latest_verdicts_select() -> Select:
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
    *(Column(col.name, col.type) for col in _latest_verdicts_select().selected_columns),
)


# ---------------------------------------------------------------- public dataclasses


@dataclass(frozen=True)
class AddOutcome:
    """What ``Store.add_case`` did: ``added``, ``unchanged`` or ``new version``."""

    case_id: str
    version: int
    status: Literal["added", "unchanged", "new version"]
    pk: int | None = field(default=None, compare=False)


@dataclass(frozen=True)
class StoredText:
    """One expression (or ``lhs = rhs`` equation) kept in the database, and where."""

    case_pk: int
    place: str
    text: str
    equation: bool = False


@dataclass(frozen=True)
class StoredCase:
    """One stored case version: enough to parse it again (``text``) and audit it (``pk``)."""

    pk: int
    case_id: str
    version: int
    content_hash: str
    text: str
    path: str | None


# ------------------------------------------------------------------- conversions


def _case_row(case: Case, version: int, source_id: int) -> CaseRow:
    """The row of one case version (claims are separate rows)."""
    names = list(case.parameters) + [n for n in case.assumptions if n not in case.parameters]
    return CaseRow(
        case_id=case.id,
        version=version,
        title=case.title,
        source_id=source_id,
        locator=case.source.locator,
        notes=case.notes,
        content_hash=case.content_hash,
        text=case.text,
        path=case.path,
        inertia=[e.text for e in case.system.inertia],
        potential=case.system.potential.text,
        torque=[e.text for e in case.system.torque],
        parameters={n: str(case.assumptions.get(n, "real")) for n in names},
        functions={name: [str(a) for a in args] for name, (_, args) in case.functions.items()},
        added_at=_now(),
    )


def _claim_row(claim: Claim, case_pk: int, position: int) -> ClaimRow:
    """The row of one claim of a stored case version."""
    return ClaimRow(
        case_pk=case_pk,
        position=position,
        label=claim.label,
        kind=str(claim.kind),
        expression=claim.expression.text,
        on=[eq.text for eq in claim.on],
        locator=claim.locator,
    )


def _witness(data: dict[str, Any] | None) -> Witness | None:
    """A Witness from its ``as_dict`` form (None stays None)."""
    if data is None:
        return None
    return Witness(
        point=data.get("point", {}),
        value=data.get("value", ""),
        approx=data.get("approx", ""),
        component=data.get("component", ""),
        functions=data.get("functions", {}),
    )


def _check_result(row: ResultRow, label: str | None) -> CheckResult:
    """A CheckResult from its row and its claim's label."""
    return CheckResult(
        check=row.check,
        verdict=Verdict(row.verdict),
        method=row.method,
        claim=label,
        reason=row.reason,
        residual=row.residual,
        witness=_witness(row.witness),
        seconds=row.seconds,
    )


def _frame(rows: Iterable[Sequence[Any]], columns: Sequence[str]) -> pd.DataFrame:
    """A DataFrame with these columns, also when there are no rows."""
    import pandas as pd  # imported here: adding cases should not pay for pandas

    return pd.DataFrame([tuple(r) for r in rows], columns=list(columns))


# ------------------------------------------------------------------------ opening


def _resolve(url_or_path: str | Path, create: bool) -> tuple[URL, str]:
    """The SQLAlchemy URL for a path, ``:memory:`` or URL, and how to name it in messages.

    A database file that does not exist is an error unless ``create``.
    """
    if isinstance(url_or_path, str) and "://" in url_or_path:
        try:
            url = make_url(url_or_path)
        except ArgumentError as err:
            raise StorageError(f"cannot open database {url_or_path!r}: {err}") from err
        return url, url.render_as_string(hide_password=True)
    if str(url_or_path) == ":memory:":
        return URL.create("sqlite", database=":memory:"), ":memory:"
    path = Path(url_or_path).expanduser()
    if not create and not path.exists():
        raise DatabaseMissingError(str(path))
    if path.is_dir():
        raise NotADatabaseError(str(path), "it is a folder")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise StorageError(f"cannot create the folder of database {str(path)!r}: {err}") from err
    return URL.create("sqlite", database=str(path)), str(path)


def _is_memory(url: URL) -> bool:
    return url.get_backend_name() == "sqlite" and url.database in (None, "", ":memory:")


def _configure_sqlite(engine: Engine, file_db: bool) -> None:
    """Per-connection SQLite settings, and BEGIN emitted by SQLAlchemy (not by sqlite3).

    sqlite3's own transaction handling skips BEGIN before SELECT and DDL; taking it
    over makes reads transactional and lets writers start with BEGIN IMMEDIATE.
    """

    @event.listens_for(engine, "connect")
    def _on_connect(dbapi_connection: Any, _record: Any) -> None:
        dbapi_connection.isolation_level = None
        cursor = dbapi_connection.cursor()
        try:
            cursor.execute("PRAGMA foreign_keys=ON")
            cursor.execute(f"PRAGMA busy_timeout={int(BUSY_TIMEOUT * 1000)}")
            if file_db:
                cursor.execute("PRAGMA journal_mode=WAL")
        finally:
            cursor.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn: Connection) -> None:
        write = conn.get_execution_options().get(_WRITE_OPTION, False)
        conn.exec_driver_sql("BEGIN IMMEDIATE" if write else "BEGIN")


P = ParamSpec("P")
T = TypeVar("T")


def _guarded(method: Callable[P, T]) -> Callable[P, T]:
    """Turn a database failure into a one-line StorageError of its kind; a transaction
    that found the database locked is retried (each method is one transaction, rolled
    back on failure, so running it again is safe)."""

    @functools.wraps(method)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> T:
        location = getattr(args[0], "location", "")
        for attempt in range(1, LOCK_ATTEMPTS + 1):
            try:
                return method(*args, **kwargs)
            except (IntegrityError, ProgrammingError):
                raise  # a bug in the caller, not a state of the database
            except DBAPIError as err:
                problem = storage_error(err, location)
                if not isinstance(problem, DatabaseLockedError) or attempt == LOCK_ATTEMPTS:
                    raise problem from err
                time.sleep(min(0.05 * 2**attempt, 1.0))
        raise AssertionError("unreachable")

    return wrapper


def storage_error(err: DBAPIError, location: str, doing: str = "write to it") -> StorageError:
    """The StorageError for a database failure, by what SQLite reports."""
    reported = str(err.orig)
    said = reported.lower()
    if "locked" in said or "busy" in said:
        return DatabaseLockedError(location, BUSY_TIMEOUT * LOCK_ATTEMPTS)
    if "readonly" in said or "read-only" in said:
        return DatabaseReadOnlyError(location, doing)
    if "disk is full" in said or "disk full" in said:
        return DatabaseFullError(location)
    if "not a database" in said or "malformed" in said:
        return NotADatabaseError(location, reported)
    return StorageError(f"database {location!r}: {reported}")


# -------------------------------------------------------------------------- store


class Store:
    """The registry database. ``Store(path)``, ``Store(":memory:")`` or ``Store(url)``.

    Every method takes and returns domain objects or plain Python values; each
    write is one transaction. Use as a context manager or call ``close()``.
    """

    def __init__(self, url_or_path: str | Path, *, create: bool = True):
        url, self.location = _resolve(url_or_path, create)
        self.backup: Path | None = None  # the copy made before a schema upgrade
        self.upgraded_from: str | None = None  # the revision upgraded from, if any
        self.busy = 0  # database sessions in progress
        self.on_idle: Callable[[], None] | None = None  # called when the last one ends
        try:
            if _is_memory(url):
                engine = create_engine(
                    url, poolclass=StaticPool, connect_args={"check_same_thread": False}
                )
            else:
                engine = create_engine(url)
        except (ArgumentError, NoSuchModuleError, ImportError) as err:
            raise StorageError(f"cannot open database {self.location!r}: {err}") from err
        if url.get_backend_name() == "sqlite":
            _configure_sqlite(engine, file_db=not _is_memory(url))
        self._engine = engine
        self._writer = engine.execution_options(**{_WRITE_OPTION: True})
        self._file = Path(url.database) if url.get_backend_name() == "sqlite" else None
        if _is_memory(url):
            self._file = None
        try:
            self._init_schema()
            self._mark_interrupted()
        except DBAPIError as err:
            engine.dispose()
            raise storage_error(err, self.location, "create or upgrade its tables") from err
        except BaseException:
            engine.dispose()
            raise

    # ----------------------------------------------------------------- lifecycle

    @property
    def engine(self) -> Engine:
        """The SQLAlchemy engine, for ad-hoc SQL (e.g. ``pandas.read_sql``)."""
        return self._engine

    def close(self) -> None:
        """Close all pooled connections."""
        self._engine.dispose()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Store({self.location!r})"

    def _init_schema(self) -> None:
        """Bring the schema to the newest revision (see ``migrate``); refuse newer ones.

        A current database is only read, so a read-only registry file still opens.
        An older one is copied aside first, then upgraded in one transaction.
        """
        with self._connect() as conn:
            state = migrate.inspect_schema(conn, self.location)
        if state.current:
            return
        if not state.empty and self._file is not None:
            try:
                self.backup = migrate.backup(self._file, state.revision or "")
            except (OSError, sqlite3.Error) as err:
                raise StorageError(
                    f"database {self.location!r} needs a schema upgrade from revision "
                    f"{state.revision}, but no backup copy could be made first ({err})"
                ) from err
        with self._writer.begin() as conn:
            state = migrate.inspect_schema(conn, self.location)  # another process may have
            if not state.current:  # upgraded it meanwhile
                migrate.upgrade(conn, state)
                self.upgraded_from = state.revision

    def _mark_interrupted(self) -> None:
        """Mark as ``interrupted`` the runs left ``running`` by a process that has died.

        Runs of processes on other hosts, or still alive, are left alone; so is a
        database this process may not write (the next writer will do it).
        """
        with self._read() as session:
            running = session.execute(
                select(RunRow.id, RunRow.host, RunRow.pid, RunRow.pid_started).where(
                    RunRow.status == "running"
                )
            ).all()
        dead = [r.id for r in running if _process_gone(r.host, r.pid, r.pid_started)]
        if not dead:
            return
        try:
            with self._write() as session:
                for run in session.scalars(
                    select(RunRow).where(RunRow.id.in_(dead), RunRow.status == "running")
                ):
                    run.status = "interrupted"
        except OperationalError as err:
            if not isinstance(storage_error(err, self.location), DatabaseReadOnlyError):
                raise

    @contextmanager
    def _write(self) -> Iterator[Session]:
        """A session in one write transaction: committed on success, rolled back on error."""
        with self._busy(), Session(self._writer) as session, session.begin():
            yield session

    @contextmanager
    def _read(self) -> Iterator[Session]:
        """A session for reading (one consistent snapshot)."""
        with self._busy(), Session(self._engine) as session:
            yield session

    @contextmanager
    def _connect(self) -> Iterator[Connection]:
        """A plain connection (no ORM session), counted like a session (``_busy``)."""
        with self._busy(), self._engine.connect() as conn:
            yield conn

    @contextmanager
    def _busy(self) -> Iterator[None]:
        """Count the sessions in progress (``busy``) and call ``on_idle`` when none is
        left: a signal handler that must not break a session waits for that moment."""
        self.busy += 1
        try:
            yield
        finally:
            self.busy -= 1
            if not self.busy and self.on_idle is not None:
                self.on_idle()

    # --------------------------------------------------------------------- cases

    @_guarded
    def add_case(self, case: Case) -> AddOutcome:
        """Store a parsed case: ``unchanged`` if the newest version has this content,
        else a new version (also when a file returns to an older content).

        One transaction: either the case version with all its claims is stored, or nothing.
        """
        if not case.content_hash:
            raise ValueError(f"case {case.id!r} has no content_hash; parse it with casefile")
        with self._write() as session:
            newest = session.execute(
                select(CaseRow.id, CaseRow.version, CaseRow.content_hash)
                .where(CaseRow.case_id == case.id)
                .order_by(CaseRow.version.desc())
                .limit(1)
            ).first()
            if newest is not None and newest.content_hash == case.content_hash:
                return AddOutcome(case.id, newest.version, "unchanged", pk=newest.id)
            version = 1 if newest is None else newest.version + 1
            row = _case_row(case, version, self._source_id(session, case))
            session.add(row)
            session.flush()
            session.add_all(_claim_row(c, row.id, i) for i, c in enumerate(case.claims))
            session.flush()
            status = "added" if version == 1 else "new version"
            return AddOutcome(case.id, version, status, pk=row.id)

    @staticmethod
    def _source_id(session: Session, case: Case) -> int:
        """The id of the source row for this citation and DOI, inserted if new."""
        citation, doi = case.source.citation, case.source.doi or ""
        found = session.scalar(
            select(SourceRow.id).where(SourceRow.citation == citation, SourceRow.doi == doi)
        )
        if found is not None:
            return found
        source = SourceRow(citation=citation, doi=doi)
        session.add(source)
        session.flush()
        return source.id

    @_guarded
    def case_ids(self) -> list[str]:
        """All stored case ids, sorted."""
        with self._read() as session:
            ids = select(CaseRow.case_id).distinct().order_by(CaseRow.case_id)
            return list(session.scalars(ids))

    @_guarded
    def case_versions(
        self, case_ids: Sequence[str] | None = None, latest_only: bool = True
    ) -> list[StoredCase]:
        """Stored versions of these cases (all cases if None), newest only by default.

        Ordered as ``case_ids`` (or by id), then by version. Raises UnknownCaseError.
        """
        with self._read() as session:
            stmt = select(CaseRow)
            if latest_only:
                newest = _newest_versions()
                stmt = stmt.join(
                    newest,
                    (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
                )
            if case_ids is not None:
                wanted = list(dict.fromkeys(case_ids))
                stmt = stmt.where(CaseRow.case_id.in_(wanted))
            rows = session.scalars(stmt.order_by(CaseRow.case_id, CaseRow.version)).all()
            if case_ids is None:
                return [_stored(r) for r in rows]
            by_id: dict[str, list[StoredCase]] = {}
            for r in rows:
                by_id.setdefault(r.case_id, []).append(_stored(r))
            missing = [c for c in wanted if c not in by_id]
            if missing:
                known = list(session.scalars(select(CaseRow.case_id).distinct()))
                raise UnknownCaseError(missing[0], known=sorted(known))
            return [s for c in wanted for s in by_id[c]]

    # ---------------------------------------------------------------------- runs

    @_guarded
    def start_run(self, options: dict[str, Any], code_version: str) -> int:
        """Record the start of an audit run (status ``running``) and return its number."""
        run = RunRow(
            started_at=_now(),
            finished_at=None,
            status="running",
            code_version=code_version,
            sympy_version=_package_version("sympy"),
            python_version=platform.python_version(),
            options=dict(options),
            host=socket.gethostname(),
            pid=os.getpid(),
            pid_started=_process_started(os.getpid()),
        )
        with self._write() as session:
            session.add(run)
            session.flush()
            return run.id

    @_guarded
    def record_case(
        self, run_id: int, case_pk: int, audit: CaseAudit, reused: bool = False
    ) -> None:
        """Store all check results of one case version in a running run, in one transaction.

        Claim results are tied to the claim with the same label in that case version
        (ValueError if there is none, or if ``audit`` is of another case or content).
        """
        with self._write() as session:
            run = self._run(session, run_id)
            if run.status != "running":
                raise ValueError(f"audit run {run_id} is {run.status}; it takes no more results")
            case = session.get(CaseRow, case_pk)
            if case is None:
                raise ValueError(f"no stored case version with key {case_pk}")
            if audit.case != case.case_id or (
                audit.content_hash and audit.content_hash != case.content_hash
            ):
                raise ValueError(
                    f"audit of {audit.case!r} does not match stored case {case.case_id!r} "
                    f"version {case.version}"
                )
            claim_ids = {
                label: claim_id
                for label, claim_id in session.execute(
                    select(ClaimRow.label, ClaimRow.id).where(ClaimRow.case_pk == case_pk)
                )
            }
            labels = [r.claim for r in audit.results] + [c.claim for c in audit.corrections]
            labels += [c.target for c in audit.conditions if c.target != "jacobi"]
            for label in labels:
                if label is not None and label not in claim_ids:
                    raise ValueError(
                        f"case {case.case_id!r} version {case.version} has no claim {label!r}"
                    )
            session.add_all(_correction_rows(run_id, case_pk, audit, claim_ids))
            session.add_all(
                EvidenceRow(
                    run_id=run_id,
                    case_pk=case_pk,
                    claim_id=claim_ids[e.claim],
                    drift=_finite(e.drift),
                    floor=_finite(e.floor),
                    runs=e.runs,
                    contradicts=e.contradicts,
                    note=e.note,
                    compared_with=e.compared_with,
                    narrowed=e.narrowed,
                )
                for e in audit.evidence
                if e.claim in claim_ids
            )
            for result in audit.results:
                session.add(
                    ResultRow(
                        run_id=run_id,
                        case_pk=case_pk,
                        claim_id=None if result.claim is None else claim_ids[result.claim],
                        check=result.check,
                        verdict=str(result.verdict),
                        method=result.method,
                        reason=result.reason,
                        residual=result.residual,
                        witness=None if result.witness is None else result.witness.as_dict(),
                        seconds=float(result.seconds),
                        reused=reused,
                    )
                )

    @_guarded
    def finish_run(self, run_id: int, status: str = "complete") -> None:
        """Mark a run ``complete``, ``failed`` or ``interrupted`` and stamp its end time."""
        if status not in RUN_STATUSES or status == "running":
            raise ValueError(f"a run cannot finish as {status!r}; use one of {RUN_STATUSES[1:]}")
        with self._write() as session:
            run = self._run(session, run_id)
            run.status = status
            run.finished_at = _now()

    @staticmethod
    def _run(session: Session, run_id: int) -> RunRow:
        run = session.get(RunRow, run_id)
        if run is None:
            raise UnknownRunError(run_id)
        return run

    @_guarded
    def run_results(self, run_id: int) -> list[tuple[str, CaseAudit]]:
        """The results of one run as (case id, CaseAudit), in the order they were recorded."""
        with self._read() as session:
            self._run(session, run_id)
            return _audits(session, ResultRow.run_id == run_id)

    @_guarded
    def stored_audit(
        self, case_pk: int, code_version: str | None = None
    ) -> tuple[int, CaseAudit] | None:
        """The newest stored audit of one case version (by runs of ``code_version``, if given).

        Returns (run number, audit), or None; lets an audit reuse results of unchanged cases.
        """
        with self._read() as session:
            stmt = select(func.max(ResultRow.run_id)).where(ResultRow.case_pk == case_pk)
            if code_version is not None:
                stmt = stmt.join(RunRow, RunRow.id == ResultRow.run_id).where(
                    RunRow.code_version == code_version
                )
            run_id = session.scalar(stmt)
            if run_id is None:
                return None
            audits = _audits(session, (ResultRow.run_id == run_id) & (ResultRow.case_pk == case_pk))
            return run_id, audits[0][1]

    # ------------------------------------------------------------------ checking

    @_guarded
    def schema_revision(self) -> tuple[str | None, str | None]:
        """(Alembic revision, ``meta.schema_version``) as stored."""
        with self._connect() as conn:
            revision = migrate.inspect_schema(conn, self.location).revision
            return revision, conn.scalar(
                select(MetaRow.value).where(MetaRow.key == "schema_version")
            )

    @_guarded
    def database_problems(self) -> list[str]:
        """What the database engine and the table relations find wrong (no algebra):
        SQLite's integrity and foreign-key checks, results tied to a claim of another
        case version, and verdicts or run states outside their sets."""
        problems = []
        with self._connect() as conn:
            if conn.dialect.name == "sqlite":
                found = [r[0] for r in conn.exec_driver_sql("PRAGMA integrity_check")]
                problems += [f"SQLite integrity check: {r}" for r in found if r != "ok"]
                problems += [
                    f"foreign key: row {row} of {table} points to a missing row of {parent}"
                    for table, row, parent, _ in conn.exec_driver_sql("PRAGMA foreign_key_check")
                ]
            claims = ClaimRow.__table__
            for table in (ResultRow.__table__, CorrectionRow.__table__, EvidenceRow.__table__):
                crossed = conn.execute(
                    select(table.c.id)
                    .join(claims, claims.c.id == table.c.claim_id)
                    .where(claims.c.case_pk != table.c.case_pk)
                ).scalars()
                problems += [
                    f"{table.name} row {i}: its claim belongs to another case version"
                    for i in crossed
                ]
            verdicts = [str(v) for v in Verdict]
            odd = conn.execute(
                select(ResultRow.id, ResultRow.verdict).where(ResultRow.verdict.not_in(verdicts))
            )
            problems += [f"check_results row {i}: unknown verdict {v!r}" for i, v in odd]
            odd = conn.execute(
                select(CorrectionRow.id, CorrectionRow.verdict).where(
                    CorrectionRow.verdict.is_not(None), CorrectionRow.verdict.not_in(verdicts)
                )
            )
            problems += [f"corrections row {i}: unknown verdict {v!r}" for i, v in odd]
            odd = conn.execute(
                select(RunRow.id, RunRow.status).where(RunRow.status.not_in(RUN_STATUSES))
            )
            problems += [f"audit run {i}: unknown status {v!r}" for i, v in odd]
        return problems

    @_guarded
    def counts(self) -> dict[str, int]:
        """How many rows each table holds."""
        tables = {
            "case versions": CaseRow,
            "claims": ClaimRow,
            "runs": RunRow,
            "results": ResultRow,
            "corrections": CorrectionRow,
        }
        with self._read() as session:
            return {
                name: session.scalar(select(func.count()).select_from(row)) or 0
                for name, row in tables.items()
            }

    @_guarded
    def running_runs(self) -> list[tuple[int, str | None, int | None]]:
        """(run, host, pid) of the runs still marked ``running``."""
        with self._read() as session:
            stmt = select(RunRow.id, RunRow.host, RunRow.pid).where(RunRow.status == "running")
            return [tuple(r) for r in session.execute(stmt)]

    @_guarded
    def stored_expressions(self) -> list[StoredText]:
        """Every expression and equation the database keeps, with its place, so that
        ``registry check`` can parse each again: the case columns, the claims, and the
        derived Casimirs, torques and parameter conditions of every run."""
        out: list[StoredText] = []
        with self._read() as session:
            cases = {r.id: r for r in session.scalars(select(CaseRow))}
            for r in cases.values():
                out.append(StoredText(r.id, "potential", r.potential))
                out += [StoredText(r.id, f"torque[{i}]", t) for i, t in enumerate(r.torque)]
                out += [StoredText(r.id, f"inertia[{i}]", t) for i, t in enumerate(r.inertia)]
            for c in session.scalars(select(ClaimRow)):
                where = f"claim {c.label!r}"
                out.append(StoredText(c.case_pk, f"{where} expression", c.expression))
                out += [
                    StoredText(c.case_pk, f"{where} on[{i}]", e, equation=True)
                    for i, e in enumerate(c.on)
                ]
            for row in session.scalars(select(CorrectionRow)):
                where = f"run {row.run_id}, {row.kind} (corrections row {row.id})"
                if row.expression:
                    out.append(StoredText(row.case_pk, where, row.expression))
                for i, t in enumerate(row.payload.get("torque") or ()):
                    out.append(StoredText(row.case_pk, f"{where} torque[{i}]", t))
                for branch in row.payload.get("branches") or ():
                    out += [StoredText(row.case_pk, where, e, equation=True) for e in branch]
        return out

    # -------------------------------------------------------------------- frames

    @_guarded
    def cases_frame(self) -> pd.DataFrame:
        """One row per case (newest version): case, version, title, citation, n_claims, ..."""
        n_claims = (
            select(ClaimRow.case_pk, func.count(ClaimRow.id).label("n"))
            .group_by(ClaimRow.case_pk)
            .subquery()
        )
        newest = _newest_versions()
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
        return self._select_frame(stmt)

    @_guarded
    def claims_frame(self) -> pd.DataFrame:
        """One row per claim of each newest case version, in file order."""
        newest = _newest_versions()
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
        return self._select_frame(stmt)

    @_guarded
    def verdicts_frame(self, run: int | None = None) -> pd.DataFrame:
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
            return self._select_frame(stmt)
        with self._read() as session:
            self._run(session, run)
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
        return self._select_frame(stmt)

    @_guarded
    def runs_frame(self) -> pd.DataFrame:
        """One row per audit run with counts of its results by verdict, newest run last."""

        def count(verdict: Verdict) -> Any:
            hit = sql_case((ResultRow.verdict == str(verdict), 1), else_=0)
            return func.coalesce(func.sum(hit), 0).label(f"n_{verdict}")

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
                func.coalesce(func.sum(sql_case((ResultRow.reused, 1), else_=0)), 0).label(
                    "n_reused"
                ),
                RunRow.options,
            )
            .outerjoin(ResultRow, ResultRow.run_id == RunRow.id)
            .group_by(RunRow.id)
            .order_by(RunRow.id)
        )
        return self._select_frame(stmt)

    @_guarded
    def corrections_frame(self, run: int | None = None) -> pd.DataFrame:
        """Families, repairs and conditions of one run (default: the newest run)."""
        with self._read() as session:
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
        return self._select_frame(stmt)

    def _select_frame(self, stmt: Select) -> pd.DataFrame:
        """Run a select and return its rows as a DataFrame named by its columns."""
        with self._connect() as conn:
            result = conn.execute(stmt)
            return _frame(result.all(), list(result.keys()))


def _newest_versions():
    """A subquery of (case_id, version) for the newest version of every case."""
    return (
        select(CaseRow.case_id, func.max(CaseRow.version).label("version"))
        .group_by(CaseRow.case_id)
        .subquery()
    )


def _stored(row: CaseRow) -> StoredCase:
    return StoredCase(row.id, row.case_id, row.version, row.content_hash, row.text, row.path)


def _correction_rows(
    run_id: int, case_pk: int, audit: CaseAudit, claim_ids: dict[str, int]
) -> list[CorrectionRow]:
    """The family, repairs and conditions of an audit, as rows."""
    rows = []
    if audit.family is not None:
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                kind="family",
                expression=audit.family.casimir,
                method=audit.family.method,
                # a family's Casimir is reported only once it re-checks
                verdict=None if audit.family.casimir is None else str(Verdict.VERIFIED),
                payload=audit.family.as_dict(),
            )
        )
    for c in audit.corrections:
        verdict = str(Verdict.combined(Verdict(v) for v in c.checks.values()))
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                claim_id=claim_ids.get(c.claim) if c.claim else None,
                kind=c.kind,
                expression=c.expression,
                method=c.method,
                verdict=verdict,
                payload={**c.as_dict(), "claim": c.claim},
            )
        )
    for cond in audit.conditions:
        payload = {
            "target": cond.target,
            "branches": [list(b) for b in cond.branches],
            "reason": cond.reason,
        }
        claim_id = None if cond.target == "jacobi" else claim_ids.get(cond.target)
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                claim_id=claim_id,
                kind="conditions",
                # every branch is re-checked before it is reported
                verdict=str(Verdict.VERIFIED) if cond.branches else None,
                payload=payload,
            )
        )
    return rows


def _nan(x: float | None) -> float:
    return float("nan") if x is None else x


def _finite(x: float) -> float | None:
    """NaN (no run) is stored as NULL."""
    return None if x != x else float(x)


def _derived(rows: Iterable[CorrectionRow]) -> dict:
    """CaseAudit fields rebuilt from correction rows."""
    family, corrections, conditions = None, [], []
    for row in rows:
        p = row.payload
        if row.kind == "family":
            family = FamilyRecord(**p)
        elif row.kind == "conditions":
            conditions.append(
                Conditions(p["target"], tuple(tuple(b) for b in p["branches"]), p.get("reason", ""))
            )
        else:
            corrections.append(
                Correction(
                    kind=row.kind,
                    claim=p.get("claim"),
                    expression=p.get("expression"),
                    torque=tuple(p["torque"]) if p.get("torque") else None,
                    changed=tuple(k - 1 for k in p.get("changed", [])),
                    method=p.get("method", ""),
                    checks=p.get("checks", {}),
                )
            )
    return {"family": family, "corrections": tuple(corrections), "conditions": tuple(conditions)}


def _audits(session: Session, where: Any) -> list[tuple[str, CaseAudit]]:
    """Rebuild CaseAudits from the result rows matching ``where``, in recording order."""
    rows = session.execute(
        select(ResultRow, CaseRow.case_id, CaseRow.content_hash, ClaimRow.label)
        .join(CaseRow, CaseRow.id == ResultRow.case_pk)
        .outerjoin(ClaimRow, ClaimRow.id == ResultRow.claim_id)
        .where(where)
        .order_by(ResultRow.id)
    ).all()
    grouped: dict[tuple[int, int], tuple[str, str, list[CheckResult]]] = {}
    for result, case_id, content_hash, label in rows:
        entry = grouped.setdefault((result.run_id, result.case_pk), (case_id, content_hash, []))
        entry[2].append(_check_result(result, label))
    audits = []
    for (run_id, case_pk), (case_id, content_hash, results) in grouped.items():
        derived = session.scalars(
            select(CorrectionRow)
            .where(CorrectionRow.run_id == run_id, CorrectionRow.case_pk == case_pk)
            .order_by(CorrectionRow.id)
        )
        found = session.execute(
            select(EvidenceRow, ClaimRow.label)
            .join(ClaimRow, ClaimRow.id == EvidenceRow.claim_id)
            .where(EvidenceRow.run_id == run_id, EvidenceRow.case_pk == case_pk)
            .order_by(EvidenceRow.id)
        ).all()
        evidence = tuple(
            Evidence(
                label,
                _nan(e.drift),
                _nan(e.floor),
                e.runs,
                e.contradicts,
                e.note,
                e.compared_with,
                e.narrowed,
            )
            for e, label in found
        )
        audit = CaseAudit(
            case_id, content_hash, tuple(results), **_derived(derived), evidence=evidence
        )
        audits.append((case_id, audit))
    return audits


def _process_started(pid: int) -> str | None:
    """When process ``pid`` started, in the kernel's clock ticks since boot (Linux), else None.

    With the pid it identifies a process: a pid reused by a later process differs here.
    """
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = stat[stat.rindex(")") + 2 :].split()  # after "pid (command) "
    return None if fields[0] in ("Z", "X") else fields[19]  # a zombie has died


def _process_gone(host: str | None, pid: int | None, started: str | None) -> bool:
    """Whether the process that ran an audit has certainly ended: it ran on this host
    and no live process has its pid and start time. Runs from before the schema
    recorded processes (no pid) count as ended."""
    if pid is None:
        return True
    if host != socket.gethostname():
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # alive, another user's
        pass
    now = _process_started(pid)
    if started is not None and Path("/proc").is_dir():
        return now != started
    return False


def _package_version(name: str) -> str:
    """An installed package's version, read from its metadata (the package is not imported)."""
    try:
        return importlib_metadata.version(name)
    except importlib_metadata.PackageNotFoundError:
        return "unknown"
