"""Verifying a registry database: what ``registry verify-db`` reports.

The database engine's own checks and the table relations (no algebra there): on SQLite
its ``integrity_check`` and ``foreign_key_check``; on PostgreSQL, which enforces foreign
keys itself, the same foreign-key check made by query, and whether any table's
enforcement was switched off. Then
every stored case version parsed again from its text, its content hash recomputed,
its columns compared with the parse, and every stored expression (claims, derived
Casimirs and torques, parameter conditions) parsed again in its case's names. A
clean report means that every stored result still refers to exactly the case text
it was computed from. The reads only this check needs live here too.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from sqlalchemy import Table, func, select, text
from sqlalchemy.engine import Connection

from ..errors import CaseFormatError, ExpressionError
from ..language import forms
from ..language.casefile import parse_case_text
from ..language.parser import Namespace, parse_equation, parse_expression
from ..model import Case
from . import migrate
from .conversions import VERDICT_TEXTS
from .database import Store
from .engine import guarded
from .tables import (
    RUN_STATUSES,
    SCHEMA_VERSION,
    Base,
    CaseRow,
    ClaimRow,
    CorrectionRow,
    DiscoveryRow,
    DriftCurveRow,
    EvidenceRow,
    MetaRow,
    ResultRow,
    RunRow,
    SearchRow,
)


@dataclass(frozen=True)
class Verification:
    """The outcome of ``verify``: the schema, what was looked at, what is wrong, and
    the database engine that holds it (``SQLite 3.45.1``, ``PostgreSQL 15.8, schema
    "public"``)."""

    revision: str | None
    counts: Mapping[str, int] = field(default_factory=dict)
    problems: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()
    engine: str = ""

    @property
    def ok(self) -> bool:
        return not self.problems


@guarded
def verify(store: Store) -> Verification:
    """Check a registry database end to end (see the module docstring), in one snapshot
    of it (one connection and one read transaction)."""
    with store.connect() as conn:
        return verify_connection(conn, store.location)


def verify_connection(conn: Connection, location: str) -> Verification:
    """``verify`` on an open connection, in its transaction: what ``registry copy``
    runs on the rows it has written, before it commits them (``location`` names the
    database in messages)."""
    revision, version = schema_revision(conn, location)
    problems = []
    if revision != migrate.head():
        problems.append(f"schema revision {revision}, expected {migrate.head()}")
    if version != str(SCHEMA_VERSION):
        problems.append(f"meta.schema_version is {version!r}, expected '{SCHEMA_VERSION}'")
    problems += database_problems(conn)

    cases: dict[int, Case] = {}
    names: dict[int, str] = {}
    stored_versions = conn.execute(
        select(
            CaseRow.id, CaseRow.case_id, CaseRow.version, CaseRow.content_hash, CaseRow.text
        ).order_by(CaseRow.case_id, CaseRow.version)
    )
    for stored in stored_versions:
        name = names[stored.id] = f"case {stored.case_id} version {stored.version}"
        try:
            case = parse_case_text(stored.text, name)
        except CaseFormatError as err:
            problems += [f"{name}: the stored text no longer parses: {p}" for p in err.problems]
            continue
        if case.content_hash != stored.content_hash:
            problems.append(f"{name}: the stored hash does not match the stored text")
        if case.id != stored.case_id:
            problems.append(f"{name}: the stored text has id {case.id!r}")
        cases[stored.id] = case

    texts = stored_expressions(conn)
    for pk, case in cases.items():
        mine = [t for t in texts if t.case_pk == pk]
        problems += [f"{names[pk]}: {p}" for p in _columns_agree(case, mine)]
    for t in texts:
        owner = cases.get(t.case_pk)
        if owner is None:
            continue  # its text did not parse: already reported
        problem = _reparse(t, forms.namespace(owner))
        if problem:
            problems.append(f"{names[t.case_pk]}: {t.place}: {problem}")

    notes = tuple(
        f"run {run} is still running (process {pid} on {host})"
        for run, host, pid in running_runs(conn)
    )
    return Verification(revision, counts(conn), tuple(problems), notes, engine_name(conn))


# ----------------------------------------------------------- integrity-only reads


@dataclass(frozen=True)
class StoredText:
    """One expression (or ``lhs = rhs`` equation) kept in the database, and where."""

    case_pk: int
    place: str
    text: str
    equation: bool = False


def schema_revision(conn: Connection, location: str) -> tuple[str | None, str | None]:
    """(Alembic revision, ``meta.schema_version``) as stored."""
    revision = migrate.inspect_schema(conn, location).revision
    return revision, conn.scalar(select(MetaRow.value).where(MetaRow.key == "schema_version"))


def engine_name(conn: Connection) -> str:
    """The database engine and its version (and, on PostgreSQL, the schema)."""
    if conn.dialect.name == "sqlite":
        return f"SQLite {conn.exec_driver_sql('SELECT sqlite_version()').scalar()}"
    if conn.dialect.name == "postgresql":
        version = conn.exec_driver_sql("SHOW server_version").scalar()
        schema = conn.exec_driver_sql("SELECT current_schema()").scalar()
        return f'PostgreSQL {str(version).split()[0]}, schema "{schema}"'
    return conn.dialect.name


def database_problems(conn: Connection) -> list[str]:
    """What the database engine and the table relations find wrong (no algebra):
    SQLite's integrity and foreign-key checks (on PostgreSQL, the foreign keys checked
    by query), results tied to a claim of another case version, and verdicts or run
    states outside their sets."""
    problems = []
    if conn.dialect.name == "sqlite":
        found = [r[0] for r in conn.exec_driver_sql("PRAGMA integrity_check")]
        problems += [f"SQLite integrity check: {r}" for r in found if r != "ok"]
        problems += [
            f"foreign key: row {row} of {table} points to a missing row of {parent}"
            for table, row, parent, _ in conn.exec_driver_sql("PRAGMA foreign_key_check")
        ]
    else:
        if conn.dialect.name == "postgresql":
            problems += _unenforced(conn)
        problems += _missing_parents(conn)
    claims = ClaimRow.__table__
    tables: tuple[Table, ...] = (
        ResultRow.__table__,
        CorrectionRow.__table__,
        EvidenceRow.__table__,
        DriftCurveRow.__table__,
    )  # type: ignore[assignment]
    for table in tables:
        crossed = conn.execute(
            select(table.c.id)
            .join(claims, claims.c.id == table.c.claim_id)
            .where(claims.c.case_pk != table.c.case_pk)
        ).scalars()
        problems += [
            f"{table.name} row {i}: its claim belongs to another case version" for i in crossed
        ]
    verdicts = VERDICT_TEXTS
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
    odd = conn.execute(select(RunRow.id, RunRow.status).where(RunRow.status.not_in(RUN_STATUSES)))
    problems += [f"audit run {i}: unknown status {v!r}" for i, v in odd]
    orphans = conn.execute(
        select(ClaimRow.id, ClaimRow.search_id)
        .outerjoin(SearchRow, SearchRow.id == ClaimRow.search_id)
        .where(ClaimRow.search_id.is_not(None), SearchRow.id.is_(None))
    )
    problems += [f"claims row {i}: attached by search {s}, which is missing" for i, s in orphans]
    return problems


def _missing_parents(conn: Connection) -> list[str]:
    """Rows whose foreign key points to no row, found by query: PostgreSQL enforces
    foreign keys, but a superuser can switch that off (``session_replication_role``,
    disabled triggers) and a restored dump may skip them."""
    problems = []
    for table in Base.metadata.sorted_tables:
        for fk in sorted(table.foreign_keys, key=lambda k: k.parent.name):
            parent = fk.column.table.alias("parent")
            target = parent.c[fk.column.name]
            missing = conn.execute(
                select(table.c.id)
                .outerjoin(parent, target == fk.parent)
                .where(fk.parent.is_not(None), target.is_(None))
                .order_by(table.c.id)
            ).scalars()
            problems += [
                f"foreign key: row {row} of {table.name} points to a missing row of "
                f"{fk.column.table.name}"
                for row in missing
            ]
    return problems


def _unenforced(conn: Connection) -> list[str]:
    """Registry tables whose foreign keys PostgreSQL no longer enforces: their
    constraint triggers disabled, or a constraint left unvalidated."""
    names = list(Base.metadata.tables)
    disabled = conn.execute(
        text(
            "SELECT DISTINCT c.relname FROM pg_trigger t JOIN pg_class c ON c.oid = t.tgrelid "
            "JOIN pg_constraint k ON k.oid = t.tgconstraint "
            "WHERE k.contype = 'f' AND t.tgenabled = 'D' "
            "AND c.relnamespace = current_schema()::regnamespace AND c.relname = ANY(:names) "
            "ORDER BY c.relname"
        ),
        {"names": names},
    ).scalars()
    unvalidated = conn.execute(
        text(
            "SELECT c.relname, k.conname FROM pg_constraint k JOIN pg_class c "
            "ON c.oid = k.conrelid WHERE NOT k.convalidated "
            "AND c.relnamespace = current_schema()::regnamespace AND c.relname = ANY(:names) "
            "ORDER BY c.relname, k.conname"
        ),
        {"names": names},
    ).all()
    return [f"{t}: its foreign keys are not enforced (triggers disabled)" for t in disabled] + [
        f"{t}: constraint {name} is not validated" for t, name in unvalidated
    ]


def counts(conn: Connection) -> dict[str, int]:
    """How many rows each table holds."""
    tables = {
        "case versions": CaseRow,
        "claims": ClaimRow,
        "runs": RunRow,
        "results": ResultRow,
        "corrections": CorrectionRow,
    }
    return {
        name: conn.scalar(select(func.count()).select_from(row)) or 0
        for name, row in tables.items()
    }


def running_runs(conn: Connection) -> list[tuple[int, str | None, int | None]]:
    """(run, host, pid) of the runs still marked ``running``."""
    stmt = select(RunRow.id, RunRow.host, RunRow.pid).where(RunRow.status == "running")
    return [(r.id, r.host, r.pid) for r in conn.execute(stmt)]


def stored_expressions(conn: Connection) -> list[StoredText]:
    """Every expression and equation the database keeps, with its place, so that
    ``registry verify-db`` can parse each again: the case columns, the claims, and the
    derived Casimirs, torques and parameter conditions of every run."""
    out: list[StoredText] = []
    cases, claims = CaseRow.__table__, ClaimRow.__table__
    corrections, discoveries = CorrectionRow.__table__, DiscoveryRow.__table__
    for r in conn.execute(select(cases).order_by(cases.c.id)):
        out.append(StoredText(r.id, "potential", r.potential))
        out += [StoredText(r.id, f"torque[{i}]", t) for i, t in enumerate(r.torque)]
        out += [StoredText(r.id, f"inertia[{i}]", t) for i, t in enumerate(r.inertia)]
        if r.hamiltonian is not None:
            out.append(StoredText(r.id, "hamiltonian", r.hamiltonian))
        out.append(StoredText(r.id, "kappa", r.kappa))
        form = r.form or {}
        for key in ("equations", "bracket", "definitions"):
            out += [StoredText(r.id, f"{key}.{k}", t) for k, t in form.get(key, {}).items()]
    for c in conn.execute(select(claims).order_by(claims.c.id)):
        # a claim a search attached to a version is not in its text: named apart
        where = (
            f"claim {c.label!r}"
            if c.search_id is None
            else (f"search {c.search_id}, claim {c.label!r}")
        )
        out.append(StoredText(c.case_pk, f"{where} expression", c.expression))
        out += [
            StoredText(c.case_pk, f"{where} on[{i}]", e, equation=True) for i, e in enumerate(c.on)
        ]
    for row in conn.execute(select(corrections).order_by(corrections.c.id)):
        where = f"run {row.run_id}, {row.kind} (corrections row {row.id})"
        if row.expression:
            out.append(StoredText(row.case_pk, where, row.expression))
        for i, t in enumerate(row.payload.get("torque") or ()):
            out.append(StoredText(row.case_pk, f"{where} torque[{i}]", t))
        for branch in row.payload.get("branches") or ():
            out += [StoredText(row.case_pk, where, e, equation=True) for e in branch]
    found = conn.execute(
        select(discoveries, SearchRow.case_pk.label("searched"))
        .join(SearchRow, SearchRow.id == discoveries.c.search_id)
        .order_by(discoveries.c.id)
    )
    for discovered in found:
        where = f"search {discovered.search_id}, integrals where {discovered.when or 'generic'}"
        out += [StoredText(discovered.searched, where, e) for e in discovered.integrals]
        out += [StoredText(discovered.searched, where, e, equation=True) for e in discovered.when]
    return out


def _reparse(stored: StoredText, ns: Namespace) -> str | None:
    """Why a stored expression or equation does not parse, or None."""
    try:
        (parse_equation if stored.equation else parse_expression)(stored.text, ns)
    except ExpressionError as err:
        return f"{stored.text!r} does not parse: {err}"
    return None


def _columns_agree(case: Case, stored: list[StoredText]) -> list[str]:
    """Differences between a case version's columns and the parse of its text."""
    expected = forms.stored_texts(case.system)
    for claim in case.claims:
        where = f"claim {claim.label!r}"
        expected[f"{where} expression"] = claim.expression.text
        expected.update({f"{where} on[{i}]": e.text for i, e in enumerate(claim.on)})
    found = {t.place: t.text for t in stored if not t.place.startswith(("run ", "search "))}
    problems = [
        f"{place}: stored as {found.get(place)!r}, but the case text says {text!r}"
        for place, text in expected.items()
        if found.get(place) != text
    ]
    problems += [f"{place}: stored, but not in the case text" for place in found.keys() - expected]
    return problems
