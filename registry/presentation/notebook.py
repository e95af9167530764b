"""Notebook display of cases and audits: escaped HTML tables and LaTeX arrays.

Importing this module installs them as Jupyter reprs (``_repr_html_``,
``_repr_latex_``) of ``Case`` and ``CaseAudit``; see ``install``.
"""

from __future__ import annotations

from html import escape

import sympy as sp

from ..model import Case, CaseAudit, CheckResult, Claim, Verdict, Witness
from . import latex

#: Colour of each verdict in the audit table.
COLOURS = {
    Verdict.VERIFIED: "#1a7f37",
    Verdict.REFUTED: "#cf222e",
    Verdict.INCONCLUSIVE: "#9a6700",
    Verdict.ERROR: "#8250df",
}


# ------------------------------------------------------------------ HTML


def _code(text: str) -> str:
    return f"<code>{escape(text)}</code>"


def _row(head: str, cell: str) -> str:
    """One table row: an escaped header and a cell that is already HTML."""
    return f"<tr><th style='text-align:left'>{escape(head)}</th><td>{cell}</td></tr>"


def _source_html(case: Case) -> str:
    """The citation, its locator and a DOI link."""
    parts = [escape(case.source.citation)]
    if case.source.locator:
        parts.append(escape(case.source.locator))
    if case.source.doi:
        url = escape(f"https://doi.org/{case.source.doi}", quote=True)
        parts.append(f"<a href='{url}'>doi:{escape(case.source.doi)}</a>")
    return ", ".join(parts)


def _claim_html(claim: Claim) -> str:
    """A claim's expression, and the level set it is claimed on."""
    cell = _code(claim.expression.text)
    if claim.on:
        cell += " on " + ", ".join(_code(eq.text) for eq in claim.on)
    return cell


def case_html(case: Case) -> str:
    """A case as an HTML table: title, id, citation, the system as its file gives it
    (moments, potential and torque, a Hamiltonian, equations or a bracket), claims."""
    rows = [
        _row("source", _source_html(case)),
        *(_row(g.label, _code(g.text)) for g in case.dynamics.given),
        *(_row(f"{c.label} ({c.kind})", _claim_html(c)) for c in case.claims),
    ]
    caption = f"<caption><b>{escape(case.title)}</b> {_code(case.id)}</caption>"
    return f"<table class='registry-case'>{caption}{''.join(rows)}</table>"


def _witness_html(witness: Witness | None) -> str:
    """Where a refuted residual is nonzero: the point and the value there."""
    if witness is None:
        return ""
    point = ", ".join(f"{k} = {v}" for k, v in witness.point.items())
    funcs = "".join(f"; {k} = {v}" for k, v in witness.functions.items())
    where = f" [{witness.component}]" if witness.component else ""
    return _code(f"{point}{funcs}") + escape(f"{where}: value {witness.value} ≈ {witness.approx}")


def _result_html(r: CheckResult) -> str:
    """One row of the audit table."""
    colour = COLOURS.get(r.verdict, "inherit")
    witness = _witness_html(r.witness) if r.verdict is Verdict.REFUTED else escape(r.reason)
    cells = [
        escape(r.check),
        escape(r.claim or ""),
        f"<span style='color:{colour}'>{escape(str(r.verdict))}</span>",
        escape(r.method),
        f"{r.seconds:.3f}",
        witness,
    ]
    return "<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>"


def audit_html(audit: CaseAudit) -> str:
    """An audit as an HTML table: check, claim, verdict, method, seconds, witness or reason."""
    head = ("check", "claim", "verdict", "method", "seconds", "witness / reason")
    header = "<tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>"
    caption = f"<caption>audit of {_code(audit.case)}</caption>"
    rows = "".join(_result_html(r) for r in audit.results)
    return f"<table class='registry-audit'>{caption}{header}{rows}</table>"


# ------------------------------------------------------------------ LaTeX


def _tex(expr: sp.Expr) -> str:
    return sp.latex(expr)


def _text(text: str) -> str:
    return r"\text{" + latex.escape(text, balanced=True) + "}"


def _claim_tex(claim: Claim) -> tuple[str, str]:
    """The head (label and kind) and body (expression, level set) of a claim's row."""
    body = _tex(claim.expression.expr)
    if claim.on:
        equations = r",\ ".join(f"{_tex(eq.lhs)} = {_tex(eq.rhs)}" for eq in claim.on)
        body += r"\quad\text{on}\ " + equations
    return _text(f"{claim.label} ({claim.kind})"), body


def case_latex(case: Case) -> str:
    """A case as a LaTeX array in math mode, expressions typeset by ``sympy.latex``."""
    rows = [
        (r"\textbf{" + latex.escape(case.title, balanced=True) + "}", _text(case.id)),
        (_text("source"), _text(case.source.citation)),
        *((_tex(g.symbol), _tex(g.expr)) for g in case.dynamics.given),
        *(_claim_tex(c) for c in case.claims),
    ]
    body = r" \\ ".join(f"{head} & {cell}" for head, cell in rows)
    return r"$\displaystyle \begin{array}{ll} " + body + r" \end{array}$"


# ------------------------------------------------------------------ Jupyter


def install() -> None:
    """Make ``Case`` and ``CaseAudit`` display themselves in Jupyter with these functions."""
    Case._repr_html_ = case_html  # type: ignore[attr-defined]
    Case._repr_latex_ = case_latex  # type: ignore[attr-defined]
    CaseAudit._repr_html_ = audit_html  # type: ignore[attr-defined]


install()
