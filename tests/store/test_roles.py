"""Readers and writers of a shared registry on PostgreSQL (``store/roles.py``,
``registry grant``), with real roles of the tests' throwaway server.

A maintainer role owns the database and the registry's tables; ``registry grant`` makes
one role a reader and another a writer. The reader's every reading command works and
every write is refused before anything is done, in one line naming the missing
privilege, leaving the database byte for byte as it was; the writer writes but cannot
grant or upgrade the schema; only the owner upgrades it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from sqlalchemy import create_engine, text

import registry
from registry.cli import main
from registry.errors import RoleError, SchemaOwnerError, WritePrivilegeError
from registry.store import migrate, roles
from registry.store.database import Store
from registry.store.tables import Base

pytestmark = pytest.mark.postgres

ROOT = Path(registry.__file__).resolve().parent.parent
SEED = ROOT / "data" / "cases"
FILES = [SEED / "zhukovsky-gyrostat.toml", SEED / "yehia-2003-kovalevskaya-b.toml"]
LATER = SEED / "grioli-1957-charged-body.toml"


def invoke(db: str, *args: str):
    """``registry --db DB ARGS`` in this process; the result's output has both streams."""
    return CliRunner().invoke(main, ["--db", db, *args], catch_exceptions=False)


class Group:
    """A database owned by a maintainer role, a reader role and a writer role."""

    def __init__(self, server, hint: str):
        self.server = server
        self.maintainer, self.reader, self.writer = (
            server.new_name(f"{hint}_{who}") for who in ("maint", "student", "colleague")
        )
        self.database = server.new_name(hint)
        server.execute(
            *(f'CREATE ROLE "{r}" LOGIN' for r in (self.maintainer, self.reader, self.writer)),
            f'CREATE DATABASE "{self.database}" OWNER "{self.maintainer}" TEMPLATE template0',
        )

    def url(self, who: str) -> str:
        return self.server.url(self.database, user=getattr(self, who))

    def snapshot(self) -> dict[str, list]:
        """Every row of every registry table, as the superuser sees it."""
        with self.server.connect(self.database) as conn:
            return {
                name: conn.execute(f'SELECT * FROM "{name}" ORDER BY 1').fetchall()
                for name in sorted(Base.metadata.tables)
            }


@pytest.fixture(scope="module")
def group(postgres_server, tmp_path_factory) -> Group:
    """The maintainer has added and audited two seed cases and recorded a search; the
    reader and the writer were granted by ``registry grant``."""
    found = Group(postgres_server, "roles")
    owner = found.url("maintainer")
    assert invoke(owner, "add", *map(str, FILES)).exit_code == 0
    assert invoke(owner, "audit", "--jobs", "1").exit_code == 0
    searched = invoke(owner, "discover", str(FILES[0]), "--degree", "2", "--record")
    assert searched.exit_code == 0, searched.output
    for level, role in (("--reader", found.reader), ("--writer", found.writer)):
        done = invoke(owner, "grant", level, role)
        assert done.exit_code == 0, done.output
        assert f"role {role!r} may now read" in done.output
    return found


READS = [
    ["cases"],
    ["verdicts"],
    ["runs"],
    ["corrections"],
    ["searches"],
    ["verify-db"],
    ["export-case", "yehia-2003-kovalevskaya-b", "--claim", "I2"],
]


@pytest.mark.parametrize("command", READS, ids=lambda c: c[0])
def test_a_reader_runs_every_reading_command(group, command):
    done = invoke(group.url("reader"), *command)
    assert done.exit_code == 0, done.output
    assert "Error" not in done.output


def test_a_reader_writes_reports_and_exports_to_files(group, tmp_path):
    reader = group.url("reader")
    for command in (
        ["report", "--format", "md", "-o", str(tmp_path / "report.md")],
        ["export", "--format", "csv", "-o", str(tmp_path / "tables")],
        ["export", "--bibtex", "-o", str(tmp_path / "sources.bib")],
        ["site", "-o", str(tmp_path / "site")],
    ):
        done = invoke(reader, *command)
        assert done.exit_code == 0, (command, done.output)
    assert "zhukovsky-gyrostat" in (tmp_path / "report.md").read_text(encoding="utf-8")
    assert any((tmp_path / "tables").iterdir())
    assert (tmp_path / "site" / "cases" / "zhukovsky-gyrostat.html").is_file()


WRITES = [
    ["add", str(LATER)],
    ["audit", "--jobs", "1"],
    ["audit", "--fresh", "--jobs", "1", "--case", "zhukovsky-gyrostat"],
    ["survey", "--jobs", "1"],
    ["discover", str(LATER), "--degree", "2", "--record"],
]


@pytest.mark.parametrize("command", WRITES, ids=lambda c: " ".join(c[:2]))
def test_a_readers_write_is_refused_in_one_line_and_changes_nothing(group, command):
    before = group.snapshot()
    done = invoke(group.url("reader"), *command)
    assert done.exit_code == 1
    lines = done.output.strip().splitlines()
    assert len(lines) == 1, done.output
    assert lines[0].startswith(f"Error: role {group.reader!r} may only read the registry at ")
    assert "(it lacks INSERT on table " in lines[0]
    assert f"registry grant --writer {group.reader}" in lines[0]
    assert group.snapshot() == before


