"""An expression of the case-file language keeps the author's text beside its meaning."""

from __future__ import annotations

import sympy as sp

from registry.expression import Expression


def test_an_expression_shows_the_text_its_author_wrote():
    x = sp.Symbol("x")
    e = Expression("0.5*x", x / 2)
    assert str(e) == "0.5*x" and e.expr == x / 2
    assert e == Expression("0.5*x", x / 2) and e != Expression("x/2", x / 2)
