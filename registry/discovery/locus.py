"""Where the rank of a block drops: free-parameter values where more integrals can exist.

A block B of the system has generic rank r over Q(p, q) (p the free parameters, q
the parameters that stay symbolic). Integrals beyond the generic ones need
rank B < r, i.e. every r x r minor vanishing. The locus is found exactly:

1. *Constant pivots.* Rows are eliminated on nonzero rational entries (a Schur
   complement): rank B is the number of pivots plus the rank of the rest S, whose
   entries stay polynomial, so the locus of B is that of S, which is small.
2. *Maximal minors.* With S of generic rank rho, three minors M_i = det(R_i S Q_i)
   for random integer projections (by Cauchy-Binet each is a combination of
   rho x rho minors, so the locus lies in their common zeros). Their gcd g holds
   every codimension-one component: an irreducible polynomial that vanishes
   wherever all minors vanish divides each of them.
3. *Components and points.* Each irreducible factor h of g that involves a free
   parameter it is linear in is solved for it (v = -h0/h1, a rational function of the
   others and of q) and S restricted there: if the rank drops there generically,
   {h = 0} is a component (searched as a family of its own); otherwise its points
   where the rank drops are found the same way, one dimension down. With two free
   parameters, the isolated points (common zeros of the M_i / g) come from the gcd of
   two resultants. Factors free of the free parameters are conditions on q alone,
   which stays generic, and are ignored.

Candidates are only candidates: each is confirmed by an exact computation of the
integrals there. What cannot be resolved (a factor of degree >= 2 in every free
parameter whose roots may carry a rank drop, codimension >= 2 with three or more free
parameters) is returned as ``undecided`` so that the search says it is not complete.
An irrational candidate is dismissed when the rank modulo a prime at one of its roots
is still rho: the rank can only fall under reduction modulo a prime, and conjugate
roots have equal ranks.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

import sympy as sp
from sympy import GF, QQ
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rings import PolyElement, PolyRing

from ..language.printer import to_text

Row = dict[int, PolyElement]

#: Attempts at a random projection whose determinant is not identically zero.
PROJECTION_ATTEMPTS = 8
#: Primes for the modular rank bounds (below 2**63, so FLINT's nmod matrices take them).
PRIMES = ((1 << 61) - 1, 2**31 - 1, 4294967291, 1000000007)
#: Range of the entries of random projections.
SPREAD = 7


@dataclass
class Locus:
    """Candidate sets of free-parameter values: ``points`` give every free parameter a
    value (a sympy expression in the symbolic parameters, often a number), and
    ``components`` give one free parameter as a rational function of the others;
    ``undecided`` are the equations of sets that could not be decided."""

    points: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    components: list[tuple[sp.Symbol, sp.Expr]] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)

    def merge(self, other: Locus) -> None:
        for mine, theirs in (
            (self.points, other.points),
            (self.components, other.components),
            (self.undecided, other.undecided),
        ):
            mine.extend(x for x in theirs if x not in mine)


# ----------------------------------------------------------------- elimination


def eliminate_constants(rows: list[Row]) -> tuple[int, list[Row]]:
    """Eliminate on nonzero rational entries (pivot rows with fewest entries first);
    return the number of pivots and the rows that remain."""
    rows = [dict(r) for r in rows if r]
    taken = 0
    while True:
        best = None
        for i, r in enumerate(rows):
            for j, v in r.items():
                if v.is_ground and (best is None or len(r) < best[0]):
                    best = (len(r), i, j)
        if best is None:
            return taken, rows
        _, i, j = best
        pivot_row = rows.pop(i)
        pivot = pivot_row.pop(j).LC
        scaled = {k: v / pivot for k, v in pivot_row.items()}
        for r in rows:
            f = r.pop(j, None)
            if f is not None:
                for k, v in scaled.items():
                    value = r.get(k, v.ring.zero) - f * v
                    if value:
                        r[k] = value
                    else:
                        r.pop(k, None)
        rows = [r for r in rows if r]
        taken += 1


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


def bareiss(matrix: list[list[PolyElement]]) -> PolyElement:
    """The determinant of a square matrix of polynomials, fraction-free."""
    n = len(matrix)
    ring = matrix[0][0].ring
    m = [row[:] for row in matrix]
    previous, sign = ring.one, 1
    for k in range(n - 1):
        if not m[k][k]:
            swap = next((i for i in range(k + 1, n) if m[i][k]), None)
            if swap is None:
                return ring.zero
            m[k], m[swap] = m[swap], m[k]
            sign = -sign
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                m[i][j] = (m[i][j] * m[k][k] - m[i][k] * m[k][j]).exquo(previous)
        previous = m[k][k]
    return sign * m[n - 1][n - 1]


def projected_minor(rows: list[Row], rho: int, rnd: random.Random) -> PolyElement:
    """det(R S Q) for random integer R (rho x rows) and Q (columns x rho), not zero."""
    cols = columns(rows)
    index = {k: i for i, k in enumerate(cols)}
    ring = next(iter(rows[0].values())).ring
    for _ in range(PROJECTION_ATTEMPTS):
        q = [[rnd.randint(-SPREAD, SPREAD) for _ in range(rho)] for _ in cols]
        sq = [
            [
                sum((v * q[index[k]][j] for k, v in r.items() if q[index[k]][j]), ring.zero)
                for j in range(rho)
            ]
            for r in rows
        ]
        left = [[rnd.randint(-SPREAD, SPREAD) for _ in rows] for _ in range(rho)]
        square = [
            [
                sum((left[a][i] * sq[i][j] for i in range(len(rows)) if left[a][i]), ring.zero)
                for j in range(rho)
            ]
            for a in range(rho)
        ]
        det = bareiss(square)
        if det:
            return det
    raise ArithmeticError("no random projection kept the generic rank")


# ----------------------------------------------------------------------- locus


def drop_locus(rows: list[Row], rho: int, free: int, rnd: random.Random) -> Locus:
    """Where the rows (generic rank rho; the first ``free`` generators of their ring are
    the free parameters, the others symbolic) lose rank (module docstring)."""
    locus = Locus()
    if rho == 0 or not rows or free == 0:
        return locus
    minors = [projected_minor(rows, rho, rnd) for _ in range(3)]
    common = minors[0].gcd(minors[1]).gcd(minors[2])
    ring = common.ring
    _, factors = common.factor_list()
    for h, _ in factors:
        degrees = h.degrees()
        if any(degrees[:free]):
            locus.merge(_on_hypersurface(rows, rho, free, h, rnd))
    quotients = [m.exquo(common) for m in minors]
    if free == 2:
        locus.merge(_isolated(rows, rho, quotients, rnd))
    elif free > 2 and not any(_is_free_of(q, free) for q in quotients):
        locus.undecided.append(
            "sets of codimension 2 or more in the free parameters (searched with at most two)"
        )
    del ring
    return locus


def _is_free_of(poly: PolyElement, free: int) -> bool:
    return not any(poly.degrees()[:free])


def equation_text(poly: PolyElement) -> str:
    """``poly = 0`` in the case-file language."""
    return f"{to_text(poly.as_expr())} = 0"


def _solved(h: PolyElement, free: int):
    """(index of a free generator h is linear in, numerator, denominator) with
    generator = numerator/denominator on h = 0, both in the ring of the others."""
    degrees = h.degrees()
    v = next((i for i in range(free) if degrees[i] == 1), None)
    if v is None:
        return None
    ring = h.ring
    others = [i for i in range(ring.ngens) if i != v]
    smaller = PolyRing([ring.symbols[i] for i in others], QQ, ring.order) if others else None
    numer, denom = {}, {}
    for exps, c in h.items():
        key = tuple(exps[i] for i in others)
        target = denom if exps[v] else numer
        target[key] = target.get(key, QQ.zero) + (c if exps[v] else -c)
    if smaller is None:
        return v, QQ(numer.get((), 0)) / QQ(denom[()]), None, None
    return v, smaller(numer), smaller(denom), smaller


def _restrict(rows: list[Row], v: int, numer: PolyElement, denom: PolyElement) -> list[Row]:
    """The rows on {x_v = numer/denom}, each row scaled by a power of denom so that its
    entries stay polynomial (which changes no rank where denom is not 0)."""
    smaller = numer.ring
    ring = next(iter(rows[0].values())).ring
    others = [i for i in range(ring.ngens) if i != v]
    out = []
    for r in rows:
        top = max(e[v] for p in r.values() for e in p.monoms())
        new = {}
        for k, p in r.items():
            total = smaller.zero
            for exps, c in p.items():
                rest = tuple(exps[i] for i in others)
                total += smaller({rest: c}) * _power(numer, exps[v]) * _power(denom, top - exps[v])
            if total:
                new[k] = total
        if new:
            out.append(new)
    return out


def _power(poly: PolyElement, exponent: int) -> PolyElement:
    """poly**exponent, with 0**0 = 1 (sympy's rings refuse it)."""
    return poly.ring.one if exponent == 0 else poly**exponent


def _on_hypersurface(rows, rho, free, h, rnd) -> Locus:
    """On {h = 0}: a component (the rank drops everywhere on it) or its points where the
    rank drops; undecided when h is linear in no free parameter."""
    locus = Locus()
    solved = _solved(h, free)
    ring = h.ring
    if solved is None:
        if not _dismissed(rows, rho, h, free, rnd):
            locus.undecided.append(equation_text(h))
        return locus
    v, numer, denom, smaller = solved
    symbol = ring.symbols[v]
    if smaller is None:  # a number
        locus.points.append({symbol: QQ.to_sympy(numer)})
        return locus
    restricted = _restrict(rows, v, numer, denom)
    point = [rnd.randrange(1, PRIMES[0]) for _ in range(smaller.ngens)]
    value = numer.as_expr() / denom.as_expr()
    if rank_mod(restricted, point) < rho and value_mod(denom, point, PRIMES[0]):
        if free == 1:
            locus.points.append({symbol: sp.cancel(value)})
        else:
            locus.components.append((symbol, sp.cancel(value)))
        return locus
    inner = drop_locus(restricted, rho, free - 1, rnd)
    for p in inner.points:
        at = sp.cancel(value.xreplace(p))
        if at.has(sp.zoo, sp.nan):
            continue
        locus.points.append({**p, symbol: at})
    locus.undecided.extend(inner.undecided)
    locus.undecided.extend(
        f"{s} = {e} on {equation_text(h)} (codimension 2)" for s, e in inner.components
    )
    return locus


def _isolated(rows, rho, quotients, rnd) -> Locus:
    """Common zeros of three polynomials in two free parameters (and the symbolic ones)
    with no common factor: first coordinates from the gcd of two resultants, second
    from the gcd of the polynomials at each."""
    locus = Locus()
    if any(_is_free_of(q, 2) for q in quotients):
        return locus
    x, y = quotients[0].ring.symbols[:2]
    exprs = [q.as_expr() for q in quotients]
    gens = quotients[0].ring.symbols
    first = sp.Poly(sp.resultant(exprs[0], exprs[1], y), *[g for g in gens if g != y])
    second = sp.Poly(sp.resultant(exprs[0], exprs[2], y), *[g for g in gens if g != y])
    both = sp.gcd(first, second)
    if both.is_zero or both.degree(x) < 1:
        return locus
    for f, _ in sp.factor_list(both.as_expr(), *[g for g in gens if g != y])[1]:
        if sp.degree(f, x) != 1:
            if sp.degree(f, x) > 1:
                locus.undecided.append(f"{sp.sstr(f)} = 0 (with a value of {y})")
            continue
        a = sp.cancel(sp.solve(f, x)[0])
        at = [sp.cancel(e.subs(x, a)) for e in exprs]
        g = sp.Poly(sp.numer(sp.together(at[0])), y)
        for other in at[1:]:
            g = sp.gcd(g, sp.Poly(sp.numer(sp.together(other)), y))
        if g.degree() < 1:
            continue
        for fy, _ in sp.factor_list(g.as_expr(), y)[1]:
            if sp.degree(fy, y) == 1:
                locus.points.append({x: a, y: sp.cancel(sp.solve(fy, y)[0])})
            elif sp.degree(fy, y) > 1:
                locus.undecided.append(f"{x} = {a}, {sp.sstr(fy)} = 0")
    return locus


def _dismissed(rows, rho, h, free, rnd) -> bool:
    """Whether the rank provably keeps rho on {h = 0}: at a point of it modulo a prime
    (random values for all generators but one free one, a root for that one), which
    bounds from below the rank at the generic point of every component of {h = 0}
    that reduces to it. Only used for a univariate h (one free parameter, nothing
    symbolic), where the roots are conjugate and so alike."""
    ring = h.ring
    if ring.ngens != 1:
        return False
    var = ring.symbols[0]
    for prime in PRIMES:
        poly = sp.Poly(h.as_expr(), var)
        _, poly = poly.clear_denoms()
        try:
            roots = sp.Poly(poly.as_expr(), var, modulus=prime).ground_roots()
        except (sp.PolynomialError, ValueError, NotImplementedError):
            continue
        if roots:
            return rank_mod(rows, [int(next(iter(roots))) % prime], prime) == rho
    return False
