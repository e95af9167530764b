"""Copying a registry into another database, whole and verified: ``registry copy``.

Every table, every case version, audit run, result and search, with its primary key,
goes from one registry (an SQLite file or a PostgreSQL database) into a new database
or an empty registry, on either backend. It is the way to move from the embedded
default to a group's server, and to back a server up and restore it::

    registry --db data/registry.sqlite copy --to postgresql+psycopg://maintainer@db/registry
    registry --db postgresql+psycopg://maintainer@db/registry copy --to backup.sqlite
    registry --db postgresql+psycopg://maintainer@db/registry copy --from backup.sqlite

All or nothing. The source is read in one snapshot (one read transaction, REPEATABLE
READ on PostgreSQL), so commands that write to it meanwhile are either wholly in the
copy or not at all. The target is filled in ONE write transaction: its tables are
created at the current schema revision (or an empty registry of an older revision is
upgraded) in that same transaction, the rows are inserted with their ids, PostgreSQL's
id sequences are moved past the copied ids, and then, still inside the transaction,
the copy is checked: ``verify-db``'s own checks (``integrity.verify_connection``:
integrity, foreign keys, every stored text against its hash, every stored expression
parsed again), the row count of every table, the content hash of every case version,
and a digest of every row of every table, each against the source's. Only then is the
transaction committed; any difference rolls it back. So an interrupted copy (an
error, Ctrl-C, SIGKILL, a power cut) leaves the target as it was: on PostgreSQL the
server drops the open transaction (DDL included) when the connection ends; an existing
SQLite file rolls back through its journal. A new SQLite file is built under a
temporary name in the target's folder (``.NAME.copy-PID.tmp``) and gets its name only
once committed and verified, by a hard link that fails if anything took the name
meanwhile (atomic, never over another file): a killed copy leaves no file of that
name, at most the temporary file, which the next copy into that folder removes once
its process is gone.

Rows are compared as data, read back through the same column types: JSON as the
values it holds (PostgreSQL's ``json`` and SQLite's text of it may differ in spaces
and key order), times as aware UTC datetimes to the microsecond (SQLite keeps them as
naive UTC text, PostgreSQL as ``timestamptz``), booleans as booleans (SQLite's 0/1),
floats exactly. A value a backend cannot hold (SQLite turns a float NaN into NULL)
makes the digests differ, and the copy is refused rather than changed.

The target must be new or an empty registry: a target holding any row is refused
(``CopyTargetNotEmptyError``) before anything is changed.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import time
from collections.abc import Iterator, Mapping
from contextlib import ExitStack, contextmanager, suppress
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from sqlalchemy import Table, func, insert, inspect, select, text
from sqlalchemy.engine import URL, Connection, Engine
from sqlalchemy.exc import DBAPIError

from ..errors import CopySameDatabaseError, CopyTargetNotEmptyError, CopyVerificationError
from . import migrate
from .database import Store
from .engine import WRITE_OPTION, hold, is_memory, make_engine, resolve, storage_error
from .integrity import Verification, verify_connection
from .tables import Base, CaseRow, MetaRow

#: Rows read from the source and inserted into the target at a time.
BATCH = 1000

#: How each table's rows are named in messages, in the order the copy writes them
#: (parents before children: ``Base.metadata.sorted_tables``).
ROW_NAMES = {
    "meta": ("fact about the database", "facts about the database"),
    "sources": ("source", "sources"),
    "cases": ("case version", "case versions"),
    "case_aliases": ("case alias", "case aliases"),
    "claims": ("claim", "claims"),
    "audit_runs": ("audit run", "audit runs"),
    "check_results": ("check result", "check results"),
    "corrections": ("correction", "corrections"),
    "evidence": ("evidence record", "evidence records"),
    "searches": ("search", "searches"),
    "discoveries": ("discovery", "discoveries"),
    "exponents": ("exponent analysis", "exponent analyses"),
    "identifications": ("identification", "identifications"),
}


def rows_named(table: str, count: int) -> str:
    """'1 case version', '7 case versions': ``count`` rows of ``table`` in words."""
    one, many = ROW_NAMES.get(table, (f"row of {table}", f"rows of {table}"))
    return f"{count} {one if count == 1 else many}"


#: The temporary name of a new SQLite target while it is filled: ``.NAME.copy-PID.tmp``.
TEMPORARY = ".{name}.copy-{pid}.tmp"


@dataclass(frozen=True)
class CopyReport:
    """What ``copy_registry`` did: from where to where, the rows of each table (by table
    name), how long it took, whether the target was created (a new file, or the tables
    of an empty database), and the verification of the target made before the commit."""

    source: str
    target: str
    rows: Mapping[str, int]
    seconds: float
    created: bool
    verification: Verification

    @property
    def case_versions(self) -> int:
        return self.rows.get("cases", 0)

    def described(self) -> str:
        """The rows copied in words: '2 audit runs, 4 sources, 7 case versions, ...'."""
        return ", ".join(rows_named(t, n) for t, n in self.rows.items() if t != "meta")


def copy_registry(source: Store, target: str | Path) -> CopyReport:
    """Copy the registry ``source`` into ``target`` (a path or URL), all or nothing.

    The target is a new SQLite file, a database on a server without tables, or an
    empty registry; it ends holding exactly the source's rows, verified, or (after any
    error or interruption) as it was. Raises CopyTargetNotEmptyError for a target that
    holds rows, CopySameDatabaseError, CopyVerificationError when the copy does not
    verify (rolled back), and the StorageError of any database failure.

    >>> from registry.store.database import Store
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> with Store(folder / "a.sqlite") as store:
    ...     report = copy_registry(store, folder / "b.sqlite")
    >>> report.created, report.verification.ok, sorted(p.name for p in folder.iterdir())
    (True, True, ['a.sqlite', 'b.sqlite'])
    """
    started = time.monotonic()
    url, location = resolve(target, create=True)
    if _same_database(source.engine.url, url):
        raise CopySameDatabaseError(location)
    file = None
    if url.get_backend_name() == "sqlite" and url.database and not is_memory(url):
        file = Path(url.database)
    if file is not None and not file.exists():
        rows, verification = _copy_to_new_file(source, file, location)
        created = True
    else:
        engine = make_engine(url, location)
        try:
            rows, verification, created = _fill(source, engine, location)
        finally:
            engine.dispose()
    return CopyReport(
        source.location, location, rows, time.monotonic() - started, created, verification
    )


# ------------------------------------------------------------------- the target


def _copy_to_new_file(
    source: Store, file: Path, location: str
) -> tuple[dict[str, int], Verification]:
    """Fill a temporary file beside ``file``, then give it that name (see the module
    docstring); the temporary file is removed whatever happens."""
    _remove_stale_copies(file)
    temporary = file.with_name(TEMPORARY.format(name=file.name, pid=os.getpid()))
    try:
        engine = make_engine(URL.create("sqlite", database=str(temporary)), location)
        try:
            rows, verification, _ = _fill(source, engine, location)
            raw = engine.raw_connection()  # outside a transaction, which WAL mode needs
            try:  # one self-contained file, no WAL beside it
                raw.cursor().execute("PRAGMA journal_mode=DELETE")
            finally:
                raw.close()
        finally:
            engine.dispose()
        _publish(temporary, file, location)
    finally:
        for leftover in _with_journals(temporary):
            with suppress(FileNotFoundError):
                leftover.unlink()
    return rows, verification


def _publish(temporary: Path, file: Path, location: str) -> None:
    """Give the committed temporary file its name, durably, unless the name is taken."""
    with open(temporary, "rb") as handle:
        os.fsync(handle.fileno())
    try:
        os.link(temporary, file)  # atomic, and never over a file that appeared meanwhile
    except FileExistsError:
        raise CopyTargetNotEmptyError(
            location, "a file that another program created while the copy ran"
        ) from None
    folder = os.open(file.parent, os.O_RDONLY)
    try:
        os.fsync(folder)
    finally:
        os.close(folder)


def _with_journals(path: Path) -> list[Path]:
    return [path, *(path.with_name(path.name + end) for end in ("-wal", "-shm", "-journal"))]


def _remove_stale_copies(file: Path) -> None:
    """Remove the temporary files of earlier copies into ``file`` whose process is gone
    (killed before it could remove them); those of a live copy stay."""
    pattern = re.compile(re.escape(f".{file.name}.copy-") + r"(\d+)\.tmp(-wal|-shm|-journal)?")
    for leftover in file.parent.glob(f".{file.name}.copy-*.tmp*"):
        found = pattern.fullmatch(leftover.name)
        if found and _dead(int(found[1])):
            with suppress(FileNotFoundError):
                leftover.unlink()


def _dead(pid: int) -> bool:
    """Whether no process of this id is running here."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:
        return False
    return False


