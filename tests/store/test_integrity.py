"""``registry check`` finds what was damaged in a database, and says nothing of a sound one;
database failures (missing, read-only, full, locked) get their own one-line errors;
runs whose process died are marked interrupted on the next start.

Every test runs on an SQLite file and on a PostgreSQL database (fixture ``backend``),
except those about SQLite itself, each with its PostgreSQL counterpart where one
makes sense (a read-only role for a read-only file, a table lock for a write lock).
"""

from __future__ import annotations

import sqlite3
import subprocess
import sys
import threading
import time
from datetime import UTC, datetime

import pytest
from click.testing import CliRunner
from sqlalchemy import event, insert, select

import registry
from registry import settings
from registry.audit import parallel
from registry.cli import main
from registry.errors import (
    DatabaseFullError,
    DatabaseLockedError,
    DatabaseMissingError,
    DatabaseReadOnlyError,
)
from registry.store import engine, migrate
from registry.store.database import Store
from registry.store.integrity import verify
from registry.store.tables import RunRow
from tests.helpers.databases import POSTGRES, connection, execute, rows
from tests.helpers.samples import CASES, ZHUKOVSKY

YEHIA_B = "yehia-2003-kovalevskaya-b"
PICK = [ZHUKOVSKY, YEHIA_B, "affine-nonsymmetric"]


@pytest.fixture(scope="module")
def audited_db(module_databases) -> str:
    """A database with three seed cases, audited once with corrections (so it holds derived
    Casimirs, torques and parameter conditions)."""
    target = module_databases.new("audited")
    reg = registry.open(target)
    reg.add(*(CASES / f"{c}.toml" for c in PICK))
    reg.audit(jobs=1)
    reg.store.close()
    return target


@pytest.fixture
def db(audited_db, databases) -> str:
    """A private copy of the audited database, to damage."""
    return databases.copy(audited_db)


def damage(target: str, *statements: str) -> None:
    """Change the database behind the registry's back (foreign keys off, as a careless
    tool would)."""
    execute(target, *statements, foreign_keys=False)


def problems(target: str) -> list[str]:
    with Store(target) as store:
        return list(verify(store).problems)


def pk_of(target: str, case_id: str) -> int:
    ((pk,),) = rows(target, "SELECT id FROM cases WHERE case_id = :c", c=case_id)
    return pk


# ---------------------------------------------------------------- registry check


