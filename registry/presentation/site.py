"""The registry as a static web site (``registry site -o DIR``): a page per case at a
permanent path, pages per source and per topic, the searches and the corrections.

The facade gathers the data (``Catalog``: the cases frame, each case's newest version
with its newest audit, the version history, the searches); this module renders it with
the Jinja2 templates shipped in ``presentation/templates`` (autoescaping on: every text
from a case file is escaped there, and the only markup that is not is the MathML that
SymPy's printer writes from parsed expressions). Formulas are MathML with their
case-file text beside them. Output is deterministic: the same registry gives
byte-identical files (sorted everywhere, no build time written), so a site can be
versioned and archived.

Links between pages are relative, so the folder can be served from any path or opened
from disk; ``base_url`` (the address it will be served at) gives each page its canonical
address and the registry entry's BibTeX its ``url``.
"""

from __future__ import annotations

import json
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import sympy as sp
from markupsafe import Markup

from ..audit.outcome import CaseOutcome, ClaimOutcome
from ..errors import RegistryError
from ..language import forms
from ..language.parser import Namespace, parse_equation, parse_expression
from ..language.printer import to_text
from ..model import Case, CheckResult, Correction, ExponentResult, Verdict
from . import bibtex, latex
from .audit_json import audit_document
from .cas_export import LANGUAGES, export
from .exponents_output import distinct_exponents, failures, painleve_word, shown
from .mathml import NAMES, equation, mathml

if TYPE_CHECKING:
    import pandas as pd
    from jinja2 import Environment

#: The topic of a case whose file names none.
OTHER_TOPIC = "other"

#: What a download is, by file extension (the case file, its audit, three CAS files).
DOWNLOADS = (
    ("toml", "case file (TOML; loads with registry add)"),
    ("audit.json", "audit (JSON, the format of registry audit --json)"),
    ("m", "Mathematica"),
    ("mpl", "Maple"),
    ("py", "Python with SymPy (Sage runs it too)"),
)


@dataclass(frozen=True)
class CaseEntry:
    """One case as the site shows it: its newest version (parsed, with its file's text)
    and the newest audit of that version (None if it has not been audited)."""

    case: Case
    version: int
    text: str
    run: int | None = None
    outcome: CaseOutcome | None = None


@dataclass(frozen=True)
class ExponentEntry:
    """A case's newest Kovalevskaya analysis as the site shows it: its number, the case
    version analysed, the analysis, and what it proves together with the newest search
    on the whole phase space (``discovery.every_degree``; None without a search)."""

    number: int
    version: int
    result: ExponentResult
    every_degree: str | None = None


@dataclass(frozen=True)
class Catalog:
    """What the site shows, gathered by the facade (``Registry.catalog``): the rows of
    ``Registry.cases()``, an entry per case, every stored version (``case, version,
    content_hash, added_at``), the recorded searches and discoveries, and the newest
    Kovalevskaya analysis of each case that has one (by case id)."""

    cases: pd.DataFrame
    entries: tuple[CaseEntry, ...]
    versions: pd.DataFrame
    searches: pd.DataFrame
    discoveries: pd.DataFrame
    exponents: dict[str, ExponentEntry] = field(default_factory=dict)
    #: one row per (case, catalog case it is the same system as): ``reg.identifications()``
    identifications: pd.DataFrame | None = None


# ------------------------------------------------------------------ formulas


@dataclass(frozen=True)
class Formula:
    """A formula to show: its MathML (or None when it could not be written) and the
    case-file text a reader copies."""

    mathml: Markup | None
    text: str
    #: The same formula inline in a sentence (a level set, a parameter condition).
    inline: Markup | None = None


def _formula(lhs: sp.Basic | None, expr: sp.Basic, text: str) -> Formula:
    """``lhs = expr`` (or ``expr``) as MathML, with its text."""
    shown = expr if lhs is None else equation(lhs, expr)
    try:
        block, inline = mathml(shown, display=True), mathml(shown)  # printed once (cached)
        return Formula(Markup(block), text, Markup(inline))
    except (ValueError, TypeError, RecursionError):
        return Formula(None, text)


