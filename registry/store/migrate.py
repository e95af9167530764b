"""Schema versions of the registry database: upgrade with Alembic, refuse what is newer.

The schema is a chain of Alembic revisions in ``registry/migrations/versions``
(0001 is the first released schema). Opening a database brings it to the newest
revision: a new database is built by running every revision; an older one is
first copied aside (``<file>.schema-<revision>.bak``) and then upgraded in one
write transaction, so an interrupted upgrade leaves it as it was; one written
by a newer release is refused. Databases from before migrations existed hold
``schema_version = 1`` in their ``meta`` table and are treated as revision 0001.
"""

from __future__ import annotations

import sqlite3
from contextlib import closing
from dataclasses import dataclass
from datetime import UTC, datetime
from functools import cache
from pathlib import Path

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import inspect, text
from sqlalchemy.engine import Connection

from ..errors import NotADatabaseError, SchemaTooNewError

MIGRATIONS = Path(__file__).parent / "migrations"

#: The revision of databases created before migrations existed (``meta.schema_version`` 1).
FIRST_REVISION = "0001"


def _config(conn: Connection | None = None) -> Config:
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    if conn is not None:
        config.attributes["connection"] = conn
    return config


@cache
def _script() -> ScriptDirectory:
    return ScriptDirectory.from_config(_config())


def head() -> str:
    """The newest schema revision this release knows."""
    found = _script().get_current_head()
    assert found is not None, "the migrations have no head"
    return found


def known_revisions() -> list[str]:
    """Every schema revision this release knows, oldest first."""
    return [r.revision for r in reversed(list(_script().walk_revisions()))]


@dataclass(frozen=True)
class SchemaState:
    """Where a database stands: its revision (None: empty) and whether it predates Alembic."""

    revision: str | None
    legacy: bool = False

    @property
    def empty(self) -> bool:
        return self.revision is None

    @property
    def current(self) -> bool:
        return self.revision == head()


def inspect_schema(conn: Connection, location: str) -> SchemaState:
    """The schema state of the database behind ``conn``.

    Raises SchemaTooNewError for a revision this release does not know, and
    NotADatabaseError for a database that holds other tables but no registry.
    """
    heads = MigrationContext.configure(conn).get_current_heads()
    if len(heads) > 1:
        raise NotADatabaseError(location, f"its schema has several heads: {', '.join(heads)}")
    if heads:
        if heads[0] not in known_revisions():
            raise SchemaTooNewError(location, f"revision {heads[0]}", f"revision {head()}")
        return SchemaState(heads[0])
    tables = set(inspect(conn).get_table_names())
    if "meta" in tables:
        version = conn.execute(
            text("SELECT value FROM meta WHERE key = 'schema_version'")
        ).scalar_one_or_none()
        if version == "1":
            return SchemaState(FIRST_REVISION, legacy=True)
        raise SchemaTooNewError(location, f"version {version}", f"revision {head()}")
    if tables:
        raise NotADatabaseError(location, f"it holds other tables: {', '.join(sorted(tables))}")
    return SchemaState(None)


def upgrade(conn: Connection, state: SchemaState) -> None:
    """Bring the database to the newest revision, inside the caller's transaction."""
    config = _config(conn)
    if state.legacy:
        command.stamp(config, FIRST_REVISION)
    command.upgrade(config, "head")


def backup(path: Path, revision: str) -> Path:
    """A consistent copy of an SQLite database file (WAL included), made before an upgrade."""
    target = path.with_name(f"{path.name}.schema-{revision}.bak")
    if target.exists():
        stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%S")
        target = path.with_name(f"{path.name}.schema-{revision}-{stamp}.bak")
    with (
        closing(sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True)) as source,
        closing(sqlite3.connect(target)) as copy,
    ):
        source.backup(copy)
    return target
