"""Worker processes: the same verdicts as in process, cases sharing a torque in one
batch (largest first), and a worker stuck where the timer cannot reach killed and
replaced, the rest of its batch still audited."""

import multiprocessing as mp
import signal
import time
from dataclasses import replace

import pytest

from registry import Verdict, audit_case, load_case
from registry.audit.checks import CHECKS
from registry.audit.parallel import _torque, audit_cases, batches, estimated_cost
from registry.execution import local
from registry.execution.executor import LocalPool
from registry.execution.time_budget import TimeBudget
from tests.helpers.clocks import PATIENT
from tests.helpers.samples import CASES


@pytest.fixture
def forked(monkeypatch):
    """The workers must see a check patched in this process: they are forked, whatever
    threads earlier tests left running (a Dask client's would make them new interpreters)."""
    monkeypatch.setattr(local, "_context", lambda: mp.get_context("fork"))


def _stuck_in_c(m, *args):
    """Simulates code the timer cannot interrupt: the alarm signal is blocked."""
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
    time.sleep(120)


def test_a_worker_stuck_where_the_timer_cannot_reach_is_killed_and_replaced(monkeypatch, forked):
    stuck = replace(CHECKS["energy"], run=_stuck_in_c)
    monkeypatch.setitem(CHECKS, "energy", stuck)
    cases = [
        load_case(CASES / "zhukovsky-gyrostat.toml"),
        load_case(CASES / "borisov-mamaev-1997.toml"),
    ]
    budget = TimeBudget(check=0.5, corrections=0.5, margin=0.5)
    started = time.monotonic()
    results = dict(audit_cases(cases, LocalPool(1), budget))
    # waiting, not computing: a wall-clock bound far above the seconds this takes, and
    # below the 120 s the stuck checks would sleep if no one killed them
    assert time.monotonic() - started < 100
    for index, case in enumerate(cases):
        audit = results[index]
        assert audit.case == case.id
        (only,) = audit.results
        assert only.verdict is Verdict.INCONCLUSIVE
        assert "worker killed" in only.reason


def test_workers_give_the_same_verdicts_as_in_process():
    cases = [
        load_case(CASES / f"{n}.toml")
        for n in ("zhukovsky-gyrostat", "affine-nonsymmetric", "borisov-mamaev-1997")
    ]
    # the same work on both sides: budgets no busy machine reaches (a correction search
    # cut off by a wall-clock budget in one and not the other would tell nothing)
    budget = PATIENT
    parallel = dict(audit_cases(cases, LocalPool(2), budget))
    for index, case in enumerate(cases):
        here = audit_case(case, budget=budget)
        there = parallel[index]
        assert [(r.check, r.claim, r.verdict) for r in there.results] == [
            (r.check, r.claim, r.verdict) for r in here.results
        ]
        assert there.corrections == here.corrections


def test_cases_sharing_a_torque_are_audited_by_one_worker_in_one_batch():
    cases = [load_case(p) for p in sorted(CASES.glob("*.toml"))]
    groups = batches(cases)
    assert sorted(i for g in groups for i, _ in g) == list(range(len(cases)))
    ids = [{c.id for _, c in g} for g in groups]
    assert {"yehia-2003-kovalevskaya-b", "bcc-yehia-b-corrected-casimir"} in ids
    assert {"zhukovsky-gyrostat"} in ids  # its own torque
    for g in groups:
        assert len({_torque(c) for _, c in g}) == 1
        costs = [estimated_cost(c) for _, c in g]
        assert costs == sorted(costs, reverse=True)
    totals = [sum(estimated_cost(c) for _, c in g) for g in groups]
    assert totals == sorted(totals, reverse=True)


def _stuck_on_a_claim_named_stuck(mech, *args):
    if any(c.label == "stuck" for c in mech.case.claims):
        _stuck_in_c(mech)
    return ORIGINAL_ENERGY.run(mech, *args)


ORIGINAL_ENERGY = CHECKS["energy"]


def test_the_rest_of_a_killed_workers_batch_is_still_audited(monkeypatch, forked):
    monkeypatch.setitem(
        CHECKS, "energy", replace(ORIGINAL_ENERGY, run=_stuck_on_a_claim_named_stuck)
    )
    zhukovsky = load_case(CASES / "zhukovsky-gyrostat.toml")
    claim = replace(zhukovsky.claims[0], label="stuck")
    # the same torque, so one batch; the larger (stuck) one goes first
    stuck = replace(zhukovsky, id="stuck-variant", claims=(claim,) * 3)
    cases = [zhukovsky, stuck]
    assert len(batches(cases)) == 1 and batches(cases)[0][0][1].id == "stuck-variant"
    # checks of a tenth of a second get 2 s each (room for a busy machine); the stuck case
    # is killed at its deadline, long before its 120 s sleep ends
    budget = TimeBudget(check=2.0, corrections=2.0, margin=0.5)
    results = dict(audit_cases(cases, LocalPool(1), budget))
    assert "worker killed" in results[1].results[0].reason
    assert {r.verdict for r in results[0].results} == {Verdict.VERIFIED}