def _parsed(lhs: sp.Basic | None, text: str, ns: Namespace, label: str = "") -> Formula:
    """A formula stored as case-file text (a residual, a correction), parsed again to show it;
    shown as text only when it no longer parses."""
    shown = f"{label} = {text}" if label else text
    try:
        return _formula(lhs, parse_expression(text, ns), shown)
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Formula(None, shown)


def _parsed_equation(text: str, ns: Namespace) -> Formula:
    """An equation ``lhs = rhs`` stored as text (a parameter condition, a level set)."""
    try:
        lhs, rhs = parse_equation(text, ns)
    except (RegistryError, ValueError, TypeError, RecursionError):
        return Formula(None, text)
    return _formula(lhs, rhs, text)


# ------------------------------------------------------------------ the bracket


def bracket(case: Case) -> tuple[str, str]:
    """The bracket of a case's system (docs/case-format.md), as (name, how it was decided):
    for the reference paper's Pi, e(3) for kappa = 0, so(4) for kappa > 0, so(3,1) for
    kappa < 0; a bracket given entry by entry; none for a system given by its equations."""
    dynamics = case.dynamics
    if dynamics.bracket is None:
        return "none", "the system is given by its equations of motion"
    if dynamics.torque is None:
        return "given", "the case gives its bracket entry by entry"
    k = dynamics.kappa.expr
    if k == 0:
        return "e(3)", "kappa = 0"
    if k.is_positive:
        return "so(4)", f"kappa = {k} > 0"
    if k.is_negative:
        return "so(3,1)", f"kappa = {k} < 0"
    return "by the sign of kappa", f"kappa = {k}: e(3), so(4) or so(3,1) as it is 0, > 0, < 0"


# ------------------------------------------------------------------ view models


def _slug(text: str) -> str:
    """A file name for a topic: lower-case letters, digits and dashes."""
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-") or "topic"


def _topic(case: Case) -> str:
    return case.topic or OTHER_TOPIC


def _verdicts(outcome: CaseOutcome | None) -> Counter:
    """How many claims came out with each verdict in the newest audit."""
    if outcome is None:
        return Counter()
    return Counter(str(c.verdict) for c in outcome.claims)


def _summary(outcome: CaseOutcome | None) -> str:
    """The verdicts in a few words: "2 verified, 1 refuted", or "not audited"."""
    if outcome is None:
        return "not audited"
    counts = _verdicts(outcome)
    if outcome.error:
        return "could not be audited"
    return ", ".join(f"{n} {v}" for v, n in sorted(counts.items())) or "no claims"


def _link(url: str) -> str | None:
    """A link to a web address from a case file, only for http(s) (never javascript:)."""
    return url if re.match(r"https?://", url, flags=re.I) else None


def _doi_url(doi: str) -> str | None:
    """The resolver address of a DOI (its characters percent-encoded where needed)."""
    from urllib.parse import quote

    return f"https://doi.org/{quote(doi, safe='/:;()._-')}" if doi else None


