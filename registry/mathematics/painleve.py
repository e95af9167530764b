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
condition is zero exactly when it is zero in F.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp
from sympy.polys.orderings import lex
from sympy.polys.rings import PolyElement, PolyRing

from . import algebraic
from .prime_components import Component
from .weighted import WeightedField


@dataclass(frozen=True)
class Resonance:
    """The step at one resonance r of multiplicity m: the free coefficients a_r brings
    (``free``) and the compatibility conditions that do not vanish (``conditions``, in
    the free coefficients of earlier resonances, the parameters and the component's u;
    empty when they all hold). Fewer than m free coefficients means K - r is not
    diagonalizable: the general solution then needs t^r log t as well."""

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
        if self.missing:
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

    elements: tuple[tuple[PolyElement, ...], ...]
    names: Mapping[sp.Symbol, sp.Symbol]
    resonances: tuple[Resonance, ...]

    @functools.cached_property
    def coefficients(self) -> tuple[tuple[sp.Expr, ...], ...]:
        return tuple(
            tuple(sp.expand(a.as_expr()).xreplace(self.names) for a in order)
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
        self.u = component.symbol
        symbols = [s for r in resonances for s in self.free[r]]
        self.ring = PolyRing([self.u, *symbols], component.domain, lex)
        self.ext = algebraic.Extension(component.symbol, component.minimal)
        self.g = self._lift(component.minimal)
        self.a = [[self._lift(component.evaluate(x))] for x in split.variables]
        self.matrix = [
            [self._lift(component.evaluate(matrix[i, j])) for j in range(n)] for i in range(n)
        ]
        self.terms = self._terms()
        self.memo: dict[tuple[int, ...], list[PolyElement]] = {}
        self._used: dict[int, int] = {}  # free coefficients brought by each resonance

    def element(self, expr: sp.Expr) -> PolyElement:
        """A rational function of u (coefficients in k) as a reduced element of F."""
        return self._lift(self.ext.element(expr))

    def _lift(self, value: sp.Poly) -> PolyElement:
        """A Poly in u over k as an element of the ring k[u, free] (no expressions)."""
        zeros = (0,) * (self.ring.ngens - 1)
        return self.ring.from_dict(
            {(e, *zeros): c for (e,), c in value.as_dict(native=True).items()}
        )

    def inverse(self, value: PolyElement) -> PolyElement:
        """1/value in F, for an element without free coefficients."""
        k = self.ring.domain
        poly = sp.Poly.from_dict({(m[0],): c for m, c in value.items()}, self.u, domain=k)
        return self._lift(self.ext.inverse(poly))

    def _terms(self) -> list[list[tuple[PolyElement, tuple[int, ...], int]]]:
        """Per component: (coefficient, monomial as a tuple of variable indices, delay
        1 - shift) for every term of the whole field."""
        variables = self.split.variables
        terms: list[list[tuple[PolyElement, tuple[int, ...], int]]] = [[] for _ in variables]
        for shift, part in self.split.parts.items():
            for i, expr in enumerate(part):
                if expr == 0:
                    continue
                for monomial, coeff in sp.Poly(expr, *variables).terms():
                    factors = tuple(j for j, m in enumerate(monomial) for _ in range(m))
                    terms[i].append((self.element(coeff), factors, 1 - shift))
        return terms

    def run(self, last: int) -> LaurentSeries:
        steps = []
        n = len(self.split.variables)
        for k in range(1, last + 1):
            for column in self.a:
                column.append(self.ring.zero)
            rest = [self._coefficient(i, k) for i in range(n)]
            system = [
                [self.matrix[i][j] - (k if i == j else 0) for j in range(n)] for i in range(n)
            ]
            symbols = self.free.get(k, [])
            solution, conditions, free = self._solve(system, [-r for r in rest], symbols)
            if free and k not in self.resonances:  # pragma: no cover - resonances are exact
                raise ArithmeticError(f"K - {k} is singular but {k} is not a resonance")
            self._used[k] = len(free)
            for i in range(n):
                self.a[i][k] = solution[i]
            if k in self.resonances:
                failing = tuple(sp.expand(c.as_expr()) for c in conditions if not c.is_zero)
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
        return LaurentSeries(elements, names, tuple(steps))

    def _names(self) -> dict[sp.Symbol, sp.Symbol]:
        """f{r} for the one free coefficient of a simple resonance (f{r}_j otherwise)."""
        taken = {str(s) for s in (*self.split.variables, *self.split.parameters)}
        taken |= {str(s) for symbols in self.free.values() for s in symbols}
        return {
            symbols[0]: _fresh(f"f{r}", taken)
            for r, symbols in self.free.items()
            if self._used.get(r, 0) == 1
        }

    def _coefficient(self, i: int, k: int) -> PolyElement:
        """The order-k coefficient of V_i with a_k = 0 (the current a's)."""
        total = self.ring.zero
        for coeff, factors, delay in self.terms[i]:
            if k - delay >= 0:
                total += coeff * self._product(factors, k - delay)
        return total.rem(self.g)

    def _product(self, factors: tuple[int, ...], q: int) -> PolyElement:
        """The order-q coefficient of prod X_j over ``factors``; orders below the current
        one are kept (they no longer change), the current one is recomputed."""
        if not factors:
            return self.ring.one if q == 0 else self.ring.zero
        if len(factors) == 1:
            return self.a[factors[0]][q]
        known = self.memo.setdefault(factors, [])
        if q < len(known):
            return known[q]
        head, last = factors[:-1], factors[-1]
        value = self.ring.zero
        for p in range(q + 1):
            value += self._product(head, p) * self.a[last][q - p]
        value = value.rem(self.g)
        if q == len(known) and q < len(self.a[0]) - 1:
            known.append(value)
        return value

    def _solve(self, system, rhs, symbols):
        """Solve system a = rhs over F (the system's entries lie in F, the right side in
        F[free]) by Gauss-Jordan elimination: the solution (``symbols`` for the columns
        without a pivot), the left-over rows (the compatibility conditions), the symbols
        used."""
        n = len(system)
        rows = [list(row) + [rhs[i]] for i, row in enumerate(system)]
        pivots: list[int] = []
        r = 0
        for col in range(n):
            pivot = next((i for i in range(r, n) if not rows[i][col].is_zero), None)
            if pivot is None:
                continue
            rows[r], rows[pivot] = rows[pivot], rows[r]
            inv = self.inverse(rows[r][col])
            rows[r] = [(e * inv).rem(self.g) for e in rows[r]]
            for i in range(n):
                if i != r and not rows[i][col].is_zero:
                    factor = rows[i][col]
                    rows[i] = [
                        (a - factor * b).rem(self.g) for a, b in zip(rows[i], rows[r], strict=True)
                    ]
            pivots.append(col)
            r += 1
        conditions = [rows[i][n] for i in range(r, n)]
        free_columns = [c for c in range(n) if c not in pivots]
        symbols = symbols[: len(free_columns)]
        values = dict(zip(free_columns, (self.ring.from_expr(s) for s in symbols), strict=True))
        for i, col in enumerate(pivots):
            value = rows[i][n]
            for c, symbol in values.items():
                value -= rows[i][c] * symbol
            values[col] = value.rem(self.g)
        return [values[c] for c in range(n)], conditions, symbols


def _fresh(name: str, taken: set[str]) -> sp.Symbol:
    while name in taken:
        name += "_"
    taken.add(name)
    return sp.Symbol(name)
