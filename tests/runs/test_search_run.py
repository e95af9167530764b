"""A search run (``registry/runs/search_run.py``): a recorded search is reused by the
same options and code version, unless fresh; a search without a registry."""

from __future__ import annotations

from registry.execution.executor import InProcess
from registry.language.casefile import load_case
from registry.runs.search_run import SearchRequest, search_run, survey_run
from registry.store import frames
from registry.store.database import Store
from tests.helpers.samples import CASES

LAGRANGE = CASES / "heavy-top" / "lagrange-1788-heavy-top.toml"


def test_a_recorded_search_is_reused_unless_fresh(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    here = InProcess()
    first = search_run(store, LAGRANGE, SearchRequest(degree=2, record=True, budget=120), here)
    assert first.number is not None and not first.reused
    again = search_run(store, load_case(LAGRANGE).id, SearchRequest(degree=2, budget=120), here)
    assert again.reused and again.number == first.number and again.search == first.search
    fresh = search_run(store, LAGRANGE, SearchRequest(degree=2, fresh=True, budget=120), here)
    assert not fresh.reused and fresh.number is None
    assert fresh.search.generic == first.search.generic
    store.close()


def test_a_case_file_is_searched_without_a_registry():
    report = search_run(None, LAGRANGE, SearchRequest(degree=2, budget=120), InProcess())
    assert report.number is None and report.search.case == load_case(LAGRANGE).id
    # M3 is the Lagrange top's extra integral of degree 1 (weights M=1, gamma=2)
    assert report.document()["generic"]["extra"] >= 1


def test_a_search_is_combined_with_the_exponents_under_its_weights():
    """Lagrange's top to degree 2: Yoshida allows 1, 2, 3, 4 (its family of balances has
    the exponents -1, 0, 1, 2, 3, 4), so degrees 3 and 4 are named, not excluded."""
    report = search_run(None, LAGRANGE, SearchRequest(degree=2, budget=120), InProcess())
    assert report.exponents is not None and report.exponents.decided
    document = report.document()
    assert document["exponents"]["degrees"] == [1, 2, 3, 4]
    assert "integrals of degree 3, 4 with a gradient not zero at some balance are not " \
        "excluded" in document["every_degree"]  # fmt: skip
    assert report.text().splitlines()[-1].startswith("at every degree: Yoshida")
    on = search_run(None, LAGRANGE, SearchRequest(degree=2, on=("s = 0",), budget=120), InProcess())
    assert on.exponents is None and "on a level set" in on.document()["every_degree"]


def test_the_survey_records_each_case_s_exponents_once_and_reuses_them(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    store.add_case(load_case(LAGRANGE))
    here = InProcess()
    first = survey_run(store, None, here)
    assert {r.exponents.decided for r in first if r.exponents is not None} == {True}
    rows = frames.exponents_frame(store)
    assert len(rows) == 1 and rows.loc[0, "case"] == load_case(LAGRANGE).id
    again = survey_run(store, None, here)
    assert len(frames.exponents_frame(store)) == 1  # reused, not recorded twice
    assert again[0].exponents == first[0].exponents
    store.close()