def test_a_sound_database_passes(db, backend):
    result = CliRunner().invoke(main, ["--db", str(db), "verify-db"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == f"database {str(db)!r}, schema revision {migrate.head()}"
    assert lines[1].startswith("3 case versions, 3 claims, 1 runs, ")
    engine = "SQLite 3." if backend == "sqlite" else "PostgreSQL "
    assert lines[2].startswith(f"engine: {engine}")
    if backend == "postgres":
        assert lines[2].endswith(', schema "public"')
    assert lines[-1] == "ok: integrity, foreign keys, hashes and every stored expression"
    with Store(db) as store:
        found = verify(store)
    assert found.ok and found.counts["corrections"] > 0  # derived texts were looked at


def test_an_edited_case_text_is_found(db):
    damage(
        db,
        f"UPDATE cases SET text = replace(text, 'Zhukovsky', 'Zhukovskii') "
        f"WHERE case_id = '{ZHUKOVSKY}'",
    )
    assert problems(db) == [
        f"case {ZHUKOVSKY} version 1: the stored hash does not match the stored text"
    ]


def test_an_edited_column_is_found(db):
    damage(db, f"UPDATE cases SET potential = 'gamma3' WHERE case_id = '{YEHIA_B}'")
    ((text,),) = rows(db, "SELECT text FROM cases WHERE case_id = :c", c=YEHIA_B)
    case = registry.parse_case_text(text)
    assert problems(db) == [
        f"case {YEHIA_B} version 1: potential: stored as 'gamma3', but the case text says "
        f"{case.system.potential.text!r}"
    ]


def test_an_edited_bracket_or_hamiltonian_column_is_found(db):
    damage(db, f"UPDATE cases SET kappa = '1', hamiltonian = 'M1**2' WHERE case_id = '{YEHIA_B}'")
    assert problems(db) == [
        f"case {YEHIA_B} version 1: kappa: stored as '1', but the case text says '0'",
        f"case {YEHIA_B} version 1: hamiltonian: stored, but not in the case text",
    ]


def test_a_stored_claim_that_no_longer_parses_is_found(db):
    damage(db, "UPDATE claims SET expression = '__import__(''os'')' WHERE label = 'I2'")
    found = problems(db)
    assert len(found) == 2
    assert found[0].startswith(
        f"case {YEHIA_B} version 1: claim 'I2' expression: stored as \"__import__('os')\""
    )
    assert found[1].startswith(
        f"case {YEHIA_B} version 1: claim 'I2' expression: \"__import__('os')\" does not parse: "
    )


def test_a_derived_expression_that_does_not_parse_is_found(db):
    damage(db, "UPDATE corrections SET expression = 'gamma1 ^ 2' WHERE kind = 'casimir'")
    found = problems(db)
    assert found and all("does not parse" in p and "'gamma1 ^ 2'" in p for p in found)
    assert all(p.startswith(f"case {YEHIA_B} version 1: run 1, casimir") for p in found)


def test_a_stored_text_that_no_longer_parses_is_found(db):
    damage(db, f"UPDATE cases SET text = 'id = ', content_hash = 'x' WHERE case_id = '{ZHUKOVSKY}'")
    (found,) = problems(db)
    assert found == (
        f"case {ZHUKOVSKY} version 1: the stored text no longer parses: "
        "invalid TOML: Invalid value (at end of document)"
    )


def test_broken_references_and_unknown_values_are_found(db):
    ((crossed,),) = rows(
        db, "SELECT min(id) FROM check_results WHERE case_pk = :pk", pk=pk_of(db, ZHUKOVSKY)
    )
    damage(
        db,
        "UPDATE check_results SET run_id = 99 WHERE id = 1",
        "UPDATE check_results SET verdict = 'probably' WHERE id = 2",
        "UPDATE check_results SET claim_id = (SELECT id FROM claims WHERE label = 'I2') "
        f"WHERE id = {crossed}",
        "UPDATE audit_runs SET status = 'done'",
    )
    assert sorted(problems(db)) == sorted(
        [
            "foreign key: row 1 of check_results points to a missing row of audit_runs",
            "check_results row 2: unknown verdict 'probably'",
            f"check_results row {crossed}: its claim belongs to another case version",
            "audit run 1: unknown status 'done'",
        ]
    )


def test_the_cli_lists_the_problems_and_exits_1(db):
    damage(db, "UPDATE check_results SET verdict = 'probably' WHERE id = 2")
    result = CliRunner().invoke(main, ["--db", str(db), "verify-db"])
    assert result.exit_code == 1
    assert "problem: check_results row 2: unknown verdict 'probably'" in result.stdout
    assert result.stderr.splitlines() == ["Error: 1 problem(s) found in the database"]


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_foreign_keys_the_server_no_longer_enforces_are_found(db):
    damage(db, "ALTER TABLE check_results DISABLE TRIGGER ALL")
    assert problems(db) == ["check_results: its foreign keys are not enforced (triggers disabled)"]


# ---------------------------------------------------------------- database errors


# SQLite only: a database file that does not exist (on PostgreSQL: test_engine.py,
# a database the server does not have)
def test_a_missing_database_is_reported_and_not_created(tmp_path):
    missing = tmp_path / "nowhere.sqlite"
    with pytest.raises(DatabaseMissingError):
        registry.open(missing, create=False)
    for command in (["cases"], ["verdicts"], ["audit"], ["verify-db"], ["runs"]):
        result = CliRunner().invoke(main, ["--db", str(missing), *command])
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [
            f"Error: no registry database at {str(missing)!r}; create one by adding cases "
            "(registry add FILES) or name another with --db"
        ]
    assert not missing.exists()


# SQLite only: a read-only file (on PostgreSQL: the read-only role below)
@pytest.mark.parametrize("backend", ["sqlite"], indirect=True)
def test_a_read_only_database_is_read_but_not_written(db):
    url = f"sqlite:///file:{db}?mode=ro&uri=true"
    reg = registry.open(url)
    assert set(reg.cases()["case"]) == set(PICK)  # reading works
    with pytest.raises(DatabaseReadOnlyError) as info:
        reg.add(CASES / "borisov-mamaev-1997.toml")
    assert str(info.value) == (
        f"database {reg.store.location!r} is read-only, so the registry cannot write to it; "
        "check the permissions of the file and of its folder"
    )
    result = CliRunner().invoke(main, ["--db", url, "add", str(CASES / "axis-torque.toml")])
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"Error: {info.value}"]


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_a_read_only_role_reads_but_does_not_write(db, databases):
    databases.server.execute(
        "DO $$ BEGIN CREATE ROLE reader LOGIN; EXCEPTION WHEN duplicate_object THEN NULL; END $$"
    )
    execute(db, "GRANT SELECT ON ALL TABLES IN SCHEMA public TO reader")
    url = db.replace("//registry@", "//reader@")
    reg = registry.open(url)
    assert set(reg.cases()["case"]) == set(PICK)  # reading works
    assert reg.verify_db().ok
    with pytest.raises(DatabaseReadOnlyError) as info:  # refused before anything is done
        reg.add(CASES / "borisov-mamaev-1997.toml")
    assert str(info.value) == (
        f"role 'reader' may only read the registry at {url!r}, so it cannot add cases (it "
        "lacks INSERT on table audit_runs); nothing was changed. A maintainer can allow it: "
        "registry grant --writer reader"
    )
    result = CliRunner().invoke(main, ["--db", url, "add", str(CASES / "axis-torque.toml")])
    assert result.exit_code == 1
    (line,) = result.stderr.splitlines()
    assert line == f"Error: {info.value}"
    reg.close()


# SQLite only: the file's page limit stands for a full disk; PostgreSQL's "disk full"
# (SQLSTATE 53100) is mapped in test_engine.py, a real one would need a full filesystem
@pytest.mark.parametrize("backend", ["sqlite"], indirect=True)
def test_a_full_disk_stores_nothing_of_the_change(db, monkeypatch):
    def tiny(sa_engine, file_db):
        original(sa_engine, file_db)

        @event.listens_for(sa_engine, "connect")
        def _limit(dbapi_connection, _record):
            pages = dbapi_connection.execute("PRAGMA page_count").fetchone()[0]
            dbapi_connection.execute(f"PRAGMA max_page_count={pages + 1}")

    original = engine.configure_sqlite
    monkeypatch.setattr(engine, "configure_sqlite", tiny)
    reg = registry.open(db)
    before = dict(zip(reg.cases()["case"], reg.cases()["version"], strict=True))
    stored = []  # (case, version) of each add that succeeded before the disk filled up
    with pytest.raises(DatabaseFullError) as info:
        for path in sorted(CASES.glob("*.toml")):
            stored += [(r.case, r.version) for r in reg.add(path) if r.status != "unchanged"]
    assert str(info.value) == (
        f"the disk holding database {str(db)!r} is full; nothing of this change was "
        "stored (free some space and run the command again)"
    )
    reg.store.close()
    monkeypatch.undo()
    with Store(db) as store:
        assert verify(store).ok  # no half-written case
    after = registry.open(db).cases()
    assert dict(zip(after["case"], after["version"], strict=True)) == {**before, **dict(stored)}


# SQLite's write lock; PostgreSQL's lock timeout is the test after this one
@pytest.mark.parametrize("backend", ["sqlite"], indirect=True)
def test_a_locked_database_is_retried_then_reported(db, monkeypatch):
    monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, "0.1")
    monkeypatch.setattr(engine, "LOCK_ATTEMPTS", 2)
    reg = registry.open(db)
    holder = sqlite3.connect(db, isolation_level=None, check_same_thread=False)
    holder.execute("BEGIN IMMEDIATE")
    try:
        with pytest.raises(DatabaseLockedError) as info:
            reg.add(CASES / "axis-torque.toml")
        assert str(info.value) == (
            f"database {str(db)!r} is locked by another process (waited 0.2 s); "
            "run the command again when the other registry command has finished"
        )
        # a lock released while the registry retries is waited out
        monkeypatch.setattr(engine, "LOCK_ATTEMPTS", 20)
        threading.Timer(0.5, holder.rollback).start()
        assert reg.add(CASES / "axis-torque.toml")[0].status == "added"
    finally:
        holder.close()


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_a_lock_held_too_long_on_the_server_is_retried_then_reported(db, monkeypatch):
    monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, "0.1")
    monkeypatch.setattr(engine, "LOCK_ATTEMPTS", 2)
    reg = registry.open(db)
    with connection(db) as holder:  # another session keeps new case versions out
        holder.exec_driver_sql("LOCK TABLE cases IN SHARE ROW EXCLUSIVE MODE")
        with pytest.raises(DatabaseLockedError) as info:
            reg.add(CASES / "axis-torque.toml")
        assert str(info.value) == (
            f"database {db!r} is locked by another process (waited 0.2 s); "
            "run the command again when the other registry command has finished"
        )
        assert set(reg.cases()["case"]) == set(PICK)  # reading goes on meanwhile
    # a lock released while the registry retries is waited out
    monkeypatch.setattr(engine, "LOCK_ATTEMPTS", 20)
    with connection(db) as holder:
        holder.exec_driver_sql("LOCK TABLE cases IN SHARE ROW EXCLUSIVE MODE")
        threading.Timer(0.5, holder.get_transaction().rollback).start()
        assert reg.add(CASES / "axis-torque.toml")[0].status == "added"
    reg.close()


