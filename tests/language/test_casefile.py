"""Case files: a full valid case, every kind of mistake with its exact message, the hash."""

from __future__ import annotations

import re

import pytest
import sympy as sp

from registry.errors import CaseFormatError, Problem
from registry.language import casefile
from registry.language.casefile import load_case, parse_case_text
from registry.language.toml_input import MAX_FILE_BYTES, content_hash
from registry.mathematics.mechanics import AXIS, gamma1, gamma2, gamma3, s
from registry.model import Assumption, ClaimKind

FULL = """\
# Yehia's singular case, shortened, with every field of docs/case-format.md filled in.
id = "yehia-2003-kovalevskaya-singular"
title = "Kovalevskaya configuration, singular potential and nonlinear torque"
notes = "Shortened; the real case has more terms."

[source]
citation = "H.M. Yehia, Regular and Chaotic Dynamics 3 (2003) 337-348"
locator = "p. 343, subsection 4.1.2"
doi = "10.1000/example"

[parameters]
C = "positive"
n = "real"
N = "nonzero"
m = "integer"
epsilon = "real"

[functions]
D = ["s"]
phi = ["gamma1", "gamma2", "gamma3"]

[system]
inertia = ["2*C", "2*C", "C"]
potential = "C*m*gamma1 + epsilon/sqrt(gamma1**2 + gamma2**2)"
torque = ["C*(-n*gamma1 + N*gamma1/(gamma1**2 + gamma2**2)**(3/2))",
          "C*(-n*gamma2 + N*gamma2/(gamma1**2 + gamma2**2)**(3/2))",
          "-C*gamma3*(3*n + N*gamma3/sqrt(gamma1**2 + gamma2**2))"]

[[claims]]
label = "I2"
kind = "casimir"
expression = "s + C*(n + N/sqrt(gamma1**2 + gamma2**2))*(2*gamma1**2 + 2*gamma2**2 + gamma3**2)"
on = []
locator = "p. 343"

[[claims]]
label = "I3"
kind = "integral"
expression = "0.5*D(s) + diff(phi(gamma1, gamma2, gamma3), gamma1)"
on = ["gamma1**2 + gamma2**2 + gamma3**2 = 1", "s = 0"]
"""

C = sp.Symbol("C", real=True, positive=True)
n = sp.Symbol("n", real=True)
N = sp.Symbol("N", real=True, nonzero=True)
m = sp.Symbol("m", real=True, integer=True)
epsilon = sp.Symbol("epsilon", real=True)
D = sp.Function("D", real=True)
phi = sp.Function("phi", real=True)
RHO = sp.sqrt(gamma1**2 + gamma2**2)


def test_full_case():
    case = parse_case_text(FULL, "full.toml")
    assert case.id == "yehia-2003-kovalevskaya-singular"
    assert case.title == "Kovalevskaya configuration, singular potential and nonlinear torque"
    assert case.notes == "Shortened; the real case has more terms."
    assert case.source.citation == "H.M. Yehia, Regular and Chaotic Dynamics 3 (2003) 337-348"
    assert (case.source.locator, case.source.doi) == ("p. 343, subsection 4.1.2", "10.1000/example")
    assert dict(case.parameters) == {"C": C, "n": n, "N": N, "m": m, "epsilon": epsilon}
    assert case.parameters["C"].is_positive and case.parameters["m"].is_integer
    assert case.parameters["N"].is_nonzero and case.parameters["n"].is_real
    assert dict(case.assumptions) == {
        "C": Assumption.POSITIVE,
        "n": Assumption.REAL,
        "N": Assumption.NONZERO,
        "m": Assumption.INTEGER,
        "epsilon": Assumption.REAL,
    }
    assert dict(case.functions) == {"D": (D, (s,)), "phi": (phi, AXIS)}
    assert case.system.inertia_exprs == (2 * C, 2 * C, C)
    assert [e.text for e in case.system.inertia] == ["2*C", "2*C", "C"]
    assert case.system.potential.expr == C * m * gamma1 + epsilon / RHO
    assert case.system.torque_exprs[2] == -C * gamma3 * (3 * n + N * gamma3 / RHO)
    i2, i3 = case.claims
    assert (i2.label, i2.kind, i2.on, i2.locator) == ("I2", ClaimKind.CASIMIR, (), "p. 343")
    assert i2.expression.expr == s + C * (n + N / RHO) * (2 * gamma1**2 + 2 * gamma2**2 + gamma3**2)
    assert (i3.label, i3.kind, i3.locator) == ("I3", ClaimKind.INTEGRAL, "")
    assert i3.expression.text == "0.5*D(s) + diff(phi(gamma1, gamma2, gamma3), gamma1)"
    assert i3.expression.expr == D(s) / 2 + sp.Derivative(phi(*AXIS), gamma1)
    sphere, cone = i3.on
    assert sphere.text == "gamma1**2 + gamma2**2 + gamma3**2 = 1"
    assert (sphere.lhs, sphere.rhs) == (gamma1**2 + gamma2**2 + gamma3**2, 1)
    assert (cone.lhs, cone.rhs) == (s, 0)
    assert case.claim("I3") is i3
    assert case.text == FULL
    assert re.fullmatch(r"[0-9a-f]{64}", case.content_hash)
    assert case.content_hash == content_hash(FULL)
    assert case.path is None


