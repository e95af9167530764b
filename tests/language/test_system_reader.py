"""The reading of [system] in any form: every new key refused with its file, field and
text when it is wrong, and nothing of such a file stored."""

import pytest
import sympy as sp

import registry
from registry import load_case
from registry.errors import CaseFormatError
from registry.language.system_reader import MAX_DEFINITIONS, MAX_VARIABLES

BASE = """\
id = "sleigh-demo"
title = "a sleigh-like demo system"
[source]
citation = "nobody"
[parameters]
a = "real"
[system]
variables = ["v", "omega"]
[system.equations]
v = "a*omega**2"
omega = "-a*v*omega"
[[claims]]
label = "E"
kind = "integral"
expression = "v**2 + omega**2"
"""

BRACKET = BASE.replace(
    '[system.equations]\nv = "a*omega**2"\nomega = "-a*v*omega"\n',
    'hamiltonian = "v**2 + omega**2"\n[system.bracket]\n"v, omega" = "1"\n',
)


def edit(old: str, new: str, base: str = BASE) -> str:
    assert old in base, old
    return base.replace(old, new)


VARIABLES = 'variables = ["v", "omega"]'

#: name -> (file text, the first problem's field, and what its message must say)
HOSTILE = {
    "variable-shadows-a-function": (
        edit(VARIABLES, 'variables = ["v", "sin"]'),
        "system.variables[1]",
        "'sin' is a function of the language",
    ),
    "variable-shadows-a-parameter": (
        edit(VARIABLES, 'variables = ["v", "a"]'),
        "system.variables[1]",
        "'a' is declared as a parameter too",
    ),
    "variable-listed-twice": (
        edit(VARIABLES, 'variables = ["v", "omega", "v"]'),
        "system.variables[2]",
        "the variable 'v' is listed twice",
    ),
    "variable-not-a-name": (
        edit(VARIABLES, 'variables = ["v", "om ega"]'),
        "system.variables[1]",
        "'om ega' is not a valid name",
    ),
    "variable-not-a-string": (
        edit(VARIABLES, 'variables = ["v", 3]'),
        "system.variables[1]",
        "expected a string, found an integer",
    ),
    "too-many-variables": (
        edit(VARIABLES, "variables = [" + ", ".join(f'"x{i}"' for i in range(40)) + "]"),
        "system.variables",
        f"too many variables (40; at most {MAX_VARIABLES})",
    ),
    "equation-missing": (
        edit('omega = "-a*v*omega"\n', ""),
        "system.equations",
        "no equation for omega",
    ),
    "equation-for-an-unknown-variable": (
        edit('omega = "-a*v*omega"\n', 'omega = "-a*v*omega"\nw = "1"\n'),
        "system.equations.w",
        "'w' is not a variable of the system",
    ),
    "equation-with-python-in-it": (
        edit('v = "a*omega**2"', "v = \"__import__('os')\""),
        "system.equations.v",
        "unknown function '__import__'",
    ),
    "equation-huge": (
        edit('v = "a*omega**2"', 'v = "' + "+".join(["omega"] * 20000) + '"'),
        "system.equations.v",
        "expression too long",
    ),
    "definition-uses-itself": (
        edit("[system.equations]", '[system.definitions]\nlam = "lam*v"\n[system.equations]'),
        "system.definitions.lam",
        "the definition of 'lam' uses itself: 'lam*v'",
    ),
    "definition-uses-one-below-it": (
        edit(
            "[system.equations]",
            '[system.definitions]\nlam = "mu*v"\nmu = "v"\n[system.equations]',
        ),
        "system.definitions.lam",
        "uses 'mu', which is defined below it",
    ),
    "too-many-definitions": (
        edit(
            "[system.equations]",
            "[system.definitions]\n"
            + "".join(f'd{i} = "v"\n' for i in range(MAX_DEFINITIONS + 1))
            + "[system.equations]",
        ),
        "system.definitions",
        "too many definitions",
    ),
    "bracket-entry-for-an-unknown-variable": (
        edit('"v, omega" = "1"', '"v, w" = "1"', BRACKET),
        'system.bracket."v, w"',
        "'w' is not a variable of the system",
    ),
    "bracket-entry-given-twice": (
        edit('"v, omega" = "1"', '"v, omega" = "1"\n"omega, v" = "-1"', BRACKET),
        'system.bracket."omega, v"',
        "{omega, v} is given twice",
    ),
    "equations-and-a-hamiltonian": (
        edit("[system.equations]", 'hamiltonian = "v"\n[system.equations]'),
        "system.variables",
        "not both",
    ),
    "equations-and-inertia": (
        edit("[system]", '[system]\ninertia = ["1", "1", "1"]'),
        "system.inertia",
        "write them into its equations",
    ),
    "casimir-without-a-bracket": (
        edit('kind = "integral"', 'kind = "casimir"'),
        "claims[0].kind",
        "a Casimir needs a bracket",
    ),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_a_wrong_system_is_refused_naming_file_field_and_text(tmp_path, name):
    text, field, says = HOSTILE[name]
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(CaseFormatError) as raised:
        load_case(path)
    first = str(raised.value).splitlines()[0]
    assert first.startswith(f"{path}: {field}: "), first
    assert says in first
    assert len(first) < 300 + len(str(path))  # one line a person reads, not the huge text


@pytest.mark.parametrize("name", ["definition-uses-itself", "bracket-entry-given-twice"])
def test_nothing_of_a_refused_file_is_stored(tmp_path, name):
    good = tmp_path / "good.toml"
    good.write_text(BASE, encoding="utf-8")
    bad = tmp_path / f"{name}.toml"
    bad.write_text(HOSTILE[name][0].replace("sleigh-demo", "sleigh-bad"), encoding="utf-8")
    with registry.open(tmp_path / "r.sqlite") as reg:
        reg.add(good)
        (refused,) = reg.add(bad)
        assert refused.status == "refused"
        assert f"{bad}: {HOSTILE[name][1]}: " in str(refused.error)
        assert list(reg.cases()["case"]) == ["sleigh-demo"]


def test_definitions_are_expanded_in_order_everywhere():
    text = edit(
        "[system.equations]",
        '[system.definitions]\nk = "a*omega"\nlam = "k*v"\n[system.equations]',
    ).replace('omega = "-a*v*omega"', 'omega = "-lam"')
    case = load_case_text(text)
    v, omega = case.dynamics.variables
    a = sp.Symbol("a", real=True)
    assert sp.expand(case.dynamics.expanded(case.dynamics.field[1]) + a * v * omega) == 0


def test_a_bracket_given_by_one_entry_is_antisymmetric():
    case = load_case_text(BRACKET)
    pi = case.dynamics.bracket
    assert pi is not None and pi == -pi.T and pi[0, 1] == 1


def load_case_text(text: str):
    from registry.language.casefile import parse_case_text

    return parse_case_text(text, "demo.toml")
