"""Hostile case files (issue "Trust: hostile files").

Each file of the corpus goes through ``registry add`` in-process and must be refused
with exit status 1, one ``Error: FILE: FIELD: MESSAGE: 'TEXT'`` line per problem (the
exact lines are asserted), no traceback, nothing stored, nothing executed, well within
a generous time bound that only catches hangs. Property tests feed random and mutated
case files to the parser: each gives a case or a clean CaseFormatError, never another
exception, never a side effect.
"""

from __future__ import annotations

import ast
import builtins
import contextlib
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest
import sympy
import sympy.parsing.sympy_parser
import tomli_w
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import registry
from registry.cli import main
from registry.errors import CaseFormatError, ExpressionError
from registry.language import casefile, limits, parser, toml_input
from registry.language.casefile import load_case, parse_case_text
from registry.model import Case
from tests.helpers.clocks import HANG, cpu_bound
from tests.helpers.samples import CASES

#: Seconds of CPU time allowed to refuse one hostile file: generous, to catch hangs (a
#: refusal takes milliseconds), not to benchmark.
TIME_LIMIT = 2.0


def q(text: str) -> str:
    """``text`` as a TOML basic string (control characters escaped, the rest as is)."""
    escaped = "".join(
        "\\" + c if c in '"\\' else f"\\u{ord(c):04x}" if ord(c) < 32 or ord(c) == 127 else c
        for c in text
    )
    return f'"{escaped}"'


GOOD = {
    "head": 'id = "hostile-demo"\ntitle = "A small valid case"\n',
    "source": '[source]\ncitation = "A. Author, Journal 1 (2003) 1-10"\n',
    "parameters": '[parameters]\nC = "positive"\nN = "real"\n',
    "functions": "",
    "system": (
        '[system]\ninertia = ["C", "C", "2*C"]\npotential = "C*gamma3"\n'
        'torque = ["0", "0", "N*gamma3"]\n'
    ),
    "claims": '[[claims]]\nlabel = "I1"\nkind = "integral"\nexpression = "M3"\non = []\n',
}


def case(**parts: str) -> str:
    """The small valid case GOOD with some of its sections replaced."""
    return "\n".join({**GOOD, **parts}.values())


def system(**fields: str) -> str:
    """A [system] section: GOOD's values, with some replaced by TOML text."""
    values = {
        "inertia": '["C", "C", "2*C"]',
        "potential": '"C*gamma3"',
        "torque": '["0", "0", "N*gamma3"]',
        **fields,
    }
    return "[system]\n" + "".join(f"{k} = {v}\n" for k, v in values.items())


def claim(**fields: str) -> str:
    """A [[claims]] table: GOOD's values, with some replaced by TOML text."""
    values = {"label": '"I1"', "kind": '"integral"', "expression": '"M3"', "on": "[]", **fields}
    return "[[claims]]\n" + "".join(f"{k} = {v}\n" for k, v in values.items())


def placed(field: str, text: str) -> str:
    """A case with the expression ``text`` in ``field`` (potential, torque[i], ...)."""
    if field == "potential":
        return case(system=system(potential=q(text)))
    if field in ("hamiltonian", "kappa"):
        fields = {"hamiltonian": q("M1**2 + M2**2 + 2*M3**2 + C*gamma1"), field: q(text)}
        return case(system="[system]\n" + "".join(f"{k} = {v}\n" for k, v in fields.items()))
    if field.startswith(("torque", "inertia")):
        name, index = field[:-3], int(field[-2])
        entries = ['"C"', '"C"', '"2*C"'] if name == "inertia" else ['"0"', '"0"', '"0"']
        entries[index] = q(text)
        return case(system=system(**{name: f"[{', '.join(entries)}]"}))
    if field == "expression":
        return case(claims=claim(expression=q(text)))
    if field == "on[0]":
        return case(claims=claim(on=f"[{q(text)}]"))
    raise ValueError(field)


FIELD_NAMES = {
    "potential": "system.potential",
    "torque[0]": "system.torque[0]",
    "torque[1]": "system.torque[1]",
    "torque[2]": "system.torque[2]",
    "inertia[0]": "system.inertia[0]",
    "inertia[2]": "system.inertia[2]",
    "expression": "claims[0].expression",
    "on[0]": "claims[0].on[0]",
    "hamiltonian": "system.hamiltonian",
    "kappa": "system.kappa",
}


def shown(text: str) -> str:
    """User text as a message quotes it: repr, cut to 80 characters."""
    return repr(text if len(text) <= 80 else text[:77] + "...")


# ----------------------------------------------------------------------- the corpus
#
# id -> (file content, expected problems). A problem is the error line without
# "Error: FILE: "; str content is written as UTF-8, bytes as they are.

HOSTILE: dict[str, tuple[str | bytes, list[str]]] = {}


def expression_cases(category: str, items: list[tuple[str, str, str]]) -> None:
    """Add hostile expressions: (field, text, message); the problem quotes the text."""
    for i, (field, text, message) in enumerate(items):
        where = FIELD_NAMES[field]
        if field == "on[0]" and "=" not in text:
            text = f"{text} = 0"
        HOSTILE[f"{category}-{i:02d}-{field}"] = (
            placed(field, text),
            [f"{where}: {message}: {shown(text)}"],
        )


ATTRIBUTE = "attribute access is not allowed"

# --- code injection: imports, dunder chains through sympy objects, builtins, syntax
expression_cases(
    "injection",
    [
        ("potential", "__import__('os').system('touch pwned')", ATTRIBUTE),
        ("torque[0]", "__import__('os')", "unknown function '__import__'"),
        ("expression", "gamma1.__class__.__mro__[-1].__subclasses__()", ATTRIBUTE),
        (
            "on[0]",
            "pi.__class__.__init__.__globals__['__builtins__']['eval']('1')",
            "only named functions can be called",
        ),
        ("inertia[0]", "sqrt.__globals__['os'].system('id')", ATTRIBUTE),
        ("torque[1]", "(sqrt)(2).func.__module__", ATTRIBUTE),
        ("torque[2]", "E.__reduce_ex__(2)", ATTRIBUTE),
        ("expression", "exec('import os')", "unknown function 'exec'"),
        ("potential", "eval('2*gamma1')", "unknown function 'eval'"),
        ("expression", "open('/etc/passwd')", "unknown function 'open'"),
        ("torque[0]", "compile('1', 'x', 'eval')", "unknown function 'compile'"),
        ("on[0]", "getattr(gamma1, '__class__')", "unknown function 'getattr'"),
        ("potential", "globals()", "unknown function 'globals'"),
        (
            "expression",
            "__builtins__",
            "unknown name '__builtins__' (declare it under [parameters])",
        ),
        ("expression", "breakpoint()", "unknown function 'breakpoint'"),
        ("torque[1]", "(lambda: __import__('os'))()", "only named functions can be called"),
        ("potential", "lambda: 0", "lambdas are not allowed"),
        ("expression", "[c for c in ().__class__.__bases__]", "comprehensions are not allowed"),
        ("on[0]", "sum(x for x in [gamma1])", "unknown function 'sum'"),
        ("torque[2]", "(gamma1 := 2)", "':=' is not allowed"),
        ("inertia[2]", "C.__dict__", ATTRIBUTE),
        ("expression", "gamma1[0]", "indexing is not allowed"),
        ("potential", "gamma1[::-1]", "indexing is not allowed"),
        ("torque[0]", "'gamma1'", "strings are not allowed"),
        ("on[0]", "f'{gamma1.__class__}'", "strings are not allowed"),
        ("expression", "sqrt(x=gamma1)", "keyword arguments are not allowed"),
        ("potential", "sqrt(**{'x': 1})", "'**' unpacking is not allowed"),
        (
            "torque[1]",
            "gamma1 if __import__('os') else 0",
            "conditional expressions are not allowed",
        ),
        ("expression", "[gamma1, gamma2]", "lists are not allowed"),
        ("expression", "gamma1; import os", "not a valid expression"),
        ("potential", "import os", "not a valid expression"),
        ("torque[2]", "gamma1\nimport os", "not a valid expression"),
        ("on[0]", "await gamma1", "'await' is not allowed"),
        ("expression", "gamma1 # __import__('os')", "comments ('#') are not allowed"),
        ("torque[1]", "gamma1\x1b[2J", "control character U+001B is not allowed"),
        ("on[0]", "gamma1\x00 = 0", "control character U+0000 is not allowed"),
    ],
)