def test_defaults():
    case = parse_case_text(case_text(claims=""))
    assert case.system.potential.text == "0" and case.system.potential.expr == 0
    assert [e.text for e in case.system.torque] == ["0", "0", "0"]
    assert case.system.torque_exprs == (0, 0, 0)
    assert case.claims == ()
    assert case.notes == "" and dict(case.functions) == {}
    assert (case.source.locator, case.source.doi) == ("", "")


def test_load_case_sets_the_path(tmp_path):
    path = tmp_path / "full.toml"
    path.write_text(FULL, encoding="utf-8")
    case = load_case(path)
    assert case.path == str(path)
    assert case.text == FULL
    assert case.content_hash == parse_case_text(FULL).content_hash


def test_load_case_drops_a_byte_order_mark(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + FULL.encode("utf-8"))
    assert load_case(path).text == FULL


def test_seed_catalog_loads():
    from tests.helpers.samples import CASES

    files = sorted(CASES.rglob("*.toml"))
    assert files, "no case files found in data/cases"
    for path in files:
        assert load_case(path).id == path.stem


# ------------------------------------------------------------------ mistakes

BASE = {
    "head": 'id = "demo"\ntitle = "Demo"\n',
    "source": '[source]\ncitation = "A. Author (2003)"\n',
    "parameters": '[parameters]\nC = "positive"\nA = "real"\n',
    "functions": "",
    "system": '[system]\ninertia = ["C", "C", "2*C"]\n',
    "claims": '[[claims]]\nlabel = "I1"\nkind = "integral"\nexpression = "gamma3"\n',
}


def case_text(**parts: str) -> str:
    """A small valid case file with some of its sections replaced."""
    return "\n".join({**BASE, **parts}.values())


def problems(text: str) -> list[tuple[str, str, str | None]]:
    """The (field, message, text) of every problem that ``text`` has."""
    with pytest.raises(CaseFormatError) as info:
        parse_case_text(text, "case.toml")
    assert info.value.file == "case.toml"
    return [(p.field, p.message, p.text) for p in info.value.problems]


def system(**fields: str) -> str:
    lines = {"inertia": '["C", "C", "2*C"]', **fields}
    return "[system]\n" + "".join(f"{k} = {v}\n" for k, v in lines.items())


def claim(**fields: str) -> str:
    lines = {"label": '"I1"', "kind": '"integral"', "expression": '"gamma3"', **fields}
    return "[[claims]]\n" + "".join(f"{k} = {v}\n" for k, v in lines.items() if v is not None)


MISSING = "required field is missing"
ZERO_MOMENT = "a moment of inertia is zero"

