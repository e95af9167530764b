"""Opening the database: where it is (a path, ``:memory:`` or any SQLAlchemy URL),
the engine and its SQLite settings, and what a database failure means to a user.

On SQLite: foreign keys on, a WAL journal for files, a busy timeout, and write
transactions that start with ``BEGIN IMMEDIATE``, so that reading the next version
number and inserting it happen under one write lock, even with several processes
on one file. ``guarded`` turns a driver error into the one-line ``StorageError`` of
its kind and retries a transaction that found the database locked. Another backend
(PostgreSQL) is another branch of ``make_engine``.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, ParamSpec, TypeVar

from sqlalchemy import create_engine, event
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
    DatabaseReadOnlyError,
    NotADatabaseError,
    StorageError,
)

#: How long one attempt waits for another process's write lock (SQLite busy timeout).
BUSY_TIMEOUT = 10.0

#: Attempts of a transaction that found the database locked, before giving up.
LOCK_ATTEMPTS = 3

#: Execution option that makes a SQLite transaction start with BEGIN IMMEDIATE.
WRITE_OPTION = "registry_write"


def resolve(url_or_path: str | Path, create: bool) -> tuple[URL, str]:
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


def is_memory(url: URL) -> bool:
    return url.get_backend_name() == "sqlite" and url.database in (None, "", ":memory:")


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
            cursor.execute(f"PRAGMA busy_timeout={int(BUSY_TIMEOUT * 1000)}")
            if file_db:
                cursor.execute("PRAGMA journal_mode=WAL")
        finally:
            cursor.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn: Connection) -> None:
        write = conn.get_execution_options().get(WRITE_OPTION, False)
        conn.exec_driver_sql("BEGIN IMMEDIATE" if write else "BEGIN")


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


def make_engine(url: URL, location: str) -> Engine:
    """The engine for ``url``: one shared connection for an in-memory database, the
    SQLite settings above for SQLite; StorageError when the URL cannot be used."""
    try:
        if is_memory(url):
            engine = create_engine(
                url, poolclass=StaticPool, connect_args={"check_same_thread": False}
            )
        else:
            engine = create_engine(url)
    except (ArgumentError, NoSuchModuleError, ImportError) as err:
        raise StorageError(f"cannot open database {location!r}: {err}") from err
    if url.get_backend_name() == "sqlite":
        configure_sqlite(engine, file_db=not is_memory(url))
    return engine