# ------------------------------------------------------------- interrupted runs


def insert_run(target: str, **values) -> int:
    """A run row written behind the registry's back; returns its number."""
    row = dict(
        started_at=datetime(2026, 1, 1, tzinfo=UTC), status="running", code_version="test",
        sympy_version="", python_version="", options={},
    )  # fmt: skip
    with connection(target) as conn:
        return conn.execute(insert(RunRow).values(**row, **values).returning(RunRow.id)).scalar()


def test_a_run_whose_process_died_is_marked_interrupted_on_the_next_start(db):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    reg = registry.open(db)
    alive = reg.store.start_run({}, "test")  # this process: alive
    reg.store.close()
    with connection(db) as conn:
        host = conn.execute(select(RunRow.host).where(RunRow.id == alive)).scalar()
    orphan = insert_run(db, host=host, pid=dead.pid, pid_started="1")
    runs = registry.open(db).runs().set_index("run")["status"]
    assert runs[orphan] == "interrupted"
    assert runs[alive] == "running"  # its process (this one) is alive
    assert runs[1] == "complete"


def test_a_run_on_another_host_is_left_alone(db):
    insert_run(db, host="elsewhere", pid=1)
    reg = registry.open(db)
    assert list(reg.runs()["status"]) == ["complete", "running"]
    assert verify(reg.store).notes == ("run 2 is still running (process 1 on elsewhere)",)


