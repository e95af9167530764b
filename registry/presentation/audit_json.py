"""The JSON document of an audit (docs/json-output.md, "Audit output").

Built from the audit's outcome objects (``audit.outcome``); the shape is a contract
with scripts, pinned by ``tests/test_golden.py``. Verdicts are written as their text.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..audit.outcome import CaseOutcome, ClaimOutcome
from ..model import Case, CheckResult


def result_document(result: CheckResult) -> dict:
    """One check's details: verdict, method, seconds, and reason, residual, witness where
    there are any."""
    detail = {
        "verdict": str(result.verdict),
        "method": result.method,
        "seconds": round(result.seconds, 4),
    }
    if result.reason:
        detail["reason"] = result.reason
    if result.residual is not None:
        detail["residual"] = result.residual
    if result.witness is not None:
        detail["witness"] = result.witness.as_dict()
    return detail


def claim_document(outcome: ClaimOutcome) -> dict:
    """One entry of a case's ``claims``: verdicts, details, evidence, corrections, conditions."""
    claim = outcome.claim
    entry: dict = {"label": claim.label, "kind": str(claim.kind)}
    # the verdict of each property checked (integral and casimir for integrals and
    # Casimirs, measure or relation for those kinds), then the claim's own
    entry.update({name: str(r.verdict) for name, r in outcome.results.items()})
    entry.pop("invariant", None)  # given below, with the level set
    entry["verdict"] = str(outcome.verdict)
    if outcome.not_applicable:
        entry["not_applicable"] = dict(outcome.not_applicable)
    if claim.on:
        entry["on"] = [eq.text for eq in claim.on]
        if outcome.invariant is not None:
            entry["invariant"] = str(outcome.invariant.verdict)
    entry["details"] = {name: result_document(r) for name, r in outcome.checks.items()}
    if outcome.evidence is not None:
        entry["numeric"] = outcome.evidence.as_dict()
    if outcome.corrections:
        entry["corrections"] = [c.as_dict() for c in outcome.corrections]
    found = outcome.conditions
    if found is not None and found.branches:
        first, *more = found.branches
        entry["holds_when"] = list(first)
        if more:
            entry["holds_when_branches"] = [list(b) for b in more]
    elif found is not None:
        entry["holds_when_note"] = found.reason
    return entry


def system_document(case: Case) -> dict | None:
    """The system, for a case that is not in the reference paper's own form (e(3) with A,
    B, C and U): its Hamiltonian and kappa as written where its bracket is the paper's
    deformed one; otherwise its variables and the parts its file gives (equations,
    Hamiltonian, bracket entries, definitions)."""
    dynamics = case.dynamics
    given = {g.name: g.text for g in dynamics.given}
    if dynamics.torque is not None:
        if not dynamics.from_bracket and dynamics.kappa.expr == 0:
            return None
        h = {"hamiltonian": given["H"]} if dynamics.from_bracket else {}
        return {**h, "kappa": dynamics.kappa.text}
    return {"variables": [str(x) for x in dynamics.variables], "given": given}


def case_document(outcome: CaseOutcome) -> dict:
    """One entry of ``cases``: case checks and claim verdicts."""
    doc: dict = {"case": outcome.case_id}
    if outcome.version is not None:
        doc["version"] = outcome.version
    if outcome.case is not None:
        doc["title"] = outcome.case.title
        system = system_document(outcome.case)
        if system is not None:
            doc["system"] = system
    if outcome.error is not None:
        doc["error"] = outcome.error
    doc["checks"] = {name: str(r.verdict) for name, r in outcome.checks.items()}
    doc["details"] = {name: result_document(r) for name, r in outcome.checks.items()}
    if outcome.not_applicable:
        doc["not_applicable"] = dict(outcome.not_applicable)
    if outcome.family is not None:
        doc["family"] = outcome.family.as_dict()
    jacobi = outcome.jacobi_conditions
    if jacobi is not None and jacobi.branches:
        first, *more = jacobi.branches
        doc["conditions"] = {"jacobi": list(first)}
        if more:
            doc["conditions"]["jacobi_branches"] = [list(b) for b in more]
    if outcome.casimirs:
        doc["casimirs"] = [c.as_dict() for c in outcome.casimirs]
    doc["claims"] = [claim_document(c) for c in outcome.claims]
    return doc


def audit_document(run: int | None, outcomes: Sequence[CaseOutcome]) -> dict:
    """The document ``registry audit --json`` prints (shape fixed by docs/json-output.md)."""
    return {"run": run, "cases": [case_document(o) for o in outcomes]}
