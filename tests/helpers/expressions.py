"""A namespace of parameters and declared functions, and parsing in it, for the tests of
the expression language (parser, printer, limits)."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.errors import ExpressionError
from registry.language.parser import Namespace, parse_expression
from registry.mathematics.mechanics import AXIS, M1, M2, M3, gamma1, s

C = sp.Symbol("C", real=True, positive=True)
n = sp.Symbol("n", real=True)
k = sp.Symbol("k", real=True, integer=True)
phi = sp.Function("phi", real=True)
a = sp.Function("a", real=True)
g = sp.Function("g", real=True)
psi = sp.Function("psi", real=True)
chi = sp.Function("chi", real=True)

NS = Namespace(
    {"C": C, "n": n, "k": k},
    {
        "phi": (phi, AXIS),
        "a": (a, (s,)),
        "g": (g, (gamma1, s)),
        "psi": (psi, (*AXIS, s)),
        "chi": (chi, (M1, M2, M3)),
    },
)
PHI = phi(*AXIS)
G = g(gamma1, s)
PSI = psi(*AXIS, s)


def parse(text: str) -> sp.Expr:
    return parse_expression(text, NS)


def refusal(text: str, ns: Namespace = NS) -> str:
    """The message of the ExpressionError that ``text`` raises."""
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, ns)
    assert info.value.text == text
    return info.value.message
