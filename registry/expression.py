"""An expression of the case-file language: the text its author wrote and what it means.

Expressions are kept twice, as sympy objects for the algebra and as the text the author
wrote, so that what is stored and printed is what the paper says.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Expression:
    """An expression of the case-file language: the text as written and its meaning."""

    text: str
    expr: sp.Expr

    def __str__(self) -> str:
        return self.text
