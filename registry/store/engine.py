"""Opening the database: where it is (a path, ``:memory:`` or any SQLAlchemy URL),
the engine and its settings per backend, and what a database failure means to a user.

On SQLite: foreign keys on, a WAL journal for files, a busy timeout, and write
transactions that start with ``BEGIN IMMEDIATE``, so that reading the next version
number and inserting it happen under one write lock, even with several processes
on one file. On PostgreSQL (``postgresql+psycopg://``): the server enforces foreign keys
and runs every transaction at READ COMMITTED; a statement waits at most
``settings.lock_timeout()`` for a lock, times are read in UTC, and the writes
that must not interleave ("read the next version number and insert it") hold advisory
locks named after what they change (``hold``). ``guarded`` turns a driver error into the
one-line ``StorageError`` of its kind and retries a transaction that found the database
locked (or, on PostgreSQL, lost a deadlock). Another backend is another branch of
``make_engine``.
"""

from __future__ import annotations

import functools
import re
import sqlite3
import time
import zlib
from collections.abc import Callable
from pathlib import Path
from typing import Any, ParamSpec, TypeVar

from sqlalchemy import create_engine, event, func, select
from sqlalchemy.engine import URL, Connection, Engine, make_url
from sqlalchemy.exc import (
    ArgumentError,
    DBAPIError,
    IntegrityError,
    NoSuchModuleError,
    ProgrammingError,
)
from sqlalchemy.pool import StaticPool

from ..errors import (
    DatabaseFullError,
    DatabaseLockedError,
    DatabaseMissingError,
    DatabasePermissionError,
    DatabaseReadOnlyError,
    NotADatabaseError,
    ServerDatabaseMissingError,
    ServerUnavailableError,
    StorageError,
)
from ..settings import lock_timeout

#: Attempts of a transaction that found the database locked, before giving up.
LOCK_ATTEMPTS = 3

#: Execution option that makes a SQLite transaction start with BEGIN IMMEDIATE.
WRITE_OPTION = "registry_write"

#: Seconds to wait for a database server to answer a connection.
CONNECT_TIMEOUT = 10

#: The first key of the registry's PostgreSQL advisory locks (``hold``): "RgB1".
LOCK_NAMESPACE = 0x52674231

#: The SQLAlchemy backend names of database servers (shared by several processes and
#: users, created by an administrator), as opposed to SQLite files.
SERVER_BACKENDS = ("postgresql",)


def resolve(url_or_path: str | Path, create: bool) -> tuple[URL, str]:
    """The SQLAlchemy URL for a path, ``:memory:`` or URL, and how to name it in messages.

    A database file that does not exist is an error unless ``create``.
    """
    if isinstance(url_or_path, str) and "://" in url_or_path:
        try:
            url = make_url(url_or_path)
        except ArgumentError as err:
            raise StorageError(f"cannot open database {url_or_path!r}: {err}") from err
        if url.drivername == "postgresql":  # SQLAlchemy's default driver is psycopg2
            url = url.set(drivername="postgresql+psycopg")
        # named as the user wrote it, unless that shows a password
        return url, url.render_as_string() if url.password else url_or_path
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


def is_memory(url: URL) -> bool:
    return url.get_backend_name() == "sqlite" and url.database in (None, "", ":memory:")


def is_server(url: URL) -> bool:
    """Whether ``url`` names a database on a server (PostgreSQL), not an SQLite file."""
    return url.get_backend_name() in SERVER_BACKENDS


def configure_sqlite(engine: Engine, file_db: bool) -> None:
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
            cursor.execute(f"PRAGMA busy_timeout={int(lock_timeout() * 1000)}")
            if file_db:
                _switch_to_wal(cursor)
        finally:
            cursor.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn: Connection) -> None:
        write = conn.get_execution_options().get(WRITE_OPTION, False)
        conn.exec_driver_sql("BEGIN IMMEDIATE" if write else "BEGIN")


