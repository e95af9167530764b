"""Schema migrations: a new database is built by the revisions and matches the models;
a database of the first released schema (a dump kept in tests/data) is upgraded
with its data intact after a backup copy; a newer schema is refused."""

from __future__ import annotations

import sqlite3
from contextlib import closing
from pathlib import Path

import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from click.testing import CliRunner
from samples import TEST_DATA
from sqlalchemy import create_engine, inspect, text

import registry
from registry.cli import main
from registry.errors import NotADatabaseError, SchemaTooNewError
from registry.store import migrate
from registry.store.database import Store
from registry.store.tables import SCHEMA_VERSION, Base, latest_verdicts

FIRST_SCHEMA_DUMP = TEST_DATA / "registry-schema-1.sql"

#: What the first released schema holds in every table (a property of the dump).
TABLES = ("sources", "cases", "claims", "audit_runs", "check_results", "corrections", "evidence")


def first_schema_db(path: Path) -> Path:
    """A database file exactly as registry 0.1.0 (schema 1, before migrations) left it."""
    with closing(sqlite3.connect(path)) as conn:
        conn.executescript(FIRST_SCHEMA_DUMP.read_text(encoding="utf-8"))
    return path


#: Columns added by later revisions, left out when rows are compared with schema 1.
ADDED = (
    "host", "pid", "pid_started", "compared_with", "narrowed",  # 0002, 0003
    "authors", "year", "title", "journal", "booktitle", "publisher", "volume", "issue",
    "pages", "url", "topic", "notes", "provenance", "search_id",  # 0004
)  # fmt: skip


def rows(path: Path, table: str) -> list[dict]:
    """The rows of ``table`` (columns of schema 1 only), in id order."""
    with closing(sqlite3.connect(path)) as conn:
        names = [r[1] for r in conn.execute(f"PRAGMA table_info({table})")]
        old = [n for n in names if n not in ADDED]
        columns = ", ".join(f'"{n}"' for n in old)
        query = f"SELECT {columns} FROM {table} ORDER BY id"
        return [dict(zip(old, r, strict=True)) for r in conn.execute(query)]


def upgraded(table: str, row: dict) -> dict:
    """A schema-1 row as revision 0003 rewrites it: derived facts carry a verdict of the
    one vocabulary or none (``unverified`` and ``""`` were no verdicts)."""
    if table == "corrections":
        verdict = {"": None, "unverified": "inconclusive"}.get(row["verdict"], row["verdict"])
        return {**row, "verdict": verdict}
    return row


def test_revisions_form_one_chain_ending_at_the_schema_version():
    assert migrate.known_revisions() == ["0001", "0002", "0003", "0004"]
    assert int(migrate.head()) == SCHEMA_VERSION


def test_a_new_database_built_by_the_revisions_matches_the_models(tmp_path):
    with Store(tmp_path / "new.sqlite") as store, store.engine.connect() as conn:
        assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
        assert MigrationContext.configure(conn).get_current_revision() == migrate.head()
        view = [c["name"] for c in inspect(conn).get_columns("latest_verdicts")]
        assert view == [c.name for c in latest_verdicts.columns]
        version = conn.scalar(text("SELECT value FROM meta WHERE key = 'schema_version'"))
        assert version == str(SCHEMA_VERSION)
    assert store.upgraded_from is None and store.backup is None  # nothing to upgrade


def test_the_first_released_schema_is_upgraded_with_its_data_intact(tmp_path):
    path = first_schema_db(tmp_path / "old.sqlite")
    before = {t: rows(path, t) for t in TABLES}
    assert before["cases"] and before["check_results"]  # the dump holds data

    with Store(path) as store:
        assert store.upgraded_from == "0001"
        assert store.backup == tmp_path / "old.sqlite.schema-0001.bak"
        with store.engine.connect() as conn:
            assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
            assert conn.scalar(text("PRAGMA integrity_check")) == "ok"
            assert conn.execute(text("PRAGMA foreign_key_check")).all() == []

    after = {t: rows(path, t) for t in TABLES}
    assert after == {t: [upgraded(t, r) for r in before[t]] for t in TABLES}
    assert [r["verdict"] for r in after["corrections"]] == [
        None, "verified", "verified", "verified", None, None
    ]  # fmt: skip
    # the backup is the database as it was: schema 1, no Alembic table
    assert {t: rows(store.backup, t) for t in TABLES} == before
    with closing(sqlite3.connect(store.backup)) as conn:
        names = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
        assert "alembic_version" not in names

    # the upgraded registry reads its old results and takes new ones
    reg = registry.open(path)
    assert set(reg.verdicts()["case"]) == {
        "zhukovsky-gyrostat",
        "yehia-2003-kovalevskaya-b",
        "grioli-1957-charged-body",
    }
    old_runs = len(reg.runs())
    report = reg.audit(["zhukovsky-gyrostat"], jobs=0)
    assert len(reg.runs()) == old_runs + 1
    assert {str(a.results[0].verdict) for a in report.audits} == {"verified"}
    reg.store.close()

    with Store(path) as again:  # already current: no second upgrade, no second copy
        assert again.upgraded_from is None and again.backup is None
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".bak") == [
        "old.sqlite.schema-0001.bak"
    ]


