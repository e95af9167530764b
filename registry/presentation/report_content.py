"""The content of a report of an audit run, built from the run's outcome objects.

A table of contents by topic, a summary table (each case linked to its section),
then the cases grouped by topic, each with its source and system in LaTeX, the
checks of the system (with the residual and witness of a refutation), its family
and Casimirs, and each claim with its verdicts, numeric evidence, corrections, parameter
conditions and the drift plot of a refuted claim. The content is said once, to a writer
(``report_writers``) that knows how its format writes each block.
"""

from __future__ import annotations

import re
import tempfile
from collections import Counter
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path

import pandas as pd
import sympy as sp

from ..audit.outcome import CaseOutcome, ClaimOutcome
from ..errors import RegistryError, UnknownRunError
from ..language import forms
from ..language.parser import Namespace, parse_equation, parse_expression
from ..model import (
    Case,
    CheckResult,
    Conditions,
    Correction,
    DriftCurve,
    Evidence,
    FamilyRecord,
    Verdict,
    nan_to_none,
)
from .mathml import NAMES, equation
from .plot_images import DriftImages
from .report_writers import FORMATS, WRITERS, Code, Link, Math, Part, Writer, anchor

#: A claim's drift plot: (case, claim label) -> the image written, or why there is none.
Plotter = Callable[[Case, str], "Path | str"]


def _formula(w: Writer, text: str, ns: Namespace) -> Math | Code:
    """An expression of the case-file language as math, or verbatim if it does not parse."""
    try:
        expr = parse_expression(text, ns)
        return Math(w.tex(expr), expr, text)
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Code(text)


def _equation(w: Writer, text: str, ns: Namespace) -> Math | Code:
    """An equation ``lhs = rhs`` (a parameter condition) as math, or verbatim."""
    try:
        lhs, rhs = parse_equation(text, ns)
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Code(text)
    return Math(f"{w.tex(lhs)} = {w.tex(rhs)}", equation(lhs, rhs), text)


#: The symbol each left-hand side of ``_show`` stands for, in the HTML writer's MathML.
_LHS: dict[str, sp.Basic] = {
    r"\mathcal{R}": NAMES["residual"],
    r"\mathcal{C}": NAMES["casimir"],
    r"\varphi": NAMES["phi"],
    r"\psi": NAMES["psi"],
    "a(s)": sp.Function("a")(sp.Symbol("s")),
    **{rf"\mu_{{{k}}}'": sp.Symbol(f"mu_{k}'") for k in (1, 2, 3)},
}


def _show(w: Writer, lhs: str, text: str, ns: Namespace) -> None:
    """Display ``lhs = expression`` (LaTeX), or the expression verbatim if it does not parse."""
    shown = _formula(w, text, ns)
    if isinstance(shown, Math):
        w.equation(f"{lhs} = {shown.latex}", equation(_LHS[lhs], shown.expr), text)
    else:
        w.para(Math(lhs, _LHS[lhs]), " = ", shown)


def _joined(parts: Iterable[Part], sep: str = ", ") -> list[Part]:
    """Parts separated by ``sep``."""
    out: list[Part] = []
    for p in parts:
        out.extend([sep, p] if out else [p])
    return out


def _header(w: Writer, run: pd.Series, outcomes: Sequence[CaseOutcome]) -> None:
    """Title, when the run ran, with which code, and how the claims came out."""
    w.heading(1, f"Audit report: run {run['run']}")
    w.para(
        f"Run {run['run']} ({run['status']}): started {_when(run['started_at'])}, "
        f"finished {_when(run['finished_at'])}."
    )
    versions = f", sympy {run['sympy_version']}, Python {run['python_version']}."
    w.para("Code version ", Code(str(run["code_version"])), versions)
    counts = Counter(c.verdict for case in outcomes for c in case.claims)
    summary = ", ".join(f"{n} {v}" for v, n in sorted(counts.items())) or "none"
    w.para(f"{len(outcomes)} cases, {sum(counts.values())} claims ({summary}).")


def _when(stamp) -> str:
    return "-" if stamp is None or pd.isna(stamp) else f"{stamp:%Y-%m-%d %H:%M:%S} UTC"


#: The topic of a case whose file names none.
OTHER_TOPIC = "other"


def topic(outcome: CaseOutcome) -> str:
    """The topic a case is filed under in a report (its ``topic``, else "other")."""
    return (outcome.case.topic if outcome.case is not None else "") or OTHER_TOPIC