def _fill(
    source: Store, engine: Engine, location: str
) -> tuple[dict[str, int], Verification, bool]:
    """Create or check the target's tables, copy every row and check the copy, in one
    write transaction of ``engine``, committed only when every check passed. Returns
    (rows per table, verification, whether the tables were created)."""
    writer = engine.execution_options(**{WRITE_OPTION: True})
    try:
        with _snapshot(source) as src, writer.begin() as conn:
            hold(conn, "schema")  # no registry command builds or upgrades it meanwhile
            state = migrate.inspect_schema(conn, location)
            if not state.empty:
                _lock(conn)
                holds = _rows_held(conn)
                if holds:
                    raise CopyTargetNotEmptyError(location, holds)
            if not state.current:
                migrate.upgrade(conn, state)  # in this transaction: undone with it
            rows, digests = _copy_rows(src, conn, source.location)
            _advance_sequences(conn)
            verification = verify_connection(conn, location)
            problems = list(verification.problems)
            names = (source.location, location)
            problems += _differences(src, conn, rows, digests, names)
            if problems:
                raise CopyVerificationError(location, problems)
    except DBAPIError as err:
        raise storage_error(err, location, "copy a registry into it") from err
    return rows, verification, state.empty


@contextmanager
def _snapshot(source: Store) -> Iterator[Connection]:
    """One read transaction of the source: every table as of one moment. A failure to
    open it is named after the source (later reads name it through ``_reading``)."""
    with ExitStack() as stack:
        with _reading(source.location):
            conn = stack.enter_context(source.connect())
            conn.execute(select(func.count()).select_from(MetaRow))  # begins the transaction
        yield conn


