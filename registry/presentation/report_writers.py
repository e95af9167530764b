"""Reports of an audit run for people: Markdown, one self-contained HTML file, or LaTeX.

The content (summary table, each case's system, claims, verdicts, residuals,
witnesses, numeric evidence, repairs and drift plots) is built once from
``report.audit_document`` and the stored case texts, and written by one small
writer per format.
"""

from __future__ import annotations

import base64
import html
import io
import re
import struct
import tempfile
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import sympy as sp

from ..audit.outcome import outcomes
from ..errors import RegistryError, UnknownRunError
from ..language.casefile import parse_case_text
from ..language.parser import Namespace, parse_equation, parse_expression
from ..model import Case, CaseAudit
from . import latex
from .audit_json import audit_document

if TYPE_CHECKING:
    from ..api import Registry

#: The formats ``build_report`` writes, by name (the name is also the file extension).
FORMATS = ("md", "html", "tex")
#: Formulas longer than this (LaTeX characters) are shown as source in HTML, not rendered.
MAX_RENDERED = 3000


@dataclass(frozen=True)
class Math:
    """A LaTeX formula, inline in a paragraph."""

    latex: str


@dataclass(frozen=True)
class Code:
    """Text shown verbatim: a witness point, or an expression that did not parse."""

    text: str


Part = str | Math | Code
#: Makes the drift plot of (case, claim label): the PNG's path, or why there is none.
Plotter = Callable[[Case, str], "Path | str"]


# ----------------------------------------------------------------------- writers


class _Writer:
    """Collects blocks of one document; subclasses say how each block is written."""

    def __init__(self) -> None:
        self.blocks: list[str] = []

    def inline(self, parts: Iterable[Part]) -> str:
        """A run of text, inline math and verbatim text."""
        out = []
        for p in parts:
            if isinstance(p, Math):
                out.append(self.math(p.latex))
            elif isinstance(p, Code):
                out.append(self.code(p.text))
            else:
                out.append(self.escape(p))
        return "".join(out)

    def para(self, *parts: Part) -> None:
        self.blocks.append(self.paragraph(self.inline(parts)))

    def table(self, header: Sequence[str], rows: Sequence[Sequence[str]]) -> None:
        cells = [[self.escape(str(c)) for c in row] for row in rows]
        self.blocks.append(self.tabular([self.escape(h) for h in header], cells))


class _Markdown(_Writer):
    """Markdown with $...$ math (GitHub, Jupyter); images linked relatively."""

    def escape(self, text: str) -> str:
        return re.sub(r"([\\`*_\[\]<>|$])", r"\\\1", text)

    def math(self, latex: str) -> str:
        return f"${latex}$"

    def code(self, text: str) -> str:
        fence = "``" if "`" in text else "`"
        return f"{fence}{text}{fence}"

    def heading(self, level: int, text: str) -> None:
        self.blocks.append(f"{'#' * level} {self.escape(text)}")

    def paragraph(self, text: str) -> str:
        return text

    def equation(self, latex: str) -> None:
        self.blocks.append(f"$$\n{latex}\n$$")

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        lines = [header, ["---"] * len(header), *rows]
        return "\n".join("| " + " | ".join(r) + " |" for r in lines)

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(f"![{self.escape(alt)}]({path.name})")

    def finish(self, title: str) -> str:
        return "\n\n".join(self.blocks) + "\n"


class _Html(_Writer):
    """One self-contained HTML file: formulas and plots are embedded PNG images."""

    def escape(self, text: str) -> str:
        return html.escape(text, quote=True)

    def math(self, latex: str, display: bool = False) -> str:
        png = _math_png(latex) if len(latex) <= MAX_RENDERED else None
        if png is None:
            return f"<code>{self.escape(latex)}</code>"
        return _img(png, latex, "eq" if display else "math", scale=0.6)

    def code(self, text: str) -> str:
        return f"<code>{self.escape(text)}</code>"

    def heading(self, level: int, text: str) -> None:
        self.blocks.append(f"<h{level}>{self.escape(text)}</h{level}>")

    def paragraph(self, text: str) -> str:
        return f"<p>{text}</p>"

    def equation(self, latex: str) -> None:
        self.blocks.append(f'<div class="display">{self.math(latex, display=True)}</div>')

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        head = "".join(f"<th>{h}</th>" for h in header)
        body = "\n".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
        return f"<table>\n<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody>\n</table>"

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(f"<figure>{_img(path.read_bytes(), alt, 'plot')}</figure>")

    def finish(self, title: str) -> str:
        body = "\n".join(self.blocks)
        return (
            '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
            f"<title>{self.escape(title)}</title>\n<style>{_CSS}</style>\n</head>\n"
            f"<body>\n{body}\n</body>\n</html>\n"
        )