CASES = {
    # the document
    "empty": ("", [("", "the file is empty", None)]),
    "blank": (" \n\n", [("", "the file is empty", None)]),
    "bad toml": (
        'id = "demo"\ntitle = \n',
        [("", "invalid TOML: Invalid value (at line 2, column 9)", None)],
    ),
    "toml duplicate key": (
        'id = "a"\nid = "b"\n',
        [("", "invalid TOML: Cannot overwrite a value (at line 2, column 9)", None)],
    ),
    # top level
    "unknown key": (
        case_text(head='id = "demo"\ntitle = "Demo"\nauthor = "me"\n'),
        [("", "unknown key 'author'", None)],
    ),
    "claim for claims": (
        case_text(claims='[[claim]]\nlabel = "I1"\n'),
        [("", "unknown key 'claim' (did you mean 'claims'?)", None)],
    ),
    "missing everything": (
        'notes = "x"\n',
        [
            ("id", MISSING, None),
            ("title", MISSING, None),
            ("source.citation", MISSING, None),
            ("system.inertia", MISSING, None),
        ],
    ),
    "id pattern": (
        case_text(head='id = "Demo_1"\ntitle = "Demo"\n'),
        [
            (
                "id",
                "an id may hold only lowercase letters, digits, '.' and '-', "
                "and starts with a letter or digit (found 'D')",
                "Demo_1",
            )
        ],
    ),
    "id starts with a dot": (
        case_text(head='id = ".demo"\ntitle = "Demo"\n'),
        [
            (
                "id",
                "an id may hold only lowercase letters, digits, '.' and '-', "
                "and starts with a letter or digit (found '.')",
                ".demo",
            )
        ],
    ),
    "id is a number": (
        case_text(head='id = 3\ntitle = "Demo"\n'),
        [("id", "expected a string, found an integer", None)],
    ),
    "title is a table": (
        case_text(head='id = "demo"\ntitle = {text = "Demo"}\n'),
        [("title", "expected a string, found a table", None)],
    ),
    "title is empty": (
        case_text(head='id = "demo"\ntitle = "  "\n'),
        [("title", "must not be empty", None)],
    ),
    "notes is a list": (
        case_text(head='id = "demo"\ntitle = "Demo"\nnotes = ["a"]\n'),
        [("notes", "expected a string, found an array", None)],
    ),
    # [source]
    "source is a string": (
        case_text(head='id = "demo"\ntitle = "Demo"\nsource = "A. Author"\n', source=""),
        [("source", "expected a table, found a string", None)],
    ),
    "source misspelt": (
        case_text(source='[source]\ncitaton = "A. Author"\n'),
        [
            ("source", "unknown key 'citaton' (did you mean 'citation'?)", None),
            ("source.citation", MISSING, None),
        ],
    ),
    "citation is a number": (
        case_text(source="[source]\ncitation = 2003\n"),
        [("source.citation", "expected a string, found an integer", None)],
    ),
    "doi is a float": (
        case_text(source='[source]\ncitation = "A"\ndoi = 10.1\n'),
        [("source.doi", "expected a string, found a float", None)],
    ),
    "locator is a boolean": (
        case_text(source='[source]\ncitation = "A"\nlocator = true\n'),
        [("source.locator", "expected a string, found a boolean", None)],
    ),
    # [parameters]
    "parameters is an array": (
        case_text(head='id = "demo"\ntitle = "Demo"\nparameters = ["C"]\n', parameters=""),
        [
            ("parameters", "expected a table, found an array", None),
            ("system.inertia[0]", "unknown name 'C' (declare it under [parameters])", "C"),
            ("system.inertia[1]", "unknown name 'C' (declare it under [parameters])", "C"),
            ("system.inertia[2]", "unknown name 'C' (declare it under [parameters])", "2*C"),
        ],
    ),
    "unknown assumption": (
        case_text(parameters='[parameters]\nC = "postive"\n'),
        [
            (
                "parameters.C",
                "unknown assumption 'postive' "
                "(expected 'real', 'positive', 'nonzero' or 'integer')",
                None,
            )
        ],
    ),
    "assumption is a boolean": (
        case_text(parameters="[parameters]\nC = true\n"),
        [("parameters.C", "expected a string, found a boolean", None)],
    ),
    "parameter reuses a variable": (
        case_text(parameters='[parameters]\nC = "real"\ns = "real"\n'),
        [("parameters.s", "'s' is a reserved name (a variable)", None)],
    ),
    "parameter reuses gamma1": (
        case_text(parameters='[parameters]\nC = "real"\ngamma1 = "real"\n'),
        [("parameters.gamma1", "'gamma1' is a reserved name (a variable)", None)],
    ),
    "parameter reuses a function": (
        case_text(parameters='[parameters]\nC = "real"\nsqrt = "real"\n'),
        [("parameters.sqrt", "'sqrt' is a reserved name (a function)", None)],
    ),
    "parameter reuses a constant": (
        case_text(parameters='[parameters]\nC = "real"\nE = "real"\n'),
        [("parameters.E", "'E' is a reserved name (a constant)", None)],
    ),
    "parameter named diff": (
        case_text(parameters='[parameters]\nC = "real"\ndiff = "real"\n'),
        [("parameters.diff", "'diff' is a reserved name (the derivative)", None)],
    ),
    "parameter named lambda": (
        case_text(parameters='[parameters]\nC = "real"\nlambda = "real"\n'),
        [("parameters.lambda", "'lambda' is a reserved name (a Python keyword)", None)],
    ),
    "parameter name with a space": (
        case_text(parameters='[parameters]\nC = "real"\n"a b" = "real"\n'),
        [
            (
                'parameters."a b"',
                "not a valid name (use ASCII letters, digits and '_', not starting with a digit)",
                None,
            )
        ],
    ),
    "parameter name not ASCII": (
        case_text(parameters='[parameters]\nC = "real"\n"\u0430" = "real"\n'),
        [
            (
                'parameters."\\u0430"',  # escaped, so that look-alikes show
                "not a valid name (use ASCII letters, digits and '_', not starting with a digit)",
                None,
            )
        ],
    ),
    "parameter name starts with a digit": (
        case_text(parameters='[parameters]\nC = "real"\n2a = "real"\n'),
        [
            (
                "parameters.2a",
                "not a valid name (use ASCII letters, digits and '_', not starting with a digit)",
                None,
            )
        ],
    ),
    # [functions]
    "function args": (
        case_text(functions='[functions]\nphi = ["gamma1", "gama2", "gamma1", 3]\n'),
        [
            (
                "functions.phi[1]",
                "unknown argument 'gama2' (expected one of M1, M2, M3, gamma1, gamma2, gamma3, s)",
                None,
            ),
            ("functions.phi[2]", "duplicate argument 'gamma1'", None),
            ("functions.phi[3]", "expected a string, found an integer", None),
        ],
    ),
    "function args not a list": (
        case_text(functions='[functions]\na = "s"\n'),
        [("functions.a", "expected an array of argument names, found a string", None)],
    ),
    "function without args": (
        case_text(functions="[functions]\na = []\n"),
        [("functions.a", "a function needs at least one argument", None)],
    ),
    "function reuses a name": (
        case_text(functions='[functions]\nexp = ["s"]\n'),
        [("functions.exp", "'exp' is a reserved name (a function)", None)],
    ),
    "function and parameter collide": (
        case_text(functions='[functions]\nC = ["s"]\n'),
        [("functions.C", "'C' is declared both as a parameter and as a function", None)],
    ),
    # [system]
    "system is an array": (
        case_text(head='id = "demo"\ntitle = "Demo"\nsystem = []\n', system=""),
        [("system", "expected a table, found an array", None)],
    ),
    "system misspelt": (
        case_text(system=system(torgue='["0", "0", "0"]')),
        [("system", "unknown key 'torgue' (did you mean 'torque'?)", None)],
    ),
    "inertia missing": (
        case_text(system='[system]\npotential = "gamma3"\n'),
        [("system.inertia", MISSING, None)],
    ),
    "inertia is a string": (
        case_text(system=system(inertia='"C"')),
        [("system.inertia", "expected an array of 3 strings, found a string", None)],
    ),
    "inertia has two entries": (
        case_text(system=system(inertia='["C", "C"]')),
        [("system.inertia", "expected 3 entries, found 2", None)],
    ),
    "inertia entry is a number": (
        case_text(system=system(inertia='["C", 1, "C"]')),
        [("system.inertia[1]", "expected a string, found an integer", None)],
    ),
    "inertia zero": (
        case_text(system=system(inertia='["C", "0", "A - A"]')),
        [
            ("system.inertia[1]", ZERO_MOMENT, "0"),
            ("system.inertia[2]", ZERO_MOMENT, "A - A"),
        ],
    ),
    "inertia depends on the state": (
        case_text(system=system(inertia='["C + M1", "C*s", "C*gamma3"]')),
        [
            (
                "system.inertia[0]",
                "a moment of inertia must be constant; it depends on M1",
                "C + M1",
            ),
            ("system.inertia[1]", "a moment of inertia must be constant; it depends on s", "C*s"),
            (
                "system.inertia[2]",
                "a moment of inertia must be constant; it depends on gamma3",
                "C*gamma3",
            ),
        ],
    ),
    "potential depends on M": (
        case_text(system=system(potential='"gamma1 + M2**2"')),
        [
            (
                "system.potential",
                "the potential may depend on gamma only, not on M2",
                "gamma1 + M2**2",
            )
        ],
    ),
    "potential depends on s": (
        case_text(functions='[functions]\na = ["s"]\n', system=system(potential='"gamma3*a(s)"')),
        [("system.potential", "the potential may depend on gamma only, not on s", "gamma3*a(s)")],
    ),
    "potential is a number": (
        case_text(system=system(potential="0")),
        [("system.potential", "expected a string, found an integer", None)],
    ),
    "torque has four entries": (
        case_text(system=system(torque='["0", "0", "0", "0"]')),
        [("system.torque", "expected 3 entries, found 4", None)],
    ),
    "torque entry is bad": (
        case_text(system=system(torque='["0", "gamma1^2", "x"]')),
        [
            ("system.torque[1]", "'^' is not a power; use '**'", "gamma1^2"),
            ("system.torque[2]", "unknown name 'x' (declare it under [parameters])", "x"),
        ],
    ),
    # [[claims]]
    "claims is a table": (
        case_text(claims='[claims]\nlabel = "I1"\n'),
        [("claims", "expected an array of tables ([[claims]]), found a table", None)],
    ),
    "claims has a string": (
        case_text(head='id = "demo"\ntitle = "Demo"\nclaims = ["I1"]\n', claims=""),
        [("claims[0]", "expected a table, found a string", None)],
    ),
    "claim misspelt": (
        case_text(claims=claim(lable='"I2"')),
        [("claims[0]", "unknown key 'lable' (did you mean 'label'?)", None)],
    ),
    "claim without anything": (
        case_text(claims=claim(label=None, kind=None, expression=None, locator='"p. 1"')),
        [
            ("claims[0].label", MISSING, None),
            ("claims[0].kind", MISSING, None),
            ("claims[0].expression", MISSING, None),
        ],
    ),
    "empty label": (
        case_text(claims=claim(label='""')),
        [("claims[0].label", "must not be empty", None)],
    ),
    "duplicate label": (
        case_text(claims=claim() + claim(expression='"gamma1"')),
        [("claims[1].label", "duplicate label 'I1'", None)],
    ),
    "unknown kind": (
        case_text(claims=claim(kind='"integrall"')),
        [
            (
                "claims[0].kind",
                "unknown claim kind 'integrall' "
                "(expected 'integral', 'casimir', 'measure' or 'relation')",
                None,
            )
        ],
    ),
    "expression is a list": (
        case_text(claims=claim(expression='["gamma3"]')),
        [("claims[0].expression", "expected a string, found an array", None)],
    ),
    "expression is refused": (
        case_text(claims=claim() + claim(label='"I2"', expression='"gamma3.real"')),
        [("claims[1].expression", "attribute access is not allowed", "gamma3.real")],
    ),
    "on is a string": (
        case_text(claims=claim(on='"s = 0"')),
        [("claims[0].on", "expected an array of equations, found a string", None)],
    ),
    "on entries": (
        case_text(claims=claim(on='["s = 0", "s == 0", "x = 1", 0]')),
        [
            ("claims[0].on[1]", "an equation needs the form lhs = rhs", "s == 0"),
            ("claims[0].on[2]", "unknown name 'x' (declare it under [parameters])", "x = 1"),
            ("claims[0].on[3]", "expected a string, found an integer", None),
        ],
    ),
    "claim locator is a number": (
        case_text(claims=claim(locator="343")),
        [("claims[0].locator", "expected a string, found an integer", None)],
    ),
    "a date where a string is expected": (
        case_text(claims=claim(locator="2003-01-01")),
        [("claims[0].locator", "expected a string, found a date or time", None)],
    ),
}


