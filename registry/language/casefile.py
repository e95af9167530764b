"""Case files: read one TOML file (docs/case-format.md) into a ``registry.model.Case``.

Everything in a file is validated before anything is built, and every problem
found is reported at once in one ``CaseFormatError`` (up to MAX_PROBLEMS of them),
each with its field (``claims[2].expression``), what is wrong and the offending
text. A file is untrusted input: the limits below and in ``registry.language.limits``
bound the work any file can cause, and nothing in it is executed.

Examples
--------
>>> case = parse_case_text('''
... id = "free-body"
... title = "Euler's free rigid body"
... [source]
... citation = "L. Euler (1765)"
... [system]
... inertia = ["A", "B", "C"]
... [parameters]
... A = "positive"
... B = "positive"
... C = "positive"
... [[claims]]
... label = "H"
... kind = "integral"
... expression = "M1**2/A + M2**2/B + M3**2/C"
... ''')
>>> case.claims[0].kind, case.parameters["A"].is_positive
(<ClaimKind.INTEGRAL: 'integral'>, True)
"""

from __future__ import annotations

import difflib
import keyword
import os
import re
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import sympy as sp

from ..errors import CaseFormatError, ExpressionError, Problem
from ..model import (
    Assumption,
    Case,
    Claim,
    ClaimKind,
    Equation,
    Expression,
    Provenance,
    Source,
    System,
)
from . import forms
from .limits import ParseBudget
from .parser import (
    RESERVED_NAMES,
    VARIABLES,
    Namespace,
    parse_equation,
    parse_expression,
)
from .system_reader import SystemReader
from .toml_input import (
    char_name,
    control_problem,
    cut,
    field_name,
    hash_data,
    kind_of,
    load_toml,
    quoted,
    read_text,
)

# Limits on a case file besides those on its expressions (``registry.language.limits``):
# each is checked before the work it bounds, so that a hostile file is refused fast.

#: Most claims in one case.
MAX_CLAIMS = 200
#: Most level-set equations (``on``) of one claim.
MAX_EQUATIONS = 20
#: Most parameters in one case (and, separately, most declared functions).
MAX_PARAMETERS = 100
#: Most problems listed in one error; the rest are counted in a last line.
MAX_PROBLEMS = 50

#: A case id: lowercase letters, digits, '.' and '-', starting with a letter or digit.
ID_PATTERN = re.compile(r"[a-z0-9][a-z0-9.-]*")

_TOP_KEYS = (
    "id",
    "title",
    "topic",
    "aliases",
    "source",
    "parameters",
    "functions",
    "system",
    "claims",
    "notes",
)
#: The optional text fields of ``[source]`` that structure the citation (for BibTeX).
SOURCE_TEXT_FIELDS = (
    "title",
    "journal",
    "booktitle",
    "publisher",
    "volume",
    "issue",
    "pages",
    "url",
)
_SOURCE_KEYS = ("citation", "locator", "doi", "authors", "year", *SOURCE_TEXT_FIELDS)
_CLAIM_KEYS = ("label", "kind", "expression", "on", "locator", "notes", "provenance")
#: Most authors of one source, and most aliases of one case.
MAX_AUTHORS = 50
MAX_ALIASES = 20
_VARIABLE_LIST = ", ".join(VARIABLES)
_ZERO = Expression("0", sp.Integer(0))


def load_case(path: str | os.PathLike) -> Case:
    """The case in the file at ``path``; CaseFormatError if it is not a valid case file."""
    file = str(path)
    text = read_text(path, file)
    return replace(parse_case_text(text, file), path=file)


def parse_case_text(text: str, file: str = "<string>") -> Case:
    """The case that a case file's ``text`` describes (``file`` names it in errors)."""
    data = load_toml(text, file)
    reader = _Reader()
    case = reader.case(data)
    if case is None:
        raise CaseFormatError(file, reader.listed())
    return replace(case, text=text, content_hash=hash_data(data))


