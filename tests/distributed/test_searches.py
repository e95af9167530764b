"""Integral searches on a Dask cluster: the candidate sets of the rank-drop locus are
searched on the workers and the search is the one made locally; a candidate that
cannot be searched there is named in the coverage, never dropped in silence."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import pytest

import registry
from registry.discovery.search import _label, discover, search_options
from registry.execution.executor import DaskCluster, LocalPool
from registry.execution.serving import Failure
from tests.helpers.samples import FAMILIES, family


def same(one, two) -> bool:
    """Two searches with the same outcome (not the same running time)."""
    return replace(one, seconds=0.0) == replace(two, seconds=0.0)


def nap(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


@pytest.mark.slow  # three-parameter search on the cluster and locally: a minute when loaded
def test_the_candidate_sets_searched_on_the_cluster_give_the_local_search(process_cluster):
    case = family("heavy-top-lam-z0")
    options = search_options(case, degree=4, free=("lam", "z0"))
    here = discover(case, options, budget=300)
    in_processes = discover(case, options, budget=300, executor=LocalPool(2))
    seen = []
    cluster = DaskCluster(process_cluster, "test")
    on_cluster = discover(
        case,
        options,
        budget=300,
        executor=cluster,
        progress=lambda done, total, where: seen.append((done, total, where)),
    )
    events = cluster.events
    assert same(on_cluster, here) and same(on_cluster, in_processes)
    assert on_cluster.complete
    assert {s.when for s in on_cluster.special} == {("lam = 1",), ("lam = 2", "z0 = 0")}
    # every candidate set went through the cluster, reported in the candidates' order
    assert [done for done, _, _ in seen] == list(range(len(seen))) and len(seen) >= 2
    assert events == []


def test_a_call_past_its_deadline_comes_back_as_a_failure(process_cluster):
    found = dict(DaskCluster(process_cluster, "test").map(nap, [0.0, 30.0], deadline=1.0))
    assert found[0] == 0.0
    assert isinstance(found[1], Failure) and found[1].kind == "killed"
    assert found[1].worker.startswith("tcp://127.0.0.1:")
    assert found[1].reason.endswith("deadline of 1 s exceeded; child process killed")


def test_candidates_are_named_by_their_equations():
    assert _label(("state", "case", [], ("lam = 2", "z0 = 0"), {})) == "lam = 2, z0 = 0"


def test_registry_discover_with_a_scheduler_records_the_same_search(tmp_path, process_cluster):
    path = FAMILIES / "heavy-top-lam-z0.toml"
    local = registry.open(tmp_path / "local.sqlite")
    on_dask = registry.open(tmp_path / "dask.sqlite")
    options = dict(degree=4, free=("lam", "z0"), record=True)
    expected = local.discover(path, **options)
    got = on_dask.discover(path, scheduler=process_cluster, **options)
    assert same(got.search, expected.search)
    assert got.derived == expected.derived and len(got.derived) == 2
    assert got.events == () and "events" not in got.document()
    assert got.number == expected.number == 1
    columns = ["case", "complete", "statement"]
    assert on_dask.searches()[columns].equals(local.searches()[columns])


def test_the_survey_on_the_cluster_records_what_local_processes_record(process_cluster, tmp_path):
    cases = Path(__file__).resolve().parents[2] / "data" / "cases"
    files = [
        cases / "heavy-top" / "goryachev-1916-heavy-top.toml",
        cases / "heavy-top" / "lagrange-1788-heavy-top.toml",
        cases / "gyroscopic-torque" / "birtea-2011-radial-torque.toml",
    ]
    found = {}
    for where, options in (("local", {"jobs": 2}), ("cluster", {"scheduler": process_cluster})):
        with registry.open(tmp_path / f"{where}.sqlite") as reg:
            reg.add(*files)
            found[where] = [r.search for r in reg.survey(**options)]
            assert all(r.reused for r in reg.survey(**options))  # stored, then reused
    assert len(found["cluster"]) == 4
    assert all(same(a, b) for a, b in zip(found["cluster"], found["local"], strict=True))
    assert [s.decided for s in found["cluster"]] == [False, True, True, True]