@contextmanager
def _reading(location: str) -> Iterator[None]:
    """Name a database failure within after ``location`` (the source, or the target
    whose rows are read back), as the StorageError of its kind."""
    try:
        yield
    except DBAPIError as err:
        raise storage_error(err, location, "read it") from err


def _lock(conn: Connection) -> None:
    """On PostgreSQL, keep every other writer off the target's tables until the commit
    (readers go on): a row added meanwhile could not be both refused and kept."""
    if conn.dialect.name != "postgresql":
        return  # SQLite: BEGIN IMMEDIATE already holds the one write lock
    names = set(inspect(conn).get_table_names()) & set(Base.metadata.tables)
    if names:
        conn.execute(text(f"LOCK TABLE {', '.join(sorted(names))} IN EXCLUSIVE MODE"))


def _rows_held(conn: Connection) -> str:
    """What rows an existing target holds ('' for an empty registry), for the message
    that refuses it. ``meta`` does not count: every registry has its facts there."""
    present = set(inspect(conn).get_table_names())
    held = []
    for table in Base.metadata.sorted_tables:
        if table.name == "meta" or table.name not in present:
            continue
        count = conn.scalar(select(func.count()).select_from(table)) or 0
        if count:
            held.append(rows_named(table.name, count))
    return ", ".join(held)


def _copy_rows(
    src: Connection, conn: Connection, source: str
) -> tuple[dict[str, int], dict[str, str]]:
    """Insert every row of every table of ``src`` (the database ``source``) into
    ``conn``, parents first, with its primary key; (rows per table, digest per table of
    the rows as read)."""
    rows: dict[str, int] = {}
    digests: dict[str, str] = {}
    for table in Base.metadata.sorted_tables:
        if table.name == "meta":  # the target's own facts (schema_version) make way
            conn.execute(table.delete())
        digest, count = hashlib.sha256(), 0
        for batch in _batches(src, table, source):
            conn.execute(insert(table), batch)
            for row in batch:
                digest.update(_canonical(row))
            count += len(batch)
        rows[table.name], digests[table.name] = count, digest.hexdigest()
    return rows, digests