def test_an_interrupted_audit_in_process_is_recorded(db, monkeypatch):
    reg = registry.open(db)

    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(parallel, "audit_case", stop)
    with pytest.raises(KeyboardInterrupt):
        reg.audit([ZHUKOVSKY], fresh=True, jobs=1)
    assert list(reg.runs()["status"]) == ["complete", "interrupted"]


def test_a_signal_during_a_database_session_waits_for_its_end(db_target):
    import os
    import signal

    from registry.runs.interruption import interruptible as _interruptible

    store = Store(db_target)
    finished = False
    with pytest.raises(KeyboardInterrupt), _interruptible(store):
        with store.write():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.05)  # the handler runs here: it must not break the transaction
            finished = True
        pytest.fail("the interrupt should take effect as the session ends")
    assert finished
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # handlers restored
    with pytest.raises(KeyboardInterrupt), _interruptible(store):
        os.kill(os.getpid(), signal.SIGTERM)  # outside a session: at once
        time.sleep(1)
        pytest.fail("not interrupted")


def test_the_python_api_gives_the_same_verification(db):
    damage(db, "UPDATE check_results SET verdict = 'probably' WHERE id = 2")
    found = registry.open(db).verify_db()
    assert not found.ok
    assert found.problems == ("check_results row 2: unknown verdict 'probably'",)
    assert found.counts["case versions"] == 3