def _switch_to_wal(cursor: Any) -> None:
    """Put the file in WAL mode (readers then never wait for the writer). The switch
    needs the file to itself for a moment, and SQLite refuses it at once, without its
    busy timeout, while another process switches the same new file: retried here, for
    up to ``lock_timeout()``, before the lock is reported."""
    deadline = time.monotonic() + lock_timeout()
    delay = 0.01
    while True:
        try:
            cursor.execute("PRAGMA journal_mode=WAL")
            return
        except sqlite3.OperationalError as err:
            if "locked" not in str(err).lower() or time.monotonic() > deadline:
                raise
        time.sleep(delay)
        delay = min(2 * delay, 0.25)


def postgresql_connect_args(url: URL) -> dict[str, Any]:
    """Connection settings for PostgreSQL (psycopg), merged with those of the URL: a
    lock held longer than ``lock_timeout()`` fails the statement (``DatabaseLockedError``,
    retried by ``guarded``) instead of waiting for ever; times come back in UTC; a server
    that does not answer within ``CONNECT_TIMEOUT`` is reported as unreachable."""
    settings = f"-c lock_timeout={int(lock_timeout() * 1000)} -c TimeZone=UTC"
    given = url.query.get("options")
    given = " ".join(given) if isinstance(given, tuple) else given
    return {
        "options": f"{given} {settings}" if given else settings,
        "connect_timeout": int(str(url.query.get("connect_timeout", CONNECT_TIMEOUT))),
        "application_name": url.query.get("application_name", "registry"),
    }


def hold(conn: Connection | Any, *names: str) -> None:
    """Serialize the current write transaction with every other one that holds any of
    ``names``, until it ends (PostgreSQL advisory transaction locks, taken in a fixed
    order; the wait is bounded by ``lock_timeout``). On SQLite every write transaction
    already holds the one write lock (``BEGIN IMMEDIATE``), so this does nothing there.

    ``conn`` is a Connection or an ORM Session.
    """
    bind = conn.get_bind() if hasattr(conn, "get_bind") else conn
    if bind.dialect.name != "postgresql":
        return
    for key in sorted({lock_key(name) for name in names}):
        conn.execute(select(func.pg_advisory_xact_lock(LOCK_NAMESPACE, key)))


def lock_key(name: str) -> int:
    """The second key (a signed 32-bit integer) of the advisory lock named ``name``."""
    return zlib.crc32(name.encode("utf-8")) - 2**31


P = ParamSpec("P")
T = TypeVar("T")


def guarded(method: Callable[P, T]) -> Callable[P, T]:
    """Turn a database failure into a one-line StorageError of its kind; a transaction
    that found the database locked is retried (each method is one transaction, rolled
    back on failure, so running it again is safe)."""

    @functools.wraps(method)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> T:
        location = getattr(args[0], "location", "")
        for attempt in range(1, LOCK_ATTEMPTS + 1):
            try:
                return method(*args, **kwargs)
            except IntegrityError:
                raise  # a bug in the caller, not a state of the database
            except DBAPIError as err:
                if isinstance(err, ProgrammingError) and not _about_the_database(err):
                    raise  # a bug in the caller
                problem = storage_error(err, location)
                if not isinstance(problem, DatabaseLockedError) or attempt == LOCK_ATTEMPTS:
                    raise problem from err
                time.sleep(min(0.05 * 2**attempt, 1.0))
        raise AssertionError("unreachable")

    return wrapper


def storage_error(err: DBAPIError, location: str, doing: str = "write to it") -> StorageError:
    """The StorageError for a database failure, by what SQLite or the server reports."""
    if _from_server(err):
        return server_error(err, location, doing)
    reported = str(err.orig)
    said = reported.lower()
    if "locked" in said or "busy" in said:
        return DatabaseLockedError(location, lock_timeout() * LOCK_ATTEMPTS)
    if "readonly" in said or "read-only" in said:
        return DatabaseReadOnlyError(location, doing)
    if "disk is full" in said or "disk full" in said:
        return DatabaseFullError(location)
    if "not a database" in said or "malformed" in said:
        return NotADatabaseError(location, reported)
    return StorageError(f"database {location!r}: {reported}")


