"""The JSON document of an audit, from its outcome objects: the shape docs/json-output.md
fixes (the seed catalog's whole document is pinned by tests/test_golden.py)."""

from __future__ import annotations

import json

import pytest

from registry import audit_case, load_case
from registry.audit.case_audit import CASE_CHECKS, failed_case
from registry.audit.outcome import case_outcome, outcomes
from registry.model import CheckResult, Verdict, Witness
from registry.presentation.audit_json import (
    audit_document,
    case_document,
    claim_document,
    result_document,
)
from tests.helpers.samples import YEHIA_B, case_file


@pytest.fixture(scope="module")
def yehia_b():
    case = load_case(case_file(YEHIA_B))
    return case_outcome(audit_case(case), case, version=1)


def test_a_result_has_its_verdict_as_text_and_only_the_fields_it_has():
    plain = CheckResult("energy", Verdict.VERIFIED, "rational normal form", seconds=0.123456)
    assert result_document(plain) == {
        "verdict": "verified",
        "method": "rational normal form",
        "seconds": 0.1235,
    }
    assert type(result_document(plain)["verdict"]) is str
    witness = Witness({"gamma1": "1"}, "2", "2.0", component="dI/dt")
    refuted = CheckResult("integral", Verdict.REFUTED, "exact probe", "I", "why", "M1", witness)
    doc = result_document(refuted)
    assert (doc["reason"], doc["residual"], doc["witness"]) == ("why", "M1", witness.as_dict())


def test_a_case_entry_has_its_checks_family_and_claims(yehia_b):
    doc = case_document(yehia_b)
    assert list(doc)[:4] == ["case", "version", "title", "checks"]
    assert list(doc["checks"]) == list(CASE_CHECKS) == list(doc["details"])
    assert doc["family"]["name"] == yehia_b.family.name
    assert [c["label"] for c in doc["claims"]] == [c.label for c in yehia_b.claims]
    json.dumps(doc)  # plain JSON throughout


def test_a_refuted_claim_lists_its_corrections_and_conditions(yehia_b):
    (claim,) = [c for c in yehia_b.claims if c.label == "I2"]
    entry = claim_document(claim)
    assert (entry["kind"], entry["casimir"], entry["verdict"]) == ("casimir", "refuted", "refuted")
    assert entry["holds_when"] == ["N = 0"]
    assert {c["kind"] for c in entry["corrections"]} == {"casimir", "torque"}
    (torque,) = [c for c in entry["corrections"] if c["kind"] == "torque"]
    assert torque["changed"] == [3]  # mu3, numbered as people read it


def test_the_document_of_a_run_keeps_its_cases_in_order():
    broken = failed_case("broken", "h", ValueError("no"))
    doc = audit_document(7, outcomes([broken], {}))
    assert doc["run"] == 7
    (entry,) = doc["cases"]
    assert entry["error"] == "ValueError: no" and entry["claims"] == []
    assert set(entry["checks"].values()) == {"error"}
