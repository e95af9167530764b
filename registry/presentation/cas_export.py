"""A case's system and claims as code for a computer algebra system: Mathematica, Maple,
and Python with SymPy (which Sage also runs).

Expressions are written by SymPy's code printers (``mathematica_code``, ``maple_code``,
and the ``str`` printer with exact rationals for Python). Names that the target language
reserves or cannot spell (Mathematica's ``C``, ``D``, ``N``, any capitalised name, ``_``
in a name; Maple's ``D``, ``I``, ``gamma``; the names the file itself defines) are renamed,
and the file says so in a comment. Text from the case file (title, id) is written only as
string literals of the language, escaped, never as code or inside a comment.

Each file defines, in its language: ``variables`` (the state), ``equations`` (dx/dt for
each variable, in that order), ``hamiltonian`` (H, where the system has one),
``poisson`` (the bracket's matrix {x_i, x_j}, where it has one), ``torque`` (mu1, mu2,
mu3) and ``kappa`` (0 for e(3)) where the bracket is the reference paper's, ``sOfState``
(what ``s`` stands for: M1*gamma1 + M2*gamma2 + M3*gamma3) where the case may use it,
and for every claim its expression and level set.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.printing.mathematica import MCodePrinter
from sympy.printing.str import StrPrinter

from ..model import Case

#: The reference paper's state variables and s, valid as they are in every language.
VARIABLES = ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3", "s")

#: The names each file defines itself (a parameter of that name is renamed).
DEFINED = {
    "title",
    "caseId",
    "case_id",
    "variables",
    "equations",
    "poisson",
    "torque",
    "hamiltonian",
    "kappa",
    "sOfState",
    "s_of_state",
    "claims",
    "levelSets",
    "level_sets",
}

#: Maple's protected names a parameter could plausibly use (the case language already
#: reserves the elementary functions and ``E``, ``pi``).
MAPLE_RESERVED = {
    "D", "I", "O", "Pi", "gamma", "Catalan", "Digits", "infinity", "true", "false", "FAIL",
    "add", "mul", "seq", "sum", "product", "int", "diff", "limit", "series", "eval", "subs",
    "solve", "op", "nops", "map", "type", "max", "min", "abs", "list", "set", "table",
    "array", "matrix", "vector", "and", "or", "not", "xor", "implies", "mod", "union",
    "minus", "intersect", "subset", "in", "to", "from", "by", "do", "od", "if", "fi",
    "then", "else", "elif", "end", "for", "while", "proc", "local", "global", "option",
    "options", "return", "break", "next", "use", "module", "export", "description",
    "error", "try", "catch", "finally", "quit", "done", "stop", "assuming", "Sum",
    "Int", "Diff", "Limit", "Product", "Eval", "Heaviside", "Dirac", "LambertW",
}  # fmt: skip


@dataclass(frozen=True)
class Language:
    """How one language writes a file: names it can spell, names it reserves, the printer
    of an expression, assignment, comment, string, list, equation and a table of claims."""

    name: str
    extension: str
    valid: Callable[[str], bool]
    reserved: frozenset[str]
    printer: Callable[[sp.Basic], str]
    assign: Callable[[str, str], str]
    comment: Callable[[str], str]
    string: Callable[[str], str]
    listing: Callable[[list[str]], str]
    equals: str
    table: Callable[[list[tuple[str, str]]], str]


def _escaped(text: str) -> str:
    """A double-quoted string literal with backslashes and quotes escaped (Mathematica,
    Maple and Python read it alike); line breaks as \\n."""
    body = text.replace("\\", "\\\\").replace('"', '\\"')
    return '"' + body.replace("\n", "\\n").replace("\r", "\\r") + '"'


class _Mathematica(MCodePrinter):
    """``mathematica_code``, with derivatives as ``D[f, x]`` (not held)."""

    def _print_Derivative(self, expr):  # noqa: N802 - sympy's dispatch names
        variables = ", ".join(
            self._print(v) if n == 1 else f"{{{self._print(v)}, {n}}}"
            for v, n in expr.variable_count
        )
        return f"D[{self._print(expr.expr)}, {variables}]"


class _Python(StrPrinter):
    """The ``str`` printer with exact rationals (``Rational(1, 2)``, never the float 0.5)."""

    def _print_Rational(self, expr):  # noqa: N802 - sympy's dispatch names
        return f"Rational({expr.p}, {expr.q})"

    def _print_Half(self, expr):  # noqa: N802
        return "Rational(1, 2)"

    def doprint(self, expr):
        text = super().doprint(expr)
        return f"S({text})" if isinstance(expr, sp.Number) else text  # a SymPy number


def _mathematica_valid(name: str) -> bool:
    """A Mathematica symbol of letters and digits that cannot be a built-in (every
    built-in starts with a capital; the state variables M1..M3 are none)."""
    return bool(re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", name)) and (
        name[0].islower() or name in VARIABLES
    )


MATHEMATICA = Language(
    name="Mathematica",
    extension="m",
    valid=_mathematica_valid,
    reserved=frozenset(DEFINED),
    printer=lambda e: _Mathematica({"order": "none"}).doprint(e),
    assign=lambda name, value: f"{name} = {value};",
    comment=lambda text: f"(* {text.replace('*)', '* )').replace('(*', '( *')} *)",
    string=_escaped,
    listing=lambda items: "{" + ", ".join(items) + "}",
    equals="==",
    table=lambda rows: "<|" + ", ".join(f"{k} -> {v}" for k, v in rows) + "|>",
)

MAPLE = Language(
    name="Maple",
    extension="mpl",
    valid=lambda name: bool(re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name)),
    reserved=frozenset(DEFINED | MAPLE_RESERVED),
    printer=lambda e: sp.maple_code(e, order="none"),
    assign=lambda name, value: f"{name} := {value}:",
    comment=lambda text: "# " + text.replace("\n", " "),
    string=_escaped,
    listing=lambda items: "[" + ", ".join(items) + "]",
    equals="=",
    table=lambda rows: "table([" + ", ".join(f"{k} = {v}" for k, v in rows) + "])",
)

#: The functions and constants of the case language (which reserves their names).
ELEMENTARY = (
    "sqrt", "exp", "log", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh",
    "tanh", "pi", "E",
)  # fmt: skip

#: Names the Python file imports or uses itself.
_PYTHON_NAMES = {"sympy", "S", "Symbol", "Function", "Derivative", "Eq", "Rational"}

PYTHON = Language(
    name="Python (SymPy; Sage runs it too)",
    extension="py",
    valid=lambda name: name.isidentifier() and not keyword.iskeyword(name),
    reserved=frozenset(DEFINED | _PYTHON_NAMES | set(dir(__builtins__))),
    printer=lambda e: _Python({"order": "none"}).doprint(e),
    assign=lambda name, value: f"{name} = {value}",
    comment=lambda text: "# " + text.replace("\n", " "),
    string=_escaped,
    listing=lambda items: "[" + ", ".join(items) + "]",
    equals="==",  # written as Eq(lhs, rhs), see _equation
    table=lambda rows: "{" + ", ".join(f"{k}: {v}" for k, v in rows) + "}",
)

LANGUAGES = {"mathematica": MATHEMATICA, "maple": MAPLE, "python": PYTHON}


def renamed(names: list[str], language: Language) -> dict[str, str]:
    """A new name for each of ``names`` the language cannot use as it is: its letters and
    digits (lower-case first letter, else prefixed ``p``), numbered until unique."""
    taken = {n for n in names if language.valid(n) and n not in language.reserved}
    taken |= set(VARIABLES)
    out: dict[str, str] = {}
    for name in names:
        if name in taken and language.valid(name) and name not in language.reserved:
            continue
        base = re.sub(r"[^A-Za-z0-9]", "", name) or "p"
        if not language.valid(base) or base in language.reserved or base in taken:
            base = "p" + base[:1].upper() + base[1:]
        candidate, k = base, 1
        while candidate in taken or candidate in language.reserved or not language.valid(candidate):
            k += 1
            candidate = f"{base}{k}"
        taken.add(candidate)
        out[name] = candidate
    return out


def _substituted(expr: sp.Basic, names: dict[str, str]) -> sp.Basic:
    """``expr`` with parameters and functions renamed (same assumptions)."""
    if not names:
        return expr
    symbols = {
        s: sp.Symbol(names[s.name], **s._assumptions_orig)
        for s in expr.free_symbols
        if isinstance(s, sp.Symbol) and s.name in names
    }
    expr = expr.xreplace(symbols)
    return expr.replace(
        lambda e: isinstance(e, AppliedUndef) and e.func.__name__ in names,
        lambda e: sp.Function(names[e.func.__name__], **e.func._kwargs)(*e.args),
    )


def export(case: Case, language: Language) -> str:
    """The case's system and claims as a file of ``language``."""
    dynamics = case.dynamics
    state = [str(x) for x in dynamics.variables]
    names = renamed([*state, *case.parameters, *case.functions], language)
    show = lambda e: language.printer(_substituted(e, names))  # noqa: E731
    lines = [
        language.comment(f"Registry of rigid-body integrability claims: {language.name}."),
        language.comment("The case's system and claimed integrals."),
    ]
    for old, new in names.items():
        lines.append(language.comment(f"{new} is the case's {old}"))
    if language is PYTHON:
        lines += _python_header(case, names)
    lines.append(language.assign(_name("case_id", language), language.string(case.id)))
    lines.append(language.assign("title", language.string(case.title)))
    lines.append(
        language.assign("variables", language.listing([show(x) for x in dynamics.variables]))
    )
    for name, value in dynamics.shorthands.items():
        lines.append(language.comment(f"{name} stands for {show(value)}"))
        lines.append(language.assign(_name(f"{name}_of_state", language), show(value)))
    lines.append(language.assign("equations", language.listing([show(x) for x in dynamics.field])))
    if dynamics.hamiltonian is not None:
        lines.append(language.assign("hamiltonian", show(dynamics.hamiltonian)))
    if dynamics.bracket is not None:
        rows = [
            language.listing([show(dynamics.bracket[i, j]) for j in range(dynamics.dimension)])
            for i in range(dynamics.dimension)
        ]
        lines.append(language.assign("poisson", language.listing(rows)))
    torque = dynamics.torque_exprs
    if torque is not None:
        lines.append(language.assign("torque", language.listing([show(e) for e in torque])))
        lines.append(language.assign("kappa", show(dynamics.kappa.expr)))
    claims = [(language.string(c.label), show(c.expression.expr)) for c in case.claims]
    lines.append(language.assign("claims", language.table(claims)))
    level_sets = [
        (language.string(c.label), language.listing([_equation(e, show, language) for e in c.on]))
        for c in case.claims
    ]
    lines.append(language.assign(_name("level_sets", language), language.table(level_sets)))
    return "\n".join(lines) + "\n"


