"""The audit pipeline: every registered check on every case, failures contained.

``audit_case`` needs no database (a notebook can audit a ``Case`` it just
loaded); ``Registry.audit`` in ``api`` runs it over stored cases and records
the run.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Mapping
from dataclasses import replace

from ..execution.serving import Failure
from ..execution.time_budget import (
    DEFAULT_BUDGET,
    BudgetExceeded,
    TimeBudget,
    default_budget,
    time_limit,
)
from ..mathematics.case_mechanics import CaseMechanics
from ..model import (
    Case,
    CaseAudit,
    CheckResult,
    Claim,
    ClaimKind,
    Evidence,
    FamilyRecord,
    Verdict,
)
from .checks import CHECKS, CheckSpec, not_applicable
from .corrections import corrections as derive_corrections
from .numeric_evidence import drift_curve
from .numeric_evidence import evidence as numeric_evidence

#: The case-level checks whose verdicts appear under ``checks`` in the JSON output.
CASE_CHECKS = tuple(name for name, spec in CHECKS.items() if not spec.per_claim)


def audit_case(
    case: Case,
    checks: Iterable[str] | None = None,
    *,
    corrections: bool | None = None,
    budget: TimeBudget | None = DEFAULT_BUDGET,
    numeric: bool = False,
) -> CaseAudit:
    """Run the named checks (default: all) on ``case``; a crash becomes an ``error`` result.

    With ``corrections`` (the default when every check runs) the torque's family, the
    corrections of refuted claims and the conditions for failed identities are derived.
    Each check runs under ``budget.check`` seconds and the corrections under
    ``budget.corrections``; one that runs out is ``inconclusive: time budget exceeded``.
    With ``numeric``, every claim also gets numerical evidence (``numeric_evidence``).
    Without ``budget``, the default's seconds may come from the environment
    (``time_budget.default_budget``); ``budget=None``: no limit.
    """
    if budget is DEFAULT_BUDGET:
        budget = default_budget()
    wanted = set(CHECKS) if checks is None else set(checks)
    unknown = wanted - set(CHECKS)
    if unknown:
        raise ValueError(f"unknown check(s): {', '.join(sorted(unknown))}")
    m = CaseMechanics(case)
    results: list[CheckResult] = []
    skipped = not_applicable(case)
    for spec in CHECKS.values():
        if spec.name not in wanted or spec.name in skipped:
            continue
        seconds = budget.check if budget else None
        if not spec.per_claim:
            results.append(_run(spec, m, seconds=seconds))
            continue
        for claim in case.claims:
            if spec.applies(claim):
                results.append(_run(spec, m, claim, seconds=seconds))
    audit = CaseAudit(case.id, case.content_hash, tuple(results))
    if corrections if corrections is not None else checks is None:
        audit = _with_corrections(audit, m, budget.corrections if budget else None)
        audit = _with_curves(audit, m, budget.corrections if budget else None)
    if numeric:
        audit = _with_evidence(audit, m, budget.corrections if budget else None)
    return audit


def _with_evidence(audit: CaseAudit, m: CaseMechanics, seconds: float | None) -> CaseAudit:
    verdicts = {(r.check, r.claim): r.verdict for r in audit.results if r.claim}
    try:
        with time_limit(seconds):
            found = numeric_evidence(m, verdicts)
    except BudgetExceeded:
        found = tuple(
            Evidence(c.label, math.nan, math.nan, 0, note="time budget exceeded")
            for c in m.case.claims
        )
    except Exception as exc:  # evidence must not lose the verdicts
        found = tuple(
            Evidence(c.label, math.nan, math.nan, 0, note=f"{type(exc).__name__}: {exc}")
            for c in m.case.claims
        )
    return replace(audit, evidence=found)


def _with_curves(audit: CaseAudit, m: CaseMechanics, seconds: float | None) -> CaseAudit:
    """The drift curve of each refuted claim (one trajectory, what a report draws), so
    that presenting an audit never integrates; a claim whose trajectory cannot be
    integrated in the time has none."""
    refuted = [
        c.label
        for c in m.case.claims
        if claim_verdict(c.kind, {r.check: r.verdict for r in audit.results if r.claim == c.label})
        is Verdict.REFUTED
    ]
    curves = []
    try:
        with time_limit(seconds):
            for label in refuted:
                try:
                    curves.append(drift_curve(m, label))
                except ValueError:
                    continue  # nothing could be integrated: the report says so
    except BudgetExceeded:
        pass  # the curves done so far are kept
    return replace(audit, curves=tuple(curves))


def count_checks(case: Case) -> int:
    """How many checks an audit of ``case`` runs (for the worker's deadline)."""
    skipped = not_applicable(case)
    return sum(
        sum(spec.applies(c) for c in case.claims) if spec.per_claim else 1
        for spec in CHECKS.values()
        if spec.name not in skipped
    )


def _with_corrections(audit: CaseAudit, m: CaseMechanics, seconds: float | None) -> CaseAudit:
    try:
        with time_limit(seconds):
            family, found, conditions = derive_corrections(m, audit.results)
    except BudgetExceeded:
        reason = f"corrections: time budget exceeded ({seconds:g} s)"
        family, found, conditions = FamilyRecord("none", reason=reason), (), ()
    except Exception as exc:  # a failed correction must not lose the verdicts
        reason = f"corrections failed: {type(exc).__name__}: {exc}"
        family, found, conditions = FamilyRecord("none", reason=reason), (), ()
    return replace(audit, family=family, corrections=found, conditions=conditions)


def _run(
    spec: CheckSpec, m: CaseMechanics, claim: Claim | None = None, *, seconds: float | None
) -> CheckResult:
    started = time.perf_counter()
    label = None if claim is None else claim.label
    try:
        with time_limit(seconds):
            return spec.run(m) if claim is None else spec.run(m, claim)
    except BudgetExceeded:
        return CheckResult(
            check=spec.name,
            verdict=Verdict.INCONCLUSIVE,
            method="time budget",
            claim=label,
            reason=f"time budget exceeded ({seconds:g} s)",
            seconds=time.perf_counter() - started,
        )
    except Exception as exc:  # one failing check must not stop the audit
        return CheckResult(
            check=spec.name,
            verdict=Verdict.ERROR,
            method="exception",
            claim=None if claim is None else claim.label,
            reason=f"{type(exc).__name__}: {exc}",
            seconds=time.perf_counter() - started,
        )


def failed_audit(case_id: str, content_hash: str, result: CheckResult) -> CaseAudit:
    """The one way to record a case with no audit: a single result (check ``load`` or
    ``audit``) saying why. Every failed case audit is built here."""
    return CaseAudit(case_id, content_hash, (result,))


def failed_case(case_id: str, content_hash: str, exc: Exception) -> CaseAudit:
    """The audit of a case that could not even be loaded: one ``error`` result."""
    why = f"{type(exc).__name__}: {exc}"
    return failed_audit(
        case_id, content_hash, CheckResult("load", Verdict.ERROR, "exception", reason=why)
    )


def killed_audit(case: Case, seconds: float) -> CaseAudit:
    """The audit of a case whose worker overran its deadline and was killed."""
    reason = f"worker killed after {seconds:.0f} s (case time budget exceeded)"
    result = CheckResult("audit", Verdict.INCONCLUSIVE, "time budget", reason=reason)
    return failed_audit(case.id, case.content_hash, result)


def crashed_audit(case: Case, why: str) -> CaseAudit:
    """The audit of a case whose worker died or failed."""
    result = CheckResult("audit", Verdict.ERROR, "exception", reason=why)
    return failed_audit(case.id, case.content_hash, result)


def as_audit(case: Case, outcome: CaseAudit | Failure) -> CaseAudit:
    """A case's audit from what its call gave (on local workers or on a cluster alike):
    the audit itself, or the record of a killed, crashed or failed call."""
    if isinstance(outcome, CaseAudit):
        return outcome
    if outcome.kind == "killed":
        return killed_audit(case, outcome.seconds or 0.0)
    if outcome.kind == "crashed":
        return crashed_audit(case, f"worker died ({outcome.exitcode})")
    return crashed_audit(case, outcome.reason)


def claim_verdict(kind: ClaimKind | str, verdicts: Mapping[str, Verdict | str]) -> Verdict:
    """A claim's overall verdict: the verdict of the check its kind names (``integral``,
    ``casimir``, ``measure``, ``relation``); inconclusive where that check did not run."""
    found = verdicts.get(str(ClaimKind(kind)))
    return Verdict.INCONCLUSIVE if found is None else Verdict(found)
