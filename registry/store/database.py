"""The registry database: the store's writes, and the reads that return domain objects.

``Store(path)``, ``Store(":memory:")`` or ``Store(url)`` opens (and creates, or
upgrades after a backup copy) a registry database and keeps cases, audit runs and
check results: an SQLite file, or a database on a PostgreSQL server that several
people and processes write at once. Every method takes and returns domain objects or
plain values; each write is one transaction. The database never does algebra: a
stored case is parsed again from its ``text`` when it is needed (``StoredCase.parse``).

Around it: ``tables`` (the rows), ``conversions`` (rows to domain objects and back),
``engine`` (opening a database, its errors), ``frames`` (DataFrame queries),
``integrity`` (``registry verify-db``), ``migrate`` (schema revisions) and
``processes`` (whose run is still alive).
"""

from __future__ import annotations

import hashlib
import platform
import sqlite3
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from importlib import metadata as importlib_metadata
from pathlib import Path
from typing import Any, Literal

from sqlalchemy import func, select, text
from sqlalchemy.engine import Connection, Engine
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session

from ..errors import (
    DatabaseMissingError,
    DatabaseReadOnlyError,
    RoleError,
    SchemaOwnerError,
    StorageError,
    UnknownCaseError,
    UnknownRunError,
    WritePrivilegeError,
)
from ..language import forms
from ..language.casefile import parse_case_text
from ..language.parser import parse_equation, parse_expression
from ..model import (
    Case,
    CaseAudit,
    CaseIdentification,
    CheckResult,
    Claim,
    ClaimKind,
    Equation,
    ExponentOptions,
    ExponentResult,
    Expression,
    Provenance,
    Search,
    SearchOptions,
)
from . import migrate, roles
from .conversions import (
    case_row,
    check_result,
    claim_row,
    correction_rows,
    curve_row,
    derived,
    discovery_rows,
    drift_curve,
    evidence,
    evidence_row,
    exponent_options_key,
    exponent_result,
    exponent_row,
    fill_source,
    identification,
    identification_row,
    options_key,
    result_row,
    search_row,
    source_fields,
)
from .conversions import (
    search as search_of,
)
from .engine import (
    WRITE_OPTION,
    guarded,
    hold,
    is_memory,
    is_server,
    make_engine,
    resolve,
    storage_error,
)
from .processes import process_gone, this_process
from .tables import (
    RUN_STATUSES,
    Base,
    CaseAliasRow,
    CaseRow,
    ClaimRow,
    CorrectionRow,
    DiscoveryRow,
    DriftCurveRow,
    EvidenceRow,
    ExponentRow,
    IdentificationRow,
    ResultRow,
    RunRow,
    SearchRow,
    SourceRow,
    newest_versions,
    now,
)


@dataclass(frozen=True)
class AddOutcome:
    """What ``Store.add_case`` did: ``added``, ``unchanged`` or ``new version``."""

    case_id: str
    version: int
    status: Literal["added", "unchanged", "new version"]
    pk: int | None = field(default=None, compare=False)


@dataclass(frozen=True)
class AttachedClaim:
    """A claim a search attached to a stored case version (it is not in the case's
    text): its label, kind, expression and level set as text, and its notes."""

    label: str
    kind: str
    expression: str
    on: tuple[str, ...] = ()
    notes: str = ""


@dataclass(frozen=True)
class StoredCase:
    """One stored case version: enough to parse it again (``text``) and audit it (``pk``),
    with the claims searches attached to it."""

    pk: int
    case_id: str
    version: int
    content_hash: str
    text: str
    path: str | None
    attached: tuple[AttachedClaim, ...] = ()

    def parse(self) -> Case:
        """The case this version's text holds (its file, or its id, names it in errors),
        with the claims attached to it by searches after its own.

        Every reader of a stored case parses it here (the audit, the reports, the export
        of a corrected case); ``registry verify-db`` parses under its own name for a version.
        """
        case = parse_case_text(self.text, self.path or self.case_id)
        if not self.attached:
            return case
        ns = forms.namespace(case)
        extra = tuple(
            Claim(
                a.label,
                ClaimKind(a.kind),
                Expression(a.expression, parse_expression(a.expression, ns)),
                tuple(Equation(e, *parse_equation(e, ns)) for e in a.on),
                notes=a.notes,
                provenance=Provenance.DISCOVERED,
            )
            for a in self.attached
        )
        return replace(case, claims=case.claims + extra)


