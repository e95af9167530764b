"""Opening a database: SQLite and PostgreSQL settings, where a path or URL leads, and
each database failure turned into the one-line StorageError of its kind.

The tests about SQLite files (WAL, folders, files that are no database) are SQLite's
own; their PostgreSQL counterparts are a server that is not running, a database the
server does not have, an empty database that reading leaves empty, and roles without
the privileges the registry needs, each against the tests' real server.
"""

from __future__ import annotations

import sqlite3
import threading

import pytest
from click.testing import CliRunner
from sqlalchemy import text
from sqlalchemy.exc import OperationalError

from registry import settings
from registry.cli import main
from registry.errors import (
    DatabaseFullError,
    DatabaseLockedError,
    DatabaseMissingError,
    DatabasePermissionError,
    DatabaseReadOnlyError,
    NotADatabaseError,
    ServerDatabaseMissingError,
    ServerUnavailableError,
    SettingError,
    StorageError,
)
from registry.store import engine, frames
from registry.store.database import Store
from tests.helpers.databases import POSTGRES, rows
from tests.helpers.samples import CASES, ZHUKOVSKY


def test_file_store_uses_wal_and_foreign_keys(file_store, tmp_path):
    assert (tmp_path / "db" / "registry.sqlite").exists()  # parent folder created
    with file_store.engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert conn.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
        busy = conn.exec_driver_sql("PRAGMA busy_timeout").scalar()
        assert busy == settings.lock_timeout() * 1000


def test_the_wait_for_a_lock_comes_from_the_environment_where_set(tmp_path, monkeypatch):
    monkeypatch.delenv(settings.LOCK_TIMEOUT_ENV, raising=False)
    assert settings.lock_timeout() == settings.DEFAULT_LOCK_TIMEOUT == 10.0
    monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, "2.5")
    with Store(tmp_path / "r.sqlite") as store, store.engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA busy_timeout").scalar() == 2500
    for bad in ("soon", "0", "-1", "inf", "nan"):
        monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, bad)
        with pytest.raises(SettingError) as caught:
            settings.lock_timeout()
        assert str(caught.value) == (
            f"$REGISTRY_LOCK_TIMEOUT must be a positive number of seconds, not {bad!r} "
            "(unset it for the built-in default)"
        )


def test_the_switch_to_wal_waits_for_another_process_that_holds_the_new_file(tmp_path, monkeypatch):
    """SQLite refuses the switch to WAL at once, without its busy timeout, while another
    process switches the same new file (two ``registry add`` on a new database): the
    switch is retried until the lock timeout. Here a second connection holds the file
    exclusively for a moment and SQLite's own wait is off, so only the retry waits."""
    monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, "5")
    path = tmp_path / "new.sqlite"
    holder = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    holder.execute("BEGIN EXCLUSIVE")
    timer = threading.Timer(0.3, holder.execute, ("COMMIT",))
    timer.start()
    switcher = sqlite3.connect(path, isolation_level=None)
    switcher.execute("PRAGMA busy_timeout=0")
    try:
        engine._switch_to_wal(switcher.cursor())
        assert switcher.execute("PRAGMA journal_mode").fetchone() == ("wal",)
    finally:
        timer.join()
        switcher.close()
        holder.close()


def test_a_switch_to_wal_still_refused_after_the_lock_timeout_is_reported(tmp_path, monkeypatch):
    monkeypatch.setenv(settings.LOCK_TIMEOUT_ENV, "0.2")
    path = tmp_path / "held.sqlite"
    holder = sqlite3.connect(path, isolation_level=None)
    holder.execute("BEGIN EXCLUSIVE")
    switcher = sqlite3.connect(path, isolation_level=None)
    switcher.execute("PRAGMA busy_timeout=0")
    try:
        with pytest.raises(sqlite3.OperationalError, match="locked"):
            engine._switch_to_wal(switcher.cursor())
        holder.close()
        assert switcher.execute("PRAGMA journal_mode").fetchone() == ("delete",)
    finally:
        switcher.close()
        holder.close()


def test_directory_path_is_a_storage_error(tmp_path):
    with pytest.raises(StorageError) as info:
        Store(tmp_path)
    expected = f"{str(tmp_path)!r} is not a usable registry database (it is a folder)"
    assert str(info.value) == expected
    assert "\n" not in str(info.value)


def test_file_that_is_not_a_database_is_a_storage_error(tmp_path):
    junk = tmp_path / "notes.sqlite"
    junk.write_bytes(b"this is not a database\n" * 100)
    with pytest.raises(StorageError, match="not a database") as info:
        Store(junk)
    assert str(junk) in str(info.value)


