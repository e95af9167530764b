"""Where a residual lives: the parameters and their assumptions, a family's arbitrary
functions, what must not vanish, the level set, and what must be defined at a point.

Both the sampling of exact points (``sampling``) and the zero test (``zero_test``)
work on a ``Domain``; it sits in a module of its own so that neither imports the other.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import sympy as sp

from ..dynamics import Dynamics, Vector
from .mechanics import SHORTHANDS, VECTORS


@dataclass(frozen=True)
class Domain:
    """Where residuals live: parameters (symbols carry assumptions), arbitrary
    functions of a family, expressions that must not vanish (moments of inertia)
    the level set ``on`` (expressions that vanish there), and expressions that must be
    defined at a sample point (the case's potential, torque and claim: a witness where
    I itself is undefined would prove nothing). ``vectors`` are the state variables,
    grouped as sample points draw them, and ``shorthands`` the names that stand for
    expressions of the state; by default the reference paper's (M, gamma and s = M.gamma).
    """

    parameters: tuple[sp.Symbol, ...] = ()
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = field(
        default_factory=dict
    )
    nonzero: tuple[sp.Expr, ...] = ()
    on: tuple[sp.Expr, ...] = ()
    defined: tuple[sp.Expr, ...] = ()
    vectors: tuple[Vector, ...] = VECTORS
    shorthands: Mapping[sp.Symbol, sp.Expr] = field(default_factory=lambda: dict(SHORTHANDS))

    @classmethod
    def of(cls, dynamics: Dynamics) -> Domain:
        """Where the residuals of a system live: its parameters, functions, state and
        shorthands, what must not vanish and what must be defined."""
        return cls(
            parameters=dynamics.parameters,
            functions=dict(dynamics.functions),
            nonzero=dynamics.nonzero,
            defined=dynamics.defined,
            vectors=dynamics.vectors,
            shorthands=dict(dynamics.shorthands),
        )

    @property
    def state(self) -> tuple[sp.Symbol, ...]:
        """The state variables, vector by vector."""
        return tuple(x for v in self.vectors for x in v.components)

    def expanded(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with every shorthand written out (``s`` as M.gamma)."""
        expr = sp.sympify(expr)
        # subs, not xreplace: a derivative d a(s)/ds becomes one at s = M.gamma
        return expr.subs(dict(self.shorthands)) if self.shorthands else expr

    def restricted(self, on: Sequence[sp.Expr]) -> Domain:
        """The same domain restricted to the level set where ``on`` vanish."""
        return replace(self, on=tuple(on))

    def requiring(self, exprs: Sequence[sp.Expr]) -> Domain:
        """The same domain where ``exprs`` must also be defined (a claim, the potential)."""
        return replace(self, defined=(*self.defined, *exprs))
