"""The Painlevé test of Ablowitz, Ramani and Segur (J. Math. Phys. 21 (1980) 715): the
Laurent series of a balance, solved order by order, and its compatibility conditions.

Put x_i = t^(-w_i) sum_k a_{i,k} t^k, with a_0 the balance c, into the whole field (its
lower-shift parts too: a part of shift s first acts at order 1 - s). With
X_i = sum_k a_{i,k} t^k the equations read t X_i' - w_i X_i = V_i(t), where V_i is the
field's i-th component times t^(w_i + 1), a power series; at order k,

    (K - k) a_k = -R_k(a_0, ..., a_{k-1}),

K the Kovalevskaya matrix at c and R_k the rest of the order-k coefficient of V. Where
k is not an exponent, a_k is determined. At a resonance r (a positive integer exponent)
K - r is singular: the equations can be solved only if R_r lies in its range, that is
l R_r = 0 for every left null vector l; those are the *compatibility conditions*. If one
fails, the series needs a term t^r log t (a movable logarithmic branch point, and the
test fails); if they hold, a_r carries free coefficients, which stay symbols at the
following orders.

Everything is exact: the coefficients lie in F[free], F = k[u]/(g) the field of the
balance's component (``algebraic``), so one computation serves all its balances, and a
condition is zero exactly when it is zero in F. F's arithmetic is done over Z[p] in FLINT
(``integral_algebra``); K - k is inverted by Cayley-Hamilton where k is not a resonance,
and over parameters a resonance step projects onto the kernel instead of dividing by
pivots (``_Recursion._order``).
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from . import algebraic
from .integral_algebra import Element, IntegralAlgebra
from .kovalevskaya import berkowitz, matrix_in
from .prime_components import Component
from .weighted import WeightedField

#: Over Q(p), a resonance step projects onto the kernel (``_Recursion._project``) only in
#: a field of larger degree than this: below, a pivot's inverse stays small, and the
#: projection's minor adds exceptional hypersurfaces of its own to a stratification (on
#: the distinct-moments heavy top one without a rational parametrisation, which left
#: the list incomplete; elimination's pivots there add none).
PROJECT_ABOVE_DEGREE = 4


@dataclass(frozen=True)
class Resonance:
    """The step at one resonance r of multiplicity m: the free coefficients a_r brings
    (``free``) and the compatibility conditions that do not vanish (``conditions``, in
    the free coefficients of earlier resonances, the parameters and the component's u;
    empty when they all hold). Fewer than m free coefficients means K - r is not
    diagonalizable: the general solution then needs t^r log t as well. At r = 0 the free
    coefficients are the leading ones, the free coordinates of a family of balances:
    fewer than m means the balance is not on a family of dimension m."""

    order: int
    multiplicity: int
    free: tuple[sp.Symbol, ...]
    conditions: tuple[sp.Expr, ...]

    @property
    def missing(self) -> int:
        """How many free coefficients the resonance lacks (a Jordan block of K)."""
        return self.multiplicity - len(self.free)

    @property
    def holds(self) -> bool:
        return not self.conditions and self.missing == 0

    @property
    def obstructions(self) -> tuple[str, ...]:
        """What fails here, in words (empty when the step holds)."""
        texts = [
            f"compatibility condition at resonance {self.order} fails: {sp.sstr(c)}"
            for c in self.conditions
        ]
        if self.missing and self.order == 0:
            where = (
                f"the balances here form a family of dimension {len(self.free)}"
                if self.free
                else "the balance is isolated"
            )
            texts.append(
                f"exponent 0 has multiplicity {self.multiplicity} but {where}: "
                f"{self.missing} free leading coefficient(s) missing (the general solution "
                "is not a Laurent series there)"
            )
        elif self.missing:
            texts.append(
                f"resonance {self.order} has multiplicity {self.multiplicity} but brings "
                f"{len(self.free)} free coefficients (K - {self.order} is not "
                "diagonalizable): a logarithmic term is needed"
            )
        return tuple(texts)


@dataclass(frozen=True)
class LaurentSeries:
    """The series of a component's balances to the last resonance: the coefficients
    a_k (k = 0, 1, ...; each a tuple over the variables) and the resonances' steps.
    The coefficients are written as expressions when first asked for (the test itself
    needs only the resonances)."""

    elements: tuple[tuple[Element, ...], ...]
    names: Mapping[sp.Symbol, sp.Symbol]
    resonances: tuple[Resonance, ...]
    algebra: IntegralAlgebra

    @functools.cached_property
    def coefficients(self) -> tuple[tuple[sp.Expr, ...], ...]:
        exported = self.algebra.exported
        return tuple(
            tuple(sp.expand(exported(a).as_expr()).xreplace(self.names) for a in order)
            for order in self.elements
        )

    @property
    def compatible(self) -> bool:
        """Every compatibility condition holds: no logarithmic term to this order."""
        return all(r.holds for r in self.resonances)


def laurent_series(
    split: WeightedField,
    component: Component,
    matrix: sp.Matrix,
    resonances: Mapping[int, int],
    *,
    order: int | None = None,
) -> LaurentSeries:
    """The ARS recursion for the balances of ``component`` up to ``order`` (default: the
    largest resonance), checking the compatibility conditions at ``resonances`` (each
    positive integer exponent with its multiplicity)."""
    last = max(resonances, default=0) if order is None else order
    return _Recursion(split, component, matrix, dict(resonances)).run(last)


class _Recursion:
    def __init__(self, split: WeightedField, component: Component, matrix, resonances):
        self.split, self.resonances = split, resonances
        n = len(split.variables)
        taken = {str(s) for s in (*split.variables, *split.parameters, *component.free)}
        self.free = {r: [_fresh(f"f{r}_{j}", taken) for j in range(n)] for r in resonances}
        symbols = [s for r in resonances for s in self.free[r]]
        # the arithmetic of F[free], over Z[p] (integral_algebra); results leave it in
        # sympy's k[u, free]
        self.algebra = IntegralAlgebra(component.symbol, component.minimal, symbols)
        self.ext = algebraic.Extension(component.symbol, component.minimal)
        self.a = [[self.algebra.lift(component.evaluate(x))] for x in split.variables]
        #: every value the series divided by or needs non-zero (pivots, minors)
        self.divisors: list[Element] = []
        self.matrix = matrix_in(self.algebra, component, matrix)
        #: each denominator D_d of the field as (coefficient, factors) terms, and 1/D_d(c):
        #: the series of 1/D_d(X) is numbered n + d (``_series``)
        self.denominators = [
            [
                (self.element(coeff), tuple(j for j, m in enumerate(mono) for _ in range(m)))
                for mono, coeff in sp.Poly(d, *split.variables).terms()
            ]
            for d, _ in split.denominators
        ]
        self.inverses = [
            self.inverse(self.algebra.lift(component.evaluate(d))) for d, _ in split.denominators
        ]
        self.terms = self._terms()
        self.memo: dict[tuple[int, ...], list[Element]] = {}
        self._used: dict[int, int] = {}  # free coefficients brought by each resonance

    def element(self, expr: sp.Expr) -> Element:
        """A rational function of u (coefficients in k) as a reduced element of F."""
        return self.algebra.lift(self.ext.element(expr))

    def inverse(self, value: Element) -> Element:
        """1/value in F, for an element without free coefficients (kept in
        ``divisors``)."""
        self.divisors.append(value)
        return self.algebra.inverse(value)

    def _terms(self) -> list[list[tuple[Element, tuple[int, ...], int]]]:
        """Per component: (coefficient, monomial as a tuple of series indices, delay
        1 - shift) for every term of the whole field; index j < n is X_j, n + d the
        series of 1/D_d(X)."""
        n = len(self.split.variables)
        terms: list[list[tuple[Element, tuple[int, ...], int]]] = [[] for _ in range(n)]
        for term in self.split.terms:
            factors = tuple(j for j, m in enumerate(term.monomial) for _ in range(m))
            factors += tuple(n + d for d, e in enumerate(term.powers) for _ in range(e))
            terms[term.component].append((self.element(term.coefficient), factors, 1 - term.shift))
        return terms

    def run(self, last: int) -> LaurentSeries:
        steps = []
        n = len(self.split.variables)
        for k in range(1, last + 1):
            for column in self.a:
                column.append(self.algebra.zero)
            rest = [self._coefficient(i, k) for i in range(n)]
            solution, conditions, free = self._order(k, [-r for r in rest])
            self._used[k] = len(free)
            for i in range(n):
                self.a[i][k] = solution[i]
            if k in self.resonances:
                failing = tuple(
                    sp.expand(self.algebra.exported(c).as_expr())
                    for c in conditions
                    if not c.is_zero
                )
                steps.append(Resonance(k, self.resonances[k], tuple(free), failing))
        names = self._names()
        elements = tuple(tuple(self.a[i][k] for i in range(n)) for k in range(last + 1))
        steps = [
            Resonance(
                s.order,
                s.multiplicity,
                tuple(names.get(f, f) for f in s.free),
                tuple(c.xreplace(names) for c in s.conditions),
            )
            for s in steps
        ]
        return LaurentSeries(elements, names, tuple(steps), self.algebra)

    def _order(self, k: int, rhs: list[Element]):
        """(K - k) a_k = rhs. Where K - k is invertible a_k is read off Cayley-Hamilton
        (``_invert``: no division in F but by det(K - k)). At a resonance, by elimination
        (``_solve``: the conditions, the free coefficients); over a field of degree above
        ``PROJECT_ABOVE_DEGREE`` over Q(p), once it meets a pivot outside k (whose inverse
        is as large as its norm), by the projection onto the kernel (``_project``)
        instead, where K - r is diagonalizable on it."""
        if k not in self.resonances:
            return self._invert(k, rhs), [], []
        n = len(rhs)
        system = [[self.matrix[i][j] - (k if i == j else 0) for j in range(n)] for i in range(n)]
        if self.algebra.parameters and self.algebra.degree > PROJECT_ABOVE_DEGREE:
            mark = len(self.divisors)
            try:  # elimination while its pivots lie in k (the printed form of before)
                return self._solve(system, rhs, self.free[k], costly=False)
            except _CostlyPivot:
                del self.divisors[mark:]
            found = self._project(k, rhs)
            if found is not None:
                return found
        return self._solve(system, rhs, self.free[k])

    def _shifted(self, k: int) -> list[Element]:
        """The coefficients of det(lambda - (K - k)) = p(lambda + k), lambda^0 first
        (Taylor shift of the characteristic polynomial)."""
        reduce, shifted = self.algebra.reduce, list(self._charpoly)
        n = len(shifted) - 1
        for i in range(n):
            for j in reversed(range(i, n)):
                shifted[j] = reduce(shifted[j] + shifted[j + 1] * k)
        return shifted

    def _times(self, k: int, y: list[Element]) -> list[Element]:
        """(K - k) y, unreduced."""
        n = len(y)
        return [
            sum((self.matrix[i][c] * y[c] for c in range(n)), self.algebra.zero) - k * y[i]
            for i in range(n)
        ]

    def _horner(self, k: int, d: list[Element], b: list[Element]) -> list[Element]:
        """sum_j d_j (K - k)^j b."""
        reduce = self.algebra.reduce
        y = [reduce(d[-1] * v) for v in b]
        for c in reversed(d[:-1]):
            y = [reduce(a + c * v) for a, v in zip(self._times(k, y), b, strict=True)]
        return y

    def _invert(self, k: int, rhs: list[Element]) -> list[Element]:
        """(K - k)^(-1) rhs by Cayley-Hamilton: with p(lambda + k) = sum_j d_j lambda^j,
        (K - k)^(-1) = -(1/d_0) sum_{j>=1} d_j (K - k)^(j-1). The one division is by
        d_0 = p(k), a number wherever the exponents are; products in F stay polynomials
        in u."""
        d = self._shifted(k)
        if d[0].is_zero:  # pragma: no cover - resonances are exact
            raise ArithmeticError(f"K - {k} is singular but {k} is not a resonance")
        scale = -self.inverse(d[0])
        return [self.algebra.reduce(scale * v) for v in self._horner(k, d[1:], rhs)]

    def _project(self, r: int, rhs: list[Element]):
        """The step at resonance r (multiplicity m) without pivots: p(lambda + r) =
        lambda^m q(lambda), q(0) = d_m != 0, and Q = q(K - r). Where (K - r) Q = 0 (K - r
        diagonalizable on its kernel) Q/d_m is the projection onto the kernel along the
        image, so the equations are solvable exactly when Q rhs = 0 (the conditions, on m
        rows of Q that are independent), a particular solution is
        -(1/d_m) sum_{j>=1} d_(m+j) (K - r)^(j-1) rhs, and m independent columns of Q
        span the kernel (the free coefficients). None where (K - r) Q != 0 (elimination
        then counts the free coefficients) or the multiplicity is not m."""
        algebra, n, m = self.algebra, len(rhs), self.resonances[r]
        d = self._shifted(r)
        if any(not c.is_zero for c in d[:m]) or d[m].is_zero:
            return None
        column = functools.partial(self._column, r, d[m:])
        minor = _independent(column, n, m, algebra)
        if minor is None:  # pragma: no cover - Q has rank m
            return None
        rows, chosen, det, columns = minor
        # Q's image is spanned by the chosen columns: K - r kills it exactly when it is
        # diagonalizable on its kernel
        if any(not algebra.reduce(v).is_zero for j in chosen for v in self._times(r, columns[j])):
            return None
        self.divisors.append(det)
        image = self._horner(r, d[m:], rhs)  # Q rhs
        scale = -self.inverse(d[m])
        solution = [algebra.reduce(scale * v) for v in self._horner(r, d[m + 1 :], rhs)]
        symbols = self.free[r][:m]
        for symbol, j in zip(symbols, chosen, strict=True):
            f = algebra.variable(symbol)
            solution = [
                algebra.reduce(a + f * q) for a, q in zip(solution, columns[j], strict=True)
            ]
        return solution, [image[i] for i in rows], symbols

    def _column(self, r: int, q: list[Element], j: int) -> list[Element]:
        """The j-th column of q(K - r)."""
        n = len(self.matrix)
        unit = [self.algebra.one if i == j else self.algebra.zero for i in range(n)]
        return self._horner(r, q, unit)

    @functools.cached_property
    def _charpoly(self) -> list[Element]:
        """det(lambda - K) over F, its coefficients from lambda^0 up (Berkowitz)."""
        return berkowitz(self.matrix, self.algebra, self.algebra.reduce)[::-1]

    def _names(self) -> dict[sp.Symbol, sp.Symbol]:
        """f{r} for the one free coefficient of a simple resonance (f{r}_j otherwise)."""
        taken = {str(s) for s in (*self.split.variables, *self.split.parameters)}
        taken |= {str(s) for symbols in self.free.values() for s in symbols}
        return {
            symbols[0]: _fresh(f"f{r}", taken)
            for r, symbols in self.free.items()
            if self._used.get(r, 0) == 1
        }

    def _coefficient(self, i: int, k: int) -> Element:
        """The order-k coefficient of V_i with a_k = 0 (the current a's)."""
        total = self.algebra.zero
        for coeff, factors, delay in self.terms[i]:
            if k - delay >= 0:
                total += coeff * self._product(factors, k - delay)
        return self.algebra.reduce(total)

    def _product(self, factors: tuple[int, ...], q: int) -> Element:
        """The order-q coefficient of prod X_j over ``factors``; orders below the current
        one are kept (they no longer change), the current one is recomputed."""
        if not factors:
            return self.algebra.one if q == 0 else self.algebra.zero
        if len(factors) == 1:
            return self._series(factors[0], q)
        known = self.memo.setdefault(factors, [])
        if q < len(known):
            return known[q]
        head, last = factors[:-1], factors[-1]
        value = self.algebra.zero
        for p in range(q + 1):
            value += self._product(head, p) * self._series(last, q - p)
        value = self.algebra.reduce(value)
        if q == len(known) and q < len(self.a[0]) - 1:
            known.append(value)
        return value

    def _series(self, j: int, q: int) -> Element:
        """The order-q coefficient of X_j (j < n), or of 1/D_d(X) for j = n + d: with
        S = D_d(X) (D_d weighted-homogeneous, so S = t^(deg) D_d(x) is a power series),
        1/S has s_0 = 1/S_0 and s_q = -s_0 sum_{p=1..q} S_p s_(q-p). Kept like
        ``_product``'s orders (the current one is recomputed)."""
        n = len(self.a)
        if j < n:
            return self.a[j][q]
        known = self.memo.setdefault((j,), [])
        if q < len(known):
            return known[q]
        if q == 0:
            value = self.inverses[j - n]
        else:
            total = self.algebra.zero
            for p in range(1, q + 1):
                total += self._denominator(j - n, p) * self._series(j, q - p)
            value = self.algebra.reduce(-(self.inverses[j - n] * self.algebra.reduce(total)))
        if q == len(known) and q < len(self.a[0]) - 1:
            known.append(value)
        return value

    def _denominator(self, d: int, q: int) -> Element:
        """The order-q coefficient of D_d(X) (a sum of products of the X's)."""
        total = self.algebra.zero
        for coeff, factors in self.denominators[d]:
            total += coeff * self._product(factors, q)
        return self.algebra.reduce(total)

    def _solve(self, system, rhs, symbols, costly: bool = True):
        """Solve system a = rhs over F (the system's entries lie in F, the right side in
        F[free]) by Gauss-Jordan elimination: the solution (``symbols`` for the columns
        without a pivot), the left-over rows (the compatibility conditions), the symbols
        used. ``costly=False``: raise ``_CostlyPivot`` rather than invert a pivot that is
        not in k."""
        n = len(system)
        rows = [list(row) + [rhs[i]] for i, row in enumerate(system)]
        pivots: list[int] = []
        r = 0
        for col in range(n):
            pivot = next((i for i in range(r, n) if not rows[i][col].is_zero), None)
            if pivot is None:
                continue
            rows[r], rows[pivot] = rows[pivot], rows[r]
            if not costly and not self.algebra.in_ground(rows[r][col]):
                raise _CostlyPivot
            inv = self.inverse(rows[r][col])
            reduce = self.algebra.reduce
            rows[r] = [reduce(e * inv) for e in rows[r]]
            for i in range(n):
                if i != r and not rows[i][col].is_zero:
                    factor = rows[i][col]
                    rows[i] = [
                        reduce(a - factor * b) for a, b in zip(rows[i], rows[r], strict=True)
                    ]
            pivots.append(col)
            r += 1
        conditions = [rows[i][n] for i in range(r, n)]
        free_columns = [c for c in range(n) if c not in pivots]
        symbols = symbols[: len(free_columns)]
        values = dict(zip(free_columns, (self.algebra.variable(s) for s in symbols), strict=True))
        for i, col in enumerate(pivots):
            value = rows[i][n]
            for c, symbol in values.items():
                value -= rows[i][c] * symbol
            values[col] = self.algebra.reduce(value)
        return [values[c] for c in range(n)], conditions, symbols


class _CostlyPivot(Exception):
    """Elimination met a pivot outside k (``_Recursion._solve`` with ``costly=False``)."""


def _independent(column, n: int, m: int, algebra: IntegralAlgebra):
    """The first non-zero m x m minor of an n x n matrix over F of rank m whose columns
    ``column(j)`` gives (computed only as needed; exact zero tests in F): its rows, its
    columns, its value and the columns computed; None if every one is zero."""
    columns: dict[int, list[Element]] = {}
    for chosen in itertools.combinations(range(n), m):
        for j in chosen:
            if j not in columns:
                columns[j] = column(j)
        if any(all(v.is_zero for v in columns[j]) for j in chosen):
            continue
        for rows in itertools.combinations(range(n), m):
            det = _determinant([[columns[j][i] for j in chosen] for i in rows], algebra)
            if not det.is_zero:
                return rows, chosen, det, columns
    return None


def _determinant(matrix, algebra: IntegralAlgebra) -> Element:
    """A small determinant over F by expansion along the first row."""
    if len(matrix) == 1:
        return matrix[0][0]
    total = algebra.zero
    for j, entry in enumerate(matrix[0]):
        if entry.is_zero:
            continue
        minor = [row[:j] + row[j + 1 :] for row in matrix[1:]]
        term = entry * _determinant(minor, algebra)
        total = total + term if j % 2 == 0 else total - term
    return algebra.reduce(total)


def _fresh(name: str, taken: set[str]) -> sp.Symbol:
    while name in taken:
        name += "_"
    taken.add(name)
    return sp.Symbol(name)
