"""Schema migrations: a new database is built by the revisions and matches the models;
a database of the first released schema (a dump kept in tests/data) is upgraded
with its data intact after a backup copy; a newer schema is refused.

On SQLite and on PostgreSQL (fixture ``backend``), except what is SQLite's own: the
dump of a registry 0.1.0 file (before Alembic), and the backup copy. On PostgreSQL the
same data is loaded into a database built by revision 0001, and upgraded in place in
one transaction, with no copy (that is the administrator's pg_dump).
"""

from __future__ import annotations

import json
import sqlite3
from contextlib import closing
from datetime import UTC, datetime
from pathlib import Path

import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from click.testing import CliRunner
from sqlalchemy import (
    JSON,
    Boolean,
    Column,
    DateTime,
    MetaData,
    Table,
    create_engine,
    insert,
    inspect,
    text,
)
from sqlalchemy import column as sql_column
from sqlalchemy import select as sql_select
from sqlalchemy import table as sql_table

import registry
from registry.cli import main
from registry.errors import NotADatabaseError, SchemaTooNewError
from registry.store import migrate
from registry.store.database import Store
from registry.store.integrity import verify
from registry.store.tables import SCHEMA_VERSION, Base, latest_verdicts
from tests.helpers.databases import POSTGRES, connection, is_url
from tests.helpers.registries import registry_rows
from tests.helpers.samples import TEST_DATA

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
    "hamiltonian", "kappa",  # 0007
    "form", "detail",  # 0008
    "same_as",  # 0010
)  # fmt: skip


def rows(target: Path | str, table: str) -> list[dict]:
    """The rows of ``table`` (columns of schema 1 only), in id order."""
    with connection(target) as conn:
        old = [c["name"] for c in inspect(conn).get_columns(table) if c["name"] not in ADDED]
        found = sql_table(table, *(sql_column(n) for n in old))
        return [dict(r._mapping) for r in conn.execute(sql_select(found).order_by(found.c.id))]


def first_schema(target: str, scratch: Path) -> str:
    """A database of the first released schema holding the dump's data: on SQLite the
    file exactly as registry 0.1.0 left it; on PostgreSQL (which 0.1.0 did not support)
    a database built by revision 0001 holding the same rows."""
    if not is_url(target):
        return str(first_schema_db(Path(target)))
    dump = first_schema_db(scratch / "first-schema.sqlite")
    with connection(target) as conn:
        migrate.command.upgrade(migrate._config(conn), migrate.FIRST_REVISION)
        found = MetaData()
        found.reflect(conn)
        for name in TABLES:  # parents before children
            table = found.tables[name]
            values = [_typed(table, row) for row in rows_all(dump, name)]
            if values:
                conn.execute(insert(table), values)
            # rows came with their ids: the next id follows them
            conn.execute(
                text(f"SELECT setval(pg_get_serial_sequence('{name}', 'id'), max(id)) FROM {name}")
            )
    return target


def _typed(table, row: dict) -> dict:
    """A row read from SQLite (JSON as text, booleans as 0/1, naive UTC times) in the
    Python types PostgreSQL's columns take."""
    out = {}
    for name, value in row.items():
        kind = table.c[name].type
        if value is not None and isinstance(kind, JSON):
            value = json.loads(value)
        elif value is not None and isinstance(kind, Boolean):
            value = bool(value)
        elif value is not None and isinstance(kind, DateTime):
            value = datetime.fromisoformat(value).replace(tzinfo=UTC)
        out[name] = value
    return out


def upgraded(table: str, row: dict) -> dict:
    """A schema-1 row as revision 0003 rewrites it: derived facts carry a verdict of the
    one vocabulary or none (``unverified`` and ``""`` were no verdicts)."""
    if table == "corrections":
        verdict = {"": None, "unverified": "inconclusive"}.get(row["verdict"], row["verdict"])
        return {**row, "verdict": verdict}
    return row


def test_revisions_form_one_chain_ending_at_the_schema_version():
    assert migrate.known_revisions() == [
        "0001", "0002", "0003", "0004", "0005", "0006", "0007", "0008", "0009", "0010",
        "0011", "0012",
    ]  # fmt: skip
    assert int(migrate.head()) == SCHEMA_VERSION