# --- the Hamiltonian form (issue 20): system.hamiltonian and system.kappa
expression_cases(
    "hamiltonian-form",
    [
        ("hamiltonian", "__import__('os').system('touch pwned')", ATTRIBUTE),
        ("hamiltonian", "M1**2 + eval('gamma1')", "unknown function 'eval'"),
        ("hamiltonian", "M1.__class__", ATTRIBUTE),
        ("hamiltonian", "lambda: M1", "lambdas are not allowed"),
        (
            "hamiltonian",
            "M1**2 + bogus*gamma1",
            "unknown name 'bogus' (declare it under [parameters])",
        ),
        ("hamiltonian", "M1**2 # __import__('os')", "comments ('#') are not allowed"),
        ("kappa", "__import__('os')", "unknown function '__import__'"),
        ("kappa", "C.__dict__", ATTRIBUTE),
        ("kappa", "'1'", "strings are not allowed"),
        ("kappa", "kappa", "unknown name 'kappa' (declare it under [parameters])"),
        ("kappa", "C*M1", "kappa must be a constant (the parameters only); it depends on M1"),
        ("kappa", "s", "kappa must be a constant (the parameters only); it depends on s"),
        ("kappa", "C\x1b[2J", "control character U+001B is not allowed"),
    ],
)
BOTH = (
    "system.hamiltonian: give either the Hamiltonian or {}, not both: with "
    "system.hamiltonian, H is the whole energy (inertia and potential are part of it)"
)
HOSTILE.update(
    {
        "hamiltonian-form-with-inertia": (
            case(system=system(hamiltonian=q("M1**2"))),
            [BOTH.format("system.inertia and system.potential")],
        ),
        "hamiltonian-form-with-potential": (
            case(system='[system]\nhamiltonian = "M1**2"\npotential = "C*gamma3"\n'),
            [BOTH.format("system.potential")],
        ),
        "hamiltonian-form-not-a-string": (
            case(system="[system]\nhamiltonian = 2\n"),
            ["system.hamiltonian: expected a string, found an integer"],
        ),
        "hamiltonian-form-kappa-boolean": (
            case(system='[system]\nhamiltonian = "M1**2"\nkappa = true\n'),
            ["system.kappa: expected a string, found a boolean"],
        ),
        "hamiltonian-form-kappa-infinite": (
            case(system='[system]\nhamiltonian = "M1**2"\nkappa = inf\n'),
            ["system.kappa: expected a finite number or an expression: 'inf'"],
        ),
        "hamiltonian-form-kappa-array": (
            case(system='[system]\nhamiltonian = "M1**2"\nkappa = ["1"]\n'),
            ["system.kappa: expected a string, found an array"],
        ),
    }
)

NAME = "not a valid name (use ASCII letters, digits and '_', not starting with a digit)"
ID = "an id may hold only lowercase letters, digits, '.' and '-', and starts with a letter or digit"
HOSTILE.update(
    {
        "injection-parameter-name": (
            case(parameters=GOOD["parameters"] + '"__import__(\'os\')" = "real"\n'),
            [f"parameters.\"__import__('os')\": {NAME}"],
        ),
        "injection-parameter-keyword": (
            case(parameters=GOOD["parameters"] + 'import = "real"\n'),
            ["parameters.import: 'import' is a reserved name (a Python keyword)"],
        ),
        "injection-function-name": (
            case(functions='[functions]\n"os.system" = ["s"]\n'),
            [f'functions."os.system": {NAME}'],
        ),
        "injection-function-argument": (
            case(functions="[functions]\nf = [\"__import__('os')\"]\n"),
            [
                "functions.f[0]: unknown argument \"__import__('os')\" "
                "(expected one of M1, M2, M3, gamma1, gamma2, gamma3, s)"
            ],
        ),
        "injection-id": (
            case(head='id = "__import__(\'os\')"\ntitle = "x"\n'),
            [f"id: {ID} (found '_'): \"__import__('os')\""],
        ),
        "injection-assumption": (
            case(parameters='[parameters]\nC = "positive"\nN = "__import__(\'os\')"\n'),
            [
                "parameters.N: unknown assumption \"__import__('os')\" "
                "(expected 'real', 'positive', 'nonzero' or 'integer')"
            ],
        ),
        "injection-kind": (
            case(claims=claim(kind=q("exec"))),
            [
                "claims[0].kind: unknown claim kind 'exec' "
                "(expected 'integral', 'casimir', 'measure' or 'relation')"
            ],
        ),
        "injection-terminal-escape-in-title": (
            case(head='id = "hostile-demo"\ntitle = "\\u001b]0;owned\\u0007 clear"\n'),
            ["title: control character U+001B is not allowed: '\\x1b]0;owned\\x07 clear'"],
        ),
        "injection-bidi-override-in-label": (
            case(claims=claim(label=q("I1\u202e2I"))),
            ["claims[0].label: control character U+202E is not allowed: 'I1\\u202e2I'"],
        ),
        "injection-line-break-in-citation": (
            case(source='[source]\ncitation = "A\\nError: all is fine"\n'),
            ["source.citation: control character U+000A is not allowed: 'A\\nError: all is fine'"],
        ),
    }
)

