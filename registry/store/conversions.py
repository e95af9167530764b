"""Rows to domain objects and back: the one place where the store meets ``model``.

Each function turns one domain object into its row (or rows), or a row back into
its domain object; nothing else in the package builds or reads a row's fields.
Verdicts are stored as their text (``verdict_text``) and read back as ``Verdict``
(``verdict_of``) here and nowhere else; a number that does not exist (NaN) is
stored as NULL.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from ..language import forms
from ..model import (
    Case,
    CaseAudit,
    CaseIdentification,
    CheckResult,
    Claim,
    Conditions,
    Correction,
    DriftCurve,
    Evidence,
    ExponentOptions,
    ExponentResult,
    FamilyRecord,
    IntegralSet,
    IntegralStatus,
    SameSystem,
    Search,
    SearchOptions,
    Source,
    Verdict,
    Witness,
    component_index,
    nan_to_none,
    none_to_nan,
)
from .tables import (
    CaseRow,
    ClaimRow,
    CorrectionRow,
    DiscoveryRow,
    DriftCurveRow,
    EvidenceRow,
    ExponentRow,
    IdentificationRow,
    ResultRow,
    SearchRow,
    SourceRow,
    now,
)


def verdict_text(verdict: Verdict) -> str:
    """A verdict as the database stores it (``verified``, ...)."""
    return Verdict(verdict).value


def verdict_of(text: str) -> Verdict:
    """A stored verdict read back (ValueError for text that is no verdict)."""
    return Verdict(text)


#: Every verdict as stored, for queries that count or validate them.
VERDICT_TEXTS = tuple(verdict_text(v) for v in Verdict)


def case_row(case: Case, version: int, source_id: int) -> CaseRow:
    """The row of one case version (claims are separate rows)."""
    names = list(case.parameters) + [n for n in case.assumptions if n not in case.parameters]
    return CaseRow(
        case_id=case.id,
        version=version,
        title=case.title,
        source_id=source_id,
        locator=case.source.locator,
        notes=case.notes,
        content_hash=case.content_hash,
        text=case.text,
        path=case.path,
        **forms.columns(case.system),
        parameters={n: str(case.assumptions.get(n, "real")) for n in names},
        functions={name: [str(a) for a in args] for name, (_, args) in case.functions.items()},
        added_at=now(),
        topic=case.topic,
    )


def claim_row(claim: Claim, case_pk: int, position: int, search_id: int | None = None) -> ClaimRow:
    """The row of one claim of a stored case version (``search_id``: the search that
    attached it to the version, for a claim that is not in the case's text)."""
    return ClaimRow(
        case_pk=case_pk,
        position=position,
        label=claim.label,
        kind=str(claim.kind),
        expression=claim.expression.text,
        on=[eq.text for eq in claim.on],
        locator=claim.locator,
        notes=claim.notes,
        provenance=str(claim.provenance),
        search_id=search_id,
    )


#: The structured fields of a source besides its citation and DOI.
SOURCE_FIELDS = (
    "authors", "year", "title", "journal", "booktitle", "publisher", "volume", "issue", "pages",
    "url",
)  # fmt: skip


def source_fields(source: Source) -> dict[str, Any]:
    """A source's structured citation as the columns of its row."""
    return {
        name: list(source.authors) if name == "authors" else getattr(source, name)
        for name in SOURCE_FIELDS
    }


def fill_source(row: SourceRow, source: Source) -> None:
    """Complete a shared source row with the fields this case gives and the row lacks
    (the first case to give a field sets it)."""
    for name, value in source_fields(source).items():
        if value and not getattr(row, name):
            setattr(row, name, value)


def search_row(case_pk: int, search: Search, code_version: str, statement: str) -> SearchRow:
    """The row of a search (what it found goes in ``discovery_rows``)."""
    options = search.options.as_dict()
    return SearchRow(
        case_pk=case_pk,
        options=options,
        options_key=options_key(search.options),
        code_version=code_version,
        started_at=now(),
        seconds=float(search.seconds),
        complete=search.complete,
        coverage=list(search.coverage),
        known=list(search.known),
        dimensions=[list(d) for d in search.dimensions],
        method=search.method,
        statement=statement,
        claims=list(search.claims),
        claims_complete=search.claims_complete,
    )


def options_key(options: SearchOptions) -> str:
    """The canonical text of a search's options: equal options, equal text."""
    return json.dumps(options.as_dict(), sort_keys=True, separators=(",", ":"))


def discovery_rows(search_id: int, search: Search, derived: dict[int, int]) -> list[DiscoveryRow]:
    """One row for the generic values and one per special set (``derived``: special set
    index -> the derived case version that holds its integrals as claims)."""
    sets = [search.generic, *search.special]
    return [
        DiscoveryRow(
            search_id=search_id,
            position=i,
            when=list(s.when),
            extra=s.extra,
            integrals=list(s.integrals),
            casimir=[verdict_text(v) for v in s.casimir],
            status=[status_data(t) for t in s.status],
            derived_case_pk=derived.get(i - 1) if i else None,
            same_as=[same.as_dict() for same in s.same_as],
        )
        for i, s in enumerate(sets)
    ]


def search(row: SearchRow, case_id: str, content_hash: str, rows, on) -> Search:
    """A Search rebuilt from its rows (``on``: its level-set equations, parsed)."""
    options = row.options
    sets = [
        IntegralSet(
            tuple(r.when),
            r.extra,
            tuple(r.integrals),
            tuple(verdict_of(v) for v in r.casimir),
            tuple(integral_status(d) for d in (r.status or [])),
            same_as=tuple(SameSystem.from_dict(d) for d in (r.same_as or [])),
        )
        for r in sorted(rows, key=lambda r: r.position)
    ]
    return Search(
        case=case_id,
        content_hash=content_hash,
        options=SearchOptions(
            degree=options["degree"],
            weights=tuple(options["weights"].items()),
            on=tuple(on),
            free=tuple(options["free"]),
            relations=bool(options.get("relations", False)),
        ),
        known=tuple(row.known),
        generic=sets[0],
        special=tuple(sets[1:]),
        complete=row.complete,
        coverage=tuple(row.coverage),
        dimensions=tuple((d[0], d[1], d[2], d[3]) for d in row.dimensions),
        seconds=row.seconds,
        method=row.method,
        claims=tuple(row.claims or ()),
    )


def status_data(status: IntegralStatus) -> dict[str, Any]:
    """An integral's status as plain data (stored, and printed by ``--json``)."""
    return {
        "status": status.status,
        "equals": list(status.equals),
        "modulo": list(status.modulo),
        "relation": status.relation,
    }


def integral_status(data: dict[str, Any]) -> IntegralStatus:
    """An IntegralStatus from its ``status_data`` form."""
    return IntegralStatus(
        data["status"],
        tuple(data.get("equals", ())),
        tuple(data.get("modulo", ())),
        data.get("relation", ""),
    )


def witness(data: dict[str, Any] | None) -> Witness | None:
    """A Witness from its ``as_dict`` form (None stays None)."""
    if data is None:
        return None
    return Witness(
        point=data.get("point", {}),
        value=data.get("value", ""),
        approx=data.get("approx", ""),
        component=data.get("component", ""),
        functions=data.get("functions", {}),
    )


def check_result(row: ResultRow, label: str | None) -> CheckResult:
    """A CheckResult from its row and its claim's label."""
    return CheckResult(
        check=row.check,
        verdict=verdict_of(row.verdict),
        method=row.method,
        claim=label,
        reason=row.reason,
        residual=row.residual,
        witness=witness(row.witness),
        seconds=row.seconds,
        detail=row.detail or "",
    )


def correction_rows(
    run_id: int, case_pk: int, audit: CaseAudit, claim_ids: dict[str, int]
) -> list[CorrectionRow]:
    """The family, corrections and conditions of an audit, as rows."""
    rows = []
    if audit.family is not None:
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                kind="family",
                expression=audit.family.casimir,
                method=audit.family.method,
                # a family's Casimir is reported only once it re-checks
                verdict=None if audit.family.casimir is None else verdict_text(Verdict.VERIFIED),
                payload=audit.family.as_dict(),
            )
        )
    for c in audit.corrections:
        verdict = verdict_text(Verdict.combined(c.checks.values()))
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                claim_id=claim_ids.get(c.claim) if c.claim else None,
                kind=c.kind,
                expression=c.expression,
                method=c.method,
                verdict=verdict,
                payload={**c.as_dict(), "claim": c.claim},
            )
        )
    for cond in audit.conditions:
        payload = {
            "target": cond.target,
            "branches": [list(b) for b in cond.branches],
            "reason": cond.reason,
        }
        claim_id = None if cond.target == "jacobi" else claim_ids.get(cond.target)
        rows.append(
            CorrectionRow(
                run_id=run_id,
                case_pk=case_pk,
                claim_id=claim_id,
                kind="conditions",
                # every branch is re-checked before it is reported
                verdict=verdict_text(Verdict.VERIFIED) if cond.branches else None,
                payload=payload,
            )
        )
    return rows