_CSS = """
body { font-family: sans-serif; max-width: 60em; margin: 2em auto; line-height: 1.45; }
table { border-collapse: collapse; } th, td { border: 1px solid #bbb; padding: 0.2em 0.6em; }
.display { overflow-x: auto; margin: 0.6em 0 0.6em 2em; }
img.math { vertical-align: middle; } img.plot { max-width: 100%; }
code { background: #f3f3f3; overflow-wrap: anywhere; }
"""


class _Tex(_Writer):
    """A LaTeX fragment to \\input (needs amsmath and graphicx); plots next to the file."""

    _HEADINGS = {1: "section", 2: "subsection", 3: "subsubsection"}

    def escape(self, text: str) -> str:
        return latex.escape(text)

    def math(self, latex: str) -> str:
        return f"${latex}$"

    def code(self, text: str) -> str:
        return rf"\texttt{{{self.escape(text)}}}"

    def heading(self, level: int, text: str) -> None:
        command = self._HEADINGS.get(level, "paragraph")
        self.blocks.append(rf"\{command}*{{{self.escape(text)}}}")

    def paragraph(self, text: str) -> str:
        return text

    def equation(self, latex: str) -> None:
        self.blocks.append(f"\\[\n{latex}\n\\]")

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        lines = [" & ".join(r) + r" \\" for r in [header, *rows]]
        lines.insert(1, r"\hline")
        body = "\n".join(lines)
        spec = "l" * len(header)
        return f"\\begin{{tabular}}{{{spec}}}\n\\hline\n{body}\n\\hline\n\\end{{tabular}}"

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(
            f"\\begin{{center}}\n\\includegraphics[width=0.8\\linewidth]{{{path.name}}}\n"
            f"\\end{{center}}"
        )

    def finish(self, title: str) -> str:
        head = f"% {title}\n% Needs \\usepackage{{amsmath,graphicx}} in the preamble.\n"
        return head + "\n\n".join(self.blocks) + "\n"


_WRITERS: dict[str, type[_Writer]] = {"md": _Markdown, "html": _Html, "tex": _Tex}


@lru_cache(maxsize=2048)
def _math_png(latex: str) -> bytes | None:
    """A formula rendered by matplotlib's mathtext (no TeX, no network); None if unsupported."""
    from matplotlib import mathtext

    buf = io.BytesIO()
    try:
        mathtext.math_to_image(f"${latex}$", buf, dpi=200, format="png")
    except (ValueError, RuntimeError):
        return None
    return buf.getvalue()


def _img(png: bytes, alt: str, css: str, scale: float = 1.0) -> str:
    """An <img> with the PNG inline as base64 (``scale`` < 1 for high-resolution formulas)."""
    width, height = struct.unpack(">II", png[16:24])
    data = base64.b64encode(png).decode("ascii")
    return (
        f'<img class="{css}" alt="{html.escape(alt, quote=True)}" '
        f'width="{round(width * scale)}" height="{round(height * scale)}" '
        f'src="data:image/png;base64,{data}">'
    )


# ----------------------------------------------------------------------- content


def _formula(text: str, ns: Namespace) -> Math | Code:
    """An expression of the case-file language in LaTeX, or verbatim if it does not parse."""
    try:
        return Math(sp.latex(parse_expression(text, ns)))
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Code(text)


def _equation(text: str, ns: Namespace) -> Math | Code:
    """An equation ``lhs = rhs`` (a parameter condition) in LaTeX, or verbatim."""
    try:
        lhs, rhs = parse_equation(text, ns)
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Code(text)
    return Math(f"{sp.latex(lhs)} = {sp.latex(rhs)}")


def _show(w: _Writer, lhs: str, text: str, ns: Namespace) -> None:
    """Display ``lhs = expression`` (LaTeX), or the expression verbatim if it does not parse."""
    shown = _formula(text, ns)
    if isinstance(shown, Math):
        w.equation(f"{lhs} = {shown.latex}")
    else:
        w.para(Math(lhs), " = ", shown)


