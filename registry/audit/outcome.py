"""What an audit found, as typed objects built once from ``(CaseAudit, Case)``.

Every renderer (the JSON document, the verdict table, the reports) reads these
instead of re-deriving them: which result stands for each check (the load error of
a case that could not be loaded, an ``error`` for a check that did not run), each
claim's overall verdict, its evidence, corrections and parameter conditions, and the
case's own discovered Casimirs and Jacobi conditions.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from ..model import (
    Case,
    CaseAudit,
    CheckResult,
    Claim,
    Conditions,
    Correction,
    Evidence,
    FamilyRecord,
    Verdict,
)
from .case_audit import CASE_CHECKS, claim_verdict
from .checks import not_applicable


def missing(check: str, claim: str | None = None) -> CheckResult:
    """The result that stands for a check that was not run."""
    return CheckResult(check, Verdict.ERROR, "not run", claim=claim, reason="check was not run")


@dataclass(frozen=True)
class ClaimOutcome:
    """One claim: its integral and Casimir results (and the invariance of its level set,
    where it was checked), its overall verdict, evidence, corrections and conditions."""

    claim: Claim
    integral: CheckResult
    casimir: CheckResult
    verdict: Verdict
    invariant: CheckResult | None = None
    evidence: Evidence | None = None
    corrections: tuple[Correction, ...] = ()
    conditions: Conditions | None = None

    @property
    def label(self) -> str:
        return self.claim.label

    @property
    def on_set(self) -> bool:
        """Whether the claim is made on a level set (its ``on`` equations)."""
        return bool(self.claim.on)

    @property
    def checks(self) -> dict[str, CheckResult]:
        """The results by check name: integral, casimir, and invariant where it ran."""
        found = {"integral": self.integral, "casimir": self.casimir}
        if self.invariant is not None:
            found["invariant"] = self.invariant
        return found

    @property
    def contradicted(self) -> bool:
        """Whether numerical evidence contradicts the verdict it was compared with."""
        return self.evidence is not None and self.evidence.contradicts


@dataclass(frozen=True)
class CaseOutcome:
    """One audited case: its case checks, family, discovered Casimirs, the conditions
    under which Pi_mu is Poisson, and its claims. ``case`` is None for a case whose
    stored text could not be parsed; ``error`` says why a case could not be loaded."""

    case_id: str
    case: Case | None
    version: int | None
    checks: Mapping[str, CheckResult]
    claims: tuple[ClaimOutcome, ...] = ()
    error: str | None = None
    family: FamilyRecord | None = None
    jacobi_conditions: Conditions | None = None
    casimirs: tuple[Correction, ...] = ()
    #: Case checks that do not apply to the case (name -> why), e.g. ``hamiltonian``
    #: where the case gives H and its vector field is Pi grad H by definition.
    not_applicable: Mapping[str, str] = field(default_factory=dict)

    @property
    def poisson(self) -> Verdict | None:
        """The verdict of the Jacobi identity: whether Pi_mu is a Poisson tensor."""
        found = self.checks.get("jacobi")
        return None if found is None else found.verdict


def case_outcome(audit: CaseAudit, case: Case | None, version: int | None = None) -> CaseOutcome:
    """The outcome of one case's audit (``case``: the case version it audited)."""
    by_key = {(r.check, r.claim): r for r in audit.results}
    load_error = by_key.get(("load", None))

    def result(check: str, claim: str | None = None) -> CheckResult:
        return by_key.get((check, claim)) or load_error or missing(check, claim)

    conditions = {c.target: c for c in audit.conditions}
    claims = []
    for claim in case.claims if case is not None else ():
        integral, casimir = result("integral", claim.label), result("casimir", claim.label)
        numbers = [e for e in audit.evidence if e.claim == claim.label]
        claims.append(
            ClaimOutcome(
                claim=claim,
                integral=integral,
                casimir=casimir,
                verdict=claim_verdict(claim.kind, integral.verdict, casimir.verdict),
                invariant=by_key.get(("invariant", claim.label)) if claim.on else None,
                evidence=numbers[0] if numbers else None,
                corrections=tuple(c for c in audit.corrections if c.claim == claim.label),
                conditions=conditions.get(claim.label),
            )
        )
    skipped = not_applicable(case) if case is not None and load_error is None else {}
    return CaseOutcome(
        case_id=audit.case,
        case=case,
        version=version,
        checks={name: result(name) for name in CASE_CHECKS if name not in skipped},
        not_applicable=skipped,
        claims=tuple(claims),
        error=None if load_error is None else load_error.reason,
        family=audit.family,
        jacobi_conditions=conditions.get("jacobi"),
        casimirs=tuple(c for c in audit.corrections if c.claim is None),
    )


def outcomes(
    audits: Sequence[CaseAudit],
    cases: Mapping[str, Case],
    versions: Mapping[str, int] | None = None,
) -> tuple[CaseOutcome, ...]:
    """The outcomes of a run's audits, in order (``cases`` and ``versions`` by case id)."""
    versions = versions or {}
    return tuple(case_outcome(a, cases.get(a.case), versions.get(a.case)) for a in audits)