class Store:
    """The registry database. ``Store(path)``, ``Store(":memory:")`` or ``Store(url)``.

    Every method takes and returns domain objects or plain Python values; each
    write is one transaction. Use as a context manager or call ``close()``.

    Without ``create``, a database that does not exist is a DatabaseMissingError, and
    so is a database on a server that holds no tables yet (reading never creates one).
    """

    def __init__(self, url_or_path: str | Path, *, create: bool = True):
        url, self.location = resolve(url_or_path, create)
        self.server = is_server(url)  # a database server (PostgreSQL), not an SQLite file
        self._create = create
        self.backup: Path | None = None  # the copy made before a schema upgrade
        self.upgraded_from: str | None = None  # the revision upgraded from, if any
        self.busy = 0  # database sessions in progress
        self.on_idle: Callable[[], None] | None = None  # called when the last one ends
        engine = make_engine(url, self.location)
        self._engine = engine
        self._writer = engine.execution_options(**{WRITE_OPTION: True})
        # reads see one snapshot, as on SQLite; writes stay READ COMMITTED, so that a
        # statement after a lock sees what the transaction that held it committed
        self._reader = (
            engine.execution_options(isolation_level="REPEATABLE READ") if self.server else engine
        )
        self._file = (
            Path(url.database) if url.get_backend_name() == "sqlite" and url.database else None
        )
        if is_memory(url):
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
        An older one is copied aside first (an SQLite file; a server's database is its
        administrator's to back up), then upgraded in one transaction. On a server, an
        empty database gets its tables only when ``create`` is set.
        """
        with self.connect() as conn:
            state = migrate.inspect_schema(conn, self.location)
        if state.current:
            return
        if state.empty and self.server and not self._create:
            raise DatabaseMissingError(self.location)
        if not state.empty and self.server:
            with self.connect() as conn:
                self._refuse_upgrade_by_other_role(conn, state)
        if not state.empty and self._file is not None:
            try:
                self.backup = migrate.backup(self._file, state.revision or "")
            except (OSError, sqlite3.Error) as err:
                raise StorageError(
                    f"database {self.location!r} needs a schema upgrade from revision "
                    f"{state.revision}, but no backup copy could be made first ({err})"
                ) from err
        with self._writer.begin() as conn:
            hold(conn, "schema")  # one process builds or upgrades the schema at a time
            state = migrate.inspect_schema(conn, self.location)  # another process may have
            if not state.current:  # upgraded it meanwhile
                migrate.upgrade(conn, state)
                self.upgraded_from = state.revision

    def _refuse_upgrade_by_other_role(self, conn: Connection, state: migrate.SchemaState) -> None:
        """SchemaOwnerError unless the connected role owns the server's registry tables:
        only their owner upgrades them (readers and writers are refused before anything
        is changed, instead of failing halfway through a revision)."""
        owner = roles.tables_owner(conn)
        if owner is not None and not roles.acts_as(conn, owner):
            role = roles.current_database(conn)[2]
            raise SchemaOwnerError(
                self.location, role, owner, state.revision or "?", migrate.head()
            )

    def _mark_interrupted(self) -> None:
        """Mark as ``interrupted`` the runs left ``running`` by a process that has died.

        Runs of processes on other hosts, or still alive, are left alone; so is a
        database this process may not write (the next writer will do it).
        """
        with self.read() as session:
            running = session.execute(
                select(RunRow.id, RunRow.host, RunRow.pid, RunRow.pid_started).where(
                    RunRow.status == "running"
                )
            ).all()
        dead = [r.id for r in running if process_gone(r.host, r.pid, r.pid_started)]
        if not dead:
            return
        try:
            with self.write() as session:
                for run in session.scalars(
                    select(RunRow).where(RunRow.id.in_(dead), RunRow.status == "running")
                ):
                    run.status = "interrupted"
        except DBAPIError as err:
            if not isinstance(storage_error(err, self.location), DatabaseReadOnlyError):
                raise

    @contextmanager
    def write(self) -> Iterator[Session]:
        """A session in one write transaction: committed on success, rolled back on error."""
        with self._busy(), Session(self._writer) as session, session.begin():
            yield session

    @contextmanager
    def read(self) -> Iterator[Session]:
        """A session for reading (one consistent snapshot)."""
        with self._busy(), Session(self._reader) as session:
            yield session

    @contextmanager
    def connect(self) -> Iterator[Connection]:
        """A plain connection for reading (no ORM session), counted like a session."""
        with self._busy(), self._reader.connect() as conn:
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

    # --------------------------------------------------------------------- roles

    @guarded
    def require_writer(self, doing: str) -> None:
        """WritePrivilegeError, before anything is done, when this connection's role may
        only read the registry (a server role without a writer's privileges, see
        ``roles``): ``doing`` says what the command was about to do. On an SQLite file the
        file's permissions decide, when the write is made."""
        if not self.server:
            return
        with self.connect() as conn:
            missing = roles.missing_write_privilege(conn, Base.metadata.tables)
            if missing is not None:
                role = roles.current_database(conn)[2]
                raise WritePrivilegeError(self.location, role, missing, doing)

    @guarded
    def grant_statements(self, level: roles.Level | None, role: str) -> list[str]:
        """The SQL that makes ``role`` a reader or a writer of this registry (``level``),
        or takes both back (``level`` None); RoleError on SQLite or for an unknown role."""
        if not self.server:
            raise RoleError(
                f"database {self.location!r} is an SQLite file, which has no roles: who may "
                "read or write it is set by the permissions of the file and its folder"
            )
        if not roles.ROLE_NAME.fullmatch(role):
            raise RoleError(
                f"{role!r} is not a role name registry grant accepts (lowercase letters, "
                "digits, '_' and '$', starting with a letter or '_'; at most 63)"
            )
        with self.connect() as conn:
            database, schema, _ = roles.current_database(conn)
            if not roles.role_exists(conn, role):
                raise RoleError(
                    f"the database server of {self.location!r} has no role {role!r}; an "
                    f"administrator creates it first (CREATE ROLE {role} LOGIN PASSWORD "
                    "'...'), then registry grant gives it its privileges"
                )
            owner = roles.tables_owner(conn) or roles.current_database(conn)[2]
        place = {"database": database, "owner": owner, "schema": schema}
        if level is None:
            return roles.revoke_statements(role, **place)
        return roles.grant_statements(level, role, **place)

    @guarded
    def grant(self, level: roles.Level | None, role: str) -> list[str]:
        """Run ``grant_statements`` in one transaction; RoleError when this connection may
        not (only the owner of the registry's tables, or a superuser, grants on them)."""
        statements = self.grant_statements(level, role)
        with self._writer.begin() as conn:
            owner = roles.tables_owner(conn)
            if owner is not None and not roles.acts_as(conn, owner):
                me = roles.current_database(conn)[2]
                raise RoleError(
                    f"role {me!r} does not own the registry's tables in {self.location!r}; "
                    f"only their owner {owner!r} (or a superuser) may grant privileges on them"
                )
            for sql in statements:
                conn.execute(text(sql))
        return statements

    # --------------------------------------------------------------------- cases

    @guarded
    def add_case(self, case: Case) -> AddOutcome:
        """Store a parsed case: ``unchanged`` if the newest version has this content,
        else a new version (also when a file returns to an older content).

        One transaction: either the case version with all its claims is stored, or nothing.
        """
        with self.write() as session:
            return self._add_case(session, case)

    def _add_case(self, session: Session, case: Case) -> AddOutcome:
        if not case.content_hash:
            raise ValueError(f"case {case.id!r} has no content_hash; parse it with casefile")
        # two processes adding this case id (or citing this new source) take turns here
        hold(session, f"case {case.id}", f"source {case.source.citation}\0{case.source.doi}")
        newest = session.execute(
            select(CaseRow.id, CaseRow.version, CaseRow.content_hash)
            .where(CaseRow.case_id == case.id)
            .order_by(CaseRow.version.desc())
            .limit(1)
        ).first()
        if newest is not None and newest.content_hash == case.content_hash:
            return AddOutcome(case.id, newest.version, "unchanged", pk=newest.id)
        version = 1 if newest is None else newest.version + 1
        row = case_row(case, version, self._source_id(session, case))
        session.add(row)
        session.flush()
        session.add_all(claim_row(c, row.id, i) for i, c in enumerate(case.claims))
        session.add_all(CaseAliasRow(case_pk=row.id, alias=a) for a in case.aliases)
        session.flush()
        return AddOutcome(case.id, version, "added" if version == 1 else "new version", pk=row.id)

    @staticmethod
    def _source_id(session: Session, case: Case) -> int:
        """The id of the source row for this citation and DOI, inserted if new."""
        citation, doi = case.source.citation, case.source.doi or ""
        found = session.scalar(
            select(SourceRow).where(SourceRow.citation == citation, SourceRow.doi == doi)
        )
        if found is not None:
            fill_source(found, case.source)
            return found.id
        source = SourceRow(citation=citation, doi=doi, **source_fields(case.source))
        session.add(source)
        session.flush()
        return source.id

    @guarded
    def case_ids(self) -> list[str]:
        """All stored case ids, sorted."""
        with self.read() as session:
            ids = select(CaseRow.case_id).distinct().order_by(CaseRow.case_id)
            return list(session.scalars(ids))

    @guarded
    def case_versions(
        self, case_ids: Sequence[str] | None = None, latest_only: bool = True
    ) -> list[StoredCase]:
        """Stored versions of these cases (all cases if None), newest only by default.

        Ordered as ``case_ids`` (or by id), then by version. Raises UnknownCaseError.
        """
        with self.read() as session:
            stmt = select(CaseRow)
            if latest_only:
                newest = newest_versions()
                stmt = stmt.join(
                    newest,
                    (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
                )
            if case_ids is not None:
                wanted = [self._resolved(session, c) for c in dict.fromkeys(case_ids)]
                wanted = list(dict.fromkeys(wanted))
                stmt = stmt.where(CaseRow.case_id.in_(wanted))
            rows = session.scalars(stmt.order_by(CaseRow.case_id, CaseRow.version)).all()
            if case_ids is None:
                return [_stored(session, r) for r in rows]
            by_id: dict[str, list[StoredCase]] = {}
            for r in rows:
                by_id.setdefault(r.case_id, []).append(_stored(session, r))
            missing = [c for c in wanted if c not in by_id]
            if missing:
                known = list(session.scalars(select(CaseRow.case_id).distinct()))
                raise UnknownCaseError(missing[0], known=sorted(known))
            return [s for c in wanted for s in by_id[c]]

    @staticmethod
    def _resolved(session: Session, case_id: str) -> str:
        """The id of a stored case, or of the case whose newest version lists ``case_id``
        as an alias (an earlier id); unchanged when neither exists."""
        if session.scalar(select(CaseRow.id).where(CaseRow.case_id == case_id).limit(1)):
            return case_id
        newest = newest_versions()
        renamed = session.scalars(
            select(CaseRow.case_id)
            .join(CaseAliasRow, CaseAliasRow.case_pk == CaseRow.id)
            .join(
                newest,
                (CaseRow.case_id == newest.c.case_id) & (CaseRow.version == newest.c.version),
            )
            .where(CaseAliasRow.alias == case_id)
            .order_by(CaseRow.added_at.desc())
        ).first()
        return renamed or case_id

    # ------------------------------------------------------------------ searches

    @guarded
    def record_search(
        self,
        case_pk: int,
        search: Search,
        code_version: str,
        statement: str,
        derived: Sequence[Case | None] = (),
    ) -> int:
        """Store a search of a case version, in one transaction: its row, a row per set
        of values it found integrals on, its new generic integrals (not the case's claims
        rediscovered) attached as claims to the searched version, and each special set's
        ``derived`` case (None to skip) stored as a case of its own. Returns the search's number."""
        with self.write() as session:
            hold(session, f"claims of version {case_pk}")  # the next positions are ours
            row = search_row(case_pk, search, code_version, statement)
            session.add(row)
            session.flush()
            position = (
                session.scalar(
                    select(func.max(ClaimRow.position)).where(ClaimRow.case_pk == case_pk)
                )
                or 0
            ) + 1
            new = set(search.generic.new)  # a rediscovered claim is not added again
            attached = 0
            for i, text in enumerate(search.generic.integrals):
                if text in new:
                    claim = _discovered_claim(row.id, i, text, search)
                    session.add(claim_row(claim, case_pk, position + attached, search_id=row.id))
                    attached += 1
            versions: dict[int, int] = {}
            for i, case in enumerate(derived):
                if case is not None:
                    added = self._add_case(session, case)
                    assert added.pk is not None  # a stored case has its key
                    versions[i] = added.pk
            session.add_all(discovery_rows(row.id, search, versions))
            return row.id

    @guarded
    def stored_search(
        self, case_pk: int, options: SearchOptions, code_version: str
    ) -> tuple[int, SearchRow, list[DiscoveryRow]] | None:
        """The newest search of this case version with these options by this code version,
        as (number, row, discovery rows), or None: what a repeated search reuses."""
        with self.read() as session:
            row = session.scalars(
                select(SearchRow)
                .where(
                    SearchRow.case_pk == case_pk,
                    SearchRow.options_key == options_key(options),
                    SearchRow.code_version == code_version,
                )
                .order_by(SearchRow.id.desc())
            ).first()
            if row is None:
                return None
            found = list(
                session.scalars(select(DiscoveryRow).where(DiscoveryRow.search_id == row.id))
            )
            session.expunge_all()
            return row.id, row, found

    # ----------------------------------------------------------------- exponents

    @guarded
    def record_exponents(self, case_pk: int, result: ExponentResult, code_version: str) -> int:
        """Store a Kovalevskaya analysis of a case version as a new row (an earlier one is
        kept, like an earlier audit); returns its number."""
        with self.write() as session:
            row = exponent_row(case_pk, result, code_version)
            session.add(row)
            session.flush()
            return row.id

    @guarded
    def stored_exponents(
        self, case_pk: int, options: ExponentOptions, code_version: str | None = None
    ) -> tuple[int, ExponentResult] | None:
        """The newest analysis of this case version with these options (by this code
        version, where given), as (number, result), or None: what a repeated analysis
        reuses, and what a search's statement is combined with."""
        with self.read() as session:
            query = select(ExponentRow, CaseRow.case_id, CaseRow.content_hash).join(
                CaseRow, CaseRow.id == ExponentRow.case_pk
            )
            query = query.where(
                ExponentRow.case_pk == case_pk,
                ExponentRow.options_key == exponent_options_key(options),
            )
            if code_version is not None:
                query = query.where(ExponentRow.code_version == code_version)
            found = session.execute(query.order_by(ExponentRow.id.desc())).first()
            if found is None:
                return None
            row, case_id, content_hash = found
            return row.id, exponent_result(row, case_id, content_hash)

    @guarded
    def newest_exponents(self) -> dict[str, tuple[int, int, ExponentResult]]:
        """The newest analysis of every case with one, by case id: (number, the version
        analysed, result); what the site shows."""
        with self.read() as session:
            rows = session.execute(
                select(ExponentRow, CaseRow.case_id, CaseRow.version, CaseRow.content_hash)
                .join(CaseRow, CaseRow.id == ExponentRow.case_pk)
                .order_by(ExponentRow.id)
            ).all()
            return {
                case_id: (row.id, version, exponent_result(row, case_id, content_hash))
                for row, case_id, version, content_hash in rows
            }

    # ---------------------------------------------------------- identifications

    @guarded
    def catalog_digest(self, versions: Sequence[StoredCase] | None = None) -> str:
        """A digest of the latest version of every case (``versions``, where the caller
        has read them): it changes when a case is added or changed, and an identification
        against another catalog is not reused."""
        versions = self.case_versions() if versions is None else versions
        text = "\n".join(sorted(f"{s.case_id} {s.content_hash}" for s in versions))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @guarded
    def record_identification(
        self, case_pk: int, found: CaseIdentification, code_version: str
    ) -> int:
        """Store a case version's identification with the catalog as a new row (earlier
        ones are kept); returns its number."""
        with self.write() as session:
            row = identification_row(case_pk, found, code_version)
            session.add(row)
            session.flush()
            return row.id

    @guarded
    def stored_identification(
        self, case_pk: int, catalog: str, code_version: str
    ) -> CaseIdentification | None:
        """The newest identification of this case version with this catalog by this code
        version, or None: what a repeated identification reuses."""
        with self.read() as session:
            found = session.execute(
                select(IdentificationRow, CaseRow.case_id, CaseRow.version)
                .join(CaseRow, CaseRow.id == IdentificationRow.case_pk)
                .where(
                    IdentificationRow.case_pk == case_pk,
                    IdentificationRow.catalog == catalog,
                    IdentificationRow.code_version == code_version,
                )
                .order_by(IdentificationRow.id.desc())
            ).first()
            if found is None:
                return None
            row, case_id, version = found
            return identification(row, case_id, version)

    @guarded
    def newest_identifications(self) -> dict[str, CaseIdentification]:
        """The newest identification of the latest version of every case with one, by
        case id: what ``reg.cases()`` and the case pages show."""
        with self.read() as session:
            latest = newest_versions()
            rows = session.execute(
                select(IdentificationRow, CaseRow.case_id, CaseRow.version)
                .join(CaseRow, CaseRow.id == IdentificationRow.case_pk)
                .join(
                    latest,
                    (latest.c.case_id == CaseRow.case_id) & (latest.c.version == CaseRow.version),
                )
                .order_by(IdentificationRow.id)
            ).all()
            return {
                case_id: identification(row, case_id, version) for row, case_id, version in rows
            }

    @guarded
    def newest_searches(self) -> dict[str, tuple[int, int, Search]]:
        """The newest search on the whole phase space of every case with one, by case id:
        (number, the version searched, search); what the site combines with the newest
        exponents."""
        with self.read() as session:
            rows = session.execute(
                select(SearchRow, CaseRow.case_id, CaseRow.version, CaseRow.content_hash)
                .join(CaseRow, CaseRow.id == SearchRow.case_pk)
                .order_by(SearchRow.id)
            ).all()
            newest = {
                case_id: (row, version, content_hash)
                for row, case_id, version, content_hash in rows
                if not row.options.get("on")
            }
            found = {}
            for case_id, (row, version, content_hash) in newest.items():
                sets = session.scalars(
                    select(DiscoveryRow).where(DiscoveryRow.search_id == row.id)
                ).all()
                found[case_id] = (
                    row.id,
                    version,
                    search_of(row, case_id, content_hash, sets, on=()),
                )
            return found

    @guarded
    def recorded_searches(
        self, case_id: str | None = None
    ) -> list[tuple[StoredCase, SearchRow, list[DiscoveryRow]]]:
        """Every recorded search (of every version of ``case_id``, or of every case),
        oldest first, as (the searched case version, its row, its discovery rows).
        UnknownCaseError for a case the registry does not hold."""
        with self.read() as session:
            stmt = select(SearchRow, CaseRow).join(CaseRow, CaseRow.id == SearchRow.case_pk)
            if case_id is not None:
                known = self._resolved(session, case_id)
                if session.scalar(select(CaseRow.id).where(CaseRow.case_id == known)) is None:
                    ids = sorted(session.scalars(select(CaseRow.case_id).distinct()))
                    raise UnknownCaseError(case_id, known=ids)
                stmt = stmt.where(CaseRow.case_id == known)
            found = session.execute(stmt.order_by(SearchRow.id)).all()
            rows: dict[int, list[DiscoveryRow]] = {row.id: [] for row, _ in found}
            for d in session.scalars(
                select(DiscoveryRow).where(DiscoveryRow.search_id.in_(list(rows)))
            ):
                rows[d.search_id].append(d)
            versions: dict[int, StoredCase] = {}
            listed = []
            for row, case in found:
                if case.id not in versions:
                    versions[case.id] = _stored(session, case)
                listed.append((versions[case.id], row, rows[row.id]))
            session.expunge_all()
            return listed

    # ---------------------------------------------------------------------- runs

    @guarded
    def start_run(self, options: dict[str, Any], code_version: str) -> int:
        """Record the start of an audit run (status ``running``) and return its number."""
        host, pid, started = this_process()
        run = RunRow(
            started_at=now(),
            finished_at=None,
            status="running",
            code_version=code_version,
            sympy_version=_package_version("sympy"),
            python_version=platform.python_version(),
            options=dict(options),
            host=host,
            pid=pid,
            pid_started=started,
        )
        with self.write() as session:
            session.add(run)
            session.flush()
            return run.id

    @guarded
    def record_case(
        self, run_id: int, case_pk: int, audit: CaseAudit, reused: bool = False
    ) -> None:
        """Store all check results of one case version in a running run, in one transaction.

        Claim results are tied to the claim with the same label in that case version
        (ValueError if there is none, or if ``audit`` is of another case or content).
        """
        with self.write() as session:
            run = get_run(session, run_id)
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
            session.add_all(correction_rows(run_id, case_pk, audit, claim_ids))
            session.add_all(
                evidence_row(run_id, case_pk, claim_ids[e.claim], e)
                for e in audit.evidence
                if e.claim in claim_ids
            )
            session.add_all(
                curve_row(run_id, case_pk, claim_ids[c.claim], c)
                for c in audit.curves
                if c.claim in claim_ids
            )
            for result in audit.results:
                claim_id = None if result.claim is None else claim_ids[result.claim]
                session.add(result_row(run_id, case_pk, claim_id, result, reused))

    @guarded
    def update_run_options(self, run_id: int, **changes: Any) -> None:
        """Add or replace keys of a run's options, in one transaction: what a run learns
        as it goes (the events of a Dask cluster: a worker lost, its cases retried)."""
        with self.write() as session:
            run = get_run(session, run_id)
            run.options = {**(run.options or {}), **changes}  # a new dict: JSON is not tracked

    @guarded
    def finish_run(self, run_id: int, status: str = "complete") -> None:
        """Mark a run ``complete``, ``failed`` or ``interrupted`` and stamp its end time."""
        if status not in RUN_STATUSES or status == "running":
            raise ValueError(f"a run cannot finish as {status!r}; use one of {RUN_STATUSES[1:]}")
        with self.write() as session:
            run = get_run(session, run_id)
            run.status = status
            run.finished_at = now()

    @guarded
    def run_results(self, run_id: int) -> list[tuple[str, CaseAudit]]:
        """The results of one run as (case id, CaseAudit), in the order they were recorded."""
        with self.read() as session:
            get_run(session, run_id)
            return _audits(session, ResultRow.run_id == run_id)

    @guarded
    def stored_audit(
        self, case_pk: int, code_version: str | None = None
    ) -> tuple[int, CaseAudit] | None:
        """The newest stored audit of one case version (by runs of ``code_version``, if given).

        Returns (run number, audit), or None; lets an audit reuse results of unchanged cases.
        """
        with self.read() as session:
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


def _stored(session: Session, row: CaseRow) -> StoredCase:
    attached = session.scalars(
        select(ClaimRow)
        .where(ClaimRow.case_pk == row.id, ClaimRow.search_id.is_not(None))
        .order_by(ClaimRow.position)
    )
    return StoredCase(
        row.id,
        row.case_id,
        row.version,
        row.content_hash,
        row.text,
        row.path,
        tuple(AttachedClaim(c.label, c.kind, c.expression, tuple(c.on), c.notes) for c in attached),
    )


def get_run(session: Session, run_id: int) -> RunRow:
    """The row of audit run ``run_id``; UnknownRunError if there is none."""
    run = session.get(RunRow, run_id)
    if run is None:
        raise UnknownRunError(run_id)
    return run


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
        entry[2].append(check_result(result, label))
    found_audits = []
    for (run_id, case_pk), (case_id, content_hash, results) in grouped.items():
        corrections = session.scalars(
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
        curves = session.execute(
            select(DriftCurveRow, ClaimRow.label)
            .join(ClaimRow, ClaimRow.id == DriftCurveRow.claim_id)
            .where(DriftCurveRow.run_id == run_id, DriftCurveRow.case_pk == case_pk)
            .order_by(DriftCurveRow.id)
        ).all()
        audit = CaseAudit(
            case_id,
            content_hash,
            tuple(results),
            **derived(corrections),
            evidence=tuple(evidence(row, label) for row, label in found),
            curves=tuple(drift_curve(row, case_id, label) for row, label in curves),
        )
        found_audits.append((case_id, audit))
    return found_audits


def _discovered_claim(search_id: int, i: int, text: str, search: Search) -> Claim:
    """Generic integral ``i`` of a search as a claim of the searched version (its
    expression is kept as text: the store does no algebra; it is parsed with the case)."""
    when = f"search {search_id} ({search.method.split(';')[0]})"
    return Claim(
        f"discovered-{search_id}-{i + 1}",
        ClaimKind.INTEGRAL,
        Expression(text, None),
        tuple(search.options.on),
        notes=f"Found by registry discover, {when}.",
        provenance=Provenance.DISCOVERED,
    )


def _package_version(name: str) -> str:
    """An installed package's version, read from its metadata (the package is not imported)."""
    try:
        return importlib_metadata.version(name)
    except importlib_metadata.PackageNotFoundError:
        return "unknown"