def _joined(parts: Iterable[Part], sep: str = ", ") -> list[Part]:
    """Parts separated by ``sep``."""
    out: list[Part] = []
    for p in parts:
        out.extend([sep, p] if out else [p])
    return out


def _header(w: _Writer, run: pd.Series, document: dict) -> None:
    """Title, when the run ran, with which code, and how the claims came out."""
    w.heading(1, f"Audit report: run {run['run']}")
    w.para(
        f"Run {run['run']} ({run['status']}): started {_when(run['started_at'])}, "
        f"finished {_when(run['finished_at'])}."
    )
    versions = f", sympy {run['sympy_version']}, Python {run['python_version']}."
    w.para("Code version ", Code(str(run["code_version"])), versions)
    counts = Counter(c["verdict"] for case in document["cases"] for c in case["claims"])
    summary = ", ".join(f"{n} {v}" for v, n in sorted(counts.items())) or "none"
    w.para(f"{len(document['cases'])} cases, {sum(counts.values())} claims ({summary}).")


def _when(stamp) -> str:
    return "-" if stamp is None or pd.isna(stamp) else f"{stamp:%Y-%m-%d %H:%M:%S} UTC"


def _summary(w: _Writer, document: dict) -> None:
    """One row per claim: case, claim, kind, integral, casimir, verdict."""
    rows = []
    for case in document["cases"]:
        if not case["claims"]:
            rows.append((case["case"], "-", "", "", "", "error" if "error" in case else ""))
        for c in case["claims"]:
            label = c["label"] + (" (on set)" if c.get("on") else "")
            rows.append((case["case"], label, c["kind"], c["integral"], c["casimir"], c["verdict"]))
    w.heading(2, "Summary")
    w.table(("case", "claim", "kind", "integral", "casimir", "verdict"), rows)


def _system(w: _Writer, case: Case) -> None:
    """Inertia, potential and torque in LaTeX, and the declared parameters."""
    w.heading(3, "System")
    inertia = (sp.latex(e) for e in case.system.inertia_exprs)
    w.equation(r",\quad ".join(f"{n} = {e}" for n, e in zip("ABC", inertia, strict=True)))
    w.equation(f"U = {sp.latex(case.system.potential.expr)}")
    for k, mu in enumerate(case.system.torque_exprs, start=1):
        w.equation(rf"\mu_{{{k}}} = {sp.latex(mu)}")
    declared = [f"{name} ({case.assumptions.get(name, 'real')})" for name in case.parameters]
    declared += [
        f"{name}({', '.join(map(str, args))})" for name, (_, args) in case.functions.items()
    ]
    if declared:
        w.para("Parameters and functions: ", ", ".join(declared), ".")


def _result(w: _Writer, name: str, detail: dict, ns: Namespace) -> None:
    """One check's verdict, method and time; for a refutation, the residual and witness."""
    reason = f"; {detail['reason']}" if detail.get("reason") else ""
    w.para(f"{name}: {detail['verdict']} ({detail['method']}, {detail['seconds']:.3g} s){reason}")
    if detail["verdict"] != "refuted":
        return
    witness = detail.get("witness") or {}
    if detail.get("residual") is not None:
        where = f" ({witness['component']})" if witness.get("component") else ""
        w.para(f"Residual{where}, which should vanish:")
        _show(w, r"\mathcal{R}", detail["residual"], ns)
    if witness:
        point = ", ".join(f"{k} = {v}" for k, v in witness["point"].items())
        w.para("Witness point: ", Code(point))
        if witness.get("functions"):
            functions = ", ".join(f"{k} = {v}" for k, v in witness["functions"].items())
            w.para("with the functions ", Code(functions))
        w.para("Residual there: ", Code(witness["value"]), f" (about {witness['approx']}).")


def _family(w: _Writer, family: dict | None, ns: Namespace) -> None:
    """The torque's family in the paper's classification, with its functions."""
    if not family:
        return
    how = f" ({family['method']})" if family.get("method") else ""
    w.para(f"Torque family: {family['name']}{how}.")
    for key, lhs in (("phi", r"\varphi"), ("psi", r"\psi"), ("a", "a(s)")):
        if family.get(key):
            _show(w, lhs, family[key], ns)
    if family.get("reason"):
        w.para(f"Note: {family['reason']}.")


