"""An audit run (``registry/runs/audit_run.py``): which stored audits are reused, the
run recorded case by case, a stored run read back, and two runs compared."""

from __future__ import annotations

from dataclasses import replace

from registry.audit.case_audit import audit_case, crashed_audit
from registry.execution.executor import InProcess
from registry.language.casefile import load_case
from registry.model import CheckResult, Verdict
from registry.runs.audit_run import AuditRequest, _reusable, audit_run, run_diff, stored_run
from registry.store.database import Store
from tests.helpers.samples import CASES

ZHUKOVSKY = CASES / "zhukovsky-gyrostat.toml"


def test_only_a_complete_audit_of_every_claim_is_reused():
    case = load_case(ZHUKOVSKY)
    audit = audit_case(case, corrections=False)
    assert _reusable((1, audit), case) is audit
    assert _reusable(None, case) is None
    crashed = crashed_audit(case, "worker died (-9)")
    assert _reusable((1, crashed), case) is None
    errored = replace(audit, results=(*audit.results, CheckResult("c1", Verdict.ERROR, "x")))
    assert _reusable((1, errored), case) is None
    more = replace(case, claims=(*case.claims, replace(case.claims[0], label="new")))
    assert _reusable((1, audit), more) is None  # a claim attached since: audit again


def test_a_second_run_reuses_and_a_fresh_one_recomputes(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    store.add_case(load_case(ZHUKOVSKY))
    first = audit_run(store, AuditRequest(), InProcess())
    second = audit_run(store, AuditRequest(), InProcess())
    third = audit_run(store, AuditRequest(fresh=True), InProcess())
    assert [r for _, r in store.run_results(first.run)] == list(first.audits)
    assert second.audits == first.audits  # the same stored audit
    assert [a.case for a in third.audits] == ["zhukovsky-gyrostat"]
    assert stored_run(store, second.run).audits == second.audits
    assert run_diff(store, first.run, third.run) == []
    store.close()