# --- resource attacks: power towers, huge literals and exponents, deep nesting, sizes
LONG = "s+" * 450_000 + "s"
expression_cases(
    "resources",
    [
        ("potential", "9**9**9**9", "exponent too large (at most 1000 in absolute value)"),
        ("torque[0]", "gamma1**(10**100)", "exponent too large (at most 1000 in absolute value)"),
        ("expression", "2**1000**1000", "exponent too large (at most 1000 in absolute value)"),
        ("on[0]", "gamma1**(1/1000)", "exponent denominator too large (at most 100)"),
        ("inertia[0]", "9" * 5000, "number literal too long (more than 100 digits)"),
        ("torque[1]", "1e100000", "number literal too long (more than 100 digits)"),
        ("expression", "0x" + "f" * 200, "number literal too long (more than 100 digits)"),
        (
            "potential",
            "10**1000*10**1000*10**1000*10**1000*10**1000",
            "number too large (it could have more than 4000 digits)",
        ),
        (
            "torque[2]",
            "E**(1000*log(10**100))",
            "number too large (it could have more than 4000 digits)",
        ),
        (
            "expression",
            "exp(2)**(500*log(10**100))",
            "number too large (it could have more than 4000 digits)",
        ),
        (
            "on[0]",
            "sqrt(10**400 + 1)",
            "number too large for a root (it could have more than 300 digits)",
        ),
        (
            "potential",
            "+".join(f"sqrt(10**299 + {k})" for k in range(1, 5)),
            "too many roots of numbers (more than 1000 digits under roots in all)",
        ),
        (
            "expression",
            "(" * 5000 + "s" + ")" * 5000,
            "expression nested too deeply (more than 100 levels)",
        ),
        ("torque[0]", "-" * 150 + "s", "expression nested too deeply (more than 100 levels)"),
        (
            "potential",
            "sin(" * 200 + "s" + ")" * 200,
            "expression nested too deeply (more than 100 levels)",
        ),
        ("expression", "+".join(["s"] * 3000), "expression too large (more than 5000 parts)"),
        ("potential", LONG, f"expression too long ({len(LONG)} characters; at most 20000)"),
        (
            "expression",
            "diff(" + "*".join(f"sin(gamma1 + {i})" for i in range(120)) + ", gamma1)",
            "expression too large to differentiate",
        ),
    ],
)

MANY_CLAIMS = "".join(
    f'[[claims]]\nlabel = "I{i}"\nkind = "integral"\nexpression = "M3"\n' for i in range(5000)
)
LARGE_CLAIMS = ["*".join(f"(gamma1 + {1000 * i + j})" for j in range(700)) for i in range(3)]
HOSTILE.update(
    {
        "resources-file-too-large": (
            case(head=GOOD["head"] + f"notes = {q('x' * toml_input.MAX_FILE_BYTES)}\n"),
            ["the file is too large (more than 1000000 bytes)"],
        ),
        "resources-many-claims": (
            case(claims=MANY_CLAIMS),
            ["claims: too many claims (5000; at most 200)"],
        ),
        "resources-many-equations": (
            case(claims=claim(on="[" + ", ".join(['"s = 0"'] * 10_000) + "]")),
            ["claims[0].on: too many equations (10000; at most 20)"],
        ),
        "resources-many-parameters": (
            case(
                parameters=GOOD["parameters"] + "".join(f'p{i} = "real"\n' for i in range(30_000))
            ),
            ["parameters: too many parameters (30002; at most 100)"],
        ),
        "resources-long-torque": (
            case(system=system(torque="[" + ", ".join(['"s"'] * 50_000) + "]")),
            ["system.torque: expected 3 entries, found 50000"],
        ),
        "resources-many-function-arguments": (
            case(functions="[functions]\nf = [" + ", ".join(['"s"'] * 50_000) + "]\n"),
            ["functions.f: too many arguments (50000; at most 7, all distinct)"],
        ),
        "resources-expressions-too-large-together": (
            case(
                claims="".join(
                    claim(label=q(f"I{i}"), expression=q(text))
                    for i, text in enumerate(LARGE_CLAIMS)
                )
            ),
            [
                "claims[1].expression: the case's expressions are too large together "
                f"(more than 5000 parts in all): {shown(LARGE_CLAIMS[1])}"
            ],
        ),
        "resources-many-problems": (
            case(
                claims="".join(claim(label=q(f"I{i}"), expression=q(f"x{i}")) for i in range(120))
            ),
            [
                f"claims[{i}].expression: unknown name 'x{i}' (declare it under [parameters]): "
                f"'x{i}'"
                for i in range(50)
            ]
            + ["70 more problems not listed (at most 50 are)"],
        ),
        "resources-many-unknown-keys": (
            case(head=GOOD["head"] + "".join(f"k{i} = 1\n" for i in range(60_000))),
            [f"unknown key 'k{i}'" for i in range(50)]
            + ["59950 more problems not listed (at most 50 are)"],
        ),
        "resources-toml-deep-arrays": (
            case(head=GOOD["head"] + "notes = " + "[" * 100_000 + "]" * 100_000 + "\n"),
            ["invalid TOML: nested too deeply (more than 10 levels) (at line 3, column 19)"],
        ),
        "resources-toml-deep-inline-tables": (
            case(head=GOOD["head"] + "notes = " + "{a = " * 5000 + "1" + "}" * 5000 + "\n"),
            ["invalid TOML: nested too deeply (more than 10 levels) (at line 3, column 59)"],
        ),
        "resources-toml-deep-dotted-key": (
            case(head=GOOD["head"] + "a" + ".a" * 100_000 + " = 1\n"),
            ["invalid TOML: nested too deeply (more than 10 levels) (at line 3, column 22)"],
        ),
        "resources-toml-deep-table-header": (
            case(source="[source" + ".a" * 100_000 + "]\n"),
            ["invalid TOML: nested too deeply (more than 10 levels) (at line 4, column 26)"],
        ),
        "resources-toml-huge-integer": (
            case(head="id = 1" + "0" * 10_000 + '\ntitle = "x"\n'),
            ["invalid TOML: number too long (more than 100 digits) (at line 1, column 6)"],
        ),
        "resources-huge-key": (
            case(head=GOOD["head"] + "k" * 500_000 + " = 1\n"),
            ["unknown key '" + "k" * 37 + "...'"],
        ),
    }
)

# --- malformed TOML
HOSTILE.update(
    {
        "toml-missing-value": (
            'id = "hostile-demo"\ntitle =\n',
            ["invalid TOML: Invalid value (at line 2, column 8)"],
        ),
        "toml-unclosed-string": (
            'id = "hostile-demo\ntitle = "x"\n',
            ["invalid TOML: Illegal character '\\n' (at line 1, column 19)"],
        ),
        "toml-unclosed-multiline-string": (
            case(head=GOOD["head"] + 'notes = """never closed\n'),
            ["invalid TOML: Unterminated string (at end of document)"],
        ),
        "toml-unclosed-array": (
            case(system='[system]\ninertia = ["C", "C", "2*C"\n'),
            ["invalid TOML: Unclosed array (at line 15, column 1)"],
        ),
        "toml-bad-header": (
            case(claims='[[claims]\nlabel = "I1"\n'),
            [
                "invalid TOML: Expected ']]' at the end of an array declaration "
                "(at line 17, column 9)"
            ],
        ),
        "toml-duplicate-key": (
            case(head=GOOD["head"] + 'id = "other"\n'),
            ["invalid TOML: Cannot overwrite a value (at line 3, column 13)"],
        ),
        "toml-duplicate-table": (
            case(source=GOOD["source"] * 2),
            ["invalid TOML: Cannot declare ('source',) twice (at line 6, column 8)"],
        ),
        "toml-table-and-array": (
            case(claims="[claims]\n[[claims]]\n"),
            ["invalid TOML: Cannot overwrite a value (at line 18, column 9)"],
        ),
        "toml-nul-byte": (
            'id = "hostile-demo"\x00\n',
            [
                "invalid TOML: Expected newline or end of document after a statement "
                "(at line 1, column 20)"
            ],
        ),
        "toml-binary-garbage": (
            b"\x00\x01\x02\x03\x7f",
            ["invalid TOML: Invalid statement (at line 1, column 1)"],
        ),
        "toml-json-instead": (
            '{"id": "hostile-demo"}\n',
            ["invalid TOML: Invalid statement (at line 1, column 1)"],
        ),
        "toml-surrogate-escape": (
            'id = "\\ud800"\n',
            [
                "invalid TOML: Escaped character is not a Unicode scalar value "
                "(at line 1, column 13)"
            ],
        ),
    }
)