#: SQLSTATEs of a transaction that lost to another one: it waited for a lock too long,
#: could not be serialized, or was chosen to break a deadlock. Running it again is safe.
LOST_TO_ANOTHER = ("55P03", "40001", "40P01")

#: SQLSTATEs of a server that cannot serve: shutting down, starting up, too many clients.
UNAVAILABLE = ("57P01", "57P02", "57P03", "53300")

#: SQLSTATEs of missing privileges: insufficient privilege, authorization, password.
REFUSED = ("42501", "28000", "28P01")


def _from_server(err: DBAPIError) -> bool:
    """Whether the failure comes from a database server's driver (psycopg), not SQLite."""
    return type(err.orig).__module__.split(".")[0] == "psycopg"


def _about_the_database(err: DBAPIError) -> bool:
    """Whether a "programming error" is a state of the database rather than a bug: on
    PostgreSQL, missing privileges (42501) or a registry table that is gone (42P01)."""
    return _from_server(err) and getattr(err.orig, "sqlstate", None) in ("42501", "42P01")


def _server_said(err: DBAPIError) -> str:
    """What the server (or libpq, for a connection that failed) said, in one line."""
    text = str(err.orig).strip()
    fatal = re.search(r"FATAL:\s+(.*)", text)
    if fatal:
        return fatal.group(1).strip()
    line = text.splitlines()[0] if text else type(err.orig).__name__
    return re.sub(r"^connection (?:failed|is bad):\s*", "", line).strip()


def server_error(err: DBAPIError, location: str, doing: str = "write to it") -> StorageError:
    """The StorageError for a failure a PostgreSQL server (or the way to it) reports,
    by its SQLSTATE or, for a connection that failed before the server answered (which
    has none), by libpq's words."""
    state = getattr(err.orig, "sqlstate", None) or ""
    said = _server_said(err)
    lowered = said.lower()
    if state in LOST_TO_ANOTHER or "lock timeout" in lowered:
        return DatabaseLockedError(location, lock_timeout() * LOCK_ATTEMPTS)
    missing = re.search(r'database "(.*)" does not exist', said)
    if state == "3D000" or missing:
        return ServerDatabaseMissingError(location, missing.group(1) if missing else location)
    if state in REFUSED or re.search(
        r"permission denied|authentication failed|role .* does not exist|no pg_hba", lowered
    ):
        return DatabasePermissionError(location, said, _role(location))
    if state == "25006":  # a read-only transaction (a standby, default_transaction_read_only)
        return DatabaseReadOnlyError(location, doing)
    if state == "53100" or "no space left" in lowered:
        return DatabaseFullError(location)
    if state in UNAVAILABLE or state.startswith("08") or not state:
        return ServerUnavailableError(location, said)
    return StorageError(f"database {location!r}: {said}")


def _role(location: str) -> str | None:
    """The role a URL connects as (None: the operating-system user's name)."""
    try:
        return make_url(location).username
    except ArgumentError:
        return None


def make_engine(url: URL, location: str) -> Engine:
    """The engine for ``url``: one shared connection for an in-memory database, the
    SQLite settings above for SQLite, the PostgreSQL settings for PostgreSQL;
    StorageError when the URL cannot be used."""
    try:
        if is_memory(url):
            engine = create_engine(
                url, poolclass=StaticPool, connect_args={"check_same_thread": False}
            )
        elif url.get_backend_name() == "postgresql":
            engine = create_engine(url, connect_args=postgresql_connect_args(url))
        else:
            engine = create_engine(url)
    except (NoSuchModuleError, ImportError) as err:
        hint = ""
        if url.get_backend_name() == "postgresql":
            hint = "; install the driver with: pip install 'rigid-body-registry[postgres]'"
        raise StorageError(f"cannot open database {location!r}: {err}{hint}") from err
    except ArgumentError as err:
        raise StorageError(f"cannot open database {location!r}: {err}") from err
    if url.get_backend_name() == "sqlite":
        configure_sqlite(engine, file_db=not is_memory(url))
    return engine