def by_topic(outcomes: Sequence[CaseOutcome]) -> dict[str, list[CaseOutcome]]:
    """The outcomes grouped by topic, topics in alphabetical order ("other" last)."""
    groups: dict[str, list[CaseOutcome]] = {}
    for outcome in outcomes:
        groups.setdefault(topic(outcome), []).append(outcome)
    return dict(sorted(groups.items(), key=lambda g: (g[0] == OTHER_TOPIC, g[0])))


def _cell(result: CheckResult | None) -> str:
    """A check's verdict in a table cell ("-" where the check does not apply)."""
    return "-" if result is None else str(result.verdict)


def _summary(w: Writer, outcomes: Sequence[CaseOutcome]) -> None:
    """One row per claim: case (linked to its section), claim, kind, integral, casimir,
    verdict."""
    rows = []
    for case in outcomes:
        name = Link(case.case_id, anchor("case", case.case_id))
        if not case.claims:
            rows.append((name, "-", "", "", "", Verdict.ERROR if case.error is not None else ""))
        for c in case.claims:
            label = c.label + (" (on set)" if c.on_set else "")
            row = (name, label, c.claim.kind, _cell(c.integral), _cell(c.casimir))
            rows.append((*row, c.verdict))
    w.heading(2, "Summary", anchor("summary"))
    w.table(("case", "claim", "kind", "integral", "casimir", "verdict"), rows)


def _contents(w: Writer, groups: dict[str, list[CaseOutcome]]) -> None:
    """The table of contents: each topic with its cases, linked."""
    w.heading(2, "Contents", anchor("contents"))
    for name, cases in groups.items():
        links = _joined(Link(c.case_id, anchor("case", c.case_id)) for c in cases)
        w.para(Link(name, anchor("topic", name)), f" ({len(cases)}): ", *links)


def _system(w: Writer, case: Case) -> None:
    """The system as its file gives it, in LaTeX (moments, potential, torque and kappa; or
    H; or equations; or a bracket), and the declared parameters."""
    w.heading(3, "System")
    for g in case.dynamics.given:
        w.equation(
            f"{w.tex(g.symbol)} = {w.tex(g.expr)}",
            equation(g.symbol, g.expr),
            f"{g.name} = {g.text}",
        )
    declared = [f"{name} ({case.assumptions.get(name, 'real')})" for name in case.parameters]
    declared += [
        f"{name}({', '.join(map(str, args))})" for name, (_, args) in case.functions.items()
    ]
    if declared:
        w.para("Parameters and functions: ", ", ".join(declared), ".")


def _result(w: Writer, name: str, result: CheckResult, ns: Namespace) -> None:
    """One check's verdict, method and time; for a refutation, the residual and witness."""
    reason = f"; {result.reason}" if result.reason else ""
    seconds = round(result.seconds, 4)  # as the JSON document gives it
    w.para(f"{name}: {result.verdict} ({result.method}, {seconds:.3g} s){reason}")
    if result.verdict is not Verdict.REFUTED:
        return
    witness = result.witness
    if result.residual is not None:
        where = f" ({witness.component})" if witness is not None and witness.component else ""
        w.para(f"Residual{where}, which should vanish:")
        _show(w, r"\mathcal{R}", result.residual, ns)
    if witness is not None:
        point = ", ".join(f"{k} = {v}" for k, v in witness.point.items())
        w.para("Witness point: ", Code(point))
        if witness.functions:
            functions = ", ".join(f"{k} = {v}" for k, v in witness.functions.items())
            w.para("with the functions ", Code(functions))
        w.para("Residual there: ", Code(witness.value), f" (about {witness.approx}).")


def _family(w: Writer, family: FamilyRecord | None, ns: Namespace) -> None:
    """The torque's family in the paper's classification, with its functions."""
    if family is None:
        return
    how = f" ({family.method})" if family.method else ""
    w.para(f"Torque family: {family.name}{how}.")
    for text, lhs in ((family.phi, r"\varphi"), (family.psi, r"\psi"), (family.a, "a(s)")):
        if text:
            _show(w, lhs, text, ns)
    if family.reason:
        w.para(f"Note: {family.reason}.")


