"""The expression language: what it accepts, what it refuses (exact messages), the printer."""

from __future__ import annotations

import warnings

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from registry.errors import ExpressionError
from registry.language.parser import Namespace, parse_equation, parse_expression
from registry.mathematics.mechanics import M1, M2, M3, gamma1, gamma2, gamma3, s
from tests.helpers.clocks import cpu_bound
from tests.helpers.expressions import NS, PHI, C, G, a, chi, k, n, parse, refusal

# ------------------------------------------------------------------ accepted


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("0.1", sp.Rational(1, 10)),
        ("1e-3", sp.Rational(1, 1000)),
        ("1.5e2", sp.Integer(150)),
        ("2.50", sp.Rational(5, 2)),
        (".5", sp.Rational(1, 2)),
        ("3.", sp.Integer(3)),
        ("1_000", sp.Integer(1000)),
        ("1E+2", sp.Integer(100)),
        ("0x10", sp.Integer(16)),
        ("0.1 + 0.2", sp.Rational(3, 10)),
        ("1/3", sp.Rational(1, 3)),
        ("0.5*gamma1**2", gamma1**2 / 2),
        ("-M1 + +M2 - -M3", -M1 + M2 + M3),
        ("M1*gamma1 / C / 2", M1 * gamma1 / (2 * C)),
        ("2**3**2", sp.Integer(512)),
        ("-2**2", sp.Integer(-4)),
        ("s", s),
        ("s**2 + M1", s**2 + M1),
        ("pi/2 + E", sp.pi / 2 + sp.E),
        ("sqrt(gamma1**2 + gamma2**2)", sp.sqrt(gamma1**2 + gamma2**2)),
        ("(gamma1**2 + gamma2**2)**(3/2)", (gamma1**2 + gamma2**2) ** sp.Rational(3, 2)),
        (
            "exp(n) + log(C) + sin(k) + cos(n) + tan(n)",
            sp.exp(n) + sp.log(C) + sp.sin(k) + sp.cos(n) + sp.tan(n),
        ),
        ("asin(n) + acos(n) + atan(n)", sp.asin(n) + sp.acos(n) + sp.atan(n)),
        ("sinh(n) + cosh(n) + tanh(n)", sp.sinh(n) + sp.cosh(n) + sp.tanh(n)),
        ("phi(gamma1, gamma2, gamma3)", PHI),
        ("a(s)*gamma3", a(s) * gamma3),
        ("  gamma1 +\n  gamma2  ", gamma1 + gamma2),
        ("C - C", sp.Integer(0)),
        ("(sqrt)(4)", sp.Integer(2)),
    ],
)
def test_accepted(text, expected):
    assert parse(text) == expected


def test_parameters_carry_their_assumptions():
    assert parse("C").is_positive
    assert parse("k").is_integer


def test_s_is_kept_as_a_symbol():
    assert parse("s") is s
    assert parse("s - M1*gamma1 - M2*gamma2 - M3*gamma3").has(s)


# ----------------------------------------------------------------------- diff


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("diff(a(s), gamma1)", M1 * sp.Derivative(a(s), s)),
        ("diff(a(s), M2)", gamma2 * sp.Derivative(a(s), s)),
        ("diff(a(s), s)", sp.Derivative(a(s), s)),
        ("diff(diff(a(s), s), s)", sp.Derivative(a(s), (s, 2))),
        ("diff(s**2, gamma3)", 2 * s * M3),
        ("diff(C*s**2, s)", 2 * C * s),
        ("diff(s*gamma1, M1)", gamma1**2),
        ("diff(phi(gamma1, gamma2, gamma3), gamma1)", sp.Derivative(PHI, gamma1)),
        ("diff(phi(gamma1, gamma2, gamma3), M1)", sp.Integer(0)),
        ("diff(g(gamma1, s), gamma1)", sp.Derivative(G, gamma1) + M1 * sp.Derivative(G, s)),
        ("diff(g(gamma1, s), M1)", gamma1 * sp.Derivative(G, s)),
        ("diff(chi(M1, M2, M3), M3)", sp.Derivative(chi(M1, M2, M3), M3)),
        ("diff(sin(gamma1), gamma1)", sp.cos(gamma1)),
    ],
)
def test_diff_is_the_total_derivative(text, expected):
    assert sp.expand(parse(text) - expected) == 0