@dataclass
class _Views:
    """The data of every page, computed once from the catalog."""

    catalog: Catalog
    base_url: str

    @cached_property
    def entries(self) -> dict[str, CaseEntry]:
        return {e.case.id: e for e in sorted(self.catalog.entries, key=lambda e: e.case.id)}

    @cached_property
    def rows(self) -> dict[str, dict[str, Any]]:
        """The cases frame's row of each case, by id."""
        return {r["case"]: r for r in self.catalog.cases.to_dict("records")}

    @cached_property
    def bib(self) -> dict[str, bibtex.BibEntry]:
        """The BibTeX entry of each case's source, by case id."""
        return {c: e for e in bibtex.entries(self.catalog.cases) for c in e.cases}

    @cached_property
    def sources(self) -> dict[str, bibtex.BibEntry]:
        """Every source's entry by its key (the source's page is ``sources/<key>.html``)."""
        return {e.key: e for e in bibtex.entries(self.catalog.cases)}

    @cached_property
    def searches(self) -> list[dict[str, Any]]:
        return _records(self.catalog.searches)

    @cached_property
    def discoveries(self) -> list[dict[str, Any]]:
        return _records(self.catalog.discoveries)

    @cached_property
    def claims(self) -> dict[str, list[dict[str, Any]]]:
        """The claims of each case with their verdicts and corrections (``_claims``), by id."""
        out = {}
        for case_id, entry in self.entries.items():
            ns = forms.namespace(entry.case)
            out[case_id] = _claims(entry.case, entry.outcome, ns)
        return out

    def newest_search(self, case_id: str) -> dict[str, Any] | None:
        """The newest recorded search of a case (any of its versions), or None."""
        found = [s for s in self.searches if s["case"] == case_id]
        return max(found, key=lambda s: s["search"]) if found else None

    def index_row(self, entry: CaseEntry) -> dict[str, Any]:
        """One row of the index (and of the JSON index the filters read)."""
        case, row = entry.case, self.rows.get(entry.case.id, {})
        search = self.newest_search(case.id)
        authors = list(case.source.authors) or list(row.get("authors") or [])
        return {
            "id": case.id,
            "title": case.title,
            "topic": _topic(case),
            "topic_page": f"topics/{_slug(_topic(case))}.html",
            "authors": authors,
            "year": case.source.year,
            "citation": case.source.citation,
            "source_page": f"sources/{self.bib[case.id].key}.html" if case.id in self.bib else None,
            "bracket": bracket(case)[0],
            "verdicts": sorted(_verdicts(entry.outcome)),
            "summary": _summary(entry.outcome),
            "search": search["statement"] if search else "no search recorded",
            "aliases": list(case.aliases),
        }

    def case_page(self, entry: CaseEntry) -> dict[str, Any]:
        """Everything a case's page shows."""
        case, outcome = entry.case, entry.outcome
        ns = forms.namespace(case)
        versions = self.catalog.versions
        history = _records(versions[versions["case"] == case.id])
        search = self.newest_search(case.id)
        found = [d for d in self.discoveries if search and d["search"] == search["search"]]
        return {
            **self.index_row(entry),
            "case": case,
            "version": entry.version,
            "run": entry.run,
            "doi_url": _doi_url(case.source.doi),
            "url": _link(case.source.url),
            "bracket_reason": bracket(case)[1],
            "system": _system(case),
            "parameters": [
                (name, str(case.assumptions.get(name, "real"))) for name in case.parameters
            ],
            "functions": [
                f"{name}({', '.join(map(str, args))})" for name, (_, args) in case.functions.items()
            ],
            "checks": _checks(outcome, ns) if outcome else [],
            "family": outcome.family if outcome else None,
            "family_functions": _family(outcome, ns) if outcome else [],
            "casimirs": [_correction(c, ns) for c in outcome.casimirs] if outcome else [],
            "jacobi": _branches(outcome.jacobi_conditions, ns) if outcome else [],
            "error": outcome.error if outcome else None,
            "claims": self.claims[case.id],
            "newest_search": search,
            "search_discoveries": [_discovery(d, ns) for d in found],
            "exponents": _exponents(self.catalog.exponents.get(case.id), frozenset(self.entries)),
            **self.same_systems(case.id),
            "history": history,
            "source_bibtex": self.bib[case.id].text if case.id in self.bib else "",
            "entry_bibtex": self.entry_bibtex(entry, history),
            "downloads": [(f"{case.id}.{ext}", what) for ext, what in DOWNLOADS],
            "audited": outcome is not None,
        }

    def same_systems(self, case_id: str) -> dict[str, Any]:
        """The catalog cases this case is the same system as (with their parameter values
        and whether each is also this case: ``equivalent``), the cases that are this one
        at some of its values (``members``), and whether it was identified at all."""
        frame = self.catalog.identifications
        cases = self.catalog.cases
        row = cases[cases["case"] == case_id].iloc[0]
        identified = row.get("same_as") is not None
        note = row.get("identification_note")
        state = {
            "identified": identified,
            "note": note,
            "complete": row.get("identification_complete") is not False,
            "current": row.get("identification_current") is not False,
        }
        if frame is None or not len(frame):
            return {**state, "same_systems": [], "members": []}
        mine = frame[frame["case"] == case_id]
        same = [
            {
                "case": row["same_as"],
                "at": ", ".join(f"{k} = {v}" for k, v in row["values"].items()),
                "via": ", ".join(f"{k} = {v}" for k, v in row["transformation"].items() if k != v),
                "equivalent": bool(row["equivalent"]),
            }
            for row in mine.to_dict("records")
        ]
        members = sorted(
            row["case"]
            for row in frame[frame["same_as"] == case_id].to_dict("records")
            if not row["equivalent"]
        )
        return {**state, "same_systems": same, "members": members}

    def entry_bibtex(self, entry: CaseEntry, history: Sequence[dict[str, Any]]) -> str:
        """The registry entry of a case as BibTeX (cite the page, next to its source)."""
        case = entry.case
        added = next((h["added_at"] for h in history if h["version"] == entry.version), None)
        fields = {
            "title": f"{case.title} (registry case {case.id})",
            "howpublished": (
                f"Registry of rigid-body integrability claims, case {case.id}, "
                f"version {entry.version}"
            ),
            "year": str(added.year) if added is not None else "",
            "note": f"Content hash {entry.case.content_hash}. Source: {case.source.citation}",
        }
        lines = [f"@misc{{registry:{case.id},"]
        lines += [f"  {k} = {{{latex.escape(v, balanced=True)}}}," for k, v in fields.items() if v]
        if self.base_url:
            lines.append(f"  url = {{{self.base_url}cases/{case.id}.html}},")
        return "\n".join([*lines, "}"])


