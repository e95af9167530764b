"""Tests of the registry database (registry.store), on SQLite (in memory and in a file)
and on PostgreSQL (fixtures ``store`` and ``db_target``)."""

from __future__ import annotations

import threading
from dataclasses import replace
from datetime import datetime

import pytest
from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from registry.errors import UnknownCaseError, UnknownRunError
from registry.model import CheckResult, Verdict
from registry.store import database, frames
from registry.store.database import AddOutcome, Store, StoredCase
from registry.store.tables import CaseRow, ClaimRow, ResultRow, SourceRow
from tests.helpers.stores import audit_of, count

# -------------------------------------------------------------------- opening


def test_reopening_a_database_keeps_its_content(db_target, sample_case):
    with Store(db_target) as store:
        store.add_case(sample_case)
    with Store(db_target, create=False) as store:
        assert store.case_ids() == [sample_case.id]
        assert store.add_case(sample_case).status == "unchanged"
        assert store.upgraded_from is None and store.backup is None


# SQLite only: a file's path and its sqlite:/// URL name the same database
def test_reopening_a_file_keeps_its_content(tmp_path, sample_case):
    path = str(tmp_path / "registry.sqlite")
    with Store(path) as store:
        store.add_case(sample_case)
    with Store(f"sqlite:///{path}") as store:
        assert store.case_ids() == [sample_case.id]
        assert store.add_case(sample_case).status == "unchanged"


# ---------------------------------------------------------------------- cases


def test_add_then_readd_is_unchanged(store, sample_case):
    first = store.add_case(sample_case)
    assert first == AddOutcome(sample_case.id, 1, "added")
    rows = {t: count(store, t) for t in (SourceRow, CaseRow, ClaimRow)}
    assert rows == {SourceRow: 1, CaseRow: 1, ClaimRow: 2}

    again = store.add_case(sample_case)
    assert again == AddOutcome(sample_case.id, 1, "unchanged")
    assert again.pk == first.pk
    assert {t: count(store, t) for t in rows} == rows


def test_changed_text_is_a_new_version_and_keeps_the_old(store, sample_case, case_factory):
    store.add_case(sample_case)
    changed = case_factory(text=sample_case.text + "# a correction\n")
    assert store.add_case(changed) == AddOutcome(sample_case.id, 2, "new version")
    assert store.add_case(changed).status == "unchanged"

    latest = store.case_versions()
    assert [(s.case_id, s.version) for s in latest] == [(sample_case.id, 2)]
    assert latest[0].text == changed.text
    every = store.case_versions([sample_case.id], latest_only=False)
    assert [s.version for s in every] == [1, 2]
    assert every[0].content_hash == sample_case.content_hash
    assert count(store, SourceRow) == 1  # same citation and DOI: one source
    assert count(store, ClaimRow) == 4  # each version has its own claims


def test_a_file_returning_to_older_content_becomes_the_newest_version(
    store, sample_case, case_factory
):
    store.add_case(sample_case)
    store.add_case(case_factory(text=sample_case.text + "# a correction\n"))
    reverted = store.add_case(sample_case)
    assert reverted == AddOutcome(sample_case.id, 3, "new version")
    (latest,) = store.case_versions([sample_case.id])
    assert latest.version == 3 and latest.content_hash == sample_case.content_hash


def test_stored_case_content(store, sample_case):
    store.add_case(sample_case)
    with Session(store.engine) as session:
        row = session.scalars(select(CaseRow)).one()
        claims = session.scalars(select(ClaimRow).order_by(ClaimRow.position)).all()
    assert row.inertia == ["C", "C", "2*C"]
    assert row.potential == "C*gamma3"
    assert row.torque == ["0", "0", "N*gamma3"]
    assert row.parameters == {"C": "positive", "N": "real"}
    assert row.functions == {}
    assert row.locator == "p. 1" and row.notes == "made in conftest"
    assert row.path == "data/cases/demo-2003-lagrange.toml"
    assert row.added_at.tzinfo is not None and row.added_at.utcoffset().total_seconds() == 0
    assert [(c.label, c.kind, c.expression, c.on) for c in claims] == [
        ("I1", "integral", "gamma3", []),
        ("I2", "casimir", "N*gamma1", ["gamma1**2 + gamma2**2 + gamma3**2 = 1"]),
    ]


