"""The system of a case as every layer reads it, whatever form its file gave it in.

A case file states its system in one of several forms (docs/case-format.md): moments of
inertia, potential and torque (the reference paper's equations (2.2)); a Hamiltonian with
the bracket parameter kappa; the equations of motion of variables of its own; or a
Hamiltonian with a Poisson bracket given entry by entry. The case language turns each of
them into one ``Dynamics`` (``language.forms``, the only place that knows the forms): its
state variables grouped into vectors, its vector field, and, where it has them, its
bracket, Hamiltonian, gyroscopic torque and the Casimirs its bracket is known to have. The
audit, discovery, numeric evidence and presentation read this object and ask what it has
(a bracket, a Hamiltonian), never which form it came from.

This module holds data only (sympy expressions and symbols); the algebra on it lives in
``mathematics.flow``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from .expression import Expression

#: The weights of a search, vector by vector: (("M", 1), ("gamma", 2)).
Weights = tuple[tuple[str, int], ...]


def as_weights(value: Weights | Mapping[str, int] | tuple[int, int]) -> Weights:
    """Weights as (vector, weight) pairs, from pairs, a mapping, or the reference paper's
    two numbers (weights of M and of gamma)."""
    pairs: Weights
    if isinstance(value, Mapping):
        pairs = tuple((str(k), v) for k, v in value.items())
    else:
        items: tuple = tuple(value)
        if len(items) == 2 and all(isinstance(w, int) for w in items):
            pairs = (("M", items[0]), ("gamma", items[1]))
        else:
            pairs = tuple((str(k), w) for k, w in items)
    for name, w in pairs:
        if isinstance(w, bool) or not isinstance(w, int) or w < 1:
            raise ValueError(f"the weight of {name} must be a positive integer, not {w!r}")
    if len({name for name, _ in pairs}) != len(pairs):
        raise ValueError(f"a vector is given two weights: {pairs}")
    return pairs


@dataclass(frozen=True)
class Vector:
    """State variables read together: a vector (``gamma`` for gamma1, gamma2, gamma3) or a
    single variable. ``weight`` is the weight a search gives its components by default;
    ``rational_norm`` asks sample points to put it on a sphere of rational radius, so that
    square roots of its length (and of one planar radius) evaluate exactly."""

    name: str
    components: tuple[sp.Symbol, ...]
    weight: int = 1
    rational_norm: bool = False


@dataclass(frozen=True)
class Given:
    """One part of the system as its case file states it, for display and export: a name
    that is an identifier and reads as the left side of an equation (``mu1``, ``H``,
    ``d(omega1)/dt``), a label for people (``torque μ1``), the left side as a sympy
    object for typesetting, the value as an expression and as the text the author wrote."""

    name: str
    label: str
    symbol: sp.Basic
    expr: sp.Expr
    text: str


@dataclass(frozen=True, eq=False)
class Dynamics:
    """The system of one case (module docstring).

    ``field`` is dx/dt for each of ``variables``. ``bracket`` is the Poisson tensor Pi
    (dx/dt = Pi grad H) where the system has one: the reference paper's Pi_mu, deformed by
    ``kappa``, or a bracket given entry by entry; ``from_bracket`` says the field is
    defined as Pi grad H (true) rather than given on its own (the paper's (2.2), whose
    equality with Pi grad H is the theorem's part iii, re-proven by the audit).
    ``torque`` is the paper's gyroscopic mu where Pi is Pi_mu (None otherwise) and
    ``kappa`` the parameter that deforms e(3) into so(4) or so(3,1) (0 otherwise), ``c1``
    the bracket's Casimir (kappa |M|^2 + |gamma|^2)/2 of mu = 0 that the audit's ``c1``
    check tests (None where the system has no such designated Casimir), and ``casimirs``
    the bracket's known Casimirs for mu = 0, each to be proven before it is used.
    ``shorthands`` are names that stand for expressions of the state (``s`` for M.gamma):
    derivatives and normal forms expand them. ``nonzero`` must not vanish (moments of
    inertia) and ``defined`` must be defined at a sample point (the potential, the
    torque, the field). ``given`` is the system as the case file states it.
    ``grading`` are the weights the registry's recorded searches use for it (a grading
    under which its field is homogeneous where there is one); a search's default weights
    are the vectors' own. ``graded`` computes it on first use (finding a grading expands
    the field, which listing or reporting a case never needs); without it the grading is
    the vectors' own weights.
    """

    variables: tuple[sp.Symbol, ...]
    vectors: tuple[Vector, ...]
    field: tuple[sp.Expr, ...]
    hamiltonian: sp.Expr | None = None
    bracket: sp.ImmutableMatrix | None = None
    from_bracket: bool = False
    torque: tuple[Expression, Expression, Expression] | None = None
    kappa: Expression = Expression("0", sp.Integer(0))
    c1: sp.Expr | None = None
    casimirs: tuple[tuple[str, sp.Expr], ...] = ()
    shorthands: Mapping[sp.Symbol, sp.Expr] = dataclasses.field(default_factory=dict)
    parameters: tuple[sp.Symbol, ...] = ()
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = dataclasses.field(
        default_factory=dict
    )
    nonzero: tuple[sp.Expr, ...] = ()
    defined: tuple[sp.Expr, ...] = ()
    given: tuple[Given, ...] = ()
    graded: Callable[[], Weights] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "shorthands", dict(self.shorthands))
        object.__setattr__(self, "functions", dict(self.functions))
        if len(self.field) != len(self.variables):
            raise ValueError(
                f"{len(self.field)} equations of motion for {len(self.variables)} variables"
            )

    @cached_property
    def grading(self) -> Weights:
        """The weights the registry's recorded searches use (class docstring)."""
        if self.graded is not None:
            return self.graded()
        return tuple((v.name, v.weight) for v in self.vectors)

    @property
    def dimension(self) -> int:
        """How many state variables the system has."""
        return len(self.variables)

    @property
    def torque_exprs(self) -> tuple[sp.Expr, ...] | None:
        """The components of the gyroscopic torque mu as expressions (None without one)."""
        return None if self.torque is None else tuple(e.expr for e in self.torque)

    def expanded(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with every shorthand written out (``s`` as M.gamma)."""
        expr = sp.sympify(expr)
        # subs, not xreplace: a derivative d a(s)/ds becomes one at s = M.gamma
        return expr.subs(dict(self.shorthands)) if self.shorthands else expr

    def weights(self, given: Mapping[str, int] | None = None) -> tuple[int, ...]:
        """The weight of each variable: its vector's weight in ``given`` (by vector name),
        else the vector's default."""
        given = given or {}
        by_symbol = {x: given.get(v.name, v.weight) for v in self.vectors for x in v.components}
        return tuple(by_symbol[x] for x in self.variables)