def test_a_new_database_built_by_the_revisions_matches_the_models(db_target):
    with Store(db_target) as store, store.engine.connect() as conn:
        assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
        assert MigrationContext.configure(conn).get_current_revision() == migrate.head()
        view = [c["name"] for c in inspect(conn).get_columns("latest_verdicts")]
        assert view == [c.name for c in latest_verdicts.columns]
        version = conn.scalar(text("SELECT value FROM meta WHERE key = 'schema_version'"))
        assert version == str(SCHEMA_VERSION)
    assert store.upgraded_from is None and store.backup is None  # nothing to upgrade


# SQLite only: registry 0.1.0's file, and the backup copy (PostgreSQL: the next test)
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
    report = reg.audit(["zhukovsky-gyrostat"], jobs=1)
    assert len(reg.runs()) == old_runs + 1
    assert {str(a.results[0].verdict) for a in report.audits} == {"verified"}
    reg.store.close()

    with Store(path) as again:  # already current: no second upgrade, no second copy
        assert again.upgraded_from is None and again.backup is None
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".bak") == [
        "old.sqlite.schema-0001.bak"
    ]


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_a_server_database_of_the_first_schema_is_upgraded_in_place(db_target, tmp_path):
    target = first_schema(db_target, tmp_path)
    before = {t: rows(target, t) for t in TABLES}
    assert before["cases"] and before["check_results"]

    with Store(target) as store:
        assert store.upgraded_from == "0001"
        assert store.backup is None  # a server's database is its administrator's to copy
        with store.engine.connect() as conn:
            assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
        assert verify(store).ok  # foreign keys, hashes and every stored expression

    after = {t: rows(target, t) for t in TABLES}
    assert after == {t: [upgraded(t, r) for r in before[t]] for t in TABLES}
    reg = registry.open(target)
    assert set(reg.verdicts()["case"]) == {
        "zhukovsky-gyrostat",
        "yehia-2003-kovalevskaya-b",
        "grioli-1957-charged-body",
    }
    old_runs = len(reg.runs())
    reg.audit(["zhukovsky-gyrostat"], jobs=1)
    assert len(reg.runs()) == old_runs + 1
    reg.close()


def test_the_cli_says_that_it_upgraded_and_where_the_copy_is(db_target, backend, tmp_path):
    target = first_schema(db_target, tmp_path)
    result = CliRunner().invoke(main, ["--db", target, "runs"])
    assert result.exit_code == 0, result.output
    done = f"Upgraded database {target!r} from schema revision 0001"
    if backend == "sqlite":
        copy = f"{target}.schema-0001.bak"
        assert result.stderr.splitlines()[0] == f"{done}; the copy made before is {copy!r}"
    else:
        assert result.stderr.splitlines()[0] == (
            f"{done} in one transaction; no copy was made before (back up a PostgreSQL "
            "database with pg_dump)"
        )


def test_a_newer_revision_is_refused_with_a_clear_message(db_target, databases, sample_case):
    """A database stamped by a newer release (a revision this code does not know) is
    refused by every command that opens it, and by ``registry copy`` as a source or as
    a target, with one line, and nothing is changed: no upgrade, no copy made, no row."""
    path = db_target
    with Store(path) as store:
        store.add_case(sample_case)
        with store.engine.begin() as conn:
            conn.execute(text("UPDATE alembic_version SET version_num = '0099'"))
    before = _snapshot(path)
    expected = (
        f"database {str(path)!r} has schema revision 0099, newer than this registry "
        "supports (revision 0012); upgrade the registry package to open it"
    )
    with pytest.raises(SchemaTooNewError) as info:
        Store(path)
    assert str(info.value) == expected
    other, target = databases.new("other"), databases.new("target")
    Store(other).close()
    for command in (
        ["--db", str(path), "cases"],
        ["--db", str(path), "copy", "--to", target],
        ["--db", other, "copy", "--from", str(path)],
        ["--db", other, "copy", "--to", str(path)],
    ):
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 1, (command, result.output)
        assert result.stderr.splitlines() == [f"Error: {expected}"], command
    assert _snapshot(path) == before
    assert not any(rows for table, rows in registry_rows(other).items() if table != "meta")
    if is_url(target):  # the server's database exists: it stays without tables
        with connection(target) as conn:
            assert inspect(conn).get_table_names() == []
    else:
        assert not databases.exists(target)


