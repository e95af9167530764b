"""The tables and the view: the schema version they record, foreign keys enforced by
the database, and the ``latest_verdicts`` view usable from plain SQL, on SQLite and on
PostgreSQL (fixture ``store``); names that fit PostgreSQL's 63 bytes."""

from __future__ import annotations

import pytest
from sqlalchemy import insert, inspect, text
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from registry.store import tables
from registry.store.tables import ResultRow, RunRow
from tests.helpers.stores import audit_of, count


def test_a_store_has_schema_version(store):
    with store.engine.connect() as conn:
        value = conn.scalar(text("SELECT value FROM meta WHERE key = 'schema_version'"))
    assert value == str(tables.SCHEMA_VERSION) == "12"


def test_foreign_keys_are_enforced(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    with pytest.raises(IntegrityError), store.engine.begin() as conn:
        conn.execute(
            insert(ResultRow).values(
                run_id=12345, case_pk=stored.pk, check="jacobi", verdict="verified",
                method="m", reason="", seconds=0.0,
            )
        )  # fmt: skip
    assert count(store, ResultRow) == 0
    assert count(store, RunRow) == 0


def test_view_is_queryable_with_plain_sql(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    run = store.start_run({}, code_version="x")
    store.record_case(run, stored.pk, audit_of(sample_case, stored))
    with store.engine.connect() as conn:
        rows = conn.execute(
            text('SELECT "case", claim, "check", verdict FROM latest_verdicts ORDER BY result')
        ).all()
    assert rows[0] == (sample_case.id, None, "jacobi", "verified")
    assert rows[-1] == (sample_case.id, "I2", "integral", "verified")


def test_the_orm_tables_are_the_registry_tables():
    names = set(tables.Base.metadata.tables)
    assert names == {
        "identifications",
        "meta",
        "sources",
        "cases",
        "claims",
        "audit_runs",
        "check_results",
        "corrections",
        "evidence",
        "drift_curves",
        "case_aliases",
        "searches",
        "discoveries",
        "exponents",
    }
    assert tables.latest_verdicts.name == tables.VIEW_NAME == "latest_verdicts"
    assert tables.RUN_STATUSES[0] == "running"


def test_every_name_fits_postgresql(store):
    """PostgreSQL cuts identifiers at 63 bytes (with a mere notice): every table, column,
    index and constraint name the schema uses must fit, as the database reports them."""
    names = {tables.VIEW_NAME}
    for table in tables.Base.metadata.tables.values():
        names |= {table.name, *(c.name for c in table.columns)}
        names |= {i.name for i in table.indexes}
    with store.engine.connect() as conn:
        found = inspect(conn)
        for table in found.get_table_names():
            names |= {i["name"] for i in found.get_indexes(table)}
            names |= {k["name"] for k in found.get_foreign_keys(table) if k["name"]}
            names |= {u["name"] for u in found.get_unique_constraints(table) if u["name"]}
    too_long = sorted(n for n in names if len(n.encode()) > 63)
    assert too_long == []
    assert {i.name for t in tables.Base.metadata.tables.values() for i in t.indexes} <= names


def test_times_are_stored_aware_in_utc(store, sample_case):
    run = store.start_run({}, code_version="x")
    with Session(store.engine) as session:
        started = session.get(RunRow, run).started_at
    assert started.tzinfo is not None and started.utcoffset().total_seconds() == 0
