"""A case as Mathematica, Maple and Python (SymPy) code.

The Python file is run and its expressions compared with the case's (the same
mathematics: their difference expands to 0). No Mathematica or Maple is installed here,
so their files are checked by ``syntax_problems``, a small checker of our own: string
literals and comments closed, brackets balanced and matched outside them, every
statement an assignment ``name = ...;`` (``name := ...:`` in Maple) of a name the
language can spell, no operator at the end of an expression. That is what is checked,
not that Mathematica or Maple evaluate the file.
"""

from __future__ import annotations

import re

import pytest
import sympy as sp

from registry.language.casefile import load_case, parse_case_text
from registry.presentation.cas_export import LANGUAGES, MAPLE, MATHEMATICA, PYTHON, export
from tests.helpers.samples import CASES

CATALOG = sorted(CASES.rglob("*.toml"))
PAIRS = {"(": ")", "[": "]", "{": "}"}


def _statements(code: str, language) -> list[str]:
    """The statements of a Mathematica or Maple file, strings and comments checked and
    blanked out; brackets checked. Raises AssertionError naming the first problem."""
    out, stack, i, current = [], [], 0, []
    comment_open = "(*" if language is MATHEMATICA else "#"
    end = ";" if language is MATHEMATICA else ":"
    while i < len(code):
        c = code[i]
        if code.startswith(comment_open, i):
            close = code.find("*)", i) + 2 if language is MATHEMATICA else code.find("\n", i)
            assert close > i, "comment not closed"
            i = close
            continue
        if c == '"':
            j = i + 1
            while j < len(code) and code[j] != '"':
                j += 2 if code[j] == "\\" else 1
            assert j < len(code), "string not closed"
            current.append('""')
            i = j + 1
            continue
        if c in PAIRS:
            stack.append(c)
        elif c in PAIRS.values():
            assert stack and PAIRS[stack.pop()] == c, f"unmatched {c!r} at {i}"
        if c == end and not stack and not code.startswith(":=", i):
            out.append("".join(current).strip())
            current = []
        else:
            current.append(c)
        i += 1
    assert not stack, "bracket not closed"
    assert not "".join(current).strip(), "last statement not ended"
    return out


def syntax_problems(code: str, language) -> list[str]:
    """What is wrong with a Mathematica or Maple file, by the checks above."""
    try:
        statements = _statements(code, language)
    except AssertionError as err:
        return [str(err)]
    problems = []
    assign = " = " if language is MATHEMATICA else " := "
    for statement in statements:
        name, sep, value = statement.partition(assign)
        if not sep or not language.valid(name) or not value.strip():
            problems.append(f"not an assignment: {statement[:60]!r}")
        elif re.search(r"[-+*/^,]\s*$|[-+*/^]\s*[)\]}]", value):
            problems.append(f"dangling operator: {statement[:60]!r}")
    return problems


@pytest.mark.parametrize("path", CATALOG, ids=lambda p: p.stem)
def test_the_python_file_evaluates_to_the_case_expressions(path):
    case = load_case(path)
    namespace: dict = {}
    exec(compile(export(case, PYTHON), f"{case.id}.py", "exec"), namespace)  # our own code
    for claim in case.claims:
        assert sp.expand(namespace["claims"][claim.label] - claim.expression.expr) == 0
        exported = namespace["level_sets"][claim.label]
        assert [(e.lhs, e.rhs) for e in exported] == [(e.lhs, e.rhs) for e in claim.on]
    dynamics = case.dynamics
    assert [str(x) for x in namespace["variables"]] == [str(x) for x in dynamics.variables]
    assert len(namespace["equations"]) == len(dynamics.field)
    for got, want in zip(
        namespace["torque"] if "torque" in namespace else (),
        dynamics.torque_exprs or (),
        strict=True,
    ):
        assert sp.expand(got - want) == 0
    if not any(sp.Symbol(str(x)) != x for x in dynamics.variables):  # plain symbols
        for got, want in zip(namespace["equations"], dynamics.field, strict=True):
            assert sp.simplify(got - want) == 0
    assert namespace["case_id"] == case.id and namespace["title"] == case.title


@pytest.mark.parametrize("language", [MATHEMATICA, MAPLE], ids=lambda lang: lang.extension)
def test_mathematica_and_maple_files_pass_the_syntax_checks(language):
    for path in CATALOG:
        case = load_case(path)
        assert syntax_problems(export(case, language), language) == [], case.id


def test_the_syntax_checker_finds_broken_files():
    assert syntax_problems("x = f[a;", MATHEMATICA)
    assert syntax_problems("x = (a + b];", MATHEMATICA)
    assert syntax_problems('x = "open;', MATHEMATICA)
    assert syntax_problems("x = a +;", MATHEMATICA)
    assert syntax_problems("x := a", MAPLE)
    assert syntax_problems("x = a;", MATHEMATICA) == []


HOSTILE = """id = "hostile-1999-names"
title = "A \\"quoted\\" title *) (* Print[1] *) # ; :="
[source]
citation = "X. Y, Z 1 (1999) 1-2"
[parameters]
C = "positive"
N = "real"
D = "nonzero"
claims = "real"
[functions]
I = ["gamma1"]
[system]
inertia = ["C", "C", "2*C"]
potential = "N*gamma3 + I(gamma1)"
torque = ["0", "0", "D*claims"]
[[claims]]
label = "x\\"y"
kind = "integral"
expression = "M3 + D*claims*gamma3"
"""


def test_reserved_names_are_renamed_and_text_stays_in_string_literals():
    case = parse_case_text(HOSTILE, "hostile.toml")
    math, maple = export(case, MATHEMATICA), export(case, MAPLE)
    assert syntax_problems(math, MATHEMATICA) == []
    assert syntax_problems(maple, MAPLE) == []
    # Mathematica's C, N, D, I are built-ins; Maple's D and I are protected
    assert re.search(r"\bpN\b", math) and re.search(r"\bpD\b", math) and "pI[gamma1]" in math
    assert re.search(r"\bpD\b", maple) and "pI(gamma1)" in maple and re.search(r"\bN\b", maple)
    assert "claims = <|" in math and re.search(r"\bpClaims\b", math)  # not the table's name
    namespace: dict = {}
    exec(compile(export(case, PYTHON), "hostile.py", "exec"), namespace)
    assert namespace["title"] == case.title
    (label,) = namespace["claims"]
    assert label == 'x"y'
    assert namespace["claims"][label] == case.claims[0].expression.expr  # SymPy names kept


@pytest.mark.parametrize("name", sorted(LANGUAGES))
def test_every_language_is_exported_deterministically(name):
    case = load_case(CATALOG[0])
    assert export(case, LANGUAGES[name]) == export(case, LANGUAGES[name])
