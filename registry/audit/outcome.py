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
    DriftCurve,
    Evidence,
    FamilyRecord,
    Verdict,
)
from .case_audit import CASE_CHECKS, claim_verdict
from .checks import CHECKS, not_applicable


def missing(check: str, claim: str | None = None) -> CheckResult:
    """The result that stands for a check that was not run."""
    return CheckResult(check, Verdict.ERROR, "not run", claim=claim, reason="check was not run")


@dataclass(frozen=True)
class ClaimOutcome:
    """One claim: the results of the checks run on it (``integral`` and ``casimir`` for
    an integral or a Casimir, ``measure`` or ``relation`` for those kinds, ``invariant``
    where it is made on a level set), its overall verdict, evidence, corrections and
    conditions, and the checks that do not apply to its system (name -> why)."""

    claim: Claim
    results: Mapping[str, CheckResult]
    verdict: Verdict
    evidence: Evidence | None = None
    corrections: tuple[Correction, ...] = ()
    conditions: Conditions | None = None
    not_applicable: Mapping[str, str] = field(default_factory=dict)

    @property
    def label(self) -> str:
        return self.claim.label

    @property
    def on_set(self) -> bool:
        """Whether the claim is made on a level set (its ``on`` equations)."""
        return bool(self.claim.on)

    @property
    def integral(self) -> CheckResult | None:
        return self.results.get("integral")

    @property
    def casimir(self) -> CheckResult | None:
        return self.results.get("casimir")

    @property
    def invariant(self) -> CheckResult | None:
        return self.results.get("invariant")

    @property
    def checks(self) -> dict[str, CheckResult]:
        """The results by check name, in the order the audit runs them."""
        return dict(self.results)

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
    #: The trajectories the audit integrated for refuted claims, for their drift plots.
    curves: tuple[DriftCurve, ...] = ()

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
    skipped = not_applicable(case) if case is not None and load_error is None else {}
    claims = []
    for claim in case.claims if case is not None else ():
        names = sorted(
            (
                spec.name
                for spec in CHECKS.values()
                if spec.per_claim and spec.applies(claim) and spec.name not in skipped
            ),
            key=lambda name: name == "invariant",  # the claim's own checks first
        )
        results = {name: result(name, claim.label) for name in names}
        if claim.on and ("invariant", claim.label) not in by_key:
            results.pop("invariant", None)  # decided only where an integral needed it
        numbers = [e for e in audit.evidence if e.claim == claim.label]
        claims.append(
            ClaimOutcome(
                claim=claim,
                results=results,
                verdict=claim_verdict(claim.kind, {n: r.verdict for n, r in results.items()}),
                evidence=numbers[0] if numbers else None,
                corrections=tuple(c for c in audit.corrections if c.claim == claim.label),
                conditions=conditions.get(claim.label),
                not_applicable={
                    n: why
                    for n, why in skipped.items()
                    if CHECKS[n].per_claim and CHECKS[n].applies(claim)
                },
            )
        )
    return CaseOutcome(
        case_id=audit.case,
        case=case,
        version=version,
        checks={name: result(name) for name in CASE_CHECKS if name not in skipped},
        not_applicable={n: why for n, why in skipped.items() if not CHECKS[n].per_claim},
        claims=tuple(claims),
        error=None if load_error is None else load_error.reason,
        family=audit.family,
        jacobi_conditions=conditions.get("jacobi"),
        casimirs=tuple(c for c in audit.corrections if c.claim is None),
        curves=audit.curves,
    )


def outcomes(
    audits: Sequence[CaseAudit],
    cases: Mapping[str, Case],
    versions: Mapping[str, int] | None = None,
) -> tuple[CaseOutcome, ...]:
    """The outcomes of a run's audits, in order (``cases`` and ``versions`` by case id)."""
    versions = versions or {}
    return tuple(case_outcome(a, cases.get(a.case), versions.get(a.case)) for a in audits)