def _records(frame: pd.DataFrame) -> list[dict[str, Any]]:
    """A frame's rows as dicts, missing values as None."""
    out = []
    for row in frame.to_dict("records"):
        out.append({k: (None if _missing(v) else v) for k, v in row.items()})
    return out


def _missing(value: Any) -> bool:
    if isinstance(value, list | dict | tuple | str):
        return False
    try:
        return bool(value != value) or value is None  # NaN, NaT
    except (TypeError, ValueError):
        return False


def _system(case: Case) -> list[Formula]:
    """The system as its file gives it (moments and potential, H, torque, kappa; or its
    equations, or its bracket), then H where the file does not give it itself."""
    dynamics = case.dynamics
    shown = [_formula(g.symbol, g.expr, f"{g.name} = {g.text}") for g in dynamics.given]
    h = dynamics.hamiltonian
    if h is not None and not any(g.name == "H" for g in dynamics.given):
        shown.append(_formula(sp.Symbol("H"), h, f"H = {to_text(h)}"))
    return shown


def _result(name: str, result: CheckResult, ns: Namespace) -> dict[str, Any]:
    """One check's verdict, method and time; the residual and witness of a refutation."""
    witness = result.witness if result.verdict is Verdict.REFUTED else None
    residual = None
    if result.verdict is Verdict.REFUTED and result.residual is not None:
        residual = _parsed(NAMES["residual"], result.residual, ns, "R")
    return {
        "check": name,
        "verdict": str(result.verdict),
        "method": result.method,
        "seconds": f"{round(result.seconds, 4):.3g}",
        "reason": result.reason,
        "residual": residual,
        "witness": witness,
    }


def _checks(outcome: CaseOutcome, ns: Namespace) -> list[dict[str, Any]]:
    return [_result(name, r, ns) for name, r in outcome.checks.items()]


def _family(outcome: CaseOutcome, ns: Namespace) -> list[Formula]:
    """The functions exhibiting the torque's family (phi, psi, a(s))."""
    family = outcome.family
    if family is None:
        return []
    lhs = {
        "phi": (NAMES["phi"], family.phi),
        "psi": (NAMES["psi"], family.psi),
        "a(s)": (sp.Function("a")(sp.Symbol("s")), family.a),
    }
    return [_parsed(sym, text, ns, name) for name, (sym, text) in lhs.items() if text]


def _correction(fix: Correction, ns: Namespace) -> dict[str, Any]:
    """A re-checked correction: a Casimir, or a torque with its changed components."""
    formulas = []
    if fix.kind == "casimir":
        formulas.append(_parsed(NAMES["casimir"], fix.expression or "", ns, "C"))
    for k, text in fix.changed_components:
        formulas.append(_parsed(sp.Symbol(f"mu_{k}'"), text, ns, f"mu{k}'"))
    return {
        "kind": fix.kind,
        "claim": fix.claim,
        "method": fix.method,
        "checks": [(k, str(v)) for k, v in fix.checks.items()],
        "kept": [f"mu{k}" for k in fix.kept_components] if fix.kind == "torque" else [],
        "formulas": formulas,
    }


