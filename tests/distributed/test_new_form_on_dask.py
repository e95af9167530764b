"""Cases in the Hamiltonian form, on so(4) and so(3,1) (issue 20), on a Dask cluster:
the audit and the search are the local ones, verdict by verdict."""

from __future__ import annotations

from dataclasses import replace

import pytest

import registry
from registry.discovery.search import discover, search_options
from registry.execution.executor import DaskCluster
from registry.execution.time_budget import TimeBudget
from registry.language.casefile import parse_case_text
from registry.model import Verdict
from tests.helpers.samples import HAMILTONIAN

#: Generous budgets: the comparisons are of verdicts, not of a busy machine's speed.
PATIENT = TimeBudget(check=60.0, corrections=120.0, margin=30.0)

SO4_FAMILY = """\
id = "so4-family"
title = "H = M1^2 + M2^2 + a M3^2 + 2 gamma1 on so(4)"
[source]
citation = "test fixture"
[parameters]
a = "real"
[system]
hamiltonian = "M1**2 + M2**2 + a*M3**2 + 2*gamma1"
kappa = "1"
"""


@pytest.mark.slow  # a new local:2 cluster and the local pool on the new forms: a minute loaded
def test_new_form_cases_audit_on_the_cluster_as_in_the_local_pool(tmp_path):
    local = registry.open(tmp_path / "local.sqlite")
    local.add(HAMILTONIAN)
    on_dask = registry.open(tmp_path / "dask.sqlite")
    on_dask.add(HAMILTONIAN)
    expected = local.audit(jobs=2, budget=PATIENT)
    got = on_dask.audit(scheduler="local:2", budget=PATIENT)
    assert [a.case for a in got.audits] == [a.case for a in expected.audits]
    assert len(got.audits) == len(list(HAMILTONIAN.glob("*.toml"))) >= 4
    for mine, theirs in zip(got.audits, expected.audits, strict=True):
        assert [(r.check, r.claim, r.verdict, r.method, r.reason) for r in mine.results] == [
            (r.check, r.claim, r.verdict, r.method, r.reason) for r in theirs.results
        ], mine.case
        assert mine.family == theirs.family
    verdicts = [r.verdict for a in got.audits for r in a.results]
    assert Verdict.REFUTED in verdicts and Verdict.ERROR not in verdicts
    local.close()
    on_dask.close()


def test_the_so4_family_is_searched_on_the_cluster_as_locally(process_cluster):
    case = parse_case_text(SO4_FAMILY)
    options = search_options(case, degree=4, weights=(1, 1), free=("a",))
    here = discover(case, options, budget=300)
    there = discover(case, options, budget=300, executor=DaskCluster(process_cluster, "test"))
    assert replace(there, seconds=0.0) == replace(here, seconds=0.0)
    assert {s.when for s in there.special} == {("a = 1",), ("a = 2",)}
