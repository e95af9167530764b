"""Bounded time: checks that run out of time are inconclusive, stuck workers are killed,
and unchanged cases are reused from storage with the same verdicts."""

import signal
import time
from dataclasses import replace
from pathlib import Path

import pytest
import sympy as sp

import registry
from registry import Verdict, audit_case, load_case
from registry.budget import Budget, BudgetExceeded, time_limit
from registry.checks import CHECKS, Mechanics
from registry.mathematics.families import recognise
from registry.model import Expression
from registry.workers import _torque, audit_in_workers, batches, estimated_cost

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"


def test_time_limit_interrupts_python_code():
    started = time.perf_counter()
    with pytest.raises(BudgetExceeded):
        with time_limit(0.3):
            while True:
                pass
    assert time.perf_counter() - started < 1.5


def test_time_limit_is_lifted_afterwards():
    handler = signal.getsignal(signal.SIGALRM)
    with time_limit(5):
        assert signal.getitimer(signal.ITIMER_REAL)[0] > 0
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # no stray alarm
    assert signal.getsignal(signal.SIGALRM) is handler
    # the same after a block that ran out of time
    with pytest.raises(BudgetExceeded):
        with time_limit(0.05):
            assert signal.getitimer(signal.ITIMER_REAL)[0] > 0
            while True:
                pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    assert signal.getsignal(signal.SIGALRM) is handler


def test_an_expression_crafted_to_take_forever_ends_inconclusive_within_its_budget():
    case = load_case(CASES / "zhukovsky-gyrostat.toml")
    g1, g2, g3 = sp.symbols("gamma1 gamma2 gamma3", real=True)
    k1 = case.parameters["k1"]
    linear = g1 + g2 + g3 + k1 + 1
    # identically zero, so no probe refutes it, but a proof must expand two powers
    # of five-variable polynomials into ~10**5 terms each
    zero = linear**40 - sp.expand(linear**2) ** 20
    expr = case.claims[0].expression.expr + zero
    claim = replace(case.claims[0], expression=Expression("crafted", expr))
    started = time.perf_counter()
    audit = audit_case(replace(case, claims=(claim,)), budget=Budget(check=1.0, repairs=1.0))
    elapsed = time.perf_counter() - started
    for check in ("integral", "casimir"):
        result = audit.result(check, claim.label)
        assert result.verdict is Verdict.INCONCLUSIVE
        assert result.reason == "time budget exceeded (1 s)"
        assert result.seconds < 2.0  # stopped within its budget (and a little slack)
    assert elapsed < 20  # two checks of 1 s, the repairs' 1 s, the cheap checks, a busy machine


def _stuck_in_c(m, *args):
    """Simulates code the timer cannot interrupt: the alarm signal is blocked."""
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
    time.sleep(120)


def test_a_worker_stuck_where_the_timer_cannot_reach_is_killed_and_replaced(monkeypatch):
    stuck = replace(CHECKS["energy"], run=_stuck_in_c)
    monkeypatch.setitem(CHECKS, "energy", stuck)
    cases = [
        load_case(CASES / "zhukovsky-gyrostat.toml"),
        load_case(CASES / "borisov-mamaev-1997.toml"),
    ]
    budget = Budget(check=0.5, repairs=0.5, margin=0.5)
    started = time.perf_counter()
    results = dict(audit_in_workers(cases, 1, budget))
    assert time.perf_counter() - started < 30
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
    parallel = dict(audit_in_workers(cases, 2, Budget()))
    for index, case in enumerate(cases):
        here = audit_case(case)
        there = parallel[index]
        assert [(r.check, r.claim, r.verdict) for r in there.results] == [
            (r.check, r.claim, r.verdict) for r in here.results
        ]
        assert there.corrections == here.corrections


def test_unchanged_cases_are_reused_and_fresh_recomputes(tmp_path):
    reg = registry.open(tmp_path / "r.sqlite")
    reg.add(CASES / "yehia-2003-kovalevskaya-b.toml", CASES / "zhukovsky-gyrostat.toml")
    first = reg.audit(jobs=0)
    second = reg.audit(jobs=0)
    third = reg.audit(jobs=0, fresh=True)
    runs = reg.runs().set_index("run")
    assert runs.loc[first.run, "n_reused"] == 0
    assert runs.loc[second.run, "n_reused"] == runs.loc[second.run, "n_results"] > 0
    assert runs.loc[third.run, "n_reused"] == 0
    assert first.document()["cases"] == second.document()["cases"]
    assert _without_timings(third.document()["cases"]) == _without_timings(
        first.document()["cases"]
    )


def _without_timings(cases):
    """Timings differ between fresh runs; everything else must be identical."""
    for case in cases:
        for detail in case["details"].values():
            detail.pop("seconds", None)
        for claim in case["claims"]:
            for detail in claim["details"].values():
                detail.pop("seconds", None)
    return cases


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


def test_recognising_a_torque_twice_reuses_the_first_result():
    case = load_case(CASES / "yehia-2003-kovalevskaya-a.toml")
    m = Mechanics(case)
    first = recognise(m.mu, m.domain)
    assert recognise(m.mu, m.domain) is first
    other = Mechanics(load_case(CASES / "yehia-2003-cyclic.toml"))
    assert recognise(other.mu, other.domain) is not first


def _stuck_on_a_claim_named_stuck(mech, *args):
    if any(c.label == "stuck" for c in mech.case.claims):
        _stuck_in_c(mech)
    return ORIGINAL_ENERGY.run(mech, *args)


ORIGINAL_ENERGY = CHECKS["energy"]


def test_the_rest_of_a_killed_workers_batch_is_still_audited(monkeypatch):
    monkeypatch.setitem(
        CHECKS, "energy", replace(ORIGINAL_ENERGY, run=_stuck_on_a_claim_named_stuck)
    )
    zhukovsky = load_case(CASES / "zhukovsky-gyrostat.toml")
    claim = replace(zhukovsky.claims[0], label="stuck")
    # the same torque, so one batch; the larger (stuck) one goes first
    stuck = replace(zhukovsky, id="stuck-variant", claims=(claim,) * 3)
    cases = [zhukovsky, stuck]
    assert len(batches(cases)) == 1 and batches(cases)[0][0][1].id == "stuck-variant"
    results = dict(audit_in_workers(cases, 1, Budget(check=0.5, repairs=0.5, margin=0.5)))
    assert "worker killed" in results[1].results[0].reason
    assert {r.verdict for r in results[0].results} == {Verdict.VERIFIED}
