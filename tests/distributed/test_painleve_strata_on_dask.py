"""Kovalevskaya analyses of a family on a Dask cluster: the strata where the Painlevé test
can pass are examined on the workers, one depth at a time, and the outcome is the one
found in this process."""

from __future__ import annotations

import pytest

from registry.discovery.exponents import analyse_case, exponent_options
from registry.execution.executor import DaskCluster
from registry.language.casefile import load_case
from tests.helpers.samples import FAMILIES


@pytest.mark.slow  # a family analysed twice, here and on the cluster: a minute when loaded
def test_the_painleve_strata_examined_on_the_cluster_give_the_local_ones(process_cluster):
    case = load_case(FAMILIES / "heavy-top-c-x0.toml")
    options = exponent_options(case, free=["c", "x0"])
    here = analyse_case(case, options, budget=300).document["painleve_sets"]
    cluster = DaskCluster(process_cluster, "test")
    there = analyse_case(case, options, budget=300, executor=cluster).document["painleve_sets"]
    assert [s["when"] for s in there["passing"]] == [["c = 1"], ["x0 = 0"]]
    for found in (here, there):
        found.pop("seconds")
    assert there == here and there["complete"]
    assert cluster.events == []