@pytest.mark.parametrize(("text", "expected"), CASES.values(), ids=CASES.keys())
def test_mistake(text, expected):
    assert problems(text) == expected


def test_every_problem_is_reported_at_once():
    text = case_text(
        head='id = "Demo"\ntitle = "Demo"\n',
        parameters='[parameters]\nC = "postive"\n',
        system=system(inertia='["C", "C"]', potential='"M1"'),
        claims=claim(kind='"casimirr"') + claim(expression='"sqrt(x)"'),
    )
    with pytest.raises(CaseFormatError) as info:
        parse_case_text(text, "demo.toml")
    fields = [p.field for p in info.value.problems]
    assert fields == [
        "id",
        "parameters.C",
        "system.inertia",
        "system.potential",
        "claims[0].kind",
        "claims[1].label",
        "claims[1].expression",
    ]
    message = str(info.value)
    assert message.splitlines()[-1] == (
        "demo.toml: claims[1].expression: unknown name 'x' (declare it under [parameters]): "
        "'sqrt(x)'"
    )
    assert isinstance(info.value, ValueError)


def test_limits(monkeypatch):
    monkeypatch.setattr(casefile, "MAX_CLAIMS", 2)
    monkeypatch.setattr(casefile, "MAX_PARAMETERS", 1)
    text = case_text(
        parameters='[parameters]\nC = "real"\nA = "real"\n',
        functions='[functions]\na = ["s"]\nb = ["s"]\n',
        claims="".join(claim(label=f'"I{i}"') for i in range(3)),
    )
    assert problems(text)[:3] == [
        ("parameters", "too many parameters (2; at most 1)", None),
        ("functions", "too many functions (2; at most 1)", None),
        ("claims", "too many claims (3; at most 2)", None),
    ]


