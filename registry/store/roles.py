"""Who may do what in a shared registry on PostgreSQL: readers and writers.

A research group's registry has maintainers, who add cases, audit and search (a
*writer* role), and readers (students, collaborators) who browse and query (a *reader*
role). ``grant_statements`` writes the SQL that makes a role one or the other (``registry
grant`` runs it, or prints it for an administrator); ``missing_write_privilege`` tells a
command before it starts what its role lacks, so a reader's write is refused before
anything is done. Creating and upgrading the tables stays with the role that owns them:
neither a reader nor a writer gets CREATE on the schema. An SQLite file has no roles:
who reads and who writes it is set by the file's permissions.

>>> for sql in grant_statements("reader", "student", database="reg", owner="maint"):
...     print(sql)
GRANT CONNECT ON DATABASE "reg" TO "student"
GRANT USAGE ON SCHEMA "public" TO "student"
GRANT SELECT ON ALL TABLES IN SCHEMA "public" TO "student"
ALTER DEFAULT PRIVILEGES FOR ROLE "maint" IN SCHEMA "public" GRANT SELECT ON TABLES TO "student"
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Literal

from sqlalchemy import text
from sqlalchemy.engine import Connection

Level = Literal["reader", "writer"]

#: What each level may do to the registry's tables (views included) and sequences.
TABLE_PRIVILEGES: dict[str, tuple[str, ...]] = {
    "reader": ("SELECT",),
    "writer": ("SELECT", "INSERT", "UPDATE"),
}
SEQUENCE_PRIVILEGES: dict[str, tuple[str, ...]] = {"reader": (), "writer": ("USAGE", "SELECT")}

#: A role name ``registry grant`` accepts: PostgreSQL's unquoted identifiers, so that a
#: name typed on the command line is the role the server knows.
ROLE_NAME = re.compile(r"[a-z_][a-z0-9_$]{0,62}")


def quote(name: str) -> str:
    """An SQL identifier in double quotes (a quote inside doubled)."""
    return '"' + name.replace('"', '""') + '"'


def grant_statements(
    level: Level, role: str, *, database: str, owner: str, schema: str = "public"
) -> list[str]:
    """The statements that give ``role`` what a reader or a writer needs, on the tables
    there are and (through default privileges of the tables' ``owner``) on those a later
    schema revision creates."""
    r, s = quote(role), quote(schema)
    tables = ", ".join(TABLE_PRIVILEGES[level])
    statements = [
        f"GRANT CONNECT ON DATABASE {quote(database)} TO {r}",
        f"GRANT USAGE ON SCHEMA {s} TO {r}",
        f"GRANT {tables} ON ALL TABLES IN SCHEMA {s} TO {r}",
    ]
    sequences = ", ".join(SEQUENCE_PRIVILEGES[level])
    if sequences:
        statements.append(f"GRANT {sequences} ON ALL SEQUENCES IN SCHEMA {s} TO {r}")
    default = f"ALTER DEFAULT PRIVILEGES FOR ROLE {quote(owner)} IN SCHEMA {s} GRANT"
    statements.append(f"{default} {tables} ON TABLES TO {r}")
    if sequences:
        statements.append(f"{default} {sequences} ON SEQUENCES TO {r}")
    return statements


def revoke_statements(role: str, *, database: str, owner: str, schema: str = "public") -> list[str]:
    """The statements that take back from ``role`` everything ``grant_statements`` gives."""
    r, s = quote(role), quote(schema)
    default = f"ALTER DEFAULT PRIVILEGES FOR ROLE {quote(owner)} IN SCHEMA {s} REVOKE ALL ON"
    return [
        f"REVOKE ALL ON ALL TABLES IN SCHEMA {s} FROM {r}",
        f"REVOKE ALL ON ALL SEQUENCES IN SCHEMA {s} FROM {r}",
        f"{default} TABLES FROM {r}",
        f"{default} SEQUENCES FROM {r}",
        f"REVOKE USAGE ON SCHEMA {s} FROM {r}",
        f"REVOKE CONNECT ON DATABASE {quote(database)} FROM {r}",
    ]


def missing_write_privilege(conn: Connection, tables: Iterable[str]) -> str | None:
    """What the connected role lacks to write the registry's ``tables`` and their id
    sequences (``"INSERT on table cases"``), or None when it has every privilege a
    writer has. Nothing is written."""
    table = conn.execute(
        text(
            "SELECT t.name, p.name FROM unnest(CAST(:tables AS text[])) AS t(name), "
            "unnest(CAST(:privileges AS text[])) WITH ORDINALITY AS p(name, i) "
            "WHERE NOT has_table_privilege(quote_ident(t.name), p.name) "
            "ORDER BY t.name, p.i LIMIT 1"
        ),
        {"tables": sorted(tables), "privileges": list(TABLE_PRIVILEGES["writer"])},
    ).first()
    if table is not None:
        return f"{table[1]} on table {table[0]}"
    sequence = conn.execute(
        text(
            "SELECT c.relname FROM pg_class c JOIN pg_namespace n ON n.oid = c.relnamespace "
            "WHERE n.nspname = current_schema() AND CASE WHEN c.relkind = 'S' "
            "THEN NOT has_sequence_privilege(c.oid, 'USAGE') ELSE false END "
            "ORDER BY c.relname LIMIT 1"
        )
    ).scalar_one_or_none()
    return None if sequence is None else f"USAGE on sequence {sequence}"


def tables_owner(conn: Connection) -> str | None:
    """The role that owns the registry's tables (that of ``alembic_version``, which the
    first schema revision creates), or None for a database without them."""
    return conn.execute(
        text(
            "SELECT tableowner FROM pg_tables WHERE schemaname = current_schema() "
            "AND tablename = 'alembic_version'"
        )
    ).scalar_one_or_none()


def acts_as(conn: Connection, role: str) -> bool:
    """Whether the connected role is ``role``, a member of it, or a superuser."""
    return bool(
        conn.execute(
            text("SELECT pg_has_role(current_user, CAST(:r AS text), 'MEMBER')"), {"r": role}
        ).scalar_one()
    )


def role_exists(conn: Connection, role: str) -> bool:
    """Whether the server knows a role of that name."""
    found = conn.execute(text("SELECT 1 FROM pg_roles WHERE rolname = :r"), {"r": role})
    return found.first() is not None


def current_database(conn: Connection) -> tuple[str, str, str]:
    """The database, schema and role the connection works in."""
    row = conn.execute(text("SELECT current_database(), current_schema(), current_user")).one()
    return row[0], row[1], row[2]