def _snapshot(target: str) -> tuple:
    """Everything a refusal must leave as it was: the revision, every row, and (for a
    file) the files of its folder (no backup copy made)."""
    if is_url(target):
        return _revision(target), rows_all(target, "cases"), rows_all(target, "claims")
    files = sorted(p.name for p in Path(target).parent.glob(f"{Path(target).name}*"))
    return _revision(target), rows_all(target, "cases"), rows_all(target, "claims"), files


# SQLite only: databases from before Alembic are registry 0.1.0's files
def test_a_newer_schema_from_before_alembic_is_refused(tmp_path):
    path = first_schema_db(tmp_path / "old.sqlite")
    with closing(sqlite3.connect(path)) as conn, conn:
        conn.execute("UPDATE meta SET value = '9' WHERE key = 'schema_version'")
    with pytest.raises(SchemaTooNewError, match="has schema version 9"):
        Store(path)
    assert not list(tmp_path.glob("*.bak"))  # refused before any copy or change


def test_a_database_of_another_program_is_refused_untouched(db_target):
    path = db_target
    with connection(path) as conn:
        conn.execute(text("CREATE TABLE notes (body TEXT)"))
    with pytest.raises(NotADatabaseError) as info:
        Store(path)
    assert str(info.value) == (
        f"{str(path)!r} is not a usable registry database (it holds other tables: notes)"
    )
    with connection(path) as conn:
        assert inspect(conn).get_table_names() == ["notes"]
        assert inspect(conn).get_view_names() == []


def test_a_failed_upgrade_leaves_the_database_as_it_was(db_target, tmp_path, monkeypatch):
    path = first_schema(db_target, tmp_path)
    before = {t: rows(path, t) for t in TABLES}
    revision_before = _revision(path)

    def broken(conn, state):
        migrate.command.stamp(migrate._config(conn), migrate.FIRST_REVISION)
        conn.execute(text("ALTER TABLE audit_runs ADD COLUMN host TEXT"))
        raise RuntimeError("power cut in the middle of the upgrade")

    monkeypatch.setattr(migrate, "upgrade", broken)
    with pytest.raises(RuntimeError):
        Store(path)
    with connection(path) as conn:
        columns = {c["name"] for c in inspect(conn).get_columns("audit_runs")}
    assert _revision(path) == revision_before and "host" not in columns
    assert {t: rows(path, t) for t in TABLES} == before
    monkeypatch.undo()
    with Store(path) as store:  # and the next open upgrades it
        assert store.upgraded_from == "0001"


def _revision(target: str) -> str | None:
    """The Alembic revision a database records (None: none, as before Alembic)."""
    with connection(target) as conn:
        return MigrationContext.configure(conn).get_current_revision()


def test_evidence_stored_before_revision_0003_keeps_the_verdict_it_was_compared_with(
    db_target, tmp_path
):
    """Before 0003 the drift was compared with the verdict the claim's kind names; the
    upgrade records that kind, so the history does not claim an integral comparison."""
    path = first_schema(db_target, tmp_path)
    engine = create_engine(path if is_url(path) else f"sqlite:///{path}")
    with engine.begin() as conn:
        config = migrate._config(conn)
        migrate.command.stamp(config, migrate.FIRST_REVISION)
        migrate.command.upgrade(config, "0002")
        claims = conn.execute(text("SELECT id, case_pk, kind FROM claims ORDER BY id")).all()
        for claim_id, case_pk, _ in claims:
            conn.execute(
                text(
                    "INSERT INTO evidence (run_id, case_pk, claim_id, drift, floor, runs, "
                    "contradicts, note) VALUES (1, :case, :claim, 1e-12, 1e-12, 3, FALSE, '')"
                ),
                {"case": case_pk, "claim": claim_id},
            )
    engine.dispose()
    with Store(path) as store:
        assert store.upgraded_from == "0002"
    stored = [(r["claim_id"], r["compared_with"]) for r in rows_all(path, "evidence")]
    assert stored == [(claim_id, kind) for claim_id, _, kind in claims]
    assert {kind for _, _, kind in claims} == {"casimir", "integral"}  # both kinds occur


def rows_all(path: Path | str, table: str) -> list[dict]:
    """Every column of every row of ``table``, in id order."""
    with connection(path) as conn:
        return [dict(r._mapping) for r in conn.execute(text(f"SELECT * FROM {table} ORDER BY id"))]