def test_bad_url_is_a_storage_error():
    with pytest.raises(StorageError):
        Store("nosuchdialect://host/db")


def test_database_failure_after_opening_is_a_storage_error(store):
    with store.engine.begin() as conn:
        conn.execute(text("DROP VIEW latest_verdicts"))
    said = {"sqlite": "no such table: latest_verdicts"}
    said["postgresql"] = 'relation "latest_verdicts" does not exist'
    with pytest.raises(StorageError) as info:
        frames.verdicts_frame(store)
    assert str(info.value) == f"database {store.location!r}: {said[store.engine.dialect.name]}"


def test_a_path_url_or_memory_resolves_to_a_sqlalchemy_url(tmp_path):
    url, name = engine.resolve(":memory:", create=False)
    assert engine.is_memory(url) and name == ":memory:"
    url, name = engine.resolve("sqlite:///" + str(tmp_path / "x.sqlite"), create=False)
    assert url.get_backend_name() == "sqlite" and not engine.is_memory(url)
    url, name = engine.resolve(tmp_path / "sub" / "r.sqlite", create=True)
    assert name == str(tmp_path / "sub" / "r.sqlite") and (tmp_path / "sub").is_dir()
    with pytest.raises(DatabaseMissingError):
        engine.resolve(tmp_path / "absent.sqlite", create=False)


@pytest.mark.parametrize(
    ("reported", "kind"),
    [
        ("database is locked", DatabaseLockedError),
        ("attempt to write a readonly database", DatabaseReadOnlyError),
        ("database or disk is full", DatabaseFullError),
        ("file is not a database", NotADatabaseError),
        ("something else", StorageError),
    ],
)
def test_each_failure_sqlite_reports_is_its_storage_error(reported, kind):
    failure = OperationalError("statement", {}, Exception(reported))
    error = engine.storage_error(failure, "r.sqlite")
    assert type(error) is kind
    assert "r.sqlite" in str(error)


# ---------------------------------------------------------------------- PostgreSQL


def invoke(target: str, *args: str):
    return CliRunner().invoke(main, ["--db", target, *args])


def test_a_postgresql_url_uses_psycopg_and_never_shows_a_password():
    url, name = engine.resolve("postgresql://reg@/registry?host=/run/pg", create=False)
    assert url.drivername == "postgresql+psycopg" and engine.is_server(url)
    assert name == "postgresql://reg@/registry?host=/run/pg"  # as the user wrote it
    url, name = engine.resolve("postgresql+psycopg://reg:secret@db.example/registry", False)
    assert url.password == "secret" and "secret" not in name and "***" in name
    assert not engine.is_server(engine.resolve(":memory:", create=False)[0])


@POSTGRES
def test_the_server_settings_of_a_registry_session(postgres_server):
    url = postgres_server.create_database("settings") + "&options=-c%20work_mem%3D8MB"
    with Store(url) as store, store.engine.connect() as conn:
        shown = {
            name: conn.exec_driver_sql(f"SHOW {name}").scalar()
            for name in ("lock_timeout", "TimeZone", "application_name", "work_mem")
        }
    assert shown == {
        "lock_timeout": f"{settings.lock_timeout():g}s",
        "TimeZone": "UTC",
        "application_name": "registry",
        "work_mem": "8MB",  # the URL's own options are kept
    }


@POSTGRES
def test_a_server_that_is_not_running_is_one_error_line(postgres_server, tmp_path):
    url = f"postgresql+psycopg://registry@/registry?host={tmp_path}"  # no server there
    expected = (
        f"cannot reach the database server of {url!r} (connection to server on socket "
        f'"{tmp_path}/.s.PGSQL.5432" failed: No such file or directory); is the PostgreSQL '
        "server running, and are the host and socket folder in the URL right?"
    )
    with pytest.raises(ServerUnavailableError) as info:
        Store(url)
    assert str(info.value) == expected
    for command in (["cases"], ["add", str(CASES / f"{ZHUKOVSKY}.toml")], ["verify-db"]):
        result = invoke(url, *command)
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [f"Error: {expected}"]


@POSTGRES
def test_a_database_the_server_does_not_have_is_never_created(postgres_server):
    url = postgres_server.missing_database("absent")
    name = url.split("@/")[1].split("?")[0]
    expected = (
        f"the database server of {url!r} has no database {name!r}; creating one is the "
        f"server administrator's job (for example: createdb {name}), then 'registry add "
        "FILES' creates the registry's tables in it"
    )
    for create in (False, True):
        with pytest.raises(ServerDatabaseMissingError) as info:
            Store(url, create=create)
        assert str(info.value) == expected
        assert isinstance(info.value, DatabaseMissingError)
    for command in (["cases"], ["add", str(CASES / f"{ZHUKOVSKY}.toml")], ["audit"]):
        result = invoke(url, *command)
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [f"Error: {expected}"]
    with postgres_server.connect() as conn:
        names = [r[0] for r in conn.execute("SELECT datname FROM pg_database")]
    assert name not in names