def _name(snake: str, language: Language) -> str:
    """A name the file defines: snake_case in Python, camelCase elsewhere."""
    if language is PYTHON:
        return snake
    head, *rest = snake.split("_")
    return head + "".join(w.title() for w in rest)


def _equation(eq, show, language: Language) -> str:
    """A level-set equation lhs = rhs in the language."""
    if language is PYTHON:
        return f"Eq({show(eq.lhs)}, {show(eq.rhs)})"
    return f"{show(eq.lhs)} {language.equals} {show(eq.rhs)}"


def _python_header(case: Case, names: dict[str, str]) -> list[str]:
    """Imports and the symbols and functions of a case, with their assumptions: a renamed
    one keeps its name in SymPy (``pS = Symbol("S")``), so the expressions are the case's."""
    dynamics = case.dynamics
    exprs = [
        *dynamics.field,
        *([] if dynamics.hamiltonian is None else [dynamics.hamiltonian]),
        *([] if dynamics.bracket is None else list(dynamics.bracket)),
        *(dynamics.torque_exprs or ()),
        *(c.expression.expr for c in case.claims),
        *(e.expr for c in case.claims for e in c.on),
    ]
    used = sorted(
        {
            type(f).__name__
            for e in exprs
            for f in e.atoms(sp.Function)
            if not isinstance(f, AppliedUndef)
        }
        | {str(c) for e in exprs for c in e.atoms(sp.NumberSymbol, sp.core.numbers.ImaginaryUnit)}
    )
    imports = ", ".join(sorted({*_PYTHON_NAMES - {"sympy"}, *ELEMENTARY, *used}))
    lines = [f"from sympy import {imports}", ""]
    for x in (*dynamics.variables, *dynamics.shorthands):
        v = str(x)
        lines.append(f'{names.get(v, v)} = Symbol("{v}", real=True)')
    for name, symbol in case.parameters.items():
        flags = ", ".join(f"{k}={v}" for k, v in sorted(symbol._assumptions_orig.items()))
        lines.append(f'{names.get(name, name)} = Symbol("{name}", {flags})')
    for name, (function, _args) in case.functions.items():
        given = {
            k: True for k in ("real", "positive", "nonzero", "integer") if function._kwargs.get(k)
        }
        flags = ", ".join(f"{k}={v}" for k, v in sorted(given.items()))
        flags = ", " + flags if flags else ""
        lines.append(f'{names.get(name, name)} = Function("{name}"{flags})')
    return lines