def _branches(w: Writer, lead: str, branches: Sequence[Sequence[str]], ns: Namespace) -> None:
    """Parameter conditions: equations joined by commas, branches by 'or'."""
    parts: list[Part] = [lead]
    for i, branch in enumerate(branches):
        parts += ([" or "] if i else []) + _joined(_equation(w, eq, ns) for eq in branch)
    w.para(*parts, ".")


def _case_checks(w: Writer, case: CaseOutcome, ns: Namespace) -> None:
    """The checks of the system itself, its family, Casimirs and Jacobi conditions."""
    w.heading(3, "Checks of the system")
    for name, result in case.checks.items():
        _result(w, name, result, ns)
    _family(w, case.family, ns)
    for found in case.casimirs:
        w.para(f"A Casimir of the case's own torque ({found.method}):")
        _show(w, r"\mathcal{C}", found.expression or "", ns)
    if case.jacobi_conditions is not None and case.jacobi_conditions.branches:
        _branches(w, "The Jacobi identity holds when ", case.jacobi_conditions.branches, ns)


def _evidence(w: Writer, found: Evidence | None) -> None:
    """Numeric evidence: the largest drift of I next to that of H (the noise floor)."""
    if found is None:
        return
    drift, floor = nan_to_none(found.drift), nan_to_none(found.floor)
    if drift is None:
        w.para(f"Numeric evidence: no trajectory could be integrated ({found.note}).")
        return
    agrees = "CONTRADICTS" if found.contradicts else "agrees with"
    if found.reason:
        agrees = "not compared with"
    where = (
        f" Trajectories on a smaller set than the claim's: {found.narrowed}."
        if found.narrowed
        else ""
    )
    departure = found.departure
    if departure is not None:
        how = "projected back onto the claim's set after each step" if found.projected else "free"
        where += f" Trajectories {how}; largest relative residual of its equations {departure:.3g}."
    if found.reason:
        where += f" Not compared: {found.reason}."
    w.para(
        f"Numeric evidence ({found.runs} trajectories): largest relative drift of I "
        f"{drift:.3g}, of H {floor:.3g}; {agrees} the "
        f"{found.compared_with} verdict.{where}"
    )


def _correction(w: Writer, fix: Correction, ns: Namespace) -> None:
    """A re-checked correction: a corrected Casimir, or a torque with its changed components."""
    checks = ", ".join(f"{k} {v}" for k, v in fix.checks.items())
    if fix.kind == "casimir":
        w.para(f"Corrected Casimir ({fix.method}; re-checked: {checks}):")
        _show(w, r"\mathcal{C}", fix.expression or "", ns)
        return
    lead = f"Corrected torque ({fix.method}; re-checked: {checks}), keeping "
    kept = (Math(rf"\mu_{{{k}}}", sp.Symbol(f"mu_{k}")) for k in fix.kept_components)
    w.para(lead, *_joined(kept), ":")
    for k, text in fix.changed_components:
        _show(w, rf"\mu_{{{k}}}'", text, ns)


def _conditions(w: Writer, found: Conditions | None, ns: Namespace) -> None:
    """The parameter conditions under which a claim holds, or why none were found."""
    if found is None:
        return
    if found.branches:
        _branches(w, "The claim holds when ", found.branches, ns)
    elif found.reason:
        w.para(f"No parameter condition found: {found.reason}.")


def _claim(w: Writer, outcome: ClaimOutcome, case: Case, ns: Namespace, plot: Plotter | None):
    """One claim: its expression, verdicts, evidence, corrections and drift plot."""
    claim = outcome.claim
    w.heading(4, f"Claim {claim.label} ({claim.kind}): {outcome.verdict}")
    w.para("Claimed" + (f" at {claim.locator}" if claim.locator else "") + ":")
    claimed = claim.expression
    w.equation(
        f"I = {w.tex(claimed.expr)}",
        equation(sp.Symbol("I"), claimed.expr),
        f"{claim.label} = {claimed.text}",
    )
    if claim.on:
        level_set = (
            Math(f"{w.tex(e.lhs)} = {w.tex(e.rhs)}", equation(e.lhs, e.rhs), e.text)
            for e in claim.on
        )
        w.para("on the level set ", *_joined(level_set), ".")
    for name, result in outcome.checks.items():
        _result(w, name, result, ns)
    _evidence(w, outcome.evidence)
    for fix in outcome.corrections:
        _correction(w, fix, ns)
    _conditions(w, outcome.conditions, ns)
    if plot is not None and outcome.verdict is Verdict.REFUTED:
        made = plot(case, claim.label)
        if isinstance(made, Path):
            w.image(made, f"drift of {claim.label} and of H along a trajectory")
        else:
            w.para(f"No drift plot: {made}.")