def result_row(
    run_id: int, case_pk: int, claim_id: int | None, result: CheckResult, reused: bool
) -> ResultRow:
    """The row of one check result (of the claim ``claim_id``, or of the case)."""
    return ResultRow(
        run_id=run_id,
        case_pk=case_pk,
        claim_id=claim_id,
        check=result.check,
        verdict=verdict_text(result.verdict),
        method=result.method,
        reason=result.reason,
        residual=result.residual,
        witness=None if result.witness is None else result.witness.as_dict(),
        seconds=float(result.seconds),
        reused=reused,
        detail=result.detail,
    )


def curve_row(run_id: int, case_pk: int, claim_id: int, curve: DriftCurve) -> DriftCurveRow:
    """The row of a drift curve of one claim."""
    return DriftCurveRow(
        run_id=run_id,
        case_pk=case_pk,
        claim_id=claim_id,
        t=list(curve.t),
        di=list(curve.di),
        dh=list(curve.dh),
    )


def drift_curve(row: DriftCurveRow, case_id: str, label: str) -> DriftCurve:
    """A drift curve from its row, its case's id and its claim's label."""
    return DriftCurve(case_id, label, tuple(row.t), tuple(row.di), tuple(row.dh))


def evidence_row(run_id: int, case_pk: int, claim_id: int, found: Evidence) -> EvidenceRow:
    """The row of the numerical evidence for one claim."""
    return EvidenceRow(
        run_id=run_id,
        case_pk=case_pk,
        claim_id=claim_id,
        drift=nan_to_none(found.drift),
        floor=nan_to_none(found.floor),
        runs=found.runs,
        contradicts=found.contradicts,
        note=found.note,
        compared_with=found.compared_with,
        narrowed=found.narrowed,
        departure=found.departure,
        projected=found.projected,
        reason=found.reason,
    )