# --- not UTF-8
VALID = case().encode("utf-8")
SMALL = VALID.index(b"small")
HOSTILE.update(
    {
        "encoding-latin-1": (
            VALID.replace(b"A. Author", "\u00c9. \u00c9crivain".encode("latin-1")),
            [f"the file is not UTF-8 text (byte 0xc9 at offset {VALID.index(b'A. Author')})"],
        ),
        "encoding-utf-16": (
            case().encode("utf-16"),
            ["the file is not UTF-8 text (byte 0xff at offset 0)"],
        ),
        "encoding-lone-continuation-byte": (
            VALID.replace(b"small", b"sm\x80ll"),
            [f"the file is not UTF-8 text (byte 0x80 at offset {SMALL + 2})"],
        ),
        "encoding-overlong-slash": (
            VALID.replace(b"small", b"sm\xc0\xafll"),
            [f"the file is not UTF-8 text (byte 0xc0 at offset {SMALL + 2})"],
        ),
        "encoding-encoded-surrogate": (
            VALID.replace(b"small", b"sm\xed\xa0\x80ll"),
            [f"the file is not UTF-8 text (byte 0xed at offset {SMALL + 2})"],
        ),
        "encoding-truncated-at-end": (
            VALID + "\u00e9".encode()[:1],
            [f"the file is not UTF-8 text (byte 0xc3 at offset {len(VALID)})"],
        ),
    }
)

# --- empty files
MISSING = "required field is missing"
HOSTILE.update(
    {
        "empty-no-bytes": (b"", ["the file is empty"]),
        "empty-blank": (" \n\t\n\r\n", ["the file is empty"]),
        "empty-byte-order-mark": (b"\xef\xbb\xbf", ["the file is empty"]),
        "empty-comments-only": (
            "# a case file\n# with nothing in it\n",
            [
                f"id: {MISSING}",
                f"title: {MISSING}",
                f"source.citation: {MISSING}",
                f"system.inertia: {MISSING}",
            ],
        ),
        "empty-tables": (
            "[source]\n[system]\n[[claims]]\n",
            [
                f"id: {MISSING}",
                f"title: {MISSING}",
                f"source.citation: {MISSING}",
                f"system.inertia: {MISSING}",
                f"claims[0].label: {MISSING}",
                f"claims[0].kind: {MISSING}",
                f"claims[0].expression: {MISSING}",
            ],
        ),
    }
)

# --- wrong types everywhere
HOSTILE.update(
    {
        "types-id-number": (
            case(head='id = 42\ntitle = "x"\n'),
            ["id: expected a string, found an integer"],
        ),
        "types-title-array": (
            case(head='id = "hostile-demo"\ntitle = ["x"]\n'),
            ["title: expected a string, found an array"],
        ),
        "types-notes-table": (
            case(head=GOOD["head"] + "notes = {text = 'x'}\n"),
            ["notes: expected a string, found a table"],
        ),
        "types-source-string": (
            case(head=GOOD["head"] + 'source = "A. Author"\n', source=""),
            ["source: expected a table, found a string"],
        ),
        "types-citation-float": (
            case(source="[source]\ncitation = 3.5\n"),
            ["source.citation: expected a string, found a float"],
        ),
        "types-doi-date": (
            case(source='[source]\ncitation = "A"\ndoi = 2003-01-01\n'),
            ["source.doi: expected a string, found a date or time"],
        ),
        "types-parameters-array": (
            case(head=GOOD["head"] + 'parameters = ["C", "N"]\n', parameters=""),
            [
                "parameters: expected a table, found an array",
                "system.inertia[0]: unknown name 'C' (declare it under [parameters]): 'C'",
                "system.inertia[1]: unknown name 'C' (declare it under [parameters]): 'C'",
                "system.inertia[2]: unknown name 'C' (declare it under [parameters]): '2*C'",
                "system.potential: unknown name 'C' (declare it under [parameters]): 'C*gamma3'",
                "system.torque[2]: unknown name 'N' (declare it under [parameters]): 'N*gamma3'",
            ],
        ),
        "types-assumption-boolean": (
            case(parameters='[parameters]\nC = true\nN = "real"\n'),
            ["parameters.C: expected a string, found a boolean"],
        ),
        "types-functions-string": (
            case(head=GOOD["head"] + 'functions = "phi"\n'),
            ["functions: expected a table, found a string"],
        ),
        "types-function-arguments-string": (
            case(functions='[functions]\nphi = "gamma1"\n'),
            ["functions.phi: expected an array of argument names, found a string"],
        ),
        "types-function-argument-number": (
            case(functions="[functions]\nphi = [1]\n"),
            ["functions.phi[0]: expected a string, found an integer"],
        ),
        "types-system-number": (
            case(head=GOOD["head"] + "system = 1\n", system=""),
            ["system: expected a table, found an integer"],
        ),
        "types-inertia-string": (
            case(system=system(inertia='"C, C, 2*C"')),
            ["system.inertia: expected an array of 3 strings, found a string"],
        ),
        "types-inertia-entry-number": (
            case(system=system(inertia='["C", 1, "2*C"]')),
            ["system.inertia[1]: expected a string, found an integer"],
        ),
        "types-potential-array": (
            case(system=system(potential='["C*gamma3"]')),
            ["system.potential: expected a string, found an array"],
        ),
        "types-torque-table": (
            case(system=system(torque='{x = "0"}')),
            ["system.torque: expected an array of 3 strings, found a table"],
        ),
        "types-torque-entry-float": (
            case(system=system(torque='["0", 0.5, "0"]')),
            ["system.torque[1]: expected a string, found a float"],
        ),
        "types-claims-string": (
            case(head=GOOD["head"] + 'claims = "I1"\n', claims=""),
            ["claims: expected an array of tables ([[claims]]), found a string"],
        ),
        "types-claims-table": (
            case(claims='[claims]\nlabel = "I1"\n'),
            ["claims: expected an array of tables ([[claims]]), found a table"],
        ),
        "types-claim-number": (
            case(head=GOOD["head"] + "claims = [1, 2]\n", claims=""),
            [
                "claims[0]: expected a table, found an integer",
                "claims[1]: expected a table, found an integer",
            ],
        ),
        "types-label-boolean": (
            case(claims=claim(label="true")),
            ["claims[0].label: expected a string, found a boolean"],
        ),
        "types-kind-number": (
            case(claims=claim(kind="1")),
            ["claims[0].kind: expected a string, found an integer"],
        ),
        "types-expression-number": (
            case(claims=claim(expression="0")),
            ["claims[0].expression: expected a string, found an integer"],
        ),
        "types-expression-table": (
            case(claims=claim(expression="{text = 'M3'}")),
            ["claims[0].expression: expected a string, found a table"],
        ),
        "types-on-string": (
            case(claims=claim(on='"s = 0"')),
            ["claims[0].on: expected an array of equations, found a string"],
        ),
        "types-on-entry-array": (
            case(claims=claim(on='[["s", "0"]]')),
            ["claims[0].on[0]: expected a string, found an array"],
        ),
        "types-locator-time": (
            case(claims=claim(locator="07:32:00")),
            ["claims[0].locator: expected a string, found a date or time"],
        ),
        "types-nan-and-inf": (
            case(system=system(inertia="[nan, inf, -inf]")),
            [f"system.inertia[{i}]: expected a string, found a float" for i in range(3)],
        ),
    }
)