# ------------------------------------------------------------------ refused


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty expression"),
        ("   \n ", "empty expression"),
        ("g\u0430mma1", "non-ASCII character '\u0430' (U+0430)"),
        ("gamma1 \u2212 1", "non-ASCII character '\u2212' (U+2212)"),
        ("\uff47amma1", "non-ASCII character '\uff47' (U+FF47)"),
        ("gamma1 # a note", "comments ('#') are not allowed"),
        ("gamma1\x0c+ 1", "control character U+000C is not allowed"),
        ("gamma1\x1b[2J", "control character U+001B is not allowed"),
        ("gamma1 +", "not a valid expression"),
        ("(gamma1", "not a valid expression"),
        ("gamma1 = 1", "not a valid expression"),
        ("x", "unknown name 'x' (declare it under [parameters])"),
        ("gama1", "unknown name 'gama1' (did you mean 'gamma1'?)"),
        ("gamma1 + Cc", "unknown name 'Cc' (did you mean 'C'?)"),
        ("foo(gamma1)", "unknown function 'foo'"),
        ("sqr(2)", "unknown function 'sqr' (did you mean 'sqrt'?)"),
        ("gamma1(2)", "unknown function 'gamma1'"),
        ("Abs(gamma1)", "unknown function 'Abs'"),
        ("__import__('os')", "unknown function '__import__'"),
        ("sqrt", "'sqrt' is a function; call it as sqrt(...)"),
        ("diff", "'diff' is a function; call it as diff(...)"),
        ("phi", "'phi' is a function; call it as phi(gamma1, gamma2, gamma3)"),
        ("phi(gamma1, gamma2)", "'phi' must be called as phi(gamma1, gamma2, gamma3)"),
        ("phi(gamma2, gamma1, gamma3)", "'phi' must be called as phi(gamma1, gamma2, gamma3)"),
        ("a(M1*gamma1 + M2*gamma2 + M3*gamma3)", "'a' must be called as a(s)"),
        ("sqrt(1, 2)", "sqrt() takes exactly one argument (2 given)"),
        ("exp()", "exp() takes exactly one argument (0 given)"),
        ("sqrt(x=1)", "keyword arguments are not allowed"),
        ("sqrt(*gamma1)", "'*' unpacking is not allowed"),
        ("sqrt(**gamma1)", "'**' unpacking is not allowed"),
        ("(gamma1 + 1)(2)", "only named functions can be called"),
        ("gamma1.real", "attribute access is not allowed"),
        ("().__class__", "attribute access is not allowed"),
        ("__import__('os').system('echo hi')", "attribute access is not allowed"),
        ("gamma1[0]", "indexing is not allowed"),
        ("lambda: 1", "lambdas are not allowed"),
        ("[x for x in y]", "comprehensions are not allowed"),
        ("(x for x in y)", "comprehensions are not allowed"),
        ("{x: 1 for x in y}", "comprehensions are not allowed"),
        ("(y := 1)", "':=' is not allowed"),
        ("'a'", "strings are not allowed"),
        ("b'a'", "strings are not allowed"),
        ("f'{gamma1}'", "strings are not allowed"),
        ("1j", "complex numbers are not allowed"),
        ("True", "booleans are not allowed"),
        ("None", "None is not allowed"),
        ("...", "'...' is not allowed"),
        ("[1, 2]", "lists are not allowed"),
        ("(1, 2)", "tuples are not allowed"),
        ("{1, 2}", "sets are not allowed"),
        ("{1: 2}", "dictionaries are not allowed"),
        ("gamma1 < 1", "comparisons are not allowed"),
        ("gamma1 == 1", "comparisons are not allowed"),
        ("gamma1 and gamma2", "'and' and 'or' are not allowed"),
        ("not gamma1", "'not' is not allowed"),
        ("~gamma1", "'~' is not allowed"),
        ("gamma1 if C else gamma2", "conditional expressions are not allowed"),
        ("gamma1^2", "'^' is not a power; use '**'"),
        ("gamma1 % 2", "'%' is not allowed"),
        ("gamma1 // 2", "'//' is not allowed"),
        ("gamma1 @ gamma2", "'@' is not allowed"),
        ("gamma1 << 2", "'<<' is not allowed"),
        ("gamma1 >> 2", "'>>' is not allowed"),
        ("gamma1 | 2", "'|' is not allowed"),
        ("gamma1 & 2", "'&' is not allowed"),
        ("await gamma1", "'await' is not allowed"),
        ("diff(gamma1)", "diff takes two arguments: diff(expression, variable)"),
        (
            "diff(gamma1, C)",
            "the second argument of diff must be one of M1, M2, M3, gamma1, gamma2, gamma3 or s",
        ),
        (
            "diff(gamma1, 2)",
            "the second argument of diff must be one of M1, M2, M3, gamma1, gamma2, gamma3 or s",
        ),
        (
            "diff(g(gamma1, s), s)",
            "diff(..., s) needs an expression that depends on the variables through s alone",
        ),
        (
            "diff(M1*s, s)",
            "diff(..., s) needs an expression that depends on the variables through s alone",
        ),
        ("1/0", "division by zero or an undefined value"),
        ("1/(1/0)", "division by zero or an undefined value"),
        ("gamma1/(C - C)", "division by zero or an undefined value"),
        ("log(0)", "division by zero or an undefined value"),
        ("tan(pi/2)", "division by zero or an undefined value"),
        ("sqrt(-1)", "the expression is not real (it involves the imaginary unit)"),
        ("sqrt(-C)", "the expression is not real (it involves the imaginary unit)"),
        ("log(-1)", "the expression is not real (it involves the imaginary unit)"),
        ("(-8)**(1/3)", "the expression is not real (a fractional power of a negative number)"),
        ("(-C)**(1/3)", "the expression is not real (a fractional power of a negative number)"),
    ],
)
def test_refused(text, message):
    assert refusal(text) == message


