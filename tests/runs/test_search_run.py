"""A search run (``registry/runs/search_run.py``): a recorded search is reused by the
same options and code version, unless fresh; a search without a registry."""

from __future__ import annotations

from registry.execution.executor import InProcess
from registry.language.casefile import load_case
from registry.runs.search_run import SearchRequest, search_run
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
