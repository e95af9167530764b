"""Where a residual lives: the parameters and their assumptions, a family's arbitrary
functions, what must not vanish, the level set, and what must be defined at a point.

Both the sampling of exact points (``sampling``) and the zero test (``zero_test``)
work on a ``Domain``; it sits in a module of its own so that neither imports the other.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import sympy as sp


@dataclass(frozen=True)
class Domain:
    """Where residuals live: parameters (symbols carry assumptions), arbitrary
    functions of a family, expressions that must not vanish (moments of inertia)
    the level set ``on`` (expressions that vanish there), and expressions that must be
    defined at a sample point (the case's potential, torque and claim: a witness where
    I itself is undefined would prove nothing)."""

    parameters: tuple[sp.Symbol, ...] = ()
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = field(
        default_factory=dict
    )
    nonzero: tuple[sp.Expr, ...] = ()
    on: tuple[sp.Expr, ...] = ()
    defined: tuple[sp.Expr, ...] = ()

    def restricted(self, on: Sequence[sp.Expr]) -> Domain:
        """The same domain restricted to the level set where ``on`` vanish."""
        return replace(self, on=tuple(on))

    def requiring(self, exprs: Sequence[sp.Expr]) -> Domain:
        """The same domain where ``exprs`` must also be defined (a claim, the potential)."""
        return replace(self, defined=(*self.defined, *exprs))