# --- unicode look-alikes
NON_ASCII = "non-ASCII character"
FULLWIDTH_EQUALS = "s \uff1d 0"
expression_cases(
    "lookalike",
    [
        ("potential", "g\u0430mma1", f"{NON_ASCII} '\u0430' (U+0430)"),
        ("torque[0]", "\uff47amma1", f"{NON_ASCII} '\uff47' (U+FF47)"),
        ("expression", "\u03b31 + M1", f"{NON_ASCII} '\u03b3' (U+03B3)"),
        ("on[0]", "gamma1 \u2212 1", f"{NON_ASCII} '\u2212' (U+2212)"),
        ("inertia[0]", "\u0421", f"{NON_ASCII} '\u0421' (U+0421)"),
        ("torque[1]", "gamma1\u200b", f"{NON_ASCII} '\\u200b' (U+200B)"),
        ("expression", "M\u2081", f"{NON_ASCII} '\u2081' (U+2081)"),
        ("potential", "\ufb01", f"{NON_ASCII} '\ufb01' (U+FB01)"),
    ],
)
HOSTILE.update(
    {
        "lookalike-key": (
            case(head='id = "hostile-demo"\n"t\u0456tle" = "x"\n'),
            ["unknown key 't\\u0456tle' (did you mean 'title'?)", f"title: {MISSING}"],
        ),
        "lookalike-table": (
            case(system=system().replace("[system]", '["s\u0443stem"]')),
            ["unknown key 's\\u0443stem' (did you mean 'system'?)", f"system.inertia: {MISSING}"],
        ),
        "lookalike-parameter": (
            case(parameters='[parameters]\n"\u0421" = "positive"\nN = "real"\n'),
            [
                f'parameters."\\u0421": {NAME}',
                "system.inertia[0]: unknown name 'C' (declare it under [parameters]): 'C'",
                "system.inertia[1]: unknown name 'C' (declare it under [parameters]): 'C'",
                "system.inertia[2]: unknown name 'C' (declare it under [parameters]): '2*C'",
                "system.potential: unknown name 'C' (declare it under [parameters]): 'C*gamma3'",
            ],
        ),
        "lookalike-id": (
            case(head='id = "hostile-d\u0435mo"\ntitle = "x"\n'),
            [f"id: {ID} (found U+0435): 'hostile-d\u0435mo'"],
        ),
        "lookalike-kind": (
            case(claims=claim(kind=q("\u0456ntegral"))),
            [
                "claims[0].kind: unknown claim kind '\\u0456ntegral' "
                "(expected 'integral', 'casimir', 'measure' or 'relation')"
            ],
        ),
        "lookalike-fullwidth-equals-in-on": (
            case(claims=claim(on=f"[{q(FULLWIDTH_EQUALS)}]")),
            ["claims[0].on[0]: an equation needs the form lhs = rhs: 's \uff1d 0'"],
        ),
    }
)

# --- found by scripts/fuzz_parser.py: a text of characters that are escaped when shown
# (line separators, emoji, lone surrogates) made an error line of up to 800 characters, as
# the text was cut before it was escaped; the cut now counts the escapes
EMOJI, ESCAPED = "\U0001f600", "'" + "\\U0001f600" * 7 + "...'"
HOSTILE.update(
    {
        "fuzz-escaped-expression": (
            placed("expression", "M1 + " + "\u2028" * 100),
            [
                "claims[0].expression: non-ASCII character '\\u2028' (U+2028): 'M1 + "
                + "\\u2028" * 25
                + "...'"
            ],
        ),
        "fuzz-escaped-kind": (
            case(claims=claim(kind=q(EMOJI * 60))),
            [
                f"claims[0].kind: unknown claim kind {ESCAPED} "
                f"(expected 'integral', 'casimir', 'measure' or 'relation')"
            ],
        ),
        "fuzz-escaped-key": (
            case(head=GOOD["head"] + f"{q(EMOJI * 60)} = 1\n"),
            [f"unknown key {ESCAPED}"],
        ),
        "fuzz-escaped-parameter": (
            case(parameters=GOOD["parameters"] + f'{q(EMOJI * 60)} = "real"\n'),
            ['parameters."' + "\\ud83d\\ude00" * 6 + f'...": {NAME}'],
        ),
        "fuzz-escaped-assumption": (
            case(parameters=f'[parameters]\nC = "positive"\nN = {q(EMOJI * 60)}\n'),
            [
                f"parameters.N: unknown assumption {ESCAPED} "
                "(expected 'real', 'positive', 'nonzero' or 'integer')"
            ],
        ),
        "fuzz-escaped-argument": (
            case(functions=f"[functions]\nf = [{q(EMOJI * 60)}]\n"),
            [
                f"functions.f[0]: unknown argument {ESCAPED} "
                "(expected one of M1, M2, M3, gamma1, gamma2, gamma3, s)"
            ],
        ),
        "fuzz-escaped-label": (
            case(claims=claim(label=q(EMOJI * 60)) * 2),
            [f"claims[1].label: duplicate label {ESCAPED}"],
        ),
    }
)

# --- '^' for a power
expression_cases(
    "caret",
    [
        ("potential", "gamma1^2", "'^' is not a power; use '**'"),
        ("torque[2]", "N*gamma3^3", "'^' is not a power; use '**'"),
        ("expression", "M1^2 + M2^2 + M3^2", "'^' is not a power; use '**'"),
        ("on[0]", "gamma1^2 + gamma2^2 + gamma3^2 = 1", "'^' is not a power; use '**'"),
        ("inertia[2]", "2*C^1", "'^' is not a power; use '**'"),
    ],
)


def categories() -> dict[str, int]:
    """How many hostile files each category has (for the report)."""
    counts: dict[str, int] = {}
    for name in HOSTILE:
        counts[name.split("-")[0]] = counts.get(name.split("-")[0], 0) + 1
    return counts


# --------------------------------------------------------------------- helpers


def write(path: Path, content: str | bytes) -> Path:
    path.write_bytes(content.encode("utf-8") if isinstance(content, str) else content)
    return path


def add(db: Path, *paths: Path):
    """``registry --db DB add PATHS`` in-process, never letting an exception escape."""
    return CliRunner().invoke(main, ["--db", str(db), "add", *map(str, paths)])


def stored_cases(db: Path) -> list[str]:
    """The ids of the cases in the database (none when add never created it)."""
    if not db.exists():
        return []
    with registry.open(db) as reg:
        return list(reg.cases()["case"]) if len(reg.cases()) else []


def tally(added: int = 0, refused: int = 0) -> str:
    """The last line ``registry add`` prints to standard output."""
    return (
        f"{added + refused} file(s): {added} added, 0 new version, 0 unchanged, {refused} refused"
    )