@POSTGRES
def test_reading_an_empty_server_database_leaves_it_empty_and_add_fills_it(postgres_server):
    url = postgres_server.create_database("empty")
    tables = "SELECT count(*) FROM information_schema.tables WHERE table_schema = 'public'"
    for command in (["cases"], ["runs"], ["verify-db"], ["audit"]):
        result = invoke(url, *command)
        assert result.exit_code == 1
        assert result.stderr.splitlines() == [
            f"Error: no registry database at {url!r}; create one by adding cases "
            "(registry add FILES) or name another with --db"
        ]
    assert rows(url, tables) == [(0,)]
    added = invoke(url, "add", str(CASES / f"{ZHUKOVSKY}.toml"))
    assert added.exit_code == 0, added.output
    assert rows(url, tables)[0][0] > 0
    listed = invoke(url, "cases")
    assert listed.exit_code == 0 and ZHUKOVSKY in listed.stdout


@POSTGRES
@pytest.mark.parametrize(
    ("role", "grant", "said"),
    [
        ("nobody", None, 'role "nobody" does not exist'),
        ("outsider", "REVOKE CONNECT ON DATABASE {db} FROM PUBLIC", "permission denied for "
         'database "{db}"'),
        ("guest", "", "permission denied for schema public"),
    ],
)  # fmt: skip
def test_a_role_without_the_privileges_is_told_so(postgres_server, role, grant, said):
    url = postgres_server.create_database(f"roles {role}")
    db = url.split("@/")[1].split("?")[0]
    if grant is not None:
        postgres_server.execute(f"CREATE ROLE {role} LOGIN")
        if grant:
            postgres_server.execute(grant.format(db=db))
    as_role = url.replace("//registry@", f"//{role}@")
    expected = (
        f"the database server of {as_role!r} refuses role {role!r}: {said.format(db=db)}; "
        "ask the server's administrator to grant the privileges the registry needs"
    )
    with pytest.raises(DatabasePermissionError) as info:
        Store(as_role)  # creating the tables (guest may connect, not create)
    assert str(info.value) == expected
    result = invoke(as_role, "add", str(CASES / f"{ZHUKOVSKY}.toml"))
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"Error: {expected}"]


def _psycopg_error(sqlstate: str | None, message: str) -> Exception:
    psycopg = pytest.importorskip("psycopg")
    kind = psycopg.OperationalError if sqlstate is None else psycopg.errors.lookup(sqlstate)
    return kind(message)


@pytest.mark.parametrize(
    ("sqlstate", "reported", "kind"),
    [
        ("55P03", "canceling statement due to lock timeout", DatabaseLockedError),
        ("40P01", "deadlock detected", DatabaseLockedError),
        ("40001", "could not serialize access due to concurrent update", DatabaseLockedError),
        ("53100", 'could not extend file "base/16384/2619": No space left on device',
         DatabaseFullError),
        ("42501", "permission denied for table cases", DatabasePermissionError),
        ("25006", "cannot execute INSERT in a read-only transaction", DatabaseReadOnlyError),
        ("57P01", "terminating connection due to administrator command", ServerUnavailableError),
        ("53300", "sorry, too many clients already", ServerUnavailableError),
        ("3D000", 'database "registry" does not exist', ServerDatabaseMissingError),
        (None, 'connection failed: connection to server on socket "/x/.s.PGSQL.5432" failed: '
         'FATAL:  database "registry" does not exist', ServerDatabaseMissingError),
        (None, 'connection failed: connection to server on socket "/x/.s.PGSQL.5432" failed: '
         'FATAL:  password authentication failed for user "reg"', DatabasePermissionError),
        (None, "connection is bad: connection to server at \"db.example\" (192.0.2.1), port "
         "5432 failed: Connection refused", ServerUnavailableError),
        ("XX000", "something else", StorageError),
    ],
)  # fmt: skip
def test_each_failure_postgresql_reports_is_its_storage_error(sqlstate, reported, kind):
    failure = OperationalError("statement", {}, _psycopg_error(sqlstate, reported))
    error = engine.storage_error(failure, "postgresql+psycopg://reg@/registry")
    assert type(error) is kind
    assert "'postgresql+psycopg://reg@/registry'" in str(error)
    assert "\n" not in str(error)