# SQLite: a database as revision 0006 left it, holding a case in the Hamiltonian form
def test_revision_0007_copies_each_stored_systems_hamiltonian_and_kappa(tmp_path):
    from registry.language.casefile import load_case
    from tests.helpers.samples import CASES

    path = tmp_path / "r6.sqlite"
    hamiltonian_form = load_case(CASES / "so4" / "komarov-1990-so31-kovalevskaya.toml")
    inertia_form = load_case(CASES / "heavy-top" / "kovalevskaya-1889-heavy-top.toml")
    with Store(path) as store:
        store.add_case(hamiltonian_form)
        store.add_case(inertia_form)
    with closing(sqlite3.connect(path)) as conn, conn:  # back to what 0006 built
        conn.execute("DROP TABLE identifications")  # 0011 (0012 changes only exponents)
        conn.execute("ALTER TABLE discoveries DROP COLUMN same_as")  # 0010
        conn.execute("DROP TABLE exponents")
        conn.execute("DROP TABLE drift_curves")
        conn.execute("ALTER TABLE check_results DROP COLUMN detail")
        conn.execute("ALTER TABLE cases DROP COLUMN form")
        conn.execute("ALTER TABLE cases DROP COLUMN hamiltonian")
        conn.execute("ALTER TABLE cases DROP COLUMN kappa")
        conn.execute("UPDATE alembic_version SET version_num = '0006'")
        conn.execute("UPDATE meta SET value = '6' WHERE key = 'schema_version'")

    with Store(path) as store:
        assert store.upgraded_from == "0006"
        with store.engine.connect() as conn:
            assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
        assert verify(store).ok  # the copied columns agree with the parse of each text
    copied = {r["case_id"]: (r["hamiltonian"], r["kappa"]) for r in rows_all(path, "cases")}
    assert copied == {
        hamiltonian_form.id: (hamiltonian_form.system.hamiltonian.text, "-1"),
        inertia_form.id: (None, "0"),
    }


# SQLite: a database as revision 0011 left it, an untested Painlevé verdict stored false
def test_revision_0012_reads_an_untested_painleve_verdict_as_null(tmp_path):
    """Before 0012 the column held false where the test was not made, which read as
    "fails"; the upgrade reads each row's verdict again from its document."""
    from tests.helpers.samples import CASES

    path = tmp_path / "r11.sqlite"
    with registry.open(path) as reg:
        reg.add(CASES / "free-rigid-body" / "euler-1765-free-rigid-body.toml")
        reg.analyse_exponents("euler-1765-free-rigid-body", record=True)
    with closing(sqlite3.connect(path)) as conn, conn:
        (document,) = conn.execute("SELECT document FROM exponents").fetchone()
        untested = json.loads(document)
        untested["painleve"] = {"passes": None, "compatible": None, "conditions": []}
        conn.execute(
            "INSERT INTO exponents (case_pk, options, options_key, code_version, started_at,"
            " seconds, decided, homogeneous, all_integer, all_rational, passes, degrees,"
            " balances, statement, document) SELECT case_pk, options, options_key,"
            " code_version, started_at, seconds, decided, homogeneous, all_integer,"
            " all_rational, 0, degrees, balances, statement, ? FROM exponents",
            (json.dumps(untested),),
        )
        conn.execute("UPDATE alembic_version SET version_num = '0011'")
        conn.execute("UPDATE meta SET value = '11' WHERE key = 'schema_version'")

    with Store(path) as store:
        assert store.upgraded_from == "0011"
    assert [r["passes"] for r in rows_all(path, "exponents")] == [True, None]
    with registry.open(path) as reg:
        assert list(reg.exponents()["painleve"]) == [True, None]


# ---------------------------------------------- upgrades from every earlier revision

#: Every revision an earlier release may have left a database at.
EARLIER = migrate.known_revisions()[:-1]