def assert_clean_refusal(result, lines: list[str]) -> None:
    """Exit status 1, no traceback, exactly ``lines`` as errors, only the tally on stdout."""
    assert result.exit_code == 1, result.output
    assert isinstance(result.exception, SystemExit), result.exception
    assert "Traceback" not in result.output
    assert result.stdout.splitlines() == [tally(refused=1)]
    assert all(line.startswith("Error: ") for line in result.stderr.splitlines())
    assert result.stderr.splitlines() == lines


# ------------------------------------------------------------------- the tests


def test_corpus_covers_every_category():
    assert categories().keys() == {
        "injection",
        "resources",
        "toml",
        "encoding",
        "empty",
        "types",
        "lookalike",
        "caret",
        "hamiltonian",
        "fuzz",
    }


@pytest.mark.parametrize(("content", "problems"), HOSTILE.values(), ids=HOSTILE.keys())
def test_hostile_file_is_refused(tmp_path, content, problems):
    path = write(tmp_path / "hostile.toml", content)
    db = tmp_path / "registry.sqlite"

    with cpu_bound(TIME_LIMIT):
        result = add(db, path)

    assert_clean_refusal(result, [f"Error: {path}: {p}" for p in problems])
    assert stored_cases(db) == []

    with pytest.raises(CaseFormatError) as info:
        load_case(path)
    assert info.value.file == str(path)
    assert str(info.value).splitlines() == [f"{path}: {p}" for p in problems]