def _name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a parameter or a function, or None if it can."""
    if not (name.isascii() and name.isidentifier()):
        return "not a valid name (use ASCII letters, digits and '_', not starting with a digit)"
    if keyword.iskeyword(name):
        return f"{quoted(name)} is a reserved name (a Python keyword)"
    if name in RESERVED_NAMES:
        return f"{quoted(name)} is a reserved name ({RESERVED_NAMES[name]})"
    return None


def _parameter_symbol(name: str, assumption: Assumption) -> sp.Symbol:
    """The real symbol of a parameter, carrying its declared assumption."""
    extra = {} if assumption is Assumption.REAL else {assumption.value: True}
    return sp.Symbol(name, real=True, **extra)


class _Reader(SystemReader):
    """Validates the TOML data of one case file, collecting every problem on the way."""

    def __init__(self) -> None:
        self.problems: list[Problem] = []
        self.unlisted = 0
        self.ns = Namespace()
        self.budget = ParseBudget()
        self.budget_reported = False

    def problem(self, field: str, message: str, text: str | None = None) -> None:
        if self.full:
            self.unlisted += 1
        else:
            self.problems.append(Problem(field, message, text))

    @property
    def full(self) -> bool:
        """Whether MAX_PROBLEMS problems are listed already (more are only counted)."""
        return len(self.problems) >= MAX_PROBLEMS

    def listed(self) -> list[Problem]:
        """The problems to report: the first MAX_PROBLEMS, then how many more there are."""
        if not self.unlisted:
            return self.problems
        more = f"{self.unlisted} more problem{'s' * (self.unlisted > 1)} not listed"
        return [*self.problems, Problem("", f"{more} (at most {MAX_PROBLEMS} are)")]

    # ------------------------------------------------------- generic checks

    def check_keys(self, table: dict, allowed: tuple[str, ...], field: str) -> None:
        """Report keys of ``table`` that the format does not know (with a suggestion)."""
        for key in table:
            if key in allowed:
                continue
            if self.full:
                self.unlisted += 1
                continue
            close = difflib.get_close_matches(cut(key), allowed, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            self.problem(field, f"unknown key {quoted(key)}{hint}")

    def table(self, data: dict, key: str, field: str) -> dict | None:
        """The sub-table ``data[key]``; None when absent or not a table (reported)."""
        value = data.get(key)
        if value is None or isinstance(value, dict):
            return value
        self.problem(field, f"expected a table, found {kind_of(value)}")
        return None

    def string(
        self,
        data: dict,
        key: str,
        field: str,
        required: bool = False,
        nonempty: bool = False,
        line_breaks: bool = False,
    ) -> str | None:
        """The string ``data[key]``; None (reported if required or wrong) otherwise.

        Control characters are refused (tab and line breaks too, unless ``line_breaks``).
        """
        if key not in data:
            if required:
                self.problem(field, "required field is missing")
            return None
        value = data[key]
        if not isinstance(value, str):
            self.problem(field, f"expected a string, found {kind_of(value)}")
            return None
        if nonempty and not value.strip():
            self.problem(field, "must not be empty")
            return None
        control = control_problem(value, line_breaks)
        if control:
            self.problem(field, control, value)
            return None
        return value

    def expression(self, text: Any, field: str) -> Expression | None:
        """A string parsed in the case's namespace; parse errors become problems."""
        if not isinstance(text, str):
            self.problem(field, f"expected a string, found {kind_of(text)}")
            return None
        try:
            return Expression(text, parse_expression(text, self.ns, self.budget))
        except ExpressionError as err:
            self.expression_problem(field, err)
            return None

    def expression_problem(self, field: str, err: ExpressionError) -> None:
        """Report a refused expression; a case past its ParseBudget is reported once."""
        if err.message != self.budget.exhausted or not self.budget_reported:
            self.problem(field, err.message, err.text)
        self.budget_reported = self.budget.exhausted is not None

    def equation(self, text: Any, field: str) -> Equation | None:
        """A level-set equation ``lhs = rhs``; parse errors become problems."""
        if not isinstance(text, str):
            self.problem(field, f"expected a string, found {kind_of(text)}")
            return None
        try:
            lhs, rhs = parse_equation(text, self.ns, self.budget)
        except ExpressionError as err:
            self.expression_problem(field, err)
            return None
        return Equation(text, lhs, rhs)

    # --------------------------------------------------------------- the case

    def case(self, data: dict) -> Case | None:
        """The whole case, or None when anything is wrong (problems hold why)."""
        self.check_keys(data, _TOP_KEYS, "")
        case_id = self.case_id(data)
        title = self.string(data, "title", "title", required=True, nonempty=True)
        topic = self.string(data, "topic", "topic")
        aliases = self.aliases(data, case_id)
        source = self.source(data)
        parameters, assumptions = self.parameters(data)
        variables = self.state_variables(data, parameters)
        functions = self.functions(data, parameters, variables)
        self.ns = Namespace(parameters, functions, variables)
        system = self.system(data)
        claims = self.claims(data)
        notes = self.string(data, "notes", "notes", line_breaks=True)
        if system is not None and claims is not None:
            self.check_claims_fit(system, claims)
        if self.problems:
            return None
        return Case(
            id=case_id,
            title=title,
            source=source,
            system=system,
            dynamics=forms.dynamics(system, parameters, functions),
            claims=claims,
            parameters=parameters,
            assumptions=assumptions,
            functions=functions,
            notes=notes or "",
            topic=topic or "",
            aliases=aliases,
        )

    def case_id(self, data: dict) -> str | None:
        """The id: lowercase letters, digits, '.' and '-', starting with a letter or digit."""
        case_id = data.get("id")
        if not self.id_pattern(case_id, "id"):
            return None
        return self.string(data, "id", "id", required=True, nonempty=True)

    def id_pattern(self, value: Any, field: str) -> bool:
        """False (reported) for a non-empty string that is not a valid id; checked before
        string(), which would only name a control character."""
        if isinstance(value, str) and value and not ID_PATTERN.fullmatch(value):
            bad = next((c for c in value if not re.fullmatch(r"[a-z0-9.-]", c)), value[0])
            self.problem(
                field,
                "an id may hold only lowercase letters, digits, '.' and '-', "
                f"and starts with a letter or digit (found {char_name(bad)})",
                value,
            )
            return False
        return True

    def aliases(self, data: dict, case_id: str | None) -> tuple[str, ...]:
        """``aliases``: earlier ids of this case, under which it is still found."""
        value = data.get("aliases", [])
        if not isinstance(value, list):
            self.problem("aliases", f"expected an array of ids, found {kind_of(value)}")
            return ()
        if len(value) > MAX_ALIASES:
            self.problem("aliases", f"too many aliases ({len(value)}; at most {MAX_ALIASES})")
            return ()
        found: list[str] = []
        for i, alias in enumerate(value):
            field = f"aliases[{i}]"
            if not self.id_pattern(alias, field):
                continue
            text = self.string({"a": alias}, "a", field, nonempty=True)
            if text is None:
                continue
            if text == case_id or text in found:
                self.problem(field, "repeats the id or another alias", text)
                continue
            found.append(text)
        return tuple(found)

    def source(self, data: dict) -> Source | None:
        """[source]: citation (required), locator, doi, and the structured fields of the
        citation (authors, year, title, journal or booktitle, publisher, volume, ...)."""
        table = self.table(data, "source", "source")
        if table is None:
            if "source" not in data:
                self.problem("source.citation", "required field is missing")
            return None
        self.check_keys(table, _SOURCE_KEYS, "source")
        citation = self.string(table, "citation", "source.citation", required=True, nonempty=True)
        locator = self.string(table, "locator", "source.locator")
        doi = self.string(table, "doi", "source.doi")
        texts = {k: self.string(table, k, f"source.{k}") or "" for k in SOURCE_TEXT_FIELDS}
        authors = self.authors(table)
        year = self.year(table)
        if citation is None:
            return None
        return Source(citation, locator or "", doi or "", authors, year, **texts)

    def authors(self, table: dict) -> tuple[str, ...]:
        """``source.authors``: an array of names as the source prints them."""
        value = table.get("authors", [])
        if not isinstance(value, list):
            self.problem("source.authors", f"expected an array of names, found {kind_of(value)}")
            return ()
        if len(value) > MAX_AUTHORS:
            self.problem(
                "source.authors", f"too many authors ({len(value)}; at most {MAX_AUTHORS})"
            )
            return ()
        names = [
            self.string({"a": name}, "a", f"source.authors[{i}]", nonempty=True)
            for i, name in enumerate(value)
        ]
        return tuple(n for n in names if n is not None)

    def year(self, table: dict) -> int | None:
        """``source.year``: an integer between 1500 and 2999."""
        value = table.get("year")
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, int):
            self.problem("source.year", f"expected an integer, found {kind_of(value)}")
            return None
        if not 1500 <= value <= 2999:
            self.problem("source.year", f"not a plausible year of publication ({value})")
            return None
        return value

    def parameters(self, data: dict) -> tuple[dict[str, sp.Symbol], dict[str, Assumption]]:
        """[parameters]: name -> assumption, each name a fresh identifier."""
        table = self.table(data, "parameters", "parameters") or {}
        if len(table) > MAX_PARAMETERS:
            self.problem(
                "parameters", f"too many parameters ({len(table)}; at most {MAX_PARAMETERS})"
            )
        symbols, assumptions = {}, {}
        for name, value in list(table.items())[:MAX_PARAMETERS]:
            field = field_name("parameters", name)
            bad_name = _name_problem(name)
            if bad_name:
                self.problem(field, bad_name)
            assumption = self.assumption(value, field)
            if bad_name is None:
                # A bad assumption still declares the name, so its uses are not reported too.
                assumptions[name] = assumption or Assumption.REAL
                symbols[name] = _parameter_symbol(name, assumptions[name])
        return symbols, assumptions

    def assumption(self, value: Any, field: str) -> Assumption | None:
        """One of real, positive, nonzero, integer."""
        if not isinstance(value, str):
            self.problem(field, f"expected a string, found {kind_of(value)}")
            return None
        try:
            return Assumption(value)
        except ValueError:
            expected = ", ".join(repr(a.value) for a in Assumption)
            expected = " or ".join(expected.rsplit(", ", 1))
            self.problem(field, f"unknown assumption {quoted(value)} (expected {expected})")
            return None

    def functions(
        self,
        data: dict,
        parameters: dict[str, sp.Symbol],
        variables: dict[str, sp.Symbol] | None = None,
    ) -> dict[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]]:
        """[functions]: name -> argument list, drawn from the state variables (the paper's
        six and s, unless the system names its own ``variables``)."""
        state = VARIABLES if variables is None else variables
        table = self.table(data, "functions", "functions") or {}
        if len(table) > MAX_PARAMETERS:
            self.problem(
                "functions", f"too many functions ({len(table)}; at most {MAX_PARAMETERS})"
            )
        functions = {}
        for name, value in list(table.items())[:MAX_PARAMETERS]:
            field = field_name("functions", name)
            bad_name = _name_problem(name)
            if bad_name:
                self.problem(field, bad_name)
            elif name in parameters:
                self.problem(
                    field, f"{quoted(name)} is declared both as a parameter and as a function"
                )
                bad_name = "clash"
            elif name in state:
                self.problem(field, f"{quoted(name)} is a variable of the system")
                bad_name = "clash"
            args = self.arguments(value, field, state)
            if bad_name is None and args is not None:
                functions[name] = (sp.Function(name, real=True), args)
        return functions

    def arguments(
        self, value: Any, field: str, state: Mapping[str, sp.Symbol] = VARIABLES
    ) -> tuple[sp.Symbol, ...] | None:
        """The argument symbols of a declared function: distinct state variables."""
        if not isinstance(value, list):
            self.problem(field, f"expected an array of argument names, found {kind_of(value)}")
            return None
        if not value:
            self.problem(field, "a function needs at least one argument")
            return None
        if len(value) > len(state):
            self.problem(
                field, f"too many arguments ({len(value)}; at most {len(state)}, all distinct)"
            )
            return None
        args: list[sp.Symbol] = []
        ok = True
        for i, arg in enumerate(value):
            where = f"{field}[{i}]"
            if not isinstance(arg, str):
                self.problem(where, f"expected a string, found {kind_of(arg)}")
            elif arg not in state:
                listed = ", ".join(state)
                self.problem(where, f"unknown argument {quoted(arg)} (expected one of {listed})")
            elif state[arg] in args:
                self.problem(where, f"duplicate argument {arg!r}")
            else:
                args.append(state[arg])
                continue
            ok = False
        return tuple(args) if ok else None

    # ------------------------------------------------------------- the claims

    def claims(self, data: dict) -> tuple[Claim, ...] | None:
        """[[claims]]: up to MAX_CLAIMS tables with distinct labels."""
        value = data.get("claims", [])
        if not isinstance(value, list):
            self.problem(
                "claims", f"expected an array of tables ([[claims]]), found {kind_of(value)}"
            )
            return None
        if len(value) > MAX_CLAIMS:
            self.problem("claims", f"too many claims ({len(value)}; at most {MAX_CLAIMS})")
        labels: set[str] = set()
        return tuple(
            self.claim(item, f"claims[{i}]", labels) for i, item in enumerate(value[:MAX_CLAIMS])
        )

    def claim(self, item: Any, field: str, labels: set[str]) -> Claim | None:
        """One claim: label, kind, expression, on, locator, notes, provenance."""
        if not isinstance(item, dict):
            self.problem(field, f"expected a table, found {kind_of(item)}")
            return None
        self.check_keys(item, _CLAIM_KEYS, field)
        label = self.string(item, "label", f"{field}.label", required=True, nonempty=True)
        if label is not None:
            if label in labels:
                self.problem(f"{field}.label", f"duplicate label {quoted(label)}")
            labels.add(label)
        kind = self.claim_kind(item, f"{field}.kind")
        expression = None
        if "expression" not in item:
            self.problem(f"{field}.expression", "required field is missing")
        else:
            expression = self.expression(item["expression"], f"{field}.expression")
        on = self.level_set(item, f"{field}.on")
        locator = self.string(item, "locator", f"{field}.locator")
        notes = self.string(item, "notes", f"{field}.notes", line_breaks=True)
        provenance = self.provenance(item, f"{field}.provenance")
        if None in (label, kind, expression, on):
            return None
        return Claim(label, kind, expression, on, locator or "", notes or "", provenance)

    def provenance(self, item: dict, field: str) -> Provenance:
        """'literature' (the default) or 'discovered' (found by registry discover)."""
        text = self.string(item, "provenance", field)
        if text is None:
            return Provenance.LITERATURE
        try:
            return Provenance(text)
        except ValueError:
            self.problem(field, "unknown provenance (expected 'literature' or 'discovered')", text)
            return Provenance.LITERATURE

    def claim_kind(self, item: dict, field: str) -> ClaimKind | None:
        """'integral', 'casimir', 'measure' or 'relation'."""
        kind = self.string(item, "kind", field, required=True)
        if kind is None:
            return None
        try:
            return ClaimKind(kind)
        except ValueError:
            self.problem(
                field,
                f"unknown claim kind {quoted(kind)} (expected 'integral', 'casimir', "
                "'measure' or 'relation')",
            )
            return None

    def check_claims_fit(self, system: System, claims: tuple[Claim | None, ...]) -> None:
        """A Casimir needs a bracket: a system given by its equations has none."""
        if not system.equations:
            return
        for i, claim in enumerate(claims):
            if claim is not None and claim.kind is ClaimKind.CASIMIR:
                self.problem(
                    f"claims[{i}].kind",
                    "a Casimir needs a bracket, and this system is given by its equations: "
                    "claim an integral",
                )

    def level_set(self, item: dict, field: str) -> tuple[Equation, ...] | None:
        """``on``: an array of equations ``lhs = rhs`` (default: none)."""
        value = item.get("on", [])
        if not isinstance(value, list):
            self.problem(field, f"expected an array of equations, found {kind_of(value)}")
            return None
        if len(value) > MAX_EQUATIONS:
            self.problem(field, f"too many equations ({len(value)}; at most {MAX_EQUATIONS})")
            return None
        equations = [self.equation(text, f"{field}[{i}]") for i, text in enumerate(value)]
        return None if None in equations else tuple(equations)