def test_different_doi_is_a_different_source(store, case_factory):
    store.add_case(case_factory("a-1", "a"))
    store.add_case(case_factory("b-1", "b", doi="10.1000/xyz"))
    store.add_case(case_factory("c-1", "c"))
    assert count(store, SourceRow) == 2


def test_failed_claim_insert_stores_nothing(store, sample_case, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(database, "claim_row", broken)
    with pytest.raises(RuntimeError, match="disk on fire"):
        store.add_case(sample_case)
    assert {count(store, t) for t in (SourceRow, CaseRow, ClaimRow)} == {0}
    assert store.case_ids() == []


def test_constraint_violation_stores_nothing(store, sample_case):
    twice = replace(sample_case, claims=sample_case.claims + sample_case.claims[:1])
    with pytest.raises(IntegrityError):
        store.add_case(twice)
    assert {count(store, t) for t in (SourceRow, CaseRow, ClaimRow)} == {0}
    assert store.add_case(sample_case).status == "added"


def test_two_stores_adding_the_same_new_case_at_once_store_it_once(
    db_target, sample_case, case_factory
):
    """Each add reads the newest version and inserts the next one; two at once, in two
    connections, must take turns (SQLite's write lock, PostgreSQL's advisory locks)."""
    Store(db_target).close()  # the tables exist; the race is about the case
    rounds = [sample_case, case_factory(text="v2"), case_factory(text="v3")]
    for case in rounds:
        stores = [Store(db_target) for _ in range(2)]
        start = threading.Barrier(len(stores))
        outcomes: list[AddOutcome] = []

        def add(store: Store, case=case, start=start, outcomes=outcomes) -> None:
            start.wait()
            outcomes.append(store.add_case(case))

        threads = [threading.Thread(target=add, args=(s,)) for s in stores]
        for t in threads:
            t.start()
        for t in threads:
            t.join(timeout=60)
        for s in stores:
            s.close()
        assert sorted(o.status for o in outcomes) == sorted(
            ["added" if case is sample_case else "new version", "unchanged"]
        )
        assert len({o.pk for o in outcomes}) == 1  # both name the one stored version
    with Store(db_target) as store:
        every = store.case_versions([sample_case.id], latest_only=False)
        assert [s.version for s in every] == [1, 2, 3]
        assert count(store, SourceRow) == 1
        assert count(store, ClaimRow) == 6


def test_case_without_hash_is_refused(store, sample_case):
    with pytest.raises(ValueError, match="content_hash"):
        store.add_case(replace(sample_case, content_hash=""))


def test_case_ids_and_versions(store, sample_case, other_case):
    store.add_case(sample_case)
    store.add_case(other_case)
    assert store.case_ids() == sorted([sample_case.id, other_case.id])
    chosen = store.case_versions([sample_case.id, other_case.id, sample_case.id])
    assert [s.case_id for s in chosen] == [sample_case.id, other_case.id]
    assert all(isinstance(s, StoredCase) for s in chosen)


def test_unknown_case_id(store, sample_case):
    store.add_case(sample_case)
    with pytest.raises(UnknownCaseError) as info:
        store.case_versions(["demo-2003-lagrang"])
    assert info.value.known == [sample_case.id]
    assert "did you mean" in str(info.value)


# ----------------------------------------------------------------------- runs


def test_run_round_trip(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    run = store.start_run({"fresh": True, "cases": [sample_case.id]}, code_version="abc123")
    audit = audit_of(sample_case, stored, integral=Verdict.REFUTED)
    store.record_case(run, stored.pk, audit)
    store.finish_run(run)

    assert store.run_results(run) == [(sample_case.id, audit)]
    witness = store.run_results(run)[0][1].result("integral", "I1").witness
    assert witness == audit.result("integral", "I1").witness
    assert store.stored_audit(stored.pk) == (run, audit)
    assert store.stored_audit(stored.pk, code_version="other") is None

    runs = frames.runs_frame(store)
    assert len(runs) == 1
    row = runs.iloc[0]
    assert (row["run"], row["status"], row["code_version"]) == (run, "complete", "abc123")
    assert (row["n_results"], row["n_refuted"], row["n_verified"], row["n_cases"]) == (4, 2, 2, 1)
    assert row["sympy_version"] and row["python_version"]
    assert row["options"] == {"fresh": True, "cases": [sample_case.id]}
    assert row["finished_at"] >= row["started_at"]
    assert isinstance(row["started_at"], datetime) and row["started_at"].tzinfo is not None


def test_run_status_and_errors(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    run = store.start_run({}, code_version="x")
    assert frames.runs_frame(store).iloc[0]["status"] == "running"
    assert frames.runs_frame(store).iloc[0]["finished_at"] is None
    with pytest.raises(ValueError, match="cannot finish"):
        store.finish_run(run, "running")
    store.finish_run(run, "interrupted")
    assert frames.runs_frame(store).iloc[0]["status"] == "interrupted"
    with pytest.raises(ValueError, match="interrupted"):
        store.record_case(run, stored.pk, audit_of(sample_case, stored))
    for call in (
        lambda: store.finish_run(99),
        lambda: store.run_results(99),
        lambda: frames.verdicts_frame(store, 99),
        lambda: store.record_case(99, stored.pk, audit_of(sample_case, stored)),
    ):
        with pytest.raises(UnknownRunError, match="99"):
            call()


def test_record_case_rejects_unknown_label_and_stores_nothing(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    run = store.start_run({}, code_version="x")
    good = audit_of(sample_case, stored)
    bad = CheckResult("integral", Verdict.VERIFIED, "exact probe", claim="I9")
    with pytest.raises(ValueError, match="I9"):
        store.record_case(run, stored.pk, replace(good, results=good.results + (bad,)))
    assert count(store, ResultRow) == 0
    with pytest.raises(ValueError, match="does not match"):
        store.record_case(run, stored.pk, replace(good, content_hash="0" * 64))


def test_claim_results_belong_to_the_audited_version(store, sample_case, case_factory):
    store.add_case(sample_case)
    store.add_case(case_factory(text="v2"))
    v1, v2 = store.case_versions(latest_only=False)
    run = store.start_run({}, code_version="x")
    store.record_case(run, v1.pk, audit_of(sample_case, v1))
    with Session(store.engine) as session:
        pairs = session.execute(
            select(ResultRow.case_pk, ClaimRow.case_pk).join(
                ClaimRow, ClaimRow.id == ResultRow.claim_id
            )
        ).all()
    assert pairs and all(result == claim == v1.pk for result, claim in pairs)
    assert set(frames.verdicts_frame(store, run)["version"]) == {1}


def test_a_renamed_case_is_found_under_its_old_id(store, case_factory):
    old = case_factory("demo-2003-lagrange", 'id = "demo-2003-lagrange"\n')
    store.add_case(old)
    renamed = replace(
        case_factory("author-2003-lagrange-top", 'id = "author-2003-lagrange-top"\n'),
        aliases=("demo-2003-lagrange", "lagrange-old"),
    )
    store.add_case(renamed)
    # an id that is still stored is itself; an alias only names the renamed case
    (same,) = store.case_versions(["demo-2003-lagrange"])
    assert same.case_id == "demo-2003-lagrange"
    (found,) = store.case_versions(["lagrange-old"])
    assert found.case_id == "author-2003-lagrange-top"
    with pytest.raises(UnknownCaseError):
        store.case_versions(["never-was"])


def test_sources_keep_their_structured_citation_and_later_cases_fill_it(store, case_factory):
    bare = case_factory("demo-1999-a", 'id = "demo-1999-a"\n')
    store.add_case(bare)
    detailed = case_factory("demo-1999-b", 'id = "demo-1999-b"\n')
    source = replace(detailed.source, authors=("A. Author",), year=2003, volume="8", pages="1-10")
    store.add_case(replace(detailed, source=source))
    with store.read() as session:
        (row,) = session.scalars(select(SourceRow)).all()
        assert (row.authors, row.year, row.volume, row.pages) == (["A. Author"], 2003, "8", "1-10")