def _branches(w: _Writer, lead: str, branches: Sequence[Sequence[str]], ns: Namespace) -> None:
    """Parameter conditions: equations joined by commas, branches by 'or'."""
    parts: list[Part] = [lead]
    for i, branch in enumerate(branches):
        parts += ([" or "] if i else []) + _joined(_equation(eq, ns) for eq in branch)
    w.para(*parts, ".")


def _case_checks(w: _Writer, entry: dict, ns: Namespace) -> None:
    """The checks of the system itself, its family, Casimirs and Jacobi conditions."""
    w.heading(3, "Checks of the system")
    for name, detail in entry["details"].items():
        _result(w, name, detail, ns)
    _family(w, entry.get("family"), ns)
    for found in entry.get("casimirs", []):
        w.para(f"A Casimir of the case's own torque ({found['method']}):")
        _show(w, r"\mathcal{C}", found["expression"], ns)
    conditions = entry.get("conditions", {})
    if conditions:
        branches = [conditions["jacobi"], *conditions.get("jacobi_branches", [])]
        _branches(w, "The Jacobi identity holds when ", branches, ns)


def _evidence(w: _Writer, numeric: dict | None) -> None:
    """Numeric evidence: the largest drift of I next to that of H (the noise floor)."""
    if not numeric:
        return
    if numeric["drift"] is None:
        w.para(f"Numeric evidence: no trajectory could be integrated ({numeric.get('note', '')}).")
        return
    agrees = "agrees with" if numeric["agrees"] else "CONTRADICTS"
    narrowed = numeric.get("narrowed")
    where = f" Trajectories on a smaller set than the claim's: {narrowed}." if narrowed else ""
    w.para(
        f"Numeric evidence ({numeric['runs']} trajectories): largest relative drift of I "
        f"{numeric['drift']:.3g}, of H {numeric['floor']:.3g}; {agrees} the "
        f"{numeric['compared_with']} verdict.{where}"
    )


def _repairs(w: _Writer, entry: dict, ns: Namespace) -> None:
    """Re-checked corrections of a claim and the parameter conditions under which it holds."""
    for fix in entry.get("corrections", []):
        checks = ", ".join(f"{k} {v}" for k, v in fix["checks"].items())
        if fix["kind"] == "casimir":
            w.para(f"Corrected Casimir ({fix['method']}; re-checked: {checks}):")
            _show(w, r"\mathcal{C}", fix["expression"], ns)
            continue
        kept = [k for k in (1, 2, 3) if k not in fix["changed"]]
        lead = f"Corrected torque ({fix['method']}; re-checked: {checks}), keeping "
        w.para(lead, *_joined(Math(rf"\mu_{{{k}}}") for k in kept), ":")
        for k in fix["changed"]:
            _show(w, rf"\mu_{{{k}}}'", fix["torque"][k - 1], ns)
    if entry.get("holds_when"):
        branches = [entry["holds_when"], *entry.get("holds_when_branches", [])]
        _branches(w, "The claim holds when ", branches, ns)
    elif entry.get("holds_when_note"):
        w.para(f"No parameter condition found: {entry['holds_when_note']}.")


def _claim(w: _Writer, entry: dict, case: Case, ns: Namespace, plot: Plotter | None) -> None:
    """One claim: its expression, verdicts, evidence, repairs and drift plot."""
    claim = case.claim(entry["label"])
    w.heading(3, f"Claim {claim.label} ({claim.kind}): {entry['verdict']}")
    w.para("Claimed" + (f" at {claim.locator}" if claim.locator else "") + ":")
    w.equation(f"I = {sp.latex(claim.expression.expr)}")
    if claim.on:
        level_set = (Math(f"{sp.latex(e.lhs)} = {sp.latex(e.rhs)}") for e in claim.on)
        w.para("on the level set ", *_joined(level_set), ".")
    for name, detail in entry["details"].items():
        _result(w, name, detail, ns)
    _evidence(w, entry.get("numeric"))
    _repairs(w, entry, ns)
    if plot is not None and entry["verdict"] == "refuted":
        made = plot(case, claim.label)
        if isinstance(made, Path):
            w.image(made, f"drift of {claim.label} and of H along a trajectory")
        else:
            w.para(f"No drift plot: {made}.")


