"""Where calls run (``registry/execution/executor.py``): one interface for this process,
local workers and a Dask cluster; ``--jobs`` means the same everywhere; results that come
in any order are put back in order, a missing one named, the calls closed."""

from __future__ import annotations

import os

import pytest

from registry import settings
from registry.errors import UsageError
from registry.execution.executor import (
    InProcess,
    LocalPool,
    in_order,
    jobs_or_default,
    open_executor,
)
from registry.execution.local import default_jobs
from registry.execution.serving import Failure


def _double(x: int) -> tuple[int, int]:
    return 2 * x, os.getpid()


def _raise(x: int) -> int:
    raise ValueError(f"no {x}")


def test_results_that_come_in_any_order_are_put_back_in_order_and_none_is_lost():
    closed = []

    def calls():
        try:
            yield from [(2, "c"), (0, "a"), (1, "b")]  # index 3 never comes back
        finally:
            closed.append(True)

    got = list(in_order(calls(), 4))
    assert [(i, v) for i, v in got[:3]] == [(0, "a"), (1, "b"), (2, "c")]
    assert got[3][0] == 3 and isinstance(got[3][1], Failure) and got[3][1].kind == "lost"
    assert closed == [True]


def test_jobs_one_runs_in_this_process_and_more_in_workers():
    with open_executor(jobs=1) as here:
        assert isinstance(here, InProcess) and here.describe() == {"jobs": 1}
        found = dict(here.map(_double, [1, 2, 3]))
        assert {v[1] for v in found.values()} == {os.getpid()}
    with open_executor(jobs=2) as pool:
        assert isinstance(pool, LocalPool) and pool.workers == 2
        found = dict(pool.map(_double, [1, 2, 3]))
        assert [found[i][0] for i in range(3)] == [2, 4, 6]
        assert os.getpid() not in {v[1] for v in found.values()}


def test_the_default_is_one_worker_per_core(monkeypatch):
    monkeypatch.delenv(settings.SCHEDULER_ENV, raising=False)
    assert jobs_or_default(None) == default_jobs() >= 1
    with open_executor() as executor:
        assert executor.workers == default_jobs()


@pytest.mark.parametrize("bad", [0, -1, True, 1.5])
def test_a_jobs_value_that_is_no_number_of_processes_is_refused(bad):
    with pytest.raises(UsageError, match="--jobs must be a whole number"):
        jobs_or_default(bad)


def test_jobs_and_a_scheduler_together_are_refused():
    with pytest.raises(UsageError, match="not both"):
        with open_executor(jobs=2, scheduler="local:1"):
            pass


def test_a_call_that_raises_is_a_failure_in_this_process_as_in_workers():
    for jobs in (1, 2):
        with open_executor(jobs=jobs) as executor:
            ((_, outcome),) = list(executor.map(_raise, [7]))
        assert isinstance(outcome, Failure) and outcome.kind == "error"
        assert "no 7" in outcome.reason


def test_groups_set_the_order_in_this_process():
    order = [index for index, _ in InProcess().map(_double, [0, 1, 2], groups=[[2, 0], [1]])]
    assert order == [2, 0, 1]
