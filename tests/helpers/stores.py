"""Rows of a store counted, and a made-up audit of a stored case to record, for the
tests of the store's tables, frames and database."""

from __future__ import annotations

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from registry.model import CaseAudit, CheckResult, Verdict, Witness
from registry.store.database import Store, StoredCase


def count(store: Store, row: type) -> int:
    with Session(store.engine) as session:
        return session.scalar(select(func.count()).select_from(row))


def audit_of(case, stored: StoredCase, integral: Verdict = Verdict.VERIFIED) -> CaseAudit:
    """An audit of ``case`` with two case checks and the integral check of each claim."""
    witness = Witness(
        point={"gamma1": "1", "N": "1/2"},
        value="1/2",
        approx="0.5",
        component="casimir[1]",
        functions={"phi": "gamma1**2"},
    )
    results = [
        CheckResult("jacobi", Verdict.VERIFIED, "rational normal form", seconds=0.25),
        CheckResult("energy", Verdict.VERIFIED, "exact probe"),
    ]
    for claim in case.claims:
        refuted = integral is Verdict.REFUTED
        results.append(
            CheckResult(
                "integral",
                integral,
                "exact probe",
                claim=claim.label,
                reason="" if not refuted else "nonzero at a point",
                residual="N*gamma1" if refuted else None,
                witness=witness if refuted else None,
                seconds=1.5,
            )
        )
    return CaseAudit(stored.case_id, stored.content_hash, tuple(results))
