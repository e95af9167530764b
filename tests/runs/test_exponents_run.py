"""An exponent analysis run (``registry/runs/exponents_run.py``): a recorded analysis is
reused by the same options and code version, unless fresh; every recorded analysis is a
new row; an analysis without a registry."""

from __future__ import annotations

import registry
from registry.execution.executor import InProcess
from registry.language.casefile import load_case
from registry.runs.exponents_run import ExponentRequest, exponents_run
from registry.store.database import Store
from tests.helpers.samples import CLASSICAL, TEST_DATA

KOVALEVSKAYA = CLASSICAL / "kovalevskaya-top.toml"


def test_a_recorded_analysis_is_reused_unless_fresh_and_history_is_kept(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    here = InProcess()
    first = exponents_run(store, KOVALEVSKAYA, ExponentRequest(record=True), here)
    assert first.number is not None and not first.reused
    case_id = load_case(KOVALEVSKAYA).id
    again = exponents_run(store, case_id, ExponentRequest(), here)
    assert again.reused and again.number == first.number
    assert again.result.document == first.result.document
    assert again.document()["analysis"] == first.number and again.document()["reused"]
    fresh = exponents_run(store, case_id, ExponentRequest(fresh=True, record=True), here)
    assert not fresh.reused and fresh.number == first.number + 1  # a new row, the old kept
    other = exponents_run(store, case_id, ExponentRequest(weights={"gamma": 1}), here)
    assert not other.reused and other.result.options.weights == (("M", 1), ("gamma", 1))
    store.close()


def test_a_case_file_is_analysed_without_a_registry():
    report = exponents_run(None, KOVALEVSKAYA, ExponentRequest(), InProcess())
    assert report.number is None and report.result.case == load_case(KOVALEVSKAYA).id
    assert report.result.all_integer and report.result.passes
    assert "analysis" not in report.document()
    assert report.text().splitlines()[0] == (
        "test-kovalevskaya-top: Kovalevskaya exponents (weights M=1,gamma=2)"
    )


def test_an_analysis_that_ran_out_of_time_is_made_again_with_a_larger_budget(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    here = InProcess()
    short = exponents_run(store, KOVALEVSKAYA, ExponentRequest(budget=1e-6, record=True), here)
    assert not short.result.decided and short.result.document["budget"] == 1e-6
    case_id = load_case(KOVALEVSKAYA).id
    same = exponents_run(store, case_id, ExponentRequest(budget=1e-6), here)
    assert same.reused and same.number == short.number
    longer = exponents_run(store, case_id, ExponentRequest(budget=120, record=True), here)
    assert not longer.reused and longer.result.decided and longer.number == short.number + 1
    assert exponents_run(store, case_id, ExponentRequest(budget=1e-6), here).reused
    store.close()


def test_a_witnessed_failure_is_recorded_as_failing_and_nothing_else(tmp_path):
    """Out of time with a witness (``exponent_witness``): the stored analysis is not
    decided, its Painlevé column says fails, and its document comes back whole."""
    path = TEST_DATA / "exponents" / "heavy-top-centre-a.toml"
    with registry.open(tmp_path / "r.sqlite") as reg:
        report = reg.analyse_exponents(path, budget=8, record=True, jobs=1)
        assert "witness" in report.result.document
        row = reg.exponents().iloc[-1]
        assert (row["case"], bool(row["decided"]), row["painleve"]) == (
            "test-heavy-top-centre-a",
            False,
            False,
        )
        again = reg.analyse_exponents("test-heavy-top-centre-a", budget=8)
        assert again.reused and again.result.document == report.result.document
        assert again.result.passes is False