def _batches(conn: Connection, table: Table, location: str) -> Iterator[list[dict[str, Any]]]:
    """The rows of ``table`` in primary-key order, as dictionaries, BATCH at a time; a
    failure to read them is named after ``location``."""
    with _reading(location):
        result = conn.execution_options(yield_per=BATCH).execute(
            select(table).order_by(*table.primary_key.columns)
        )
        for partition in result.partitions():
            yield [dict(row._mapping) for row in partition]


def _canonical(row: Mapping[str, Any]) -> bytes:
    """A row as bytes that two backends agree on when they hold the same data: its
    values in column order as JSON (floats exactly, JSON values with sorted keys),
    times as ISO text in UTC."""
    return (
        json.dumps(
            list(row.values()), sort_keys=True, separators=(",", ":"), default=_utc_text
        ).encode()
        + b"\n"
    )


def _utc_text(value: Any) -> str:
    """What JSON cannot hold: a time (as ISO text in UTC), else the value's repr."""
    if isinstance(value, datetime):
        return value.astimezone(UTC).isoformat()
    return repr(value)


def _advance_sequences(conn: Connection) -> None:
    """On PostgreSQL, set each table's id sequence to its largest copied id, so that the
    next row gets the id after it (SQLite takes the largest id + 1 by itself)."""
    if conn.dialect.name != "postgresql":
        return
    for table in Base.metadata.sorted_tables:
        if "id" not in table.c or not table.c.id.primary_key:
            continue
        conn.execute(
            text(
                f"SELECT setval(pg_get_serial_sequence('{table.name}', 'id'), "
                f"COALESCE(MAX(id), 1), MAX(id) IS NOT NULL) FROM {table.name}"
            )
        )


def _differences(
    src: Connection,
    conn: Connection,
    rows: Mapping[str, int],
    digests: Mapping[str, str],
    names: tuple[str, str],
) -> list[str]:
    """How the target's rows (in the open transaction) differ from the source's: row
    counts of every table (counted again on both sides), content hashes of every case
    version, and the digest of every table's rows read back. ``names``: the source's
    and the target's, for a database failure."""
    source, target = names
    problems = []
    for table in Base.metadata.sorted_tables:
        with _reading(source):
            there = src.scalar(select(func.count()).select_from(table)) or 0
        with _reading(target):
            here = conn.scalar(select(func.count()).select_from(table)) or 0
        if not there == here == rows[table.name]:
            problems.append(
                f"table {table.name}: {rows_named(table.name, here)} copied, the source has {there}"
            )
            continue
        digest = hashlib.sha256()
        for batch in _batches(conn, table, target):
            for row in batch:
                digest.update(_canonical(row))
        if digest.hexdigest() != digests[table.name]:
            problems.append(f"table {table.name}: the rows read back differ from the source's")
    hashes = select(CaseRow.id, CaseRow.case_id, CaseRow.version, CaseRow.content_hash)
    with _reading(source):
        theirs = {r.id: tuple(r) for r in src.execute(hashes)}
    with _reading(target):
        mine = {r.id: tuple(r) for r in conn.execute(hashes)}
    for pk in sorted(theirs.keys() | mine.keys()):
        if theirs.get(pk) != mine.get(pk):
            _, case_id, version, _ = mine.get(pk) or theirs[pk]
            problems.append(
                f"case {case_id} version {version}: its content hash differs from the source's"
            )
    return problems


def _same_database(a: URL, b: URL) -> bool:
    """Whether two URLs name the same database (the same file, or the same database of
    the same server)."""
    if a.get_backend_name() != b.get_backend_name():
        return False
    if a.get_backend_name() == "sqlite":
        if is_memory(a) or is_memory(b):
            return False
        return Path(a.database or "").resolve() == Path(b.database or "").resolve()
    where = ("host", "port", "database")
    return all(getattr(a, k) == getattr(b, k) for k in where) and a.query.get(
        "host"
    ) == b.query.get("host")