def test_limit_constants():
    assert MAX_FILE_BYTES == 1_000_000
    assert casefile.MAX_CLAIMS == 200
    assert casefile.MAX_PARAMETERS == 100


def test_text_too_large():
    text = case_text() + "#" * MAX_FILE_BYTES
    assert problems(text) == [("", "the file is too large (more than 1000000 bytes)", None)]


# ------------------------------------------------------------------- files


def load_problems(path) -> list[Problem]:
    with pytest.raises(CaseFormatError) as info:
        load_case(path)
    assert info.value.file == str(path)
    return info.value.problems


def test_file_not_utf8(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(case_text(head='id = "demo"\ntitle = "Caf\u00e9"\n').encode("latin-1"))
    [problem] = load_problems(path)
    assert problem == Problem("", "the file is not UTF-8 text (byte 0xe9 at offset 24)")


def test_file_empty(tmp_path):
    path = tmp_path / "empty.toml"
    path.write_bytes(b"")
    assert load_problems(path) == [Problem("", "the file is empty")]


def test_file_too_large(tmp_path):
    path = tmp_path / "big.toml"
    path.write_bytes(b"#" * (MAX_FILE_BYTES + 1))
    assert load_problems(path) == [Problem("", "the file is too large (more than 1000000 bytes)")]


def test_file_missing(tmp_path):
    path = tmp_path / "nowhere.toml"
    assert load_problems(path) == [Problem("", "cannot read the file (No such file or directory)")]


def test_error_names_the_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(case_text(claims=claim(kind='"integrall"')), encoding="utf-8")
    with pytest.raises(CaseFormatError) as info:
        load_case(path)
    assert str(info.value) == (
        f"{path}: claims[0].kind: unknown claim kind 'integrall' "
        f"(expected 'integral', 'casimir', 'measure' or 'relation')"
    )