def _case_section(w: _Writer, entry: dict, case: Case | None, plot: Plotter | None) -> None:
    """Everything about one case: source, system, checks and claims."""
    w.heading(2, f"{entry['case']}: {case.title if case else entry.get('title', '')}")
    if case is None:
        w.para("The case could not be audited: ", Code(entry.get("error", "unknown error")))
        return
    source = ", ".join(x for x in (case.source.citation, case.source.locator) if x)
    doi = f" (doi {case.source.doi})" if case.source.doi else ""
    w.para(f"Source: {source}{doi}. Version {entry.get('version', '?')}.")
    ns = Namespace(case.parameters, case.functions)
    _system(w, case)
    _case_checks(w, entry, ns)
    for claim in entry["claims"]:
        _claim(w, claim, case, ns, plot)


# ------------------------------------------------------------------------ runs


def _run_row(reg: Registry, run: int | None) -> pd.Series:
    """The runs() row of ``run`` (default: the newest); UnknownRunError if there is none."""
    frame = reg.runs()
    if run is None:
        if frame.empty:
            raise RegistryError("no audit run yet; run 'registry audit' first")
        run = int(frame["run"].max())
    rows = frame[frame["run"] == run]
    if rows.empty:
        raise UnknownRunError(run)
    return rows.iloc[0]


def _run_cases(
    reg: Registry, audits: Sequence[CaseAudit]
) -> tuple[dict[str, Case], dict[str, int]]:
    """The case versions a run audited, parsed (by id), and their version numbers."""
    ids = list(dict.fromkeys(a.case for a in audits))
    stored = reg.store.case_versions(ids, latest_only=False) if ids else []
    by_hash = {(s.case_id, s.content_hash): s for s in stored}
    cases, versions = {}, {}
    for a in audits:
        found = by_hash.get((a.case, a.content_hash))
        if found is None:
            continue
        versions[a.case] = found.version
        try:
            cases[a.case] = parse_case_text(found.text, found.path or found.case_id)
        except RegistryError:
            pass  # shown as a case that could not be audited
    return cases, versions


@lru_cache(maxsize=32)
def _drift_png(case: Case, label: str) -> bytes:
    """The drift plot of a claim as PNG bytes (cached: reports of one run in several formats)."""
    from .plots import drift_plot

    with tempfile.TemporaryDirectory() as scratch:
        return drift_plot(case, label, Path(scratch) / "drift.png").read_bytes()


def _plotter(directory: Path) -> Plotter:
    """Drift plots written into ``directory`` as drift-<case>-<claim>.png."""

    def plot(case: Case, label: str) -> Path | str:
        name = re.sub(r"[^A-Za-z0-9-]+", "-", f"drift-{case.id}-{label}") + ".png"
        try:
            png = _drift_png(case, label)
        except (ValueError, KeyError) as exc:
            return str(exc)
        directory.mkdir(parents=True, exist_ok=True)
        (directory / name).write_bytes(png)
        return directory / name

    return plot


def build_report(
    reg: Registry,
    run: int | None = None,
    fmt: str = "md",
    out_dir: Path | None = None,
    plots: bool = True,
) -> str:
    """The text of a report of one audit run (default: the newest) in ``fmt`` (md, html, tex).

    Drift plots of refuted claims are written into ``out_dir`` (default: the current
    directory) for md and tex, and embedded in the file for html.
    """
    if fmt not in _WRITERS:
        raise RegistryError(f"unknown report format {fmt!r}; choose one of {', '.join(FORMATS)}")
    row = _run_row(reg, run)
    number = int(row["run"])
    audits = [a for _, a in sorted(reg.store.run_results(number), key=lambda item: item[0])]
    cases, versions = _run_cases(reg, audits)
    document = audit_document(number, outcomes(audits, cases, versions))
    with tempfile.TemporaryDirectory() as scratch:
        where = Path(scratch) if fmt == "html" else Path(out_dir or ".")
        plot = _plotter(where) if plots else None
        w = _WRITERS[fmt]()
        _header(w, row, document)
        _summary(w, document)
        for entry in document["cases"]:
            _case_section(w, entry, cases.get(entry["case"]), plot)
        return w.finish(f"Audit report: run {number}")
