"""A search run (``registry/runs/search_run.py``): a recorded search is reused by the
same options and code version, unless fresh; a search without a registry."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import SimpleNamespace

from registry.execution.executor import InProcess
from registry.language.casefile import load_case
from registry.model import ExponentOptions, ExponentResult
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
    assert "\nat every degree: Yoshida" in report.text(width=80)
    assert max(len(line) for line in report.text(width=80).splitlines()) <= 80
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


def _main_job():
    """scripts/audit.py, the main job, as a module."""
    path = Path(__file__).resolve().parents[2] / "scripts" / "audit.py"
    spec = importlib.util.spec_from_file_location("main_job", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_main_job_sums_up_the_analyses_in_one_line():
    """Lagrange's top: Yoshida allows the degrees 1, 2, 3, 4, so a complete search to
    degree 2 leaves 3 and 4 open and one to degree 4 covers them all."""
    here = InProcess()
    reports = [
        search_run(None, LAGRANGE, SearchRequest(degree=k, budget=120), here) for k in (2, 4)
    ]
    assert [r.search.complete for r in reports] == [True, True]
    assert [r.bounded for r in reports] == [False, True]
    assert _main_job().exponents_line(reports) == (
        "1 Kovalevskaya analyses: 1 decided, 1 passing the ARS test; of the others, 0 failing "
        "it for generic values (a witness at rational values); 1 case(s) with every degree "
        "Yoshida allows searched; see reg.exponents()"
    )


def test_the_main_job_counts_a_test_not_made_as_not_passing():
    """An analysis whose Painlevé test was not made (passes None) is decided but does not
    pass; the line is still written (a sum over None would raise). An analysis out of
    time counts as failing only where it found a witness."""
    options = ExponentOptions((("M", 1), ("gamma", 2)))
    made = {True: "a", None: "b", False: "c"}
    documents = [(case, {"painleve": {"passes": verdict}}) for verdict, case in made.items()]
    failing = {"passes": False, "compatible": None, "conditions": []}
    documents += [
        ("d", {"decided": False, "painleve": failing, "witness": {}}),
        ("e", {"decided": False, "painleve": failing}),
        ("f", {"decided": False, "reason": "time budget exceeded"}),
    ]
    reports = [
        SimpleNamespace(
            search=SimpleNamespace(case=case),
            exponents=ExponentResult(case, "h", options, document),
            bounded=False,
        )
        for case, document in documents
    ]
    assert (
        _main_job()
        .exponents_line(reports)
        .startswith(
            "6 Kovalevskaya analyses: 3 decided, 1 passing the ARS test; of the others, 1 failing "
            "it for generic values (a witness at rational values); 0 case(s)"
        )
    )


def test_a_family_search_among_other_parameters_gets_the_generic_exponents():
    """Euler's body searched with A free: B and C are neither free nor fixed, so the
    exponents beside it are those for generic A, B, C (a family's analysis needs every
    parameter of the field free or fixed), and the statement says so."""
    euler = CASES / "free-rigid-body" / "euler-1765-free-rigid-body.toml"
    request = SearchRequest(degree=2, free=("A",), budget=120)
    report = search_run(None, euler, request, InProcess())
    assert report.exponents is not None and report.exponents.decided
    assert report.exponents.options.free == ()
    assert report.exponents.document["degrees"] == [1, 2, 3]
    assert "(for generic values of A, B, C)" in report.every_degree
    assert "a complete search to degree 3 would cover every degree Yoshida allows" in (
        report.every_degree
    )
