"""Presenting audit results: the JSON document of CASE_FORMAT.md and the verdict table.

Only presentation lives here; the verdicts themselves come from ``audit``.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence

from ..audit.case_audit import CASE_CHECKS, claim_verdict
from ..model import Case, CaseAudit, CheckResult, Verdict
from .text_table import text_table


def _detail(result: CheckResult) -> dict:
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


def _missing(check: str, claim: str | None = None) -> CheckResult:
    return CheckResult(check, Verdict.ERROR, "not run", claim=claim, reason="check was not run")


def case_document(audit: CaseAudit, case: Case | None, version: int | None = None) -> dict:
    """One entry of ``cases`` in the audit JSON: case checks and claim verdicts."""
    by_key = {(r.check, r.claim): r for r in audit.results}
    load_error = by_key.get(("load", None))
    doc: dict = {"case": audit.case}
    if version is not None:
        doc["version"] = version
    if case is not None:
        doc["title"] = case.title
    if load_error is not None:
        doc["error"] = load_error.reason
    checks = {
        name: by_key.get((name, None)) or load_error or _missing(name) for name in CASE_CHECKS
    }
    doc["checks"] = {name: str(r.verdict) for name, r in checks.items()}
    doc["details"] = {name: _detail(r) for name, r in checks.items()}
    if audit.family is not None:
        doc["family"] = audit.family.as_dict()
    conditions = {c.target: c for c in audit.conditions}
    if "jacobi" in conditions and conditions["jacobi"].branches:
        first, *more = conditions["jacobi"].branches
        doc["conditions"] = {"jacobi": list(first)}
        if more:
            doc["conditions"]["jacobi_branches"] = [list(b) for b in more]
    discovered = [c.as_dict() for c in audit.corrections if c.claim is None]
    if discovered:
        doc["casimirs"] = discovered
    doc["claims"] = []
    for claim in case.claims if case is not None else ():
        per = {
            name: by_key.get((name, claim.label)) or load_error or _missing(name, claim.label)
            for name in ("integral", "casimir")
        }
        entry = {
            "label": claim.label,
            "kind": str(claim.kind),
            "integral": str(per["integral"].verdict),
            "casimir": str(per["casimir"].verdict),
            "verdict": claim_verdict(claim.kind, per["integral"].verdict, per["casimir"].verdict),
        }
        if claim.on:
            entry["on"] = [eq.text for eq in claim.on]
            kept = by_key.get(("invariant", claim.label))
            if kept is not None:
                per["invariant"] = kept
                entry["invariant"] = str(kept.verdict)
        entry["details"] = {name: _detail(r) for name, r in per.items()}
        numbers = [e for e in audit.evidence if e.claim == claim.label]
        if numbers:
            entry["numeric"] = numbers[0].as_dict()
        repairs = [c.as_dict() for c in audit.corrections if c.claim == claim.label]
        if repairs:
            entry["corrections"] = repairs
        found = conditions.get(claim.label)
        if found is not None and found.branches:
            first, *more = found.branches
            entry["holds_when"] = list(first)
            if more:
                entry["holds_when_branches"] = [list(b) for b in more]
        elif found is not None:
            entry["holds_when_note"] = found.reason
        doc["claims"].append(entry)
    return doc


def audit_document(
    run: int | None,
    audits: Sequence[CaseAudit],
    cases: Mapping[str, Case],
    versions: Mapping[str, int] | None = None,
) -> dict:
    """The document ``registry audit --json`` prints (shape fixed by CASE_FORMAT.md)."""
    versions = versions or {}
    return {
        "run": run,
        "cases": [case_document(a, cases.get(a.case), versions.get(a.case)) for a in audits],
    }


def disagreements(document: dict) -> list[str]:
    """Claims whose numerical evidence contradicts their symbolic verdict."""
    return [
        f"{case['case']}/{claim['label']}"
        for case in document["cases"]
        for claim in case["claims"]
        if claim.get("numeric") and not claim["numeric"]["agrees"]
    ]


def verdict_table(document: dict) -> str:
    """A plain-text table of an audit document: one row per claim, then a summary."""
    header = ("case", "family", "Poisson", "claim", "kind", "integral", "casimir", "verdict")
    rows = []
    notes = []
    repairs = []
    for case in document["cases"]:
        poisson = case["checks"].get("jacobi", "")
        family = case.get("family", {}).get("name", "")
        repairs.extend(_repair_lines(case))
        for name, detail in case["details"].items():
            if detail["verdict"] != "verified" and name != "jacobi":
                notes.append(
                    f"{case['case']}: {name} {detail['verdict']}"
                    + (f" ({detail['reason']})" if detail.get("reason") else "")
                )
        if not case["claims"]:
            rows.append((case["case"], family, poisson, "-", "", "", "", ""))
        for claim in case["claims"]:
            label = claim["label"] + (" (on set)" if claim.get("on") else "")
            rows.append(
                (
                    case["case"],
                    family,
                    poisson,
                    label,
                    claim["kind"],
                    claim["integral"],
                    claim["casimir"],
                    claim["verdict"],
                )
            )
            numeric = claim.get("numeric")
            if numeric and not numeric["agrees"]:
                compared = numeric["compared_with"]
                notes.insert(
                    0,
                    f"DISAGREEMENT {case['case']}/{claim['label']}: {compared} "
                    f"{claim[compared]} but the drift of I is {numeric['drift']:.2e} "
                    f"against {numeric['floor']:.2e} for H",
                )
            for prop in ("integral", "casimir", "invariant"):
                detail = claim["details"].get(prop)
                if detail and detail["verdict"] in ("inconclusive", "error"):
                    notes.append(
                        f"{case['case']}/{claim['label']}: {prop} {detail['verdict']}: "
                        f"{detail.get('reason', '')}"
                    )
    lines = [text_table(header, rows)]
    counts = Counter(c["verdict"] for case in document["cases"] for c in case["claims"])
    n_cases = len(document["cases"])
    summary = ", ".join(f"{n} {v}" for v, n in sorted(counts.items()))
    run = f"run {document['run']}: " if document.get("run") is not None else ""
    lines.append("")
    lines.append(f"{run}{n_cases} cases, {sum(counts.values())} claims ({summary or 'none'})")
    with_numbers = [c for case in document["cases"] for c in case["claims"] if c.get("numeric")]
    if with_numbers:
        agree = sum(c["numeric"]["agrees"] for c in with_numbers)
        lines.append(
            f"numeric evidence: {agree} of {len(with_numbers)} claims agree with their "
            "integral verdicts"
        )
    lines.extend(f"  note: {n}" for n in notes)
    if repairs:
        lines += ["", "Repairs (each re-checked):", *repairs]
    return "\n".join(lines)


def _repair_lines(case: dict) -> list[str]:
    """Readable lines for a case's conditions, discovered Casimirs and claim repairs."""
    lines = []
    name = case["case"]
    if "conditions" in case:
        lines.append(f"  {name}: Poisson when {', '.join(case['conditions']['jacobi'])}")
    for c in case.get("casimirs", []):
        lines.append(f"  {name}: a Casimir: {c['expression']}")
    for claim in case["claims"]:
        where = f"{name}/{claim['label']}"
        if "holds_when" in claim:
            lines.append(f"  {where}: holds when {', '.join(claim['holds_when'])}")
        for c in claim.get("corrections", []):
            if c["kind"] == "casimir":
                lines.append(f"  {where}: corrected Casimir: {c['expression']}")
            else:
                changed = ", ".join(f"mu{k} = {c['torque'][k - 1]}" for k in c["changed"])
                lines.append(f"  {where}: corrected torque: {changed}")
    return lines