def evidence(row: EvidenceRow, label: str) -> Evidence:
    """Numerical evidence from its row and its claim's label."""
    return Evidence(
        label,
        none_to_nan(row.drift),
        none_to_nan(row.floor),
        row.runs,
        row.contradicts,
        row.note,
        row.compared_with,
        row.narrowed,
        row.departure,
        row.projected,
        row.reason,
    )


def derived(rows: Iterable[CorrectionRow]) -> dict:
    """CaseAudit fields rebuilt from correction rows."""
    family, corrections, conditions = None, [], []
    for row in rows:
        p = row.payload
        if row.kind == "family":
            family = FamilyRecord(**p)
        elif row.kind == "conditions":
            conditions.append(
                Conditions(p["target"], tuple(tuple(b) for b in p["branches"]), p.get("reason", ""))
            )
        else:
            corrections.append(
                Correction(
                    kind=row.kind,
                    claim=p.get("claim"),
                    expression=p.get("expression"),
                    torque=tuple(p["torque"]) if p.get("torque") else None,
                    changed=tuple(component_index(k) for k in p.get("changed", [])),
                    method=p.get("method", ""),
                    checks={name: verdict_of(v) for name, v in p.get("checks", {}).items()},
                )
            )
    return {"family": family, "corrections": tuple(corrections), "conditions": tuple(conditions)}


def exponent_row(case_pk: int, result: ExponentResult, code_version: str) -> ExponentRow:
    """The row of a Kovalevskaya analysis: its summary columns and its whole document."""
    return ExponentRow(
        case_pk=case_pk,
        options=result.options.as_dict(),
        options_key=exponent_options_key(result.options),
        code_version=code_version,
        started_at=now(),
        seconds=float(result.seconds),
        decided=result.decided,
        homogeneous=result.homogeneous,
        all_integer=result.all_integer,
        all_rational=result.all_rational,
        passes=result.passes,
        degrees=list(result.degrees),
        balances=result.balances,
        statement=result.statement,
        document=dict(result.document),
    )


def exponent_options_key(options: ExponentOptions) -> str:
    """The canonical text of an analysis's options: equal options, equal text."""
    return json.dumps(options.as_dict(), sort_keys=True, separators=(",", ":"))


def exponent_result(row: ExponentRow, case_id: str, content_hash: str) -> ExponentResult:
    """A Kovalevskaya analysis rebuilt from its row."""
    options = ExponentOptions(tuple(row.options["weights"].items()), tuple(row.options["free"]))
    return ExponentResult(case_id, content_hash, options, dict(row.document), row.seconds)


def identification_row(
    case_pk: int, found: CaseIdentification, code_version: str
) -> IdentificationRow:
    """The row of one case version's identification with the catalog."""
    return IdentificationRow(
        case_pk=case_pk,
        catalog=found.catalog,
        code_version=code_version,
        recorded_at=now(),
        seconds=float(found.seconds),
        same_as=[s.as_dict() for s in found.same_as],
        compared=list(found.compared),
        skipped=list(found.skipped),
        failed=[list(f) for f in found.failed],
        note=found.note,
    )


def identification(row: IdentificationRow, case_id: str, version: int) -> CaseIdentification:
    """An identification rebuilt from its row (``reused``: it was recorded before)."""
    return CaseIdentification(
        case_id,
        version,
        row.catalog,
        tuple(SameSystem.from_dict(d) for d in row.same_as),
        tuple(row.compared),
        tuple(row.skipped),
        tuple((str(c), str(e)) for c, e in row.failed),
        row.seconds,
        reused=True,
        note=row.note,
    )
