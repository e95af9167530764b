"""Audits on a Dask cluster give the local pool's results, case by case and verdict by
verdict; the per-check time budget still holds in the workers' child processes; the
run records the cluster and what happened on it; only the client writes."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

import registry
from registry.audit.case_audit import as_audit, count_checks
from registry.audit.case_audit import crashed_audit as crashed
from registry.audit.case_audit import killed_audit as killed
from registry.audit.parallel import audit_cases, batches
from registry.cli import main
from registry.execution.cluster_calls import guided
from registry.execution.executor import MAX_BATCH, SHARES_PER_THREAD, DaskCluster, LocalPool
from registry.execution.serving import Failure
from registry.execution.time_budget import TimeBudget
from registry.language.casefile import load_case
from registry.model import Expression, Verdict
from tests.helpers.clocks import HANG, within
from tests.helpers.samples import slow_case

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "data" / "cases"
#: Generous budgets: the comparisons are of verdicts, not of a busy machine's speed.
PATIENT = TimeBudget(check=60.0, corrections=120.0, margin=30.0)
#: What a verdict is, apart from when and how fast it was found.
COLUMNS = [
    "case",
    "version",
    "claim",
    "check",
    "verdict",
    "method",
    "reason",
    "witness",
    "residual",
]


def seed_cases():
    return [load_case(p) for p in sorted(SEED.rglob("*.toml"))]


def verdicts(reg, run: int):
    frame = reg.verdicts()
    assert set(frame.run) == {run}, "every verdict comes from the run compared"
    return frame[COLUMNS].sort_values(["case", "check", "claim"]).reset_index(drop=True)


# ---------------------------------------------------------------------- plan


def plan(cases, n_threads: int) -> list[list[int]]:
    """The tasks a cluster of ``n_threads`` worker threads cuts an audit of ``cases`` into
    (``DaskCluster.plan`` with that many threads)."""
    groups = [[i for i, _ in group] for group in batches(cases)]
    return guided(groups, SHARES_PER_THREAD * n_threads, MAX_BATCH)


def on_cluster(client, cases, budget):
    """The audits of ``cases`` on the cluster of ``client``."""
    return list(audit_cases(cases, DaskCluster(client, "test"), budget))


def in_workers(cases, budget):
    """The audits of ``cases`` in one local worker process (killable, like a child)."""
    return list(audit_cases(cases, LocalPool(1), budget))


def test_the_plan_keeps_torque_groups_together_and_every_case_once():
    cases = seed_cases()
    tasks = plan(cases, n_threads=2)
    assert sorted(i for t in tasks for i in t) == list(range(len(cases)))
    assert all(0 < len(t) <= MAX_BATCH for t in tasks)
    size = max(len(t) for t in tasks)
    task_of = {i: k for k, t in enumerate(tasks) for i in t}
    for group in batches(cases):  # a group that fits in a task is never split
        if len(group) <= size:
            assert len({task_of[i] for i, _ in group}) == 1, [cases[i].id for i, _ in group]
    assert len(tasks[0]) == size and len(tasks[-1]) == 1  # the tasks shrink as the run goes


def test_a_thousand_cases_are_cut_into_tasks_of_at_most_max_batch():
    cases = seed_cases() * 25  # 1200 cases, the seed's torque groups 25 times larger
    tasks = plan(cases, n_threads=2)
    assert sorted(i for t in tasks for i in t) == list(range(len(cases)))
    assert max(len(t) for t in tasks) == MAX_BATCH


def test_a_call_without_result_becomes_the_local_pools_record():
    case = seed_cases()[0]
    assert as_audit(case, Failure("killed", "x", seconds=45.0)) == killed(case, 45.0)
    assert as_audit(case, Failure("crashed", "x", exitcode=-9)) == crashed(case, "worker died (-9)")
    lost = Failure("lost", "KilledWorker: ...")
    assert as_audit(case, lost) == crashed(case, "KilledWorker: ...")
    assert as_audit(case, Failure("error", "ValueError: no")) == crashed(case, "ValueError: no")


# ------------------------------------------------------ the seed catalog on local:2


@pytest.mark.slow  # the 16 seed cases on a local:2 cluster and in the local pool: 5 min when loaded
def test_local_2_audits_the_seed_catalog_exactly_as_the_local_pool(tmp_path):
    local = registry.open(tmp_path / "local.sqlite")
    local.add(SEED)
    on_dask = registry.open(tmp_path / "dask.sqlite")
    on_dask.add(SEED)
    expected = local.audit(jobs=2, budget=PATIENT)
    got = on_dask.audit(scheduler="local:2", budget=PATIENT)

    assert len(got.audits) == len(expected.audits) == len(seed_cases())
    assert [a.case for a in got.audits] == [a.case for a in expected.audits]
    for mine, theirs in zip(got.audits, expected.audits, strict=True):
        assert [(r.check, r.claim, r.verdict, r.method, r.reason) for r in mine.results] == [
            (r.check, r.claim, r.verdict, r.method, r.reason) for r in theirs.results
        ], mine.case
    assert verdicts(on_dask, got.run).equals(verdicts(local, expected.run))
    refuted = sum(r.verdict is Verdict.REFUTED for a in got.audits for r in a.results)
    assert refuted > 0 and not any(
        r.verdict is Verdict.ERROR for a in got.audits for r in a.results
    )

    (run,) = on_dask.runs().to_dict("records")
    # n_cases counts the cases with results: a system given by its equations, without
    # claims, has nothing to decide
    silent = [a.case for a in got.audits if not a.results]
    assert all(not c.claims for c in seed_cases() if c.id in silent)
    assert run["status"] == "complete" and run["n_cases"] == len(seed_cases()) - len(silent)
    options = run["options"]
    assert options["scheduler"] == "local:2" and options["jobs"] is None
    assert options["cluster"]["workers"] == 2 and options["cluster"]["threads"] == 2
    assert options["cluster"]["address"].startswith("tcp://127.0.0.1:")
    assert options["events"] == [] and got.events == ()


# ------------------------------------------------------------- the time budget


def crafted_case():
    """A seed case whose claim is identically zero plus an expression whose proof must
    expand two powers of five-variable polynomials (``tests/audit/test_time_budget.py``):
    slow in Python code, where the audit's alarm reaches."""
    case = load_case(SEED / "zhukovsky-gyrostat.toml")
    g1, g2, g3 = sp.symbols("gamma1 gamma2 gamma3", real=True)
    linear = g1 + g2 + g3 + case.parameters["k1"] + 1
    zero = linear**40 - sp.expand(linear**2) ** 20
    claim = case.claims[0]
    claim = replace(claim, expression=Expression("crafted", claim.expression.expr + zero))
    return replace(case, id="crafted", claims=(claim,))


