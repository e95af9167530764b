"""Deciding a component of the rank-drop locus that has no rational parametrisation, at
its points: the largest number of extra integrals any of its members can have.

A component (``components.Piece``) is first cut down to points. The family's scalings
(``mathematics.scalings``) keep ranks and counts of integrals, so a component is a cone
under them, and its part where a parameter x of non-zero weight is not 0 is decided by
its slice x = 1 (several parameters at once where independent scalings allow); the
part where x = 0 is a smaller algebraic set, returned to be resolved again. A slice of
dimension 0 is a finite set of points over number fields Q(alpha), one irreducible
factor g of the eliminant at a time (conjugate points have the same ranks).

At each such point the extra integrals are counted modulo a prime q at which g has a
root: the residues of the point's coordinates are the image of the number field's ring
under a homomorphism to GF(q), every minor that does not vanish there does not vanish
at the point, so the count modulo q bounds the count at the point from above (as the
search's generic count does). A point whose bound is no more than the set it lies in
carries no more integrals: it is decided. Where the bound is above that, the real points
of a component that is finite to begin with (not a slice), over Q, are returned with
exact values (radicals, or CRootOf) to be searched like any other candidate, where
the members' field is rational there (a parameter that enters only through its square);
otherwise the point is undecided, never a special set. A slice of
positive dimension (a component with no scaling to cut it down) is not decided either:
its sub-loci would need a search over its function field.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import flint
import sympy as sp
from sympy import GF

from ..mathematics.algebraic import exact_roots
from ..mathematics.prime_components import Component, DecompositionLimit, components
from ..mathematics.scalings import slicing_variables
from .ansatz import PolynomialSystem
from .components import Piece
from .integrals import Generator, analyse
from .linear import PRIME, Field
from .splitting import AlgebraicSet

#: How many primes below 2**61 are tried for one at which a point's polynomial has a root.
PRIMES_TRIED = 64


@dataclass
class Decision:
    """What deciding a piece established: ``decided`` texts (points whose bound is no
    more than the set's), ``undecided`` texts, and the smaller algebraic sets where a
    slicing parameter is 0 (``further``), to be resolved again."""

    decided: list[str] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)
    further: list[AlgebraicSet] = field(default_factory=list)
    #: real points with exact values, to be searched as candidate sets
    points: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)


def decide(
    piece: Piece,
    system: PolynomialSystem,
    known: Sequence[Generator],
    reference: int,
    weights: Sequence[Mapping[sp.Symbol, int]],
    rnd: random.Random,
) -> Decision:
    """Decide ``piece`` (module docstring) for a set whose members have at most
    ``reference`` extra integrals generically; ``weights`` are the family's scalings,
    ``known`` the known integrals' generators of ``system``."""
    out = Decision()
    part = piece.component
    points: Sequence[Component] = (part,)
    if part.dimension:
        cut = slicing_variables(weights, [x for x in part.free if any(w.get(x) for w in weights)])
        if cut:
            for x in cut:  # the part where x = 0, unless the branch assumed x != 0
                if not any(sp.sympify(u).free_symbols == {x} for u in piece.units):
                    out.further.append(
                        AlgebraicSet(piece.values, (*part.equations(), x), piece.units)
                    )
            try:
                points = components(
                    [*part.equations(), *(x - 1 for x in cut)],
                    part.variables,
                    part.parameters,
                    origin=(),
                )
            except DecompositionLimit as err:
                out.undecided.append(f"{piece.text} (its slice was not decomposed: {err})")
                return out
    for point in points:
        where = _text(piece, point)
        if point.dimension:
            out.undecided.append(
                f"{where} (no rational parametrisation, and no scaling cuts it to points: "
                "its members are not searched)"
            )
            continue
        bound = _bound(point, piece.values, system, known, rnd)
        if bound is not None and bound <= reference:
            out.decided.append(where)
        elif (exact := _exact_points(point, piece.values) if point is part else None) is not None:
            out.points.extend(exact)
        elif bound is None:
            out.undecided.append(f"{where} (no prime found at which to count its integrals)")
        else:
            out.undecided.append(
                f"{where} (up to {bound} more counted modulo a prime at a point of it; "
                "not decided over its number field)"
            )
    return out


def _exact_points(
    point: Component, values: Mapping[sp.Symbol, sp.Expr]
) -> list[dict[sp.Symbol, sp.Expr]] | None:
    """The real points of a finite component over Q with exact coordinates (and the
    solved parameters' values there), those the assumptions allow; None where the ground
    field has parameters or the roots are not found."""
    if point.parameters:
        return None
    roots = exact_roots(sp.Poly(point.minimal.as_expr(), point.symbol, domain=sp.QQ))
    if roots is None:
        return None
    out = []
    for root in roots:
        if not root.is_real:
            continue
        at = {
            x: sp.radsimp(sp.sympify(point.coordinates[x]).subs(point.symbol, root))
            for x in point.variables
        }
        at.update({s: sp.radsimp(sp.sympify(e).xreplace(at)) for s, e in values.items()})
        if all(not x.is_positive or v.is_positive for x, v in at.items()):
            out.append(at)
    return out


def _text(piece: Piece, point: Component) -> str:
    """A point's equations: the piece's solved parameters and its prime ideal."""
    return AlgebraicSet(piece.values, tuple(point.equations())).text()


def _bound(
    point: Component,
    values: Mapping[sp.Symbol, sp.Expr],
    system: PolynomialSystem,
    known: Sequence[Generator],
    rnd: random.Random,
) -> int | None:
    """An upper bound of the extra integrals at the point (module docstring), or None
    where no prime within PRIMES_TRIED gives a root."""
    prime = PRIME
    for _ in range(PRIMES_TRIED):
        prime = int(sp.prevprime(prime))
        residues = _residues(point, values, system.params, prime, rnd)
        if residues is None:
            continue
        try:
            fld = Field(GF(prime), system.params, residues, system.inverses)
            return analyse(system, known, fld).extra
        except ZeroDivisionError:  # a denominator of the system vanishes at the residues
            continue
    return None


def _residues(
    point: Component,
    values: Mapping[sp.Symbol, sp.Expr],
    params: Sequence[sp.Symbol],
    prime: int,
    rnd: random.Random,
) -> dict[int, int] | None:
    """Residues modulo ``prime`` of every parameter at a point of the component: the
    symbolic ones at random, the component's coordinates through a root of its minimal
    polynomial there, the solved ones from their values. None where the polynomial has
    no root modulo ``prime`` or a denominator vanishes."""
    residue: dict[sp.Symbol, int] = {}
    for p in params:
        if p not in point.variables and p not in values:
            residue[p] = rnd.randrange(1, prime)
    try:
        coefficients = [_mod(c, residue, prime) for c in reversed(point.minimal.all_coeffs())]
        roots = flint.nmod_poly(coefficients, prime).roots()
        if not roots:
            return None
        u = int(roots[0][0])
        residue[point.symbol] = u
        for x in point.variables:
            residue[x] = _mod(sp.sympify(point.coordinates[x]), residue, prime)
        for s, e in values.items():
            residue[s] = _mod(sp.sympify(e), residue, prime)
    except ZeroDivisionError:
        return None
    return {i: residue.get(p, rnd.randrange(1, prime)) for i, p in enumerate(params)}


def _mod(expr: sp.Expr, residue: Mapping[sp.Symbol, int], prime: int) -> int:
    """A rational function of the symbols with residues, modulo ``prime``
    (ZeroDivisionError where its denominator vanishes there)."""
    numer, denom = sp.fraction(sp.together(sp.sympify(expr)))
    top, bottom = _poly_mod(numer, residue, prime), _poly_mod(denom, residue, prime)
    if bottom == 0:
        raise ZeroDivisionError("a denominator vanishes modulo the prime")
    return top * pow(bottom, -1, prime) % prime


def _poly_mod(expr: sp.Expr, residue: Mapping[sp.Symbol, int], prime: int) -> int:
    symbols = sorted(expr.free_symbols, key=str)
    if not symbols:
        value = Fraction(str(sp.Rational(expr)))
        return value.numerator * pow(value.denominator, -1, prime) % prime
    poly = sp.Poly(expr, *symbols)
    total = 0
    for exps, c in poly.terms():
        value = Fraction(str(sp.Rational(c)))
        term = value.numerator * pow(value.denominator, -1, prime)
        for s, e in zip(symbols, exps, strict=True):
            if e:
                term = term * pow(residue[s], int(e), prime) % prime
        total += term
    return total % prime
