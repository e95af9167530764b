"""Opening a database: SQLite settings, where a path or URL leads, and each database
failure turned into the one-line StorageError of its kind."""

from __future__ import annotations

import pytest
from sqlalchemy import text
from sqlalchemy.exc import OperationalError

from registry.errors import (
    DatabaseFullError,
    DatabaseLockedError,
    DatabaseMissingError,
    DatabaseReadOnlyError,
    NotADatabaseError,
    StorageError,
)
from registry.store import engine, frames
from registry.store.database import Store


def test_file_store_uses_wal_and_foreign_keys(file_store, tmp_path):
    assert (tmp_path / "db" / "registry.sqlite").exists()  # parent folder created
    with file_store.engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert conn.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
        busy = conn.exec_driver_sql("PRAGMA busy_timeout").scalar()
        assert busy == engine.BUSY_TIMEOUT * 1000


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


def test_database_failure_after_opening_is_a_storage_error(memory_store):
    with memory_store.engine.begin() as conn:
        conn.execute(text("DROP VIEW latest_verdicts"))
    with pytest.raises(StorageError, match="no such table: latest_verdicts"):
        frames.verdicts_frame(memory_store)


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