def test_the_cli_says_that_it_upgraded_and_where_the_copy_is(tmp_path):
    path = first_schema_db(tmp_path / "old.sqlite")
    result = CliRunner().invoke(main, ["--db", str(path), "runs"])
    assert result.exit_code == 0, result.output
    backup = tmp_path / "old.sqlite.schema-0001.bak"
    assert result.stderr.splitlines()[0] == (
        f"Upgraded database {str(path)!r} from schema revision 0001; "
        f"the copy made before is {str(backup)!r}"
    )


def test_a_newer_revision_is_refused_with_a_clear_message(tmp_path):
    path = tmp_path / "new.sqlite"
    with Store(path) as store, store.engine.begin() as conn:
        conn.execute(text("UPDATE alembic_version SET version_num = '0099'"))
    expected = (
        f"database {str(path)!r} has schema revision 0099, newer than this registry "
        "supports (revision 0004); upgrade the registry package to open it"
    )
    with pytest.raises(SchemaTooNewError) as info:
        Store(path)
    assert str(info.value) == expected
    result = CliRunner().invoke(main, ["--db", str(path), "cases"])
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"Error: {expected}"]


def test_a_newer_schema_from_before_alembic_is_refused(tmp_path):
    path = first_schema_db(tmp_path / "old.sqlite")
    with closing(sqlite3.connect(path)) as conn, conn:
        conn.execute("UPDATE meta SET value = '7' WHERE key = 'schema_version'")
    with pytest.raises(SchemaTooNewError, match="has schema version 7"):
        Store(path)
    assert not list(tmp_path.glob("*.bak"))  # refused before any copy or change


def test_a_database_of_another_program_is_refused_untouched(tmp_path):
    path = tmp_path / "other.sqlite"
    with closing(sqlite3.connect(path)) as conn, conn:
        conn.execute("CREATE TABLE notes (body TEXT)")
    with pytest.raises(NotADatabaseError) as info:
        Store(path)
    assert str(info.value) == (
        f"{str(path)!r} is not a usable registry database (it holds other tables: notes)"
    )
    with closing(sqlite3.connect(path)) as conn:
        assert [r[0] for r in conn.execute("SELECT name FROM sqlite_master")] == ["notes"]


def test_a_failed_upgrade_leaves_the_database_as_it_was(tmp_path, monkeypatch):
    path = first_schema_db(tmp_path / "old.sqlite")
    before = {t: rows(path, t) for t in TABLES}

    def broken(conn, state):
        migrate.command.stamp(migrate._config(conn), migrate.FIRST_REVISION)
        conn.execute(text("ALTER TABLE audit_runs ADD COLUMN host TEXT"))
        raise RuntimeError("power cut in the middle of the upgrade")

    monkeypatch.setattr(migrate, "upgrade", broken)
    with pytest.raises(RuntimeError):
        Store(path)
    with closing(sqlite3.connect(path)) as conn:
        names = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
        columns = {r[1] for r in conn.execute("PRAGMA table_info(audit_runs)")}
    assert "alembic_version" not in names and "host" not in columns
    assert {t: rows(path, t) for t in TABLES} == before
    monkeypatch.undo()
    with Store(path) as store:  # and the next open upgrades it
        assert store.upgraded_from == "0001"


def test_evidence_stored_before_revision_0003_keeps_the_verdict_it_was_compared_with(tmp_path):
    """Before 0003 the drift was compared with the verdict the claim's kind names; the
    upgrade records that kind, so the history does not claim an integral comparison."""
    path = first_schema_db(tmp_path / "old.sqlite")
    engine = create_engine(f"sqlite:///{path}")
    with engine.begin() as conn:
        config = migrate._config(conn)
        migrate.command.stamp(config, migrate.FIRST_REVISION)
        migrate.command.upgrade(config, "0002")
        claims = conn.execute(text("SELECT id, case_pk, kind FROM claims ORDER BY id")).all()
        for claim_id, case_pk, _ in claims:
            conn.execute(
                text(
                    "INSERT INTO evidence (run_id, case_pk, claim_id, drift, floor, runs, "
                    "contradicts, note) VALUES (1, :case, :claim, 1e-12, 1e-12, 3, 0, '')"
                ),
                {"case": case_pk, "claim": claim_id},
            )
    engine.dispose()
    with Store(path) as store:
        assert store.upgraded_from == "0002"
    stored = [(r["claim_id"], r["compared_with"]) for r in rows_all(path, "evidence")]
    assert stored == [(claim_id, kind) for claim_id, _, kind in claims]
    assert {kind for _, _, kind in claims} == {"casimir", "integral"}  # both kinds occur


def rows_all(path: Path, table: str) -> list[dict]:
    """Every column of every row of ``table``, in id order."""
    with closing(sqlite3.connect(path)) as conn:
        conn.row_factory = sqlite3.Row
        return [dict(r) for r in conn.execute(f"SELECT * FROM {table} ORDER BY id")]