def test_a_reader_cannot_grant(group):
    before = group.snapshot()
    done = invoke(group.url("reader"), "grant", "--reader", group.writer)
    assert done.exit_code == 1
    assert f"role {group.reader!r} does not own the registry's tables" in done.output
    assert group.snapshot() == before


def test_the_api_reads_for_a_reader_and_names_the_missing_privilege(group):
    with registry.open(group.url("reader"), create=False) as reg:
        assert set(reg.cases()["case"]) == {"zhukovsky-gyrostat", "yehia-2003-kovalevskaya-b"}
        assert not reg.verdicts().empty
        assert not reg.searches().empty
        with pytest.raises(WritePrivilegeError) as refused:
            reg.add(LATER)
        assert refused.value.role == group.reader
        assert refused.value.missing.startswith("INSERT on table ")
        with pytest.raises(WritePrivilegeError):
            reg.audit(jobs=1)


def test_a_writer_adds_and_audits_but_cannot_grant(group):
    writer = group.url("writer")
    added = invoke(writer, "add", str(LATER))
    assert added.exit_code == 0, added.output
    audited = invoke(writer, "audit", "--jobs", "1", "--case", "grioli-1957-charged-body")
    assert audited.exit_code == 0, audited.output
    assert "grioli-1957-charged-body" in invoke(group.url("reader"), "verdicts").output
    refused = invoke(writer, "grant", "--writer", group.reader)
    assert refused.exit_code == 1
    assert f"only their owner {group.maintainer!r}" in refused.output


def test_printed_sql_is_what_grant_runs(group):
    done = invoke(group.url("maintainer"), "grant", "--print-sql", "--reader", group.reader)
    assert done.exit_code == 0
    with Store(group.url("maintainer"), create=False) as store:
        expected = store.grant_statements("reader", group.reader)
    assert done.output.splitlines() == [f"{sql};" for sql in expected]
    assert f'GRANT SELECT ON ALL TABLES IN SCHEMA "public" TO "{group.reader}"' in expected


def test_grant_names_a_missing_role_and_refuses_sqlite(group, tmp_path):
    done = invoke(group.url("maintainer"), "grant", "--reader", "nobody_here")
    assert done.exit_code == 1
    assert "has no role 'nobody_here'; an administrator creates it first" in done.output
    sqlite = tmp_path / "r.sqlite"
    assert invoke(str(sqlite), "add", str(FILES[0])).exit_code == 0
    done = invoke(str(sqlite), "grant", "--reader", "student")
    assert done.exit_code == 1
    assert "is an SQLite file, which has no roles" in done.output
    with Store(sqlite) as store, pytest.raises(RoleError):
        store.grant("reader", "student")


def test_a_revoked_reader_reads_nothing(postgres_server):
    found = Group(postgres_server, "revoke")
    owner = found.url("maintainer")
    assert invoke(owner, "add", str(FILES[0])).exit_code == 0
    assert invoke(owner, "grant", "--reader", found.reader).exit_code == 0
    assert invoke(found.url("reader"), "cases").exit_code == 0
    assert invoke(owner, "grant", "--revoke", found.reader).exit_code == 0
    done = invoke(found.url("reader"), "cases")
    assert done.exit_code == 1
    assert f"refuses role {found.reader!r}: permission denied for table alembic_version" in (
        done.output
    )


def test_only_the_owner_upgrades_the_schema(postgres_server):
    """Readers and writers are refused an older schema before anything is changed; the
    owner's next command upgrades it, and the default privileges granted before reach
    the tables the upgrade creates."""
    found = Group(postgres_server, "upgrade")
    engine = create_engine(found.url("maintainer"))
    with engine.begin() as conn:
        migrate.command.upgrade(migrate._config(conn), migrate.FIRST_REVISION)
        owner = roles.tables_owner(conn)
        assert owner == found.maintainer
        for level, role in (("reader", found.reader), ("writer", found.writer)):
            place = {"database": found.database, "owner": owner}
            for sql in roles.grant_statements(level, role, **place):
                conn.execute(text(sql))
    engine.dispose()
    for who in ("reader", "writer"):
        with pytest.raises(SchemaOwnerError) as refused:
            Store(found.url(who), create=False)
        message = str(refused.value)
        assert "has schema revision 0001 and this release needs" in message
        assert f"only the owner of its tables, role {found.maintainer!r}, may upgrade it" in message
        done = invoke(found.url(who), "cases")
        assert done.exit_code == 1 and len(done.output.strip().splitlines()) == 1
    with found.server.connect(found.database) as conn:
        assert conn.execute("SELECT version_num FROM alembic_version").fetchall() == [("0001",)]
    with Store(found.url("maintainer"), create=False) as store:
        assert store.upgraded_from == migrate.FIRST_REVISION
    with Store(found.url("writer")) as store:
        store.require_writer("add cases")  # the tables the upgrade created are writable
    assert invoke(found.url("writer"), "add", str(FILES[0])).exit_code == 0
    assert invoke(found.url("reader"), "cases").exit_code == 0


def test_the_operations_page_gives_the_roles_recipe():
    page = (ROOT / "docs" / "operations.md").read_text(encoding="utf-8")
    for line in ("registry grant --reader", "registry grant --writer", "registry grant --revoke"):
        assert line in page
