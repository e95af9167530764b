"""The outcome of an audit, built once from (CaseAudit, Case): which result stands for
each check, each claim's verdict, evidence, corrections and conditions."""

from __future__ import annotations

from dataclasses import replace

import pytest

from registry import ClaimKind, Verdict, audit_case, load_case
from registry.audit.case_audit import CASE_CHECKS, failed_case
from registry.audit.outcome import case_outcome, missing, outcomes
from tests.helpers.samples import YEHIA_B, ZHUKOVSKY, case_file


@pytest.fixture(scope="module")
def yehia_b():
    case = load_case(case_file(YEHIA_B))
    return case, audit_case(case)


def test_a_claim_s_verdict_is_that_of_the_property_its_kind_names(yehia_b):
    case, audit = yehia_b
    outcome = case_outcome(audit, case, version=3)
    assert (outcome.case_id, outcome.version, outcome.error) == (YEHIA_B, 3, None)
    assert list(outcome.checks) == list(CASE_CHECKS)
    assert outcome.poisson is Verdict.VERIFIED
    (claim,) = [c for c in outcome.claims if c.label == "I2"]
    assert claim.claim.kind is ClaimKind.CASIMIR
    assert claim.casimir.verdict is Verdict.REFUTED and claim.verdict is Verdict.REFUTED
    assert claim.integral is audit.result("integral", "I2")
    assert list(claim.checks) == ["integral", "casimir"] and claim.invariant is None


def test_a_claim_carries_its_corrections_and_conditions_and_the_case_its_casimirs(yehia_b):
    case, audit = yehia_b
    (claim,) = [c for c in case_outcome(audit, case).claims if c.label == "I2"]
    assert {c.kind for c in claim.corrections} == {"casimir", "torque"}
    assert all(c.claim == "I2" for c in claim.corrections)
    assert claim.conditions is not None and claim.conditions.branches == (("N = 0",),)
    assert claim.evidence is None and not claim.contradicted
    bare = audit_case(replace(case, claims=()))
    (found,) = case_outcome(bare, replace(case, claims=())).casimirs
    assert found.kind == "casimir" and found.claim is None


def test_a_case_that_could_not_be_loaded_has_its_load_error_for_every_check():
    audit = failed_case("broken", "hash", ValueError("no"))
    outcome = case_outcome(audit, None)
    assert outcome.error == "ValueError: no"
    assert outcome.case is None and outcome.claims == ()
    assert {r.check for r in outcome.checks.values()} == {"load"}
    assert {r.verdict for r in outcome.checks.values()} == {Verdict.ERROR}


def test_a_check_that_did_not_run_stands_as_an_error_not_run():
    case = load_case(case_file(ZHUKOVSKY))
    audit = audit_case(case, checks=["energy"])
    outcome = case_outcome(audit, case)
    assert outcome.checks["energy"].verdict is Verdict.VERIFIED
    assert outcome.checks["jacobi"] == missing("jacobi")
    (claim,) = outcome.claims
    assert claim.integral == missing("integral", claim.label)
    assert claim.integral.reason == "check was not run"


def test_a_claim_on_a_level_set_carries_the_invariance_of_the_set():
    case = load_case(case_file("goryachev-chaplygin-1900"))
    (found,) = [c for c in case_outcome(audit_case(case), case).claims if c.on_set]
    assert found.invariant is not None
    assert list(found.checks) == ["integral", "casimir", "invariant"]


def test_outcomes_follow_the_audits_in_order_with_their_cases_and_versions(yehia_b):
    case, audit = yehia_b
    broken = failed_case("broken", "h", ValueError("no"))
    found = outcomes([broken, audit], {case.id: case}, {case.id: 2})
    assert [o.case_id for o in found] == ["broken", YEHIA_B]
    assert (found[0].version, found[1].version) == (None, 2)
    assert found[1].case is case
