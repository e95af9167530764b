"""Rows to domain objects and back: every field survives the round trip, and a number
that does not exist (NaN: no trajectory was integrated) is stored as NULL."""

from __future__ import annotations

import math

from registry.model import (
    CheckResult,
    Conditions,
    Correction,
    Evidence,
    FamilyRecord,
    Verdict,
    Witness,
)
from registry.store import conversions
from registry.store.tables import CorrectionRow

WITNESS = Witness({"gamma1": "1/2"}, "3/4", "0.75", component="dI/dt", functions={"a": "s**2"})


def test_a_check_result_round_trips_through_its_row():
    result = CheckResult(
        "casimir", Verdict.REFUTED, "exact probe", "I2", "why", "N*gamma1", WITNESS, 1.25
    )
    row = conversions.result_row(7, 3, 11, result, reused=True)
    assert (row.run_id, row.case_pk, row.claim_id, row.reused) == (7, 3, 11, True)
    assert row.verdict == "refuted"
    assert conversions.check_result(row, "I2") == result


def test_evidence_round_trips_and_nan_is_null():
    found = Evidence("I1", 1e-3, 2e-14, 3, contradicts=True, note="n", narrowed="one instance")
    row = conversions.evidence_row(1, 2, 3, found)
    assert conversions.evidence(row, "I1") == found
    on_set = Evidence("s", 1e-15, 2e-14, 3, departure=1e-16, projected=True)
    assert conversions.evidence(conversions.evidence_row(1, 2, 3, on_set), "s") == on_set
    left = Evidence("s", 9.2, 2e-14, 3, departure=0.3, reason="every trajectory left")
    assert conversions.evidence(conversions.evidence_row(1, 2, 3, left), "s") == left
    missing = Evidence("I1", math.nan, math.nan, 0, note="no start point")
    row = conversions.evidence_row(1, 2, 3, missing)
    assert row.drift is None and row.floor is None
    back = conversions.evidence(row, "I1")
    assert math.isnan(back.drift) and math.isnan(back.floor) and back.runs == 0


def test_family_corrections_and_conditions_round_trip_through_correction_rows():
    from registry.model import CaseAudit

    family = FamilyRecord("constant", phi="gamma3", casimir="s + gamma3", method="mu0 . gamma")
    torque = Correction(
        "torque",
        claim="I2",
        torque=("0", "0", "gamma3"),
        changed=(2,),
        method="m",
        checks={"jacobi": Verdict.VERIFIED, "casimir": Verdict.VERIFIED},
    )
    casimir = Correction("casimir", expression="s", method="m", checks={"casimir": "verified"})
    conditions = (Conditions("jacobi", (("T12 = T21",),)), Conditions("I2", reason="none"))
    audit = CaseAudit("c", "h", (), family, (torque, casimir), conditions)
    rows = conversions.correction_rows(1, 2, audit, {"I2": 5})
    assert [r.kind for r in rows] == ["family", "torque", "casimir", "conditions", "conditions"]
    assert [r.claim_id for r in rows] == [None, 5, None, None, 5]
    assert [r.verdict for r in rows] == ["verified", "verified", "verified", "verified", None]
    # rows read back as they are stored: payloads as JSON would give them
    stored = [CorrectionRow(kind=r.kind, payload=dict(r.payload), verdict=r.verdict) for r in rows]
    back = conversions.derived(stored)
    assert back["family"] == family
    assert back["corrections"] == (torque, casimir)
    assert back["conditions"] == conditions