def test_declared_functions_belong_to_the_namespace():
    assert refusal("phi(gamma1, gamma2, gamma3)", Namespace()) == "unknown function 'phi'"
    assert refusal("C", Namespace()) == "unknown name 'C' (declare it under [parameters])"


def test_error_shows_the_text():
    with pytest.raises(ExpressionError) as info:
        parse("gamma1 + x")
    assert str(info.value) == "unknown name 'x' (declare it under [parameters]): 'gamma1 + x'"
    assert isinstance(info.value, ValueError)


def test_non_strings_are_a_type_error():
    with pytest.raises(TypeError):
        parse_expression(1, NS)  # type: ignore[arg-type]


# ------------------------------------------------------------------ equations


def test_equation():
    lhs, rhs = parse_equation("gamma1**2 + gamma2**2 + gamma3**2 = 1", NS)
    assert (lhs, rhs) == (gamma1**2 + gamma2**2 + gamma3**2, 1)
    assert parse_equation("s = 0", NS) == (s, 0)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("gamma1 == 1", "an equation needs the form lhs = rhs"),
        ("gamma1 = 1 = 2", "an equation needs the form lhs = rhs"),
        ("gamma1", "an equation needs the form lhs = rhs"),
        ("= 1", "an equation needs the form lhs = rhs"),
        ("gamma1 =  ", "an equation needs the form lhs = rhs"),
        ("gamma1 <= 1", "an equation needs the form lhs = rhs"),
        ("gamma1 >= 1", "an equation needs the form lhs = rhs"),
        ("gamma1 != 1", "an equation needs the form lhs = rhs"),
        ("x = 1", "unknown name 'x' (declare it under [parameters])"),
        ("gamma1 = 1/0", "division by zero or an undefined value"),
    ],
)
def test_equation_refused(text, message):
    with pytest.raises(ExpressionError) as info:
        parse_equation(text, NS)
    assert (info.value.message, info.value.text) == (message, text)


# ------------------------------------------------------------- random input

ALPHABET = "Mgamma123s CpinE+-*/()**.,=e0xy'_[]:lambd^#%" + "\n\t"


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(max_size=60), st.text(alphabet=ALPHABET, max_size=80)))
def test_random_text_is_an_expression_or_an_expression_error(text):
    _parses_or_says_why(text)


def _parses_or_says_why(text: str) -> None:
    """A sympy expression, or an ExpressionError carrying the text and a message, within
    two seconds of CPU time (a parse takes milliseconds)."""
    with cpu_bound(2.0):
        try:
            result = parse_expression(text, NS)
        except ExpressionError as err:
            assert err.text == text and err.message
        else:
            assert isinstance(result, sp.Expr)


TOKENS = [
    "M1",
    "M2",
    "gamma1",
    "gamma3",
    "s",
    "C",
    "n",
    "k",
    "pi",
    "E",
    "0",
    "1",
    "2",
    "0.5",
    "1e-3",
    "+",
    "-",
    "*",
    "/",
    "**",
    "(",
    ")",
    "sqrt(",
    "exp(",
    "log(",
    "sin(",
    "atan(",
    "tanh(",
    "diff(",
    ", gamma1)",
    ", s)",
    ", M2)",
    "phi(gamma1, gamma2, gamma3)",
    "a(s)",
    "g(gamma1, s)",
    ",",
    "x",
    "^",
    ".real",
    "[0]",
]


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(TOKENS), max_size=30).map(" ".join))
def test_token_soup_is_an_expression_or_an_expression_error(text):
    _parses_or_says_why(text)


@pytest.mark.parametrize("text", ["2and M1", "1if M1 else M2", "M1 + 3or 2"])
def test_text_python_would_warn_about_is_refused_without_a_python_warning(text):
    # "invalid decimal literal" is Python's SyntaxWarning, not a message for the user
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(ExpressionError) as error:
            parse_expression(text)
    assert caught == [] and text in str(error.value)
