"""A search run (``registry/runs/search_run.py``): a recorded search is reused by the
same options and code version, unless fresh; a search without a registry."""

from __future__ import annotations

from registry.language.casefile import load_case
from registry.runs.search_run import discover_file, search_run
from registry.store.database import Store
from tests.helpers.samples import CASES

LAGRANGE = CASES / "heavy-top" / "lagrange-1788-heavy-top.toml"


def test_a_recorded_search_is_reused_unless_fresh(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    first = search_run(store, LAGRANGE, degree=2, record=True, budget=120)
    assert first.number is not None and not first.reused
    again = search_run(store, load_case(LAGRANGE).id, degree=2, budget=120)
    assert again.reused and again.number == first.number and again.search == first.search
    fresh = search_run(store, LAGRANGE, degree=2, fresh=True, budget=120)
    assert not fresh.reused and fresh.number is None
    assert fresh.search.generic == first.search.generic
    store.close()


def test_a_case_file_is_searched_without_a_registry():
    report = discover_file(LAGRANGE, degree=2, budget=120)
    assert report.number is None and report.search.case == load_case(LAGRANGE).id
    # M3 is the Lagrange top's extra integral of degree 1 (weights M=1, gamma=2)
    assert report.document()["generic"]["extra"] >= 1