def _case_section(w: Writer, outcome: CaseOutcome, plot: Plotter | None) -> None:
    """Everything about one case: source, system, checks and claims."""
    case = outcome.case
    w.heading(
        3, f"{outcome.case_id}: {case.title if case else ''}", anchor("case", outcome.case_id)
    )
    if case is None:
        w.para("The case could not be audited: ", Code(outcome.error or "unknown error"))
        return
    source = ", ".join(x for x in (case.source.citation, case.source.locator) if x)
    doi = f" (doi {case.source.doi})" if case.source.doi else ""
    version = "?" if outcome.version is None else outcome.version
    w.para(f"Source: {source}{doi}. Version {version}.")
    ns = forms.namespace(case)
    _system(w, case)
    _case_checks(w, outcome, ns)
    for claim in outcome.claims:
        _claim(w, claim, case, ns, plot)


# ------------------------------------------------------------------------ runs


def run_row(frame: pd.DataFrame, run: int | None) -> pd.Series:
    """The row of ``run`` (default: the newest) in ``Registry.runs()``; UnknownRunError if
    there is none."""
    if run is None:
        if frame.empty:
            raise RegistryError("no audit run yet; run 'registry audit' first")
        run = int(frame["run"].max())
    rows = frame[frame["run"] == run]
    if rows.empty:
        raise UnknownRunError(run)
    return rows.iloc[0]


def _plotter(directory: Path, curves: Mapping[tuple[str, str], DriftCurve | str]) -> Plotter:
    """Drift plots of the ``curves`` (by case and claim; a text says why there is none)
    written into ``directory`` as drift-<case>-<claim>.png: drawn once per curve, then
    read from the cache folder (``plot_images``)."""
    images = DriftImages()

    def plot(case: Case, label: str) -> Path | str:
        curve = curves.get((case.id, label), "no trajectory was integrated")
        if isinstance(curve, str):
            return curve
        name = re.sub(r"[^A-Za-z0-9-]+", "-", f"drift-{case.id}-{label}") + ".png"
        directory.mkdir(parents=True, exist_ok=True)
        (directory / name).write_bytes(images.png(curve))
        return directory / name

    return plot


def plotted(outcomes: Sequence[CaseOutcome]) -> list[tuple[Case, str]]:
    """The claims whose drift a report plots: the refuted ones, (case, label) each."""
    return [
        (o.case, c.label)
        for o in outcomes
        if o.case is not None
        for c in o.claims
        if c.verdict is Verdict.REFUTED
    ]


def build_report(
    run: pd.Series,
    outcomes: Sequence[CaseOutcome],
    fmt: str = "md",
    out_dir: Path | None = None,
    curves: Mapping[tuple[str, str], DriftCurve | str] | None = None,
) -> str:
    """The text of a report of one audit run in ``fmt`` (md, html, tex): ``run`` is its
    row of ``Registry.runs()`` (``run_row``), ``outcomes`` what it found case by case
    (``AuditReport.outcomes()``); ``Registry.report`` gathers both.

    The drift plots of refuted claims (``plotted``) draw ``curves`` (by case and claim,
    computed by the audit; None: no plots), written into ``out_dir`` (default: the
    current directory) for md and tex, and embedded in the file for html.
    """
    if fmt not in WRITERS:
        raise RegistryError(f"unknown report format {fmt!r}; choose one of {', '.join(FORMATS)}")
    row = run
    number = int(row["run"])
    outcomes = sorted(outcomes, key=lambda o: o.case_id)
    with tempfile.TemporaryDirectory() as scratch:
        where = Path(scratch) if fmt == "html" else Path(out_dir or ".")
        plot = _plotter(where, curves) if curves is not None else None
        w = WRITERS[fmt]()
        _header(w, row, outcomes)
        groups = by_topic(outcomes)
        _contents(w, groups)
        _summary(w, outcomes)
        for name, cases in groups.items():
            w.heading(2, name[:1].upper() + name[1:], anchor("topic", name))
            for outcome in cases:
                _case_section(w, outcome, plot)
        return w.finish(f"Audit report: run {number}")
