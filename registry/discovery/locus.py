"""Where the rank of a block drops: free-parameter values where more integrals can exist.

A block B of the system has generic rank r over Q(p, q) (p the free parameters, q
the parameters that stay symbolic). Integrals beyond the generic ones need
rank B < r somewhere. The candidate sets are found by case splitting on the pivots of
a fraction-free elimination (``splitting``): pivots are entries that cannot vanish
where the assumptions hold (constants, monomials in positive or nonzero parameters),
and where there is none the branch splits on a factor (= 0, solved rationally for a
free parameter, or != 0). Each candidate gives some free parameters as rational
functions of the others (and of q); it is only a candidate, confirmed by an exact
search there. What cannot be solved rationally is returned as an algebraic set
(``splitting.AlgebraicSet``), which the search decides at the points of its components
(``components``).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

import sympy as sp
from sympy import GF
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rings import PolyElement

from .components import Piece
from .splitting import AlgebraicSet, Region, Spread, drop_sets

Row = dict[int, PolyElement]

#: Primes for the modular rank bounds (below 2**63, so FLINT's nmod matrices take them).
PRIMES = ((1 << 61) - 1, 2**31 - 1, 4294967291, 1000000007)


@dataclass
class Locus:
    """Candidate sets of free-parameter values, each an assignment of some free
    parameters (sympy expressions in the others and the symbolic parameters, often
    numbers); ``algebraic`` are the candidate sets not solved rationally, ``undecided``
    the equations of sets that could not be decided."""

    sets: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)
    algebraic: list[AlgebraicSet] = field(default_factory=list)
    #: the components of the algebraic sets with no rational parametrisation
    pieces: list[Piece] = field(default_factory=list)

    def merge(self, other: Locus) -> None:
        self.sets.extend(x for x in other.sets if x not in self.sets)
        self.undecided.extend(x for x in other.undecided if x not in self.undecided)
        self.algebraic.extend(x for x in other.algebraic if x not in self.algebraic)

    def maximal(self) -> list[dict[sp.Symbol, sp.Expr]]:
        """The sets to search: one parametrisation of each set (one without denominators
        where there is one), and no set that lies where another's parametrisation is
        defined (the search of that one covers every special set within it). A set in
        the closure of another, where that one's denominators vanish, stays."""
        kept: list[dict[sp.Symbol, sp.Expr]] = []
        for s in sorted(self.sets, key=lambda s: (not polynomial(s), len(s))):
            if not any(same(t, s) for t in kept):
                kept.append(s)
        return [s for s in kept if not any(t is not s and contains(t, s) for t in kept)]


def polynomial(values: dict[sp.Symbol, sp.Expr]) -> bool:
    """Whether a parametrisation has no denominator (it is defined everywhere)."""
    return all(sp.denom(sp.together(e)).is_number for e in values.values())


def _holds(big: dict[sp.Symbol, sp.Expr], small: dict[sp.Symbol, sp.Expr]) -> bool:
    """Whether big's equations hold on small's values, with big's denominators nonzero
    there (the generic point of small lies where big's parametrisation is defined)."""
    for s, e in big.items():
        numer, denom = sp.fraction(sp.together(e))
        if sp.cancel(denom.xreplace(small)) == 0:
            return False
        if sp.cancel((s * denom - numer).xreplace(small)) != 0:
            return False
    return True


def same(a: dict[sp.Symbol, sp.Expr], b: dict[sp.Symbol, sp.Expr]) -> bool:
    """Whether two parametrisations describe the same set (each one's equations hold
    on the other's values)."""
    return a == b or (len(a) == len(b) and _holds(a, b) and _holds(b, a))


def contains(big: dict[sp.Symbol, sp.Expr], small: dict[sp.Symbol, sp.Expr]) -> bool:
    """Whether the set ``small`` is a smaller set within the part of ``big`` where its
    parametrisation is defined."""
    return len(small) > len(big) and _holds(big, small)


def columns(rows: list[Row]) -> list[int]:
    return sorted({k for r in rows for k in r})


def value_mod(poly: PolyElement, point, prime: int) -> int:
    """poly(point) modulo ``prime`` (point: residues of the ring's generators)."""
    total = 0
    for exps, c in poly.items():
        term = int(c.numerator) * pow(int(c.denominator), -1, prime)
        for x, e in zip(point, exps, strict=True):
            if e:
                term = term * pow(x, e, prime) % prime
        total += term
    return total % prime


def rank_mod(rows: list[Row], point, prime: int = PRIMES[0]) -> int:
    """The rank of the rows at ``point`` modulo ``prime``: a lower bound of the rank at
    every point over a number field that reduces to it, and of the generic rank."""
    cols = columns(rows)
    if not rows or not cols:
        return 0
    domain = GF(prime)
    index = {k: i for i, k in enumerate(cols)}
    dense = [[domain.zero] * len(cols) for _ in rows]
    for i, r in enumerate(rows):
        for k, v in r.items():
            dense[i][index[k]] = domain(value_mod(v, point, prime))
    return DomainMatrix(dense, (len(rows), len(cols)), domain).rank()


def drop_locus(
    rows: list[Row],
    rho: int,
    free: int,
    rnd: random.Random,
    *,
    positive: frozenset[int] = frozenset(),
    nonzero: frozenset[int] = frozenset(),
    spread: Spread | None = None,
) -> Locus:
    """Where the rows (generic rank rho; the first ``free`` generators of their ring are
    the free parameters, the others symbolic; ``positive`` and ``nonzero`` the indices
    the assumptions keep so) lose rank (module docstring); ``spread`` explores the
    splitting's open branches elsewhere (``splitting.drop_sets``)."""
    locus = Locus()
    rows = [r for r in rows if r]
    if rho == 0 or not rows or free == 0:
        return locus
    ring = next(iter(rows[0].values())).ring
    region = Region(
        tuple(str(s) for s in ring.symbols),
        free,
        frozenset(positive),
        frozenset(nonzero) | frozenset(positive),
    )
    ctx = region.context
    converted = []
    for r in rows:
        scale = 1
        for v in r.values():
            for c in v.values():
                scale = math.lcm(scale, int(c.denominator))
        converted.append(
            {k: ctx.from_dict({e: int(c * scale) for e, c in v.items()}) for k, v in r.items()}
        )
    split = drop_sets(converted, rho, region, rnd, spread)
    locus.sets = split.sets
    locus.undecided = split.undecided
    locus.algebraic = split.algebraic
    return locus