def _branches(found, ns: Namespace) -> list[list[Formula]]:
    """Parameter conditions: each branch (the most general first) a list of equations."""
    if found is None:
        return []
    return [[_parsed_equation(eq, ns) for eq in branch] for branch in found.branches]


def _claim(claim, outcome: ClaimOutcome | None, ns: Namespace) -> dict[str, Any]:
    """A claim with its verdicts, evidence, corrections and conditions."""
    view: dict[str, Any] = {
        "claim": claim,
        "formula": _formula(
            sp.Symbol(claim.label) if re.fullmatch(r"[A-Za-z]\w*", claim.label) else None,
            claim.expression.expr,
            f"{claim.label} = {claim.expression.text}",
        ),
        "on": [_formula(e.lhs, e.rhs, e.text) for e in claim.on],
        "verdict": str(outcome.verdict) if outcome else "not audited",
        "checks": [],
        "evidence": None,
        "corrections": [],
        "conditions": [],
        "conditions_reason": "",
    }
    if outcome is not None:
        view["checks"] = [_result(name, r, ns) for name, r in outcome.checks.items()]
        view["evidence"] = outcome.evidence
        view["corrections"] = [_correction(c, ns) for c in outcome.corrections]
        view["conditions"] = _branches(outcome.conditions, ns)
        if outcome.conditions is not None and not outcome.conditions.branches:
            view["conditions_reason"] = outcome.conditions.reason
    return view


def _claims(case: Case, outcome: CaseOutcome | None, ns: Namespace) -> list[dict[str, Any]]:
    found = {c.label: c for c in outcome.claims} if outcome else {}
    return [_claim(c, found.get(c.label), ns) for c in case.claims]


def _discovery(row: dict[str, Any], ns: Namespace) -> dict[str, Any]:
    """A set of parameter values a search found integrals on, with the integrals."""
    return {
        **row,
        "when_formulas": [_parsed_equation(eq, ns) for eq in row.get("when") or []],
        "integral_formulas": [_parsed(None, text, ns) for text in row.get("integrals") or []],
    }


def _classifications(searches: list[dict[str, Any]], views: _Views) -> list[dict[str, Any]]:
    """The recorded searches of families (free parameters), newest first, each with its
    special sets: the catalog cases each is the same system as (those the site holds),
    and how many of its integrals are new."""
    out = []
    for s in reversed(searches):
        if not s.get("free"):
            continue
        sets = []
        for d in s["discoveries"]:
            if not d.get("when"):
                continue  # the generic values
            status = d.get("status") or []
            same = [x for x in d.get("same_as") or [] if x["case"] in views.entries]
            sets.append({**d, "same_as": same, "new": sum(st["status"] == "new" for st in status)})
        out.append({**s, "sets": sets})
    return out


# ------------------------------------------------------------------ writing


def _exponents(
    entry: ExponentEntry | None, pages: frozenset[str] = frozenset()
) -> dict[str, Any] | None:
    """A case's newest Kovalevskaya analysis for its page: the weights, each balance with
    its exponents and Painlevé test, the degrees, a family's special sets (with what the
    method guarantees of their list), the sets its stratifications found (each named by
    the cases it is, linked where ``pages`` has them), the statements."""
    if entry is None:
        return None
    d = entry.result.document
    balances = []
    for b in d.get("balances", ()):
        whole = ", ".join(f"{x} = {v}" for x, v in b["point"].items())
        point = ", ".join(f"{x} = {shown(v)}" for x, v in b["point"].items())
        root_of = b.get("root_of", "")
        conditions = [c for r in b["painleve"]["resonances"] for c in r["conditions"]]
        elided = [w for w, s in ((whole, point), (root_of, shown(root_of))) if w != s]
        elided += [c for c in conditions if shown(c) != c]
        balances.append(
            {
                "point": point,
                "root_of": shown(root_of),
                "whole": elided,  # the point, polynomial and conditions elided, in full
                "family": b.get("dimension", 0),
                "along": ", ".join(b.get("along", ())),
                "exponents": ", ".join(b["exponents"]),
                "compatible": b["painleve"]["compatible"],
                "failing": failures(b["painleve"]["resonances"]),
            }
        )
    special = [
        {
            "kind": s["kind"],
            "when": ", ".join(s["when"]) or "every value",
            "painleve": s["painleve"]["passes"] if "painleve" in s else None,
            "exponents": [", ".join(e) for e in s.get("exponents", ())],
        }
        for s in d.get("special", ())
    ]
    complete = d.get("complete", {})
    return {
        "number": entry.number,
        "version": entry.version,
        "weights": ", ".join(f"{k} = {v}" for k, v in d["weights"].items()),
        "free": ", ".join(d.get("free", ())),
        "decided": entry.result.decided,
        "homogeneous": d.get("homogeneous"),
        "balances": balances,
        "degrees": ", ".join(map(str, d.get("degrees", ()))) or "none",
        "painleve": painleve_word(entry.result.passes),
        "family": "special" in d,
        "special": special,
        "complete": ", ".join(
            f"{k.replace('_', '-')} {'yes' if v else 'no'}" for k, v in complete.items()
        ),
        "coverage": [] if all(complete.values()) else list(d.get("coverage", ())),
        "strata": [
            _strata(d[key], heading, pages)
            for key, heading in (
                ("painleve_sets", "Sets where the Painlevé (ARS) test passes"),
                ("half_integer_sets", "Sets where every exponent is in ½ℤ"),
            )
            if key in d
        ],
        "witness": _witness(d["witness"]) if "witness" in d else None,
        "statement": entry.result.statement,
        "every_degree": entry.every_degree,
    }


