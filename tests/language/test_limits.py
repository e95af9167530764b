"""The size limits of the expression language: hostile texts are refused fast with the
limit's message, texts within the limits parse, and the limits are the documented values."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.errors import ExpressionError
from registry.language import limits
from registry.language.limits import ParseBudget
from registry.language.parser import parse_expression
from tests.helpers.clocks import cpu_bound
from tests.helpers.expressions import parse, refusal

LIMIT_CASES = [
    ("x" * 10**6, "expression too long (1000000 characters; at most 20000)"),
    ("1+" * 10_000 + "1", "expression too long (20001 characters; at most 20000)"),
    ("(" * 5000 + "1" + ")" * 5000, "expression nested too deeply (more than 100 levels)"),
    ("(" * 101 + "1" + ")" * 101, "expression nested too deeply (more than 100 levels)"),
    ("-" * 15_000 + "1", "expression too large (more than 5000 parts)"),
    ("-" * 150 + "1", "expression nested too deeply (more than 100 levels)"),
    ("2**" * 200 + "2", "expression nested too deeply (more than 100 levels)"),
    ("sin(" * 101 + "1" + ")" * 101, "expression nested too deeply (more than 100 levels)"),
    ("+".join(["gamma1"] * 2600), "expression too large (more than 5000 parts)"),
    ("1" * 101, "number literal too long (more than 100 digits)"),
    ("1" * 5000, "number literal too long (more than 100 digits)"),
    ("0." + "1" * 99, "number literal too long (more than 100 digits)"),
    ("1e101", "number literal too long (more than 100 digits)"),
    ("1e-101", "number literal too long (more than 100 digits)"),
    ("9**9**9**9", "exponent too large (at most 1000 in absolute value)"),
    ("gamma1**1001", "exponent too large (at most 1000 in absolute value)"),
    ("gamma1**(-1001)", "exponent too large (at most 1000 in absolute value)"),
    ("gamma1**(10**9)", "exponent too large (at most 1000 in absolute value)"),
    ("gamma1**(1/101)", "exponent denominator too large (at most 100)"),
    (
        "10**1000*10**1000*10**1000*10**1000",
        "number too large (it could have more than 4000 digits)",
    ),
    ("(10**999 + 1)**5", "number too large (it could have more than 4000 digits)"),
    (
        "(7*gamma1)**1000*(7*gamma2)**1000*(7*gamma3)**1000*(7*M1)**1000*(7*M2)**1000",
        "number too large (it could have more than 4000 digits)",
    ),
    ("exp(1000*log(10**100))", "number too large (it could have more than 4000 digits)"),
    ("E**(1000*log(10**100))", "number too large (it could have more than 4000 digits)"),
    ("(E**1000)**log(10**100)", "number too large (it could have more than 4000 digits)"),
    ("exp(2)**(500*log(10**100))", "number too large (it could have more than 4000 digits)"),
    ("E**(log(10**301 + 1)/2)", "number too large for a root (it could have more than 300 digits)"),
    (
        "+".join(f"1/{p}**300" for p in (2, 3, 5, 7, 11, 13, 17)),
        "number too large (it could have more than 4000 digits)",
    ),
    ("sqrt(10**400 + 1)", "number too large for a root (it could have more than 300 digits)"),
    ("(10**400 + 1)**(1/3)", "number too large for a root (it could have more than 300 digits)"),
    (
        "*".join(f"sqrt(10**99 + {i})" for i in range(1, 5)),
        "number too large for a root (it could have more than 300 digits)",
    ),
    (
        "+".join(f"sqrt(10**299 + {i})" for i in range(1, 5)),
        "too many roots of numbers (more than 1000 digits under roots in all)",
    ),
    (
        "diff(diff(" + "*".join(f"sin(gamma1 + {i})" for i in range(20)) + ", gamma1), gamma1)",
        "expression too large to differentiate",
    ),
    (
        "+".join(
            f"diff({'*'.join(f'sin(gamma1 + {i + j})' for i in range(30))}, gamma1)"
            for j in range(20)
        ),
        "expression too large to differentiate",
    ),
]


#: Seconds of CPU time after which parsing one text counts as hung. The bounds below are
#: hang bounds, not speed tests: a parse within the limits takes well under a second.
HANG_BOUND = 10.0


@pytest.mark.parametrize(("text", "message"), LIMIT_CASES, ids=range(len(LIMIT_CASES)))
def test_hostile_input_refused_fast(text, message):
    # a bound against hangs (the limits make these refusals take milliseconds), on the
    # CPU time of the parse, so that a loaded machine does not fail it
    with cpu_bound(HANG_BOUND):
        assert refusal(text) == message


@pytest.mark.parametrize(
    "text",
    [
        "(" * 100 + "1" + ")" * 100,
        "1" * 100,
        "gamma1**1000 + gamma1**(-1000) + gamma1**(99/100)",
        "9**1000",
        "sqrt(10**299 + 1)",
        "+".join(["gamma1"] * 2000),
        "*".join(f"(gamma1 + {i})" for i in range(1000)),
        "gamma1 + " * 2200 + "1",
    ],
)
def test_within_the_limits(text):
    with cpu_bound(HANG_BOUND):  # a hang bound, not a speed test
        assert isinstance(parse(text), sp.Expr)


def test_limits_are_documented_constants():
    assert limits.MAX_LENGTH == 20_000
    assert limits.MAX_NODES == 5_000
    assert limits.MAX_DEPTH == 100
    assert limits.MAX_DIGITS == 100
    assert limits.MAX_EXPONENT == 1000


def test_a_parse_budget_is_shared_by_the_expressions_of_a_case():
    budget = ParseBudget(parts=5)
    parse_expression("gamma1 + gamma2", budget=budget)  # 3 parts
    with pytest.raises(ExpressionError) as first:
        parse_expression("gamma1 + gamma2", budget=budget)  # 3 more: past the 5 allowed
    assert budget.exhausted == first.value.message
    with pytest.raises(ExpressionError) as later:
        parse_expression("1", budget=budget)  # refused once the budget is spent
    assert later.value.message == first.value.message