def at_revision(target: str, revision: str, source: Path) -> tuple[dict, dict]:
    """A database built by the revisions up to ``revision`` (Alembic, as that release
    did), holding the rows of the full registry ``source`` that this revision can hold:
    its tables and its columns, and only from 0004 on the searches, discoveries, aliases
    and what hangs on them (claims attached by a search, cases derived by one); a
    derived fact's missing verdict is "" before 0003, which made it NULL. Rows keep
    their ids. Returns (the rows inserted, by table; the columns of each table then)."""
    found = registry_rows(source)
    with connection(target) as conn:
        migrate.command.upgrade(migrate._config(conn), revision)
        names = inspect(conn).get_table_names()
        present = {t: {c["name"] for c in inspect(conn).get_columns(t)} for t in names}
        kept = _valid_at(found, present)
        for table in Base.metadata.sorted_tables:
            if not kept[table.name]:
                continue
            columns = [c for c in table.c if c.name in present[table.name]]
            then = Table(table.name, MetaData(), *(Column(c.name, c.type) for c in columns))
            values = [{c.name: row[c.name] for c in columns} for row in kept[table.name]]
            if table.name == "corrections" and "compared_with" not in present["evidence"]:
                values = [{**v, "verdict": "" if v["verdict"] is None else v["verdict"]}
                          for v in values]  # fmt: skip
            conn.execute(insert(then), values)
            if conn.dialect.name == "postgresql":  # rows came with their ids
                conn.execute(
                    text(f"SELECT setval(pg_get_serial_sequence('{table.name}', 'id'), "
                         f"max(id)) FROM {table.name}")
                )  # fmt: skip
    return kept, present


def _valid_at(found: dict[str, list[dict]], present: dict[str, set[str]]) -> dict:
    """The rows (by table) a database with the tables and columns ``present`` can hold:
    what needs a later table or column is left out, and so is every row pointing to a
    row left out. ``meta`` stays the revision's own."""
    derived = set()
    if "discoveries" not in present:
        derived = {d["derived_case_pk"] for d in found["discoveries"]}
    gone: dict[str, set] = {}
    kept: dict[str, list[dict]] = {}
    for table in Base.metadata.sorted_tables:
        kept[table.name], gone[table.name] = [], set()
        if table.name == "meta" or table.name not in present:
            gone[table.name] = {r.get("id") for r in found[table.name]}
            continue
        for row in found[table.name]:
            later = (table.name == "cases" and row["id"] in derived) or (
                table.name == "claims"
                and row["search_id"] is not None
                and "search_id" not in present["claims"]
            )
            orphan = any(
                row[fk.parent.name] in gone[fk.column.table.name] for fk in table.foreign_keys
            )
            if later or orphan:
                gone[table.name].add(row["id"])
            else:
                kept[table.name].append(row)
    return kept


def _view(target: str) -> list[dict]:
    """The ``latest_verdicts`` view (the newest verdict of every check and claim), typed."""
    with connection(target) as conn:
        order = (latest_verdicts.c.case, latest_verdicts.c.claim, latest_verdicts.c.check)
        found = conn.execute(sql_select(latest_verdicts).order_by(*order))
        return [dict(r._mapping) for r in found]


@pytest.mark.parametrize("revision", EARLIER)
def test_a_database_at_each_earlier_revision_is_upgraded_with_nothing_lost(
    revision, db_target, full_registry_file
):
    """Built by the revisions up to ``revision`` and filled with what that revision holds
    (cases, claims, runs, results, corrections, evidence; from 0004 also searches,
    discoveries and aliases), then opened by this release: every row and every column
    it had is there, the case texts and hashes, and the newest verdicts are the same."""
    inserted, present = at_revision(db_target, revision, full_registry_file)
    assert all(inserted[t] for t in TABLES), {t: len(inserted[t]) for t in TABLES}
    if revision >= "0004":
        assert inserted["searches"] and inserted["discoveries"] and inserted["case_aliases"]
    verdicts = _view(db_target)
    assert verdicts

    with Store(db_target) as store:
        assert store.upgraded_from == revision
        assert (store.backup is None) == is_url(db_target)  # a file is copied first
        with store.engine.connect() as conn:
            assert compare_metadata(MigrationContext.configure(conn), Base.metadata) == []
        found = verify(store)
    assert found.ok, found.problems

    after = registry_rows(db_target)
    for table, rows in inserted.items():
        if table == "meta":
            continue
        columns = present.get(table, set())
        assert len(after[table]) == len(rows), table
        assert [{c: r[c] for c in columns} for r in after[table]] == [
            {c: r[c] for c in columns} for r in rows
        ], table
    # the case texts and hashes, and what 0007 reads from each text, as the source has them
    copied = ("id", "case_id", "version", "text", "content_hash", "hamiltonian", "kappa")
    assert [[r[c] for c in copied] for r in after["cases"]] == [
        [r[c] for c in copied] for r in inserted["cases"]
    ]
    assert _view(db_target) == verdicts
    with registry.open(db_target) as reg:  # and the registry reads them as before
        assert len(reg.verdicts()) == len(verdicts)
