"""The audit of one case: every check (or the named ones) run, a crash contained as an
``error`` result, corrections derived when every check ran, and no database needed."""

from __future__ import annotations

from dataclasses import replace

import pytest

from registry import Verdict, load_case
from registry.audit import case_audit
from registry.audit.case_audit import (
    CASE_CHECKS,
    audit_case,
    claim_verdict,
    count_checks,
    failed_case,
)
from registry.audit.checks import CHECKS
from registry.model import ClaimKind
from tests.helpers.samples import YEHIA_B, ZHUKOVSKY, case_file


def test_every_check_runs_once_per_case_or_per_claim_and_corrections_follow():
    case = load_case(case_file(YEHIA_B))
    audit = audit_case(case)
    assert (audit.case, audit.content_hash) == (case.id, case.content_hash)
    assert len(audit.results) == count_checks(case)
    assert [r.check for r in audit.results[: len(CASE_CHECKS)]] == list(CASE_CHECKS)
    assert audit.family is not None and audit.corrections  # corrections of the refuted claim
    assert audit.evidence == ()  # numeric evidence only when asked for


def test_only_the_named_checks_run_and_then_no_corrections():
    case = load_case(case_file(YEHIA_B))
    audit = audit_case(case, checks=["casimir"])
    assert {r.check for r in audit.results} == {"casimir"}
    assert audit.family is None and audit.corrections == ()
    with pytest.raises(ValueError, match="unknown check"):
        audit_case(case, checks=["no-such-check"])


def test_a_crashing_check_is_an_error_and_the_others_go_on(monkeypatch):
    def crash(m):
        raise ZeroDivisionError("simulated")

    monkeypatch.setitem(CHECKS, "energy", replace(CHECKS["energy"], run=crash))
    audit = audit_case(load_case(case_file(ZHUKOVSKY)))
    energy = audit.result("energy")
    assert (energy.verdict, energy.method) == (Verdict.ERROR, "exception")
    assert energy.reason == "ZeroDivisionError: simulated"
    assert audit.result("jacobi").verdict is Verdict.VERIFIED


def test_a_case_that_cannot_be_loaded_is_one_error():
    audit = failed_case("broken", "hash", ValueError("bad file"))
    (only,) = audit.results
    assert (only.check, only.verdict, only.reason) == (
        "load",
        Verdict.ERROR,
        "ValueError: bad file",
    )


def test_a_claim_s_verdict_is_that_of_the_property_its_kind_names():
    v, r = Verdict.VERIFIED, Verdict.REFUTED
    assert claim_verdict(ClaimKind.INTEGRAL, {"integral": v, "casimir": r}) is v
    assert claim_verdict("casimir", {"integral": "verified", "casimir": "refuted"}) is r
    assert claim_verdict("measure", {"measure": "refuted"}) is r
    assert claim_verdict("relation", {}) is Verdict.INCONCLUSIVE  # its check did not run


def test_the_default_budget_bounds_every_check():
    assert case_audit.DEFAULT_BUDGET.check > 0 and case_audit.DEFAULT_BUDGET.corrections > 0
