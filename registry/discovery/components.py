"""An algebraic candidate set of the rank-drop locus, split into its irreducible
components: those with a rational parametrisation become ordinary candidate sets, the
others are decided at their points (``algebraic_points``).

The splitting (``splitting``) leaves a set unsolved when its equations are nonlinear in
every free parameter: ``x0**2 - 4*z0**2 = 0`` (two rational lines), ``x0**2 + z0**2 = 0``
(no real point but the origin), ``49*x0**2 - 30*z0**2 = 0`` (two lines defined over
Q(sqrt(30)) only). Its components over Q (``prime_components``, Groebner bases and shape
position; symbolic parameters stay in the ground field) are taken one by one:

* a component on which a factor the branch assumed nonzero vanishes belongs to another
  branch, and is dropped;
* only real points matter: an equation that is a sum of positive multiples of even
  powers of single parameters vanishes on real points only where each of them is 0, so
  the component's real points are those of the component with them set to 0 (decomposed
  again); a positive parameter set to a non-positive number leaves nothing;
* a component of degree 1 over the field of its free coordinates (its bound parameters
  rational functions of the free ones) is an ordinary candidate set, searched by
  substitution like every other;
* the rest (defined over an algebraic extension, or without a rational parametrisation)
  is returned as a ``Piece``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy as sp

from ..mathematics.prime_components import Component, DecompositionLimit, components
from .splitting import AlgebraicSet

#: How often the real-point rule may add equations to one set before it stops.
MAX_REAL_STEPS = 8


@dataclass(frozen=True)
class Piece:
    """An irreducible component with no rational parametrisation: the parameters the
    splitting solved (``values``, rational in the others), the ``component`` of the
    others (its prime ideal and generic point), its equations as text, and the factors
    the splitting assumed nonzero on it."""

    values: dict[sp.Symbol, sp.Expr]
    component: Component
    text: str
    units: tuple[sp.Expr, ...] = ()


@dataclass
class Resolved:
    """What an algebraic set holds: ordinary candidate sets (values of some free
    parameters), ``pieces`` to decide at their points, and ``undecided`` texts."""

    sets: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    pieces: list[Piece] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)


def resolve(
    found: AlgebraicSet,
    free: Sequence[sp.Symbol],
    symbolic: Sequence[sp.Symbol] = (),
) -> Resolved:
    """The components of ``found`` (module docstring); ``free`` are the free parameters of
    the set searched, ``symbolic`` those that stay generic (the ground field's)."""
    out = Resolved()
    _resolve(found, list(free), list(symbolic), out, 0)
    return out


def _resolve(
    found: AlgebraicSet, free: list[sp.Symbol], symbolic: list[sp.Symbol], out: Resolved, depth
) -> None:
    variables = [f for f in free if f not in found.values]
    equations = [sp.numer(sp.together(e)) for e in found.equations]
    try:
        parts = components(equations, variables, symbolic, origin=())
    except DecompositionLimit as err:
        out.undecided.append(f"{found.text()} (its components were not found: {err})")
        return
    for part in parts:
        if any(part.vanishes(u) for u in found.units if u.free_symbols & set(variables)):
            continue
        zero = _real_zeros(part)
        if zero:
            if depth >= MAX_REAL_STEPS:
                out.undecided.append(f"{found.text()} (its real points were not found)")
                continue
            smaller = AlgebraicSet(found.values, (*part.equations(), *zero), found.units)
            _resolve(smaller, free, symbolic, out, depth + 1)
            continue
        if part.degree == 1:
            values = _rational(found.values, part)
            if _allowed(values):
                out.sets.append(values)
        else:
            text = AlgebraicSet(found.values, tuple(part.equations())).text()
            piece = Piece(found.values, part, text, found.units)
            if piece.text not in {p.text for p in out.pieces}:
                out.pieces.append(piece)


def _real_zeros(part: Component) -> list[sp.Symbol]:
    """Parameters that vanish at every real point of the component: those of an equation
    that is a sum of positive multiples of even powers of single parameters (beyond the
    ones already 0 on it)."""
    for equation in part.equations():
        poly = sp.Poly(sp.numer(sp.together(equation)), *part.variables)
        terms = poly.terms()
        if len(terms) < 2:
            continue
        signs = {c > 0 for _, c in terms if c.is_number}
        if len(signs) != 1 or not all(c.is_number for _, c in terms):
            continue
        if all(sum(1 for e in m if e) == 1 and all(e % 2 == 0 for e in m) for m, _ in terms):
            return [
                x
                for m, _ in terms
                for x, e in zip(part.variables, m, strict=True)
                if e and not part.vanishes(x)
            ]
    return []


def _allowed(values: dict[sp.Symbol, sp.Expr]) -> bool:
    """False where a positive parameter is set to a number that is not positive."""
    return not any(x.is_positive and v.is_number and not v > 0 for x, v in values.items())


def _rational(values: dict[sp.Symbol, sp.Expr], part: Component) -> dict[sp.Symbol, sp.Expr]:
    """A degree-1 component as values of its bound parameters (rational in its free
    ones), with the splitting's solved parameters written in the same free ones."""
    u = part.symbol
    root = -part.minimal.nth(0) / part.minimal.nth(1)
    bound = {
        x: sp.cancel(sp.sympify(e).subs(u, root))
        for x, e in part.coordinates.items()
        if x not in part.free
    }
    out = {s: sp.cancel(sp.sympify(e).xreplace(bound)) for s, e in values.items()}
    out.update(bound)
    return out