def test_a_check_that_would_run_for_minutes_is_stopped_by_its_budget_on_the_worker(
    process_cluster,
):
    """In a Dask worker's child process the audit's alarm stops each slow check at its
    budget: inconclusive, on time, as in the local pool."""
    # the case's deadline far away (margin HANG): this test is about the alarm alone,
    # which a busy machine may deliver seconds late, after a long call into C returns
    budget = TimeBudget(check=1.0, corrections=1.0, margin=HANG)
    (case,) = cases = [crafted_case()]
    ((_, audit),) = on_cluster(process_cluster, cases, budget)
    for check in ("integral", "casimir"):
        result = audit.result(check, case.claims[0].label)
        assert result.verdict is Verdict.INCONCLUSIVE
        assert result.reason == "time budget exceeded (1 s)"
        # stopped by the alarm, not after the minutes the proof would take
        assert result.seconds < HANG
    ((_, local),) = in_workers(cases, budget)
    for check in ("integral", "casimir"):  # the slow checks end as in the local pool
        mine, theirs = (a.result(check, case.claims[0].label) for a in (audit, local))
        assert (mine.verdict, mine.reason) == (theirs.verdict, theirs.reason)


@pytest.mark.slow  # waits out a case deadline on the cluster: over a minute when loaded
def test_a_check_stuck_where_the_alarm_cannot_reach_is_killed_at_the_case_deadline(
    process_cluster,
):
    """The slow case of ``tests/helpers/samples.py`` spends minutes in compiled code, where
    no alarm interrupts it: its child process is killed at the case's deadline, and the
    case is recorded inconclusive exactly as the local pool records it."""
    budget = TimeBudget(check=1.0, corrections=1.0, margin=1.0)
    slow = registry.parse_case_text(slow_case(1), "slow-1")
    fine = load_case(SEED / "axis-torque.toml")
    deadline = budget.case_deadline(count_checks(slow))
    # killed on time, not after the minutes of the proof: waiting, so a wall-clock bound
    # far above the deadline, after which the test stops waiting
    found = dict(within(deadline + HANG, lambda: on_cluster(process_cluster, [slow, fine], budget)))
    assert found[0] == killed(slow, deadline)
    (result,) = found[0].results
    assert result.verdict is Verdict.INCONCLUSIVE
    assert result.reason == f"worker killed after {deadline:.0f} s (case time budget exceeded)"
    assert all(r.verdict is Verdict.VERIFIED for r in found[1].results if r.claim is not None)
    assert found[0] == dict(in_workers([slow], budget))[0]


# --------------------------------------------------------------- the command line


@pytest.mark.parametrize("command", ["audit", "discover", "survey"])
def test_jobs_and_scheduler_together_are_one_error_line(tmp_path, command):
    target = [str(SEED / "axis-torque.toml")] if command == "discover" else []
    args = ["--db", str(tmp_path / "r.sqlite"), command, *target]
    result = CliRunner().invoke(main, [*args, "--jobs", "2", "--scheduler", "local:2"])
    assert result.exit_code == 1
    assert result.output == (
        "Error: give --jobs (local worker processes) or --scheduler (Dask), not both\n"
    )


def test_a_bad_scheduler_address_is_one_line(tmp_path):
    db = tmp_path / "r.sqlite"
    assert CliRunner().invoke(main, ["--db", str(db), "add", str(SEED / "axis-torque.toml")])
    result = CliRunner().invoke(main, ["--db", str(db), "audit", "--scheduler", "local:0"])
    assert result.exit_code == 1
    assert result.output.startswith("Error: bad Dask scheduler address 'local:0'")
    assert len(result.output.strip().splitlines()) == 1


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_jobs_beats_the_environment_variable(tmp_path, monkeypatch, jobs):
    """--jobs runs locally even with $REGISTRY_SCHEDULER set (here to a bad address that
    would fail at once if it were read)."""
    db = tmp_path / "r.sqlite"
    CliRunner().invoke(main, ["--db", str(db), "add", str(SEED / "axis-torque.toml")])
    monkeypatch.setenv("REGISTRY_SCHEDULER", "local:0")
    result = CliRunner().invoke(main, ["--db", str(db), "audit", "--jobs", jobs])
    assert result.exit_code == 0, result.output
    refused = CliRunner().invoke(main, ["--db", str(db), "audit"])
    assert refused.exit_code == 1 and "bad Dask scheduler address 'local:0'" in refused.output
