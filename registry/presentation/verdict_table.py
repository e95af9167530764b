"""The plain-text verdict table of an audit (what ``registry audit`` prints), and the
table of the verdicts that changed between two runs (``registry report --diff``).

Built from the audit's outcome objects (``audit.outcome``) and printed with the one
table printer (``text_table``), grouped by case; verdicts are compared as ``Verdict``
values.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

from ..audit.outcome import CaseOutcome
from ..model import CheckResult, Verdict, VerdictChange
from .text_table import grouped_table, wrapped

#: Verdicts that leave a note under the table.
_UNDECIDED = (Verdict.INCONCLUSIVE, Verdict.ERROR)


def disagreements(outcomes: Sequence[CaseOutcome]) -> list[str]:
    """Claims whose numerical evidence contradicts their symbolic verdict (case/claim)."""
    return [f"{o.case_id}/{c.label}" for o in outcomes for c in o.claims if c.contradicted]


def _verdict(result: CheckResult | None) -> str:
    """A check's verdict in a table cell ("-" where the check does not apply)."""
    return "-" if result is None else str(result.verdict)


def verdict_table(
    outcomes: Sequence[CaseOutcome], run: int | None = None, width: int | None = None
) -> str:
    """A plain-text table of an audit: each case heads its claims (with the torque's
    family and the Jacobi verdict, ``Poisson``), one row per claim; then a summary, notes
    on what was not decided, and the corrections. Wrapped to ``width`` (None: no limit).
    """
    header = ("claim", "kind", "integral", "casimir", "verdict")
    groups = []
    notes = []
    corrections = []
    for case in outcomes:
        about = [f"family {case.family.name}"] if case.family is not None else []
        about += [f"Poisson {case.poisson}"] if case.poisson else []
        title = case.case_id + (f" ({'; '.join(about)})" if about else "")
        corrections.extend(_correction_lines(case))
        for name, result in case.checks.items():
            if result.verdict is not Verdict.VERIFIED and name != "jacobi":
                notes.append(
                    f"{case.case_id}: {name} {result.verdict}"
                    + (f" ({result.reason})" if result.reason else "")
                )
        rows = []
        if not case.claims:
            rows.append(("-", "", "", "", ""))
        for claim in case.claims:
            label = claim.label + (" (on set)" if claim.on_set else "")
            verdicts = (_verdict(claim.integral), _verdict(claim.casimir), claim.verdict)
            rows.append((label, claim.claim.kind, *verdicts))
            found = claim.evidence
            if claim.contradicted and found is not None:
                compared = found.compared_with
                notes.insert(
                    0,
                    f"DISAGREEMENT {case.case_id}/{claim.label}: {compared} "
                    f"{claim.checks[compared].verdict} but the drift of I is {found.drift:.2e} "
                    f"against {found.floor:.2e} for H",
                )
            if found is not None and found.reason:
                notes.append(f"{case.case_id}/{claim.label}: numbers not compared: {found.reason}")
            for prop, result in claim.checks.items():
                if result.verdict in _UNDECIDED:
                    notes.append(
                        f"{case.case_id}/{claim.label}: {prop} {result.verdict}: {result.reason}"
                    )
        groups.append((title, rows))
    lines = [grouped_table("case (torque family; Poisson)", header, groups, width=width)]
    counts = Counter(c.verdict for case in outcomes for c in case.claims)
    summary = ", ".join(f"{n} {v}" for v, n in sorted(counts.items()))
    prefix = f"run {run}: " if run is not None else ""
    lines.append("")
    lines.append(
        wrapped(
            f"{prefix}{len(outcomes)} cases, {sum(counts.values())} claims ({summary or 'none'})",
            width,
        )
    )
    with_numbers = [c for case in outcomes for c in case.claims if c.evidence is not None]
    if with_numbers:
        agree = sum(not c.contradicted for c in with_numbers)
        lines.append(
            wrapped(
                f"numeric evidence: {agree} of {len(with_numbers)} claims agree with their "
                "integral verdicts",
                width,
            )
        )
    lines.extend(wrapped(f"note: {n}", width, indent="  ", subsequent="    ") for n in notes)
    if corrections:
        lines += ["", "Corrections (each re-checked):"]
        lines.extend(wrapped(c, width, indent="  ", subsequent="    ") for c in corrections)
    return "\n".join(lines)


def _correction_lines(case: CaseOutcome) -> list[str]:
    """Readable lines for a case's conditions, discovered Casimirs and claim corrections."""
    lines = []
    name = case.case_id
    jacobi = case.jacobi_conditions
    if jacobi is not None and jacobi.branches:
        lines.append(f"{name}: Poisson when {branches_text(jacobi.branches)}")
    for c in case.casimirs:
        lines.append(f"{name}: a Casimir: {c.expression}")
    for claim in case.claims:
        where = f"{name}/{claim.label}"
        found = claim.conditions
        if found is not None and found.branches:
            lines.append(f"{where}: holds when {branches_text(found.branches)}")
        for c in claim.corrections:
            if c.kind == "casimir":
                lines.append(f"{where}: corrected Casimir: {c.expression}")
            else:
                changed = ", ".join(f"mu{k} = {text}" for k, text in c.changed_components)
                lines.append(f"{where}: corrected torque: {changed}")
    return lines


def branches_text(branches: Sequence[Sequence[str]]) -> str:
    """Every branch of a parameter condition: equations joined by commas, branches by
    'or' (``A = C, B = C or k1 = 0, k2 = 0, k3 = 0``)."""
    return " or ".join(", ".join(branch) for branch in branches)


def diff_table(
    changes: Sequence[VerdictChange], run_a: int, run_b: int, width: int | None = None
) -> str:
    """The verdicts that changed between two runs, under each case ("no changes" when
    none), wrapped to ``width`` (None: no limit)."""
    if not changes:
        return f"no changes between run {run_a} and run {run_b}"
    header = ("claim", "check", f"run {run_a}", f"run {run_b}")
    groups: dict[str, list[tuple[str, ...]]] = {}
    for c in changes:
        row = (c.claim or "-", c.check, c.before or "-", c.after or "-")
        groups.setdefault(c.case, []).append(row)
    return grouped_table("case", header, groups.items(), width=width)