def _witness(w: dict[str, Any]) -> dict[str, Any]:
    """The balance at rational values that shows the Painlevé test failing for generic
    values (an analysis out of time), long expressions elided with the whole behind."""
    point = ", ".join(f"{x} = {shown(v)}" for x, v in w["point"].items())
    exponents = ", ".join(map(shown, w["exponents"]))
    whole = [
        (", ".join(f"{x} = {v}" for x, v in w["point"].items()), point),
        (w["root_of"], shown(w["root_of"])),
        (", ".join(w["exponents"]), exponents),
    ]
    return {
        "at": ", ".join(f"{p} = {v}" for p, v in w["values"].items()),
        "point": point,
        "root_of": shown(w["root_of"]),
        "exponents": exponents,
        "approximate": ", ".join(w.get("approximate", ())),
        "whole": [full for full, short in whole if full != short],
    }


def _strata(found: dict[str, Any], heading: str, pages: frozenset[str]) -> dict[str, Any]:
    """One stratification of a family for its page: each set (its equations, the
    parameters free on it, its kind, its exponents once each with their count, the
    catalog cases it is), whether the list is complete, and what was left undecided."""
    sets = []
    for s in found.get("passing", found.get("sets", ())):
        sets.append(
            {
                "when": ", ".join(s["when"]) or "every value",
                "free": ", ".join(s["free"]),
                "kind": s.get("kind") or "",
                "exponents": distinct_exponents(s.get("exponents", ())),
                "same_as": [(c, c in pages) for c in s.get("same_as", ())],
                "named": "same_as" in s,
                "notes": list(s.get("notes", ())),
            }
        )
    return {
        "heading": heading,
        "sets": sets,
        "strata": found["strata"],
        "complete": found["complete"],
        "undecided": list(found["undecided"]),
    }


def _environment() -> Environment:
    from jinja2 import Environment, PackageLoader, StrictUndefined, select_autoescape

    env = Environment(
        loader=PackageLoader("registry.presentation", "templates"),
        autoescape=select_autoescape(["html"], default_for_string=True, default=True),
        undefined=StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )
    env.policies["json.dumps_kwargs"] = {"sort_keys": True, "ensure_ascii": False}
    return env


def _asset(env: Environment, name: str) -> str:
    """A file shipped beside the templates (the stylesheet, the script), unrendered."""
    assert env.loader is not None
    return env.loader.get_source(env, name)[0]


def _normalised_base(base_url: str) -> str:
    """The base address with exactly one trailing slash ("" when none is given)."""
    return base_url.rstrip("/") + "/" if base_url else ""


