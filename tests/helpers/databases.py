"""Database targets for the tests, on either backend: fresh ones (``Databases``), and
plain SQL on a target behind the registry's back (``execute``, ``rows``), as a careless
tool or another program would.

A target is what ``--db`` and ``registry.open`` take: the path of an SQLite file, or
the URL of a database on the tests' PostgreSQL server (``postgres_server.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import create_engine, text
from sqlalchemy.engine import Connection, make_url

from tests.helpers.postgres_server import PostgresServer

#: Marks the PostgreSQL variant of a test (deselect them with ``-m "not postgres"``).
POSTGRES = pytest.mark.postgres

#: The backends the storage, API and CLI tests run on.
BACKENDS = ("sqlite", pytest.param("postgres", marks=POSTGRES))


def is_url(target: str | Path) -> bool:
    return "://" in str(target)


class Databases:
    """Fresh databases of one backend: ``new()`` is the path of an SQLite file that does
    not exist yet, or the URL of a new, empty PostgreSQL database; ``missing()`` names a
    database that does not exist; ``copy()`` copies one (closed) database."""

    def __init__(self, backend: str, folder: Callable[[], Path], request: pytest.FixtureRequest):
        self.backend = backend
        self._folder = folder
        self._request = request
        self._server: PostgresServer | None = None

    @property
    def server(self) -> PostgresServer:
        """The session's PostgreSQL server (started, or skipped, on first use)."""
        if self._server is None:
            self._server = self._request.getfixturevalue("postgres_server")
        return self._server

    def new(self, name: str = "registry") -> str:
        if self.backend == "sqlite":
            return str(self._folder() / f"{name}.sqlite")
        return self.server.create_database(f"{self._request.node.name}_{name}")

    def missing(self, name: str = "nowhere") -> str:
        if self.backend == "sqlite":
            return str(self._folder() / f"{name}.sqlite")
        return self.server.missing_database(name)

    def exists(self, target: str) -> bool:
        """Whether the database ``target`` exists (a file, or a database of the server)."""
        if self.backend == "sqlite":
            return Path(target).exists()
        with self.server.connect() as conn:
            found = conn.execute(
                "SELECT 1 FROM pg_database WHERE datname = %s", (database_name(target),)
            )
            return found.fetchone() is not None

    def missing_message(self, target: str) -> str:
        """What the registry says of the database ``target`` that does not exist."""
        if self.backend == "sqlite":
            return (
                f"no registry database at {target!r}; create one by adding cases "
                "(registry add FILES) or name another with --db"
            )
        name = database_name(target)
        return (
            f"the database server of {target!r} has no database {name!r}; creating one is "
            f"the server administrator's job (for example: createdb {name}), then "
            "'registry add FILES' creates the registry's tables in it"
        )

    def copy(self, target: str, name: str = "copy") -> str:
        """A copy of the database ``target``; no connection may be open to it."""
        if self.backend == "sqlite":
            copy = self._folder() / f"{name}.sqlite"
            copy.write_bytes(Path(target).read_bytes())
            return str(copy)
        return self.server.create_database(name, template=database_name(target))


def database_name(url: str) -> str:
    """The database a PostgreSQL URL names."""
    return make_url(url).database


@contextmanager
def connection(target: str | Path, *, foreign_keys: bool = True) -> Iterator[Connection]:
    """A plain SQLAlchemy connection to a target, in one transaction committed at the end.

    Without ``foreign_keys``, the database does not check them (SQLite's default; on
    PostgreSQL, ``session_replication_role = replica``, as the superuser may).
    """
    url = str(target) if is_url(target) else f"sqlite:///{target}"
    engine = create_engine(url)
    try:
        with engine.begin() as conn:
            if not foreign_keys and conn.dialect.name == "postgresql":
                conn.execute(text("SET LOCAL session_replication_role = replica"))
            elif foreign_keys and conn.dialect.name == "sqlite":
                conn.execute(text("PRAGMA foreign_keys=ON"))
            yield conn
    finally:
        engine.dispose()


def execute(target: str | Path, *statements: str, foreign_keys: bool = True) -> None:
    """Run SQL statements on a target in one transaction."""
    with connection(target, foreign_keys=foreign_keys) as conn:
        for sql in statements:
            conn.execute(text(sql))


def rows(target: str | Path, sql: str, **params: Any) -> list[tuple]:
    """The rows a query returns, as tuples."""
    with connection(target) as conn:
        return [tuple(r) for r in conn.execute(text(sql), params)]
