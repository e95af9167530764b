"""Linear algebra of a search over one field: the rationals Q, the rational functions
Q(q) of the parameters left symbolic, or the integers modulo a large prime.

Everything goes through sympy's ``DomainMatrix``, which hands the work to FLINT
(python-flint) where it is installed and runs in pure Python otherwise, so both
backends run the same code. Modular arithmetic only ever *bounds* dimensions: the
rank of a matrix modulo a prime is at most its rank over Q, so a kernel modulo p
is at least as large as over Q; exact statements are made over Q or Q(q) only.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import sympy as sp
from sympy import GF, QQ
from sympy.polys.domains import Domain
from sympy.polys.matrices import DomainMatrix

try:
    import flint
except ImportError:  # pragma: no cover - python-flint is a dependency; sympy still works
    flint = None  # type: ignore[assignment]

#: The prime of modular computations (the Mersenne prime 2**61 - 1).
PRIME = (1 << 61) - 1
GF_PRIME = GF(PRIME)


def rational(value) -> Any:
    """A QQ element from a QQ element, an int, or a sympy Rational."""
    return QQ.from_sympy(value) if isinstance(value, sp.Basic) else QQ.convert(value)


class Field:
    """Where a search evaluates parameter polynomials: ``domain`` is QQ, GF(PRIME) (or
    another prime, at a point of an algebraic set) or QQ(q); ``point`` maps parameter
    indices to the rational values substituted for them, and the other parameters are
    the symbols of the fraction field."""

    def __init__(
        self,
        domain: Domain,
        params: Sequence[sp.Symbol],
        point: Mapping[int, object],
        inverses: Mapping[int, sp.Expr] | None = None,
    ):
        self.domain = domain
        self.params = tuple(params)
        self.point = {i: self.number(v) for i, v in point.items()}
        self.symbolic = {i: domain.from_sympy(p) for i, p in enumerate(params) if i not in point}
        self.zero = domain.zero
        self.one = domain.one
        self._cache: dict[tuple, object] = {}
        # the parameters that are the fraction field's own symbols (not numbers, inverses)
        self._plain = frozenset(
            i for i in self.symbolic if i not in (inverses or {}) and domain.is_FractionField
        )
        # a parameter that stands for 1/c(p) (a level set divided by c) takes that value
        for i, c in (inverses or {}).items():
            value = self.one / self.evaluate(sp.Poly(c, *self.params).as_dict())
            if i in self.point:
                self.point[i] = value
            else:
                self.symbolic[i] = value
        self._cache.clear()

    @property
    def exact(self) -> bool:
        return not self.domain.is_FiniteField

    def number(self, value) -> Any:
        """A rational number as an element of the field."""
        q = rational(value)
        if self.domain.is_FiniteField:
            return self.domain(int(q.numerator)) / self.domain(int(q.denominator))
        return self.domain.convert(q)

    def evaluate(self, poly: Mapping[tuple[int, ...], object]) -> Any:
        """A parameter polynomial (exponents -> rational) as an element of the field."""
        key = tuple(sorted(poly.items()))
        hit = self._cache.get(key)
        if hit is None:
            if self.domain.is_FractionField:
                hit = self._fraction(poly)
            else:
                hit = self.zero
                for exps, coeff in poly.items():
                    term = self.number(coeff)
                    for i, e in enumerate(exps):
                        if e:
                            term *= self._value(i) ** e
                    hit += term
            self._cache[key] = hit
        return hit

    def _value(self, i: int) -> Any:
        return self.point[i] if i in self.point else self.symbolic[i]

    def _fraction(self, poly: Mapping[tuple[int, ...], object]) -> Any:
        """``evaluate`` in Q(q): the terms in the symbols alone summed as one polynomial
        of Q[q] (no fraction arithmetic, whose every step takes a gcd), then times the
        values of the other parameters (numbers, and 1/c(q) for an inverse), grouped."""
        plain = self._plain
        groups: dict[tuple[int, ...], dict[tuple[int, ...], Any]] = {}
        for exps, coeff in poly.items():
            mine = tuple(e if i in plain else 0 for i, e in enumerate(exps))
            other = tuple(0 if i in plain else e for i, e in enumerate(exps))
            terms = groups.setdefault(other, {})
            terms[mine] = terms.get(mine, QQ.zero) + rational(coeff)
        field = self.domain.field
        total = self.zero
        for other, terms in groups.items():
            part = field.new(field.ring.from_dict({m: c for m, c in terms.items() if c}))
            for i, e in enumerate(other):
                if e:
                    part *= self._value(i) ** e
            total += part
        return total


def _matrix(rows: int, cols: int, entries: Iterable[tuple[int, int, object]], field: Field):
    """A sparse matrix (the systems are a few entries per row of thousands)."""
    sparse: dict[int, dict[int, object]] = {}
    for r, c, v in entries:
        if v:
            sparse.setdefault(r, {})[c] = v
    return DomainMatrix(sparse, (rows, cols), field.domain)


def nullspace(rows: int, cols: int, entries: Iterable[tuple[int, int, object]], field: Field):
    """A basis of the kernel of the matrix given by (row, column, value) entries."""
    if cols == 0:
        return []
    if rows == 0:
        return [[field.one if i == j else field.zero for i in range(cols)] for j in range(cols)]
    matrix = _matrix(rows, cols, entries, field)
    if not field.domain.is_FractionField:
        return matrix.nullspace().to_list()
    # Over Q(p), fraction-free elimination in Z[p] (denominators cleared row by row),
    # with FLINT's multivariate polynomials where python-flint is there: an order of
    # magnitude faster than elimination with gcds in Q(p), and again than sympy's own
    # polynomials. Each vector has 1 at its free column: the reduced echelon form's
    # kernel basis, the field's own.
    _, over_ring = matrix.clear_denoms_rowwise(convert=True)
    if flint is not None:
        return _nullspace_flint(over_ring, cols, field)
    basis = over_ring.nullspace().convert_to(field.domain).to_list()
    return [[v / last for v in vector] for vector in basis for last in [_last_nonzero(vector)]]


def _nullspace_flint(matrix: DomainMatrix, cols: int, field: Field) -> list[list]:
    """The kernel basis of a matrix over Q[p] (one vector per free column, 1 there), by
    fraction-free Gauss-Jordan elimination over Z[p] in FLINT: a row is only ever
    multiplied by a pivot (over its gcd with the entry removed) and divided by the
    gcd of its entries, so that at the end each pivot row reads d x_c + sum R_f x_f = 0."""
    ring = matrix.domain.ring
    ctx = flint.fmpz_mpoly_ctx.get(tuple(str(s) for s in ring.symbols), "lex")
    rows = []
    for row in matrix.to_sdm().values():
        scale = math.lcm(*(int(c.denominator) for p in row.values() for c in p.values()))
        rows.append(
            {j: ctx.from_dict({e: int(c * scale) for e, c in p.items()}) for j, p in row.items()}
        )
    pivots: dict[int, dict] = {}  # pivot column -> its row
    for c in range(cols):
        holders = [r for r in rows if c in r]
        if not holders:
            continue
        pivot_row = min(holders, key=lambda r: (len(r[c]), len(r)))
        rows = [r for r in rows if r is not pivot_row]
        d = pivot_row[c]
        others = [*(r for r in rows if c in r), *(r for r in pivots.values() if c in r)]
        for r in others:
            a = r.pop(c)
            g = d.gcd(a)
            p, q = d / g, a / g
            for j in set(r) | set(pivot_row):
                if j == c:
                    continue
                value = p * r[j] if j in r else ctx.constant(0)
                if j in pivot_row:
                    value -= q * pivot_row[j]
                if value.is_zero():
                    r.pop(j, None)
                else:
                    r[j] = value
            _divide_content(r)
        rows = [r for r in rows if r]
        pivots[c] = pivot_row
    free = [f for f in range(cols) if f not in pivots]
    fraction = field.domain.field
    target = fraction.ring

    def plain(poly) -> object:
        # Python integers: FLINT's do not convert under sympy's pure-Python ground types
        return target.from_dict(
            {
                tuple(int(e) for e in m): target.domain.convert(int(c))
                for m, c in poly.to_dict().items()
            }
        )

    def element(numer, denom) -> object:
        return fraction.new(plain(numer), plain(denom))

    basis = []
    for f in free:
        vector = [field.zero] * cols
        vector[f] = field.one
        for c, row in pivots.items():
            if f in row:
                vector[c] = field.domain.convert(element(-row[f], row[c]))
        basis.append(vector)
    return basis


def _divide_content(row: dict) -> None:
    """Divide a row of Z[p] by the gcd of its entries (its rank is unchanged)."""
    g = None
    for v in row.values():
        g = v if g is None else g.gcd(v)
        if g.is_one():
            return
    if g is not None and not g.is_one():
        for j in row:
            row[j] = row[j] / g


def _last_nonzero(vector: Sequence) -> object:
    return next(v for v in reversed(vector) if v)


def rank(rows: int, cols: int, entries: Iterable[tuple[int, int, object]], field: Field) -> int:
    """The rank of the matrix given by (row, column, value) entries."""
    if cols == 0 or rows == 0:
        return 0
    return _matrix(rows, cols, entries, field).rank()


class Span:
    """An echelon basis of a subspace of K^n: membership tests and extension."""

    def __init__(self, field: Field):
        self.field = field
        self.rows: list[tuple[int, list]] = []  # (pivot, vector with 1 at the pivot)

    def reduce(self, vector: Sequence) -> list:
        """``vector`` minus its part in the span along the pivots (a canonical residue)."""
        v = list(vector)
        for pivot, row in self.rows:
            c = v[pivot]
            if c:
                v = [a - c * b for a, b in zip(v, row, strict=True)]
        return v

    def add(self, vector: Sequence) -> bool:
        """Add ``vector``; False when it lies in the span already."""
        v = self.reduce(vector)
        for pivot, c in enumerate(v):
            if c:
                inv = self.field.one / c
                v = [a * inv for a in v]
                self.rows = [
                    (q, [a - r[pivot] * b for a, b in zip(r, v, strict=True)])
                    if r[pivot]
                    else (q, r)
                    for q, r in self.rows
                ]
                self.rows.append((pivot, v))
                return True
        return False

    @property
    def dim(self) -> int:
        return len(self.rows)