def site_files(catalog: Catalog, base_url: str = "") -> dict[str, bytes]:
    """Every file of the site, by its path relative to the site's folder."""
    views = _Views(catalog, _normalised_base(base_url))
    env = _environment()
    files: dict[str, str | bytes] = {}
    common = {"base_url": views.base_url}

    def page(path: str, template: str, **context: Any) -> None:
        root = "../" * path.count("/")
        files[path] = env.get_template(template).render(root=root, path=path, **common, **context)

    entries = list(views.entries.values())
    rows = [views.index_row(e) for e in entries]
    topics = sorted({r["topic"] for r in rows}, key=lambda t: (t == OTHER_TOPIC, t))
    index = {
        "cases": rows,
        "topics": topics,
        "brackets": sorted({r["bracket"] for r in rows}),
        "verdicts": [*[str(v) for v in Verdict], "not audited"],
    }
    page("index.html", "index.html", **index)
    files["index.json"] = json.dumps(rows, indent=1, sort_keys=True, ensure_ascii=False) + "\n"
    for asset in ("site.css", "site.js"):  # the loader's own files, as they are
        files[asset] = _asset(env, asset)

    taken = set(views.entries)
    for entry in entries:
        case = entry.case
        page(f"cases/{case.id}.html", "case.html", **views.case_page(entry))
        files[f"cases/{case.id}.toml"] = entry.text
        document = audit_document(entry.run, [entry.outcome] if entry.outcome else [])
        files[f"cases/{case.id}.audit.json"] = json.dumps(document, indent=2) + "\n"
        for ext, language in (("m", "mathematica"), ("mpl", "maple"), ("py", "python")):
            files[f"cases/{case.id}.{ext}"] = export(case, LANGUAGES[language])
        for alias in case.aliases:
            if alias not in taken:  # a case's own id wins over another's old id
                taken.add(alias)
                page(f"cases/{alias}.html", "redirect.html", alias=alias, target=case)

    for name in topics:
        members = [r for r in rows if r["topic"] == name]
        page(f"topics/{_slug(name)}.html", "topic.html", topic=name, cases=members)
    page(
        "topics/index.html",
        "topics.html",
        topics=[(t, _slug(t), sum(r["topic"] == t for r in rows)) for t in topics],
    )
    for key, source in views.sources.items():
        members = [r for r in rows if r["id"] in source.cases]
        first = views.entries[members[0]["id"]].case.source if members else None
        page(f"sources/{key}.html", "source.html", key=key, entry=source, cases=members,
             source=first, doi_url=_doi_url(first.doi) if first else None,
             url=_link(first.url) if first else None)  # fmt: skip
    page(
        "sources/index.html",
        "sources.html",
        sources=[
            (key, views.entries[s.cases[0]].case.source.citation, len(s.cases))
            for key, s in views.sources.items()
            if s.cases and s.cases[0] in views.entries
        ],
    )

    searches = []
    for s in views.searches:
        searched = views.entries.get(s["case"])
        ns = forms.namespace(searched.case) if searched else Namespace({})
        found = [_discovery(d, ns) for d in views.discoveries if d["search"] == s["search"]]
        searches.append({**s, "discoveries": found, "known_case": searched is not None})
    page("searches.html", "searches.html", searches=searches)
    page(
        "classifications.html",
        "classifications.html",
        classifications=_classifications(searches, views),
    )

    corrections = []
    for entry in entries:
        outcome = entry.outcome
        if outcome is None:
            continue
        ns = forms.namespace(entry.case)
        claims = [c for c in views.claims[entry.case.id] if c["corrections"] or c["conditions"]]
        jacobi = _branches(outcome.jacobi_conditions, ns)
        casimirs = [_correction(c, ns) for c in outcome.casimirs]
        if claims or jacobi or casimirs or outcome.family is not None:
            corrections.append(
                {"id": entry.case.id, "title": entry.case.title, "run": entry.run,
                 "family": outcome.family, "family_functions": _family(outcome, ns),
                 "claims": claims, "jacobi": jacobi, "casimirs": casimirs}
            )  # fmt: skip
    page("corrections.html", "corrections.html", cases=corrections)
    return {p: (v if isinstance(v, bytes) else v.encode("utf-8")) for p, v in sorted(files.items())}


def build_site(catalog: Catalog, out_dir: Path, base_url: str = "") -> list[Path]:
    """Write the site into ``out_dir`` (created if need be); the paths written, sorted.
    Files of earlier builds that the registry no longer has are left alone."""
    written = []
    for relative, data in site_files(catalog, base_url).items():
        path = Path(out_dir) / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.is_file() or path.read_bytes() != data:
            path.write_bytes(data)
        written.append(path)
    return written