def test_a_folder_stores_the_good_file_and_refuses_the_hostile_ones(tmp_path):
    folder = tmp_path / "cases"
    folder.mkdir()
    good = write(folder / "a-good.toml", case())
    hostile = write(folder / "b-hostile.toml", placed("potential", "__import__('os')"))
    (folder / "c-folder.toml").mkdir()
    write(folder / "notes.txt", "not a case file, not read")
    db = tmp_path / "registry.sqlite"

    result = add(db, folder)

    assert result.exit_code == 1
    assert "Traceback" not in result.output
    assert result.stdout.splitlines() == [
        f"{'added':12} hostile-demo (version 1)  {good}",
        tally(added=1, refused=2),
    ]
    assert result.stderr.splitlines() == [
        f"Error: {hostile}: system.potential: unknown function '__import__': \"__import__('os')\"",
        f"Error: {folder / 'c-folder.toml'}: not a regular file",
    ]
    assert stored_cases(db) == ["hostile-demo"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes need POSIX")
def test_a_named_pipe_is_refused_without_waiting(tmp_path):
    pipe = tmp_path / "pipe.toml"
    os.mkfifo(pipe)
    db = tmp_path / "registry.sqlite"
    # opening a pipe that no one writes to waits without computing: the wait is watched on
    # the wall clock, in a thread, so that a blocked open fails the test instead of hanging it
    found = []
    reader = threading.Thread(target=lambda: found.append(add(db, pipe)), daemon=True)
    reader.start()
    reader.join(HANG)
    if reader.is_alive():
        os.close(os.open(pipe, os.O_WRONLY | os.O_NONBLOCK))  # let the blocked open go
        pytest.fail(f"registry add waited {HANG:g} s on a named pipe")
    (result,) = found
    assert_clean_refusal(result, [f"Error: {pipe}: not a regular file"])
    assert stored_cases(db) == []


def test_a_file_name_cannot_forge_error_lines(tmp_path):
    path = write(tmp_path / "x\nError: all fine\x1b[0m.toml", placed("expression", "gamma1^2"))
    result = add(tmp_path / "registry.sqlite", path)
    shown_path = str(path).replace("\n", "\\n").replace("\x1b", "\\x1b")
    assert_clean_refusal(
        result,
        [f"Error: {shown_path}: claims[0].expression: '^' is not a power; use '**': 'gamma1^2'"],
    )


# ----------------------------------------------------------- nothing is executed

#: Files that the payloads below would create, relative to the working directory.
SENTINELS = ("pwned-os", "pwned-open", "pwned-path", "pwned-exec", "pwned-sympy")
PAYLOADS = [
    "__import__('os').system('touch pwned-os')",
    "__import__('os').mkdir('pwned-os')",
    "open('pwned-open', 'w').write('x')",
    "__import__('pathlib').Path('pwned-path').touch()",
    "exec(\"open('pwned-exec', 'w')\")",
    "eval(\"__import__('os').mkdir('pwned-exec')\")",
    "(lambda: __import__('os').mkdir('pwned-os'))()",
    "[__import__('os').mkdir('pwned-os') for _ in 'x']",
    "gamma1.__class__.__init__.__globals__['__builtins__']['open']('pwned-sympy', 'w')",
    "sqrt.__globals__['__builtins__']['exec'](\"open('pwned-sympy', 'w')\")",
    "pi.func.__call__.__globals__['os'].mkdir('pwned-sympy')",
    'S(\'open("pwned-sympy", "w")\')',
    'sympify(\'open("pwned-sympy", "w")\')',
    'parse_expr(\'open("pwned-sympy", "w")\')',
]


def payload_files(folder: Path) -> list[Path]:
    """Every payload in every expression field, and as names, id, title and notes."""
    files = []
    for i, payload in enumerate(PAYLOADS):
        for k, field in enumerate(FIELD_NAMES):
            text = f"{payload} = 0" if field == "on[0]" else payload
            files.append(write(folder / f"p{i:02d}-field{k}.toml", placed(field, text)))
        files.append(
            write(
                folder / f"p{i:02d}-names.toml",
                case(
                    head=f"id = {q(payload)}\ntitle = {q(payload)}\nnotes = {q(payload)}\n",
                    parameters=f'[parameters]\nC = "positive"\n{q(payload)} = "real"\n',
                    functions=f"[functions]\n{q(payload)} = [{q(payload)}]\n",
                    claims=claim(label=q(payload), kind=q(payload)),
                ),
            )
        )
    return files


@contextlib.contextmanager
def no_code_execution():
    """Make every way of running text as code fail loudly: eval and exec of text,
    compiling text to code, sympy's parsing of strings, shells.

    ``ast.parse`` compiles to a syntax tree only (PyCF_ONLY_AST), which is allowed;
    so is compiling a module's source file, which sympy's lazy imports may do. Code
    objects (made by those) may run.
    """
    real = {name: getattr(builtins, name) for name in ("eval", "exec", "compile")}

    def forbidden(name):
        def fail(*args, **kwargs):
            raise AssertionError(f"{name} was called")

        return fail

    def no_text(name):
        def run(source, *args, **kwargs):
            if isinstance(source, str | bytes):
                raise AssertionError(f"{name} of text was called")
            return real[name](source, *args, **kwargs)

        return run

    def compile_to_tree_only(source, filename, mode, flags=0, *args, **kwargs):
        module_source = str(filename).endswith(".py") and os.path.isfile(filename)
        if not (flags & ast.PyCF_ONLY_AST or module_source):
            raise AssertionError("compile was called to make code")
        return real["compile"](source, filename, mode, flags, *args, **kwargs)

    sympify_module = sys.modules["sympy.core.sympify"]
    real_sympify = sympify_module.sympify

    def sympify_no_strings(a, *args, **kwargs):
        if isinstance(a, str):
            raise AssertionError("sympify of a string was called")
        return real_sympify(a, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(builtins, "eval", no_text("eval"))
        mp.setattr(builtins, "exec", no_text("exec"))
        mp.setattr(builtins, "compile", compile_to_tree_only)
        mp.setattr(sympify_module, "sympify", sympify_no_strings)
        mp.setattr(sympy, "sympify", sympify_no_strings)
        mp.setattr(sympy.parsing.sympy_parser, "parse_expr", forbidden("parse_expr"))
        mp.setattr(os, "system", forbidden("os.system"))
        mp.setattr(subprocess, "Popen", forbidden("subprocess.Popen"))
        yield


def test_nothing_is_executed(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "payloads"
    folder.mkdir()
    files = payload_files(folder)
    with no_code_execution():
        for path in files:
            with pytest.raises(CaseFormatError):
                load_case(path)
            with pytest.raises(CaseFormatError):
                parse_case_text(path.read_text(encoding="utf-8"), path.name)
    assert not any((tmp_path / name).exists() for name in SENTINELS)


def test_nothing_is_executed_through_the_command_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "payloads"
    folder.mkdir()
    files = payload_files(folder)
    db = tmp_path / "registry.sqlite"

    result = add(db, folder)

    assert result.exit_code == 1
    assert result.stdout.splitlines() == [tally(refused=len(files))]
    assert "Traceback" not in result.output
    errors = result.stderr.splitlines()
    assert all(line.startswith("Error: ") for line in errors)
    assert {line.split(": ", 2)[1] for line in errors} == {str(p) for p in files}
    assert not any((tmp_path / name).exists() for name in SENTINELS)
    assert stored_cases(db) == []


def test_the_guard_notices_execution():
    with no_code_execution():
        with pytest.raises(AssertionError, match="eval of text was called"):
            eval("1")
        with pytest.raises(AssertionError, match="exec of text was called"):
            exec("import os")
        with pytest.raises(AssertionError, match="sympify of a string"):
            sympy.sympify("1")
        with pytest.raises(AssertionError, match="compile was called"):
            compile("1", "<test>", "eval")


# --------------------------------------------------------------------- limits


def test_limits_are_documented_constants():
    assert (toml_input.MAX_FILE_BYTES, toml_input.MAX_TOML_DEPTH) == (1_000_000, 10)
    assert (casefile.MAX_CLAIMS, casefile.MAX_EQUATIONS, casefile.MAX_PARAMETERS) == (200, 20, 100)
    assert casefile.MAX_PROBLEMS == 50
    assert (limits.MAX_CASE_PARTS, limits.MAX_CASE_ROOT_DIGITS) == (5_000, 1_000)
    assert limits.MAX_CASE_DIFF_WORK == 10_000
    page = Path(__file__).resolve().parents[1] / "docs" / "case-format.md"
    table = page.read_text(encoding="utf-8")
    for name in (
        "MAX_FILE_BYTES",
        "MAX_TOML_DEPTH",
        "MAX_CLAIMS",
        "MAX_EQUATIONS",
        "MAX_PARAMETERS",
        "MAX_PROBLEMS",
        "MAX_LENGTH",
        "MAX_NODES",
        "MAX_DEPTH",
        "MAX_DIGITS",
        "MAX_EXPONENT",
        "MAX_CASE_PARTS",
        "MAX_CASE_ROOT_DIGITS",
        "MAX_CASE_DIFF_WORK",
    ):
        assert f".{name}`" in table, name


def test_a_large_case_within_the_limits_loads(tmp_path):
    text = case(
        claims="".join(
            claim(label=q(f"I{i}"), expression=q(f"M3 + {i}*(gamma1**2 + gamma2**2)"))
            for i in range(casefile.MAX_CLAIMS)
        )
    )
    with cpu_bound(TIME_LIMIT):
        loaded = parse_case_text(text)
    assert len(loaded.claims) == casefile.MAX_CLAIMS


def test_trigonometric_values_stay_as_written():
    """sympy would expand cos(pi/120) into nested radicals, slowly; the value is kept."""
    text = "+".join(f"cos({p}*pi/120)*tan({p}*pi/120)" for p in range(1, 120, 2))
    with cpu_bound(TIME_LIMIT):
        value = parser.parse_expression(text)
    assert value.has(sympy.cos(sympy.pi / 120, evaluate=False))
    assert parser.parse_expression("cos(pi/3)") == sympy.Rational(1, 2)


# -------------------------------------------------------- random and mutated files

SEEDS = [path.read_text(encoding="utf-8") for path in sorted(CASES.glob("*.toml"))]

#: Pieces that mutations insert: code, syntax, types, resources, look-alikes.
TOKENS = [
    "__import__('os').mkdir('pwned-os')",
    ".__class__",
    "[0]",
    "^",
    "**9**9**9",
    "9" * 150,
    "(" * 120,
    "lambda: 0",
    "x := 1",
    "'",
    '"',
    '"""',
    "'''",
    "\\",
    "[",
    "]]",
    "{",
    "}",
    "=",
    ",",
    ".",
    "#",
    "\n",
    "\n[[claims]]\n",
    "\n[system]\n",
    "\na.b.c.d.e.f.g.h.i.j.k = 1\n",
    " = 1979-05-27T07:32:00Z",
    "1e999",
    "nan",
    "true",
    "\u0430",
    "\u202e",
    "\x1b",
    "\x00",
    "\ufeff",
    "\ud800",
    "gamma1",
    "s",
    "diff(",
    ", s)",
    "sqrt(10**299 + 1)",
]

#: Replacements for a value, changing its type.
VALUES = ['"x"', "1", "-0.5", "true", "[]", '["C"]', "{}", '{a = "b"}', "1979-05-27", '""']


@st.composite
def mutated_case_files(draw) -> str:
    """A seed case file after a few random edits of its characters, lines and values."""
    text = draw(st.sampled_from(SEEDS))
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(
            st.sampled_from(
                ["delete", "duplicate", "insert", "swap", "drop line", "retype", "char"]
            )
        )
        lines = text.splitlines(keepends=True)
        if kind in ("swap", "drop line", "retype") and len(lines) > 1:
            i = draw(st.integers(0, len(lines) - 1))
            j = draw(st.integers(0, len(lines) - 1))
            if kind == "swap":
                lines[i], lines[j] = lines[j], lines[i]
            elif kind == "drop line":
                del lines[i]
            elif "=" in lines[i]:
                key = lines[i].split("=", 1)[0]
                lines[i] = f"{key}= {draw(st.sampled_from(VALUES))}\n"
            text = "".join(lines)
            continue
        start = draw(st.integers(0, len(text)))
        end = min(len(text), start + draw(st.integers(0, 40)))
        if kind == "delete":
            text = text[:start] + text[end:]
        elif kind == "duplicate":
            text = text[:end] + text[start:end] + text[end:]
        elif kind == "insert":
            text = text[:start] + draw(st.sampled_from(TOKENS)) + text[start:]
        else:
            text = text[:start] + draw(st.characters()) + text[start + 1 :]
    return text


def check_parse(text: str) -> None:
    """A case, or a CaseFormatError of one well-formed line per problem; nothing else."""
    with cpu_bound(TIME_LIMIT):
        try:
            result = parse_case_text(text, "mutant.toml")
        except CaseFormatError as err:
            assert err.problems
            lines = str(err).splitlines()
            assert len(lines) == len(err.problems)
            assert all(line.startswith("mutant.toml: ") and len(line) < 400 for line in lines)
        else:
            assert isinstance(result, Case)


PROPERTY = settings(
    max_examples=200,
    deadline=None,  # the time bound is asserted in check_parse
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@PROPERTY
@given(mutated_case_files())
def test_mutated_case_files(text):
    with no_code_execution():
        check_parse(text)


def seed_expressions() -> list[tuple[str, parser.Namespace]]:
    """Every expression of the seed catalog, with its case's namespace."""
    found = []
    for text in SEEDS:
        seed = parse_case_text(text)
        ns = parser.Namespace(seed.parameters, seed.functions)
        system = seed.system
        texts = [e.text for e in (*system.inertia, system.potential, *system.torque)]
        for c in seed.claims:
            texts += [c.expression.text, *(e.text for e in c.on)]
        found += [(t, ns) for t in texts]
    return found


SEED_EXPRESSIONS = seed_expressions()


@st.composite
def mutated_expressions(draw) -> tuple[str, parser.Namespace]:
    """A seed expression after a few character edits and hostile insertions."""
    text, ns = draw(st.sampled_from(SEED_EXPRESSIONS))
    for _ in range(draw(st.integers(1, 3))):
        start = draw(st.integers(0, len(text)))
        end = min(len(text), start + draw(st.integers(0, 10)))
        piece = draw(st.sampled_from(TOKENS) | st.characters())
        text = draw(
            st.sampled_from(
                [
                    text[:start] + text[end:],
                    text[:end] + text[start:end] + text[end:],
                    text[:start] + piece + text[start:],
                    text[:start] + piece + text[end:],
                ]
            )
        )
    return text, ns


@PROPERTY
@given(mutated_expressions())
def test_mutated_expressions(mutant):
    text, ns = mutant
    with cpu_bound(TIME_LIMIT):
        with no_code_execution():
            try:
                value = parser.parse_expression(text, ns)
            except ExpressionError as err:
                assert err.text == text and err.message
            else:
                assert isinstance(value, sympy.Expr)


@PROPERTY
@given(st.text(alphabet=st.characters(codec="utf-8"), max_size=300) | st.text(max_size=300))
def test_random_text(text):
    with no_code_execution():
        check_parse(text)


@PROPERTY
@given(st.binary(max_size=300) | mutated_case_files().map(lambda t: t.encode("utf-8", "replace")))
def test_random_bytes_through_load_case(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("bytes") / "random.toml"
    path.write_bytes(data)
    with no_code_execution():
        try:
            case = load_case(path)
        except CaseFormatError as err:
            assert err.problems and err.file == str(path)
        else:
            assert isinstance(case, registry.Case)


EXPRESSION_TEXT = st.lists(
    st.sampled_from(
        TOKENS[:22] + ["M1", "gamma2", "C", "N", "+", "*", "**", "/", "(", ")", "1", "0.5"]
    ),
    max_size=12,
).map(" ".join)
TOML_SCALARS = st.one_of(
    st.text(max_size=20),
    EXPRESSION_TEXT,
    st.integers(),
    st.floats(allow_nan=True),
    st.booleans(),
)
TOML_VALUES = st.recursive(
    TOML_SCALARS,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=10,
)


def table(keys: tuple[str, ...], values) -> st.SearchStrategy[dict]:
    """Tables with some of the format's ``keys`` and a few others, of any type."""
    return st.dictionaries(
        st.sampled_from(keys) | st.text(max_size=8), values, max_size=len(keys) + 1
    )


RANDOM_CASES = st.fixed_dictionaries(
    {},
    optional={
        "id": st.sampled_from(["hostile-demo", "Demo", ""]) | TOML_VALUES,
        "title": TOML_VALUES,
        "source": table(("citation", "locator", "doi"), TOML_VALUES) | TOML_VALUES,
        "parameters": st.dictionaries(
            st.sampled_from(["C", "N", "s", "sqrt", "lambda", "x y", "\u0421"]),
            st.sampled_from(["real", "positive", "nonzero", "integer", "complex"]) | TOML_VALUES,
        ),
        "functions": st.dictionaries(
            st.sampled_from(["phi", "a", "C", "exp"]),
            st.lists(st.sampled_from(["s", "gamma1", "M1", "x"]) | TOML_SCALARS, max_size=8)
            | TOML_VALUES,
        ),
        "system": table(
            ("inertia", "potential", "torque"),
            st.lists(EXPRESSION_TEXT | TOML_SCALARS, max_size=4) | EXPRESSION_TEXT | TOML_VALUES,
        ),
        "claims": st.lists(
            table(
                ("label", "kind", "expression", "on", "locator"),
                EXPRESSION_TEXT | st.sampled_from(["integral", "casimir"]) | TOML_VALUES,
            ),
            max_size=3,
        )
        | TOML_VALUES,
        "notes": TOML_VALUES,
    },
)


@PROPERTY
@given(RANDOM_CASES)
def test_random_case_files(data):
    text = tomli_w.dumps(data)
    with no_code_execution():
        check_parse(text)


TRICKY_BUT_VALID = '''\
# a comment with "quotes", 'apostrophes', [brackets] and a.b.c.d.e.f.g.h.i.j.k.l dots
id = "hostile-demo"  # it's fine
title = 'A [literal] title with "quotes", # and a.b.c.d.e.f.g.h.i.j.k.l.m'
notes = """Multi-line notes with [[[[[[[[[[[[ brackets ]]]]]]]]]]]], a.b.c.d.e.f.g.h.i.j.k.l,
an escaped \\""" quote, 1234567890123456789012345678901234567890123456789012345678901234567890\
12345678901234567890123456789012345678901234567890 digits and a quote at the end\""""
"source".citation = 'A. Author, J. 1 (2003) 1-10, {not a table}'
source . locator = \'\'\'p. 1 \'\' two quotes at the end\'\'\'\'\'

[parameters]
C = "positive"
N = "real"

[system]
inertia = [ "C", "C",
            "2*C", ]  # a trailing comma
potential = "C*gamma3"
torque = ["0", "0", "N*gamma3"]

[[claims]]
label = "I1"
kind = "integral"
expression = "M3 + 0*(1.5 + 2.25)"
on = []
'''


@pytest.mark.parametrize("line_end", ["\n", "\r\n"])
def test_tricky_but_valid_toml_passes_the_pre_scan(line_end):
    text = TRICKY_BUT_VALID.replace("\n", line_end)
    loaded = parse_case_text(text)
    assert loaded.id == "hostile-demo"
    assert loaded.source.locator == "p. 1 '' two quotes at the end''"
    assert loaded.notes.endswith('a quote at the end"')
    assert toml_input.toml_shape_problem(text) is None


@pytest.mark.parametrize("path", sorted(CASES.glob("*.toml")), ids=lambda p: p.stem)
def test_seed_catalog_passes_the_pre_scan_with_any_line_ends(path):
    text = path.read_text(encoding="utf-8")
    for variant in (text, text.replace("\n", "\r\n")):
        assert toml_input.toml_shape_problem(variant) is None
        assert parse_case_text(variant).id == path.stem
