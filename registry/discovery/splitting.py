"""Where a parametric matrix loses rank, by case splitting on its pivots.

A matrix B with entries in Z[p, q] (p the free parameters, q those that stay symbolic
and generic) has rank ``need`` at the generic point; the question is the set of p where
its rank is lower. Fraction-free elimination answers it branch by branch, the way a
classification by hand (or CRACK) proceeds:

* a *unit* is a polynomial that cannot vanish where the branch lives: a constant, a
  polynomial in q alone, a monomial in parameters the assumptions keep nonzero, a
  polynomial of one sign there (b + c with b, c positive), or a factor the branch
  assumed nonzero. A unit entry is a pivot: the other rows are multiplied by units
  only, and each row is divided by the units it has in common, so that
  rank B = pivots + rank of the rest at *every* point of the branch;
* where no entry is a unit, the branch splits on an irreducible factor h of an entry:
  h != 0 (h becomes a unit) or h = 0, solved for a free parameter v it is linear in
  (h = h1 v + h0; v = -h0/h1 where h1 != 0, and h1 = h0 = 0 as a branch of its own),
  so that every branch is a rational parametrisation of its points. A parameter that
  may vanish (z0 real) is split on in the same way: z0 = 0 or z0 != 0, and each point
  of parameter space lies in exactly one branch;
* an irreducible h nonlinear in every free parameter is kept as an equation of the
  branch (*pending*), with the others met on the way: the branch then lives on the
  variety they define, entries divisible by one of them are zero there, and a factor
  split on that is one of them is met again as zero;
* a branch whose rank falls short of ``need`` (fewer rows than needed, or a rank
  modulo a prime at a random point of it below it) is a *candidate set*: the values
  of the solved parameters as rational functions of the others, and, where equations
  are pending, those equations (an ``AlgebraicSet``, decomposed into its components
  by ``components``). A branch whose rank
  modulo a prime reaches ``need`` has that generic rank exactly (a modular rank at a
  point bounds the rank over Q(p, q) from below), so its independent parts (connected
  components of the rest) are split on separately, each with its own rank.

The candidate sets hold every point where the rank drops (their union is the rank-drop
locus, closed under taking closures); they are candidates only, each confirmed by an
exact search. What the splitting cannot solve rationally (equations of degree >= 2 in
every free parameter that remains after the others are solved) is returned as an
algebraic set: its solved parameters, its equations and the factors assumed nonzero
on it, decided by the search at the points of its components; only a matrix that needs
more than ``MAX_BRANCHES`` branches is left undecided.

Branches are independent: with a ``spread`` (the search's executor, when it has more
than one worker), a matrix still open after ``SPREAD_AFTER`` branches has its
shallowest branches opened until ``SPREAD`` are (the deepest part of the tree stays
with the earliest branches), and these are explored by other processes, each with a
generator of its own; their candidate sets are merged in the order one process would
have found them.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, cast

import flint
import sympy as sp
from sympy.polys.domains import QQ, ZZ
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rootisolation import dup_count_real_roots

from ..mathematics.factoring import factor_mpoly

#: The prime of the modular rank checks (below 2**63, as FLINT's nmod_mat needs).
PRIME = (1 << 61) - 1
#: Most branches one matrix may split into before the rest is called undecided.
MAX_BRANCHES = 20_000
#: Most entries each memo below keeps before it starts afresh (bounds the memory).
MEMO_SIZE = 200_000

#: How many open branches the splitting hands to other processes at once (``spread``),
#: once it has explored SPREAD_AFTER here (a small matrix is split before a call returns).
SPREAD = 24
SPREAD_AFTER = 50

Poly = flint.fmpz_mpoly
Row = dict[int, Poly]


@dataclass(frozen=True)
class Region:
    """The parameters and what the assumptions say of them: ``names`` of the ring's
    variables, the first ``free`` of them free (the rest symbolic), and the indices
    of those declared positive and of those declared nonzero (positive included)."""

    names: tuple[str, ...]
    free: int
    positive: frozenset[int] = frozenset()
    nonzero: frozenset[int] = frozenset()

    @property
    def context(self) -> flint.fmpz_mpoly_ctx:
        return flint.fmpz_mpoly_ctx.get(self.names, "lex")


@dataclass(frozen=True)
class Step:
    """One solved equation: ``variable`` = numerator / denominator (both free of it)."""

    variable: int
    numerator: Poly
    denominator: Poly


@dataclass
class Branch:
    """A part of parameter space and the matrix on it: the rows left after the pivots
    taken, the rank still ``need``-ed there, the factors assumed nonzero, the solved
    parameters (in order), and the equations kept unsolved (each irreducible and
    nonlinear in every free one): the branch lies on their common zeros."""

    rows: list[Row]
    need: int
    units: dict[str, Poly] = field(default_factory=dict)
    steps: tuple[Step, ...] = ()
    pending: tuple[Poly, ...] = ()


@dataclass(frozen=True)
class AlgebraicSet:
    """A candidate set the splitting could not solve rationally: the solved parameters'
    ``values`` (rational functions of the others), the ``equations`` (= 0) the others
    satisfy there, and the ``units``: polynomials assumed nonzero on it (a component on
    which one vanishes lies in another branch)."""

    values: dict[sp.Symbol, sp.Expr]
    equations: tuple[sp.Expr, ...]
    units: tuple[sp.Expr, ...] = ()

    def text(self) -> str:
        """Its equations as a search states them: ``y0 = 0, 3*x0**2 - c = 0``."""
        parts = [f"{s} = {sp.sstr(e)}" for s, e in self.values.items()]
        return ", ".join(parts + [f"{sp.sstr(e)} = 0" for e in self.equations])


@dataclass
class Split:
    """The outcome: candidate sets (each the solved parameters' values as sympy
    expressions in the others), algebraic candidate sets (``AlgebraicSet``), and
    undecided sets (their equations, as text)."""

    sets: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)
    branches: int = 0
    algebraic: list[AlgebraicSet] = field(default_factory=list)


class _Splitter:
    def __init__(self, region: Region, rnd: random.Random, limit: int = MAX_BRANCHES):
        self.limit = limit
        self.region = region
        self.ctx = region.context
        self.rnd = rnd
        self.nowhere_zero = _memo(_NOWHERE_ZERO, region)
        self.factored: dict[str, tuple] = {}
        self.out = Split()
        self.symbols = [sp.Symbol(n) for n in region.names]

    # ------------------------------------------------------------- polynomials

    def factor(self, poly: Poly) -> list[Poly]:
        """The distinct irreducible factors (primitive, positive leading coefficient)."""
        memo = _memo(_FACTORS, poly.context())
        key = str(poly)
        hit = memo.get(key)
        if hit is None:
            hit = [f for f, _ in factor_mpoly(poly)[1]]
            memo[key] = hit
        return hit

    def is_unit(self, h: Poly, branch: Branch) -> bool:
        """Whether the irreducible ``h`` cannot vanish on the branch: a constant, a factor
        assumed nonzero there, a condition on the symbolic parameters alone (which stay
        generic), or a polynomial with no real zero where the assumptions hold."""
        if h.is_constant() or str(h) in branch.units:
            return True
        degrees = h.degrees()
        if not any(degrees[: self.region.free]):
            return True
        key = str(h)
        hit = self.nowhere_zero.get(key)
        if hit is None:
            hit = self._one_signed(h) or self._no_real_point(h)
            self.nowhere_zero[key] = hit
        return hit

    def _one_signed(self, h: Poly) -> bool:
        """h > 0 or h < 0 wherever the assumptions hold: coefficients of one sign, a
        variable of odd power only if positive, and one term that cannot vanish."""
        positive, nonzero = self.region.positive, self.region.nonzero
        signs = set()
        strict = False
        for exps, c in h.terms():
            signs.add(c > 0)
            if any(e % 2 and i not in positive for i, e in enumerate(exps)):
                return False
            if all(not e or i in positive or i in nonzero for i, e in enumerate(exps)):
                strict = True
        return len(signs) == 1 and strict

    def unit_entry(self, poly: Poly, branch: Branch) -> bool:
        return all(self.is_unit(f, branch) for f in self.factor(poly))

    def unit_part(self, poly: Poly, branch: Branch) -> Poly:
        """The product of the unit factors of ``poly`` (with its content). A row's gcd
        recurs in branch after branch: its factorization is computed once."""
        part = self.ctx.constant(1)
        key = str(poly)
        hit = self.factored.get(key)
        if hit is None:
            hit = self.factored[key] = factor_mpoly(poly)
        content, factors = hit
        part *= content
        for f, e in factors:
            if self.is_unit(f, branch):
                part *= f**e
        return part

    # ---------------------------------------------------------------- matrices

    def normalise(self, branch: Branch) -> None:
        """Zero entries dropped (multiples of a pending equation too), each row
        divided by the units its entries share, empty rows dropped."""
        rows = []
        for row in branch.rows:
            row = {k: v for k, v in row.items() if not v.is_zero()}
            if branch.pending:
                row = {
                    k: v for k, v in row.items() if not any(_divides(h, v) for h in branch.pending)
                }
            if not row:
                continue
            first, *others = row.values()
            g = first
            for v in others:
                if g.is_one():
                    break
                g = g.gcd(v)
            if not g.is_one() and not g.is_constant():
                unit = self.unit_part(g, branch)
                if not unit.is_one() and not unit.is_constant():
                    row = {k: v / unit for k, v in row.items()}
            elif g.is_constant() and abs(int(g.leading_coefficient())) > 1:
                c = int(g.leading_coefficient())
                row = {k: v / c for k, v in row.items()}
            rows.append(row)
        branch.rows = rows

    def unit_pivot(self, branch: Branch) -> tuple[int, int] | None:
        """A unit entry (row, column), the sparsest first (Markowitz: fewest entries
        in its row and column, then fewest terms)."""
        counts: dict[int, int] = {}
        for row in branch.rows:
            for k in row:
                counts[k] = counts.get(k, 0) + 1
        best, choice = None, None
        for i, row in enumerate(branch.rows):
            for k, v in row.items():
                cost = ((len(row) - 1) * (counts[k] - 1), len(v))
                if (best is None or cost < best) and self.unit_entry(v, branch):
                    best, choice = cost, (i, k)
        return choice

    def eliminate(self, branch: Branch, i: int, k: int) -> None:
        """Fraction-free elimination on the unit entry (i, k): every other row is
        multiplied by a unit (the pivot over its gcd with the row's entry)."""
        pivot_row = branch.rows.pop(i)
        pivot = pivot_row.pop(k)
        for row in branch.rows:
            a = row.pop(k, None)
            if a is None:
                continue
            g = pivot.gcd(a)
            p, q = pivot / g, a / g
            for j in set(row) | set(pivot_row):
                value = p * row.get(j, self.ctx.constant(0)) - q * pivot_row.get(
                    j, self.ctx.constant(0)
                )
                row[j] = value
        branch.need -= 1

    def rank_mod(self, rows: Sequence[Row]) -> int:
        """The rank at a random point modulo PRIME: a lower bound of the generic rank."""
        cols = sorted({k for r in rows for k in r})
        if not rows or not cols:
            return 0
        point = [self.rnd.randrange(1, PRIME) for _ in self.region.names]
        index = {k: j for j, k in enumerate(cols)}
        entries = [0] * (len(rows) * len(cols))
        for i, r in enumerate(rows):
            for k, v in r.items():
                entries[i * len(cols) + index[k]] = int(v(*point)) % PRIME
        return flint.nmod_mat(len(rows), len(cols), entries, PRIME).rank()

    # --------------------------------------------------------------- splitting

    def run(self, stack: list[Branch], spread: Spread | None = None) -> Split:
        """Explore the branches (the last first, each with all its sub-branches before the
        next): here, or by ``spread`` once ``SPREAD_AFTER`` were explored here and more
        than one is open (module docstring)."""
        while stack:
            if spread is not None and len(stack) > 1 and self.out.branches >= SPREAD_AFTER:
                self.widen(stack)
                self.spread(stack[::-1], spread)
                break
            self.out.branches += 1
            if self.out.branches > self.limit:
                self.out.undecided.append(
                    f"the rank-drop locus of a block (more than {MAX_BRANCHES} branches)"
                )
                break
            stack.extend(self.explore(stack.pop()))
        return self.out

    def widen(self, stack: list[Branch]) -> None:
        """Open branches until ``SPREAD`` are: the shallowest (fewest splits above it:
        solved parameters and factors assumed nonzero) explored first, its place in the
        stack taken by its sub-branches, in order."""
        while stack and len(stack) < SPREAD and self.out.branches < self.limit:
            i = min(range(len(stack)), key=lambda k: len(stack[k].steps) + len(stack[k].units))
            self.out.branches += 1
            stack[i : i + 1] = self.explore(stack[i])

    def spread(self, branches: list[Branch], spread: Spread) -> None:
        """Each branch explored elsewhere (``_explored``), the outcomes merged in order."""
        work = [
            (self.region, self.rnd.randrange(2**62), _packed(b), self.limit - self.out.branches)
            for b in branches
        ]
        for found in spread(_explored, work):
            if isinstance(found, str):  # the call failed: that part is not decided
                self.out.undecided.append(f"a part of the rank-drop locus of a block ({found})")
                continue
            self.out.branches += found.branches
            self.out.sets.extend(x for x in found.sets if x not in self.out.sets)
            self.out.algebraic.extend(x for x in found.algebraic if x not in self.out.algebraic)
            self.out.undecided.extend(x for x in found.undecided if x not in self.out.undecided)

    def explore(self, branch: Branch) -> list[Branch]:
        """Eliminate on units; then either the branch is decided (full rank, or a
        candidate set) or it splits: into independent parts, or on a factor."""
        while True:
            self.normalise(branch)
            if branch.need <= 0:
                return []
            columns = {k for r in branch.rows for k in r}
            if len(branch.rows) < branch.need or len(columns) < branch.need:
                self.emit(branch)
                return []
            pivot = self.unit_pivot(branch)
            if pivot is None:
                break
            self.eliminate(branch, *pivot)
        if not branch.pending:
            if self.rank_mod(branch.rows) < branch.need:
                self.emit(branch)
                return []
            parts = _components(branch.rows)
            if len(parts) > 1:
                return [
                    replace(branch, rows=part, need=self.rank_mod(part), units=dict(branch.units))
                    for part in parts
                ]
        h = self.splitting_factor(branch)
        nonzero = replace(branch, rows=[dict(r) for r in branch.rows], units=dict(branch.units))
        nonzero.units[str(h)] = h
        return [nonzero, *self.impose(branch, [h])]

    def splitting_factor(self, branch: Branch) -> Poly:
        """The simplest non-unit irreducible factor of an entry (fewest terms, lowest
        degree): z0 before b - c before anything longer."""
        best, choice = None, None
        for row in branch.rows:
            for v in row.values():
                for f in self.factor(v):
                    if self.is_unit(f, branch):
                        continue
                    degrees = f.degrees()[: self.region.free]
                    cost = (1 not in degrees, len(f), f.total_degree(), str(f))
                    if best is None or cost < best:
                        best, choice = cost, f
        assert choice is not None  # no unit entry, so some factor is not a unit
        return choice

    # --------------------------------------------------------------- equations

    def impose(self, branch: Branch, equations: list[Poly]) -> list[Branch]:
        """The branch restricted to the common zeros of ``equations``: a list of
        branches (one per way of satisfying them), each solved rationally where it
        can be."""
        if not equations:
            return [branch]
        first, rest = equations[0], equations[1:]
        if first.is_zero():
            return self.impose(branch, rest)
        factors = [f for f in self.factor(first) if not self.is_unit(f, branch)]
        out = []
        for n, h in enumerate(factors):
            # h = 0 and the factors before it nonzero: the branches do not overlap
            sub = replace(branch, rows=[dict(r) for r in branch.rows], units=dict(branch.units))
            for g in factors[:n]:
                sub.units[str(g)] = g
            out.extend(self.solve(sub, h, rest))
        return out

    def solve(self, branch: Branch, h: Poly, rest: list[Poly]) -> list[Branch]:
        """h = 0 on the branch (h irreducible, not a unit), then ``rest``."""
        free = self.region.free
        degrees = h.degrees()
        linear = [v for v in range(free) if degrees[v] == 1]
        if not linear:
            if any(_divides(g, h) for g in branch.pending):  # implied already
                return self.impose(branch, rest)
            if any(self._inconsistent(branch, g, h) for g in branch.pending):
                return []
            if len(branch.pending) == 1 and self._full_at_points(branch, [*branch.pending, h]):
                return []
            branch.pending = (*branch.pending, h)
            return self.impose(branch, rest)
        options = []
        for v in linear:
            parts = _coefficients(h, v)
            lead = parts[1]  # h is linear in v
            unit = self.unit_entry(lead, branch)
            # a parameter with no assumption first: the others keep theirs
            kept = v in self.region.nonzero
            options.append((not lead.is_constant(), not unit, kept, len(lead), len(h), v))
        *_, v = min(options)
        parts = _coefficients(h, v)
        lead, tail = parts[1], parts.get(0, self.ctx.constant(0))
        out = []
        if not self.unit_entry(lead, branch):  # h1 = h0 = 0 as a branch of its own
            zero = replace(branch, rows=[dict(r) for r in branch.rows], units=dict(branch.units))
            out.extend(self.impose(zero, [lead, tail, *rest]))
            for f in self.factor(lead):
                if not self.is_unit(f, branch):
                    branch.units[str(f)] = f
        for solved in self.substitute(branch, v, -tail, lead):
            out.extend(self.impose(solved, rest))
        return out

    def substitute(self, branch: Branch, v: int, numer: Poly, denom: Poly) -> list[Branch]:
        """The branch on v = numer/denom (denom a unit there): none where that
        contradicts it (a factor assumed nonzero vanishes, or a positive parameter
        would be negative), several where the pending equation splits there."""
        if v in self.region.positive and not self._may_be_positive(numer, denom):
            return []
        rows = []
        for row in branch.rows:
            top = max(r.degrees()[v] for r in row.values())
            rows.append({k: _put(e, v, numer, denom, top) for k, e in row.items()})
        units: dict[str, Poly] = {}
        for f in branch.units.values():
            value = _put(f, v, numer, denom, f.degrees()[v])
            if value.is_zero():
                return []
            for g in self.factor(value):
                if not g.is_constant():
                    units[str(g)] = g
        for g in self.factor(denom):
            units[str(g)] = g
        new = Branch(rows, branch.need, units, (*branch.steps, Step(v, numer, denom)))
        if not branch.pending:
            return [new]
        values = [_put(h, v, numer, denom, h.degrees()[v]) for h in branch.pending]
        return self.impose(new, values)

    def _may_be_positive(self, numer: Poly, denom: Poly) -> bool:
        """False when numer/denom is negative (or zero) wherever the assumptions hold."""
        if numer.is_zero():
            return False
        sign_n, sign_d = self._sign(numer), self._sign(denom)
        return sign_n is None or sign_d is None or sign_n == sign_d

    def _sign(self, poly: Poly) -> bool | None:
        """True (> 0), False (< 0) or None (either) wherever the assumptions hold: a
        polynomial of one sign, or a product of such factors and of even powers of
        polynomials in the symbolic parameters alone (generic, so nonzero): the
        discriminant -4 A^2 C^2 (A - C)^2 is negative."""
        if self._one_signed(poly):
            return next(iter(poly.terms()))[1] > 0
        if poly.is_zero():
            return None
        content, factors = factor_mpoly(poly)
        positive = content > 0
        for f, e in factors:
            if e % 2 == 0 and not any(f.degrees()[: self.region.free]):
                continue
            if not self._one_signed(f):
                return None
            if e % 2 and not next(iter(f.terms()))[1] > 0:
                positive = not positive
        return positive

    # ------------------------------------------------------------------ output

    def emit(self, branch: Branch) -> None:
        """A candidate set: the solved parameters' values (and the pending equations,
        as an algebraic set)."""
        if branch.pending:
            found = AlgebraicSet(
                self.values(branch),
                tuple(self.expr(h) for h in branch.pending),
                tuple(self.expr(u) for u in branch.units.values()),
            )
            if found not in self.out.algebraic:
                self.out.algebraic.append(found)
            return
        values = self.values(branch)
        if values not in self.out.sets:
            self.out.sets.append(values)

    def values(self, branch: Branch) -> dict[sp.Symbol, sp.Expr]:
        out: dict[sp.Symbol, sp.Expr] = {}
        for step in branch.steps:
            value = sp.cancel(self.expr(step.numerator) / self.expr(step.denominator))
            symbol = self.symbols[step.variable]
            out = {s: sp.cancel(e.xreplace({symbol: value})) for s, e in out.items()}
            out[symbol] = value
        return out

    def expr(self, poly: Poly) -> sp.Expr:
        return sp.Add(
            *(
                int(c) * sp.Mul(*(s ** int(e) for s, e in zip(self.symbols, exps, strict=True)))
                for exps, c in poly.terms()
            )
        )

    def _inconsistent(self, branch: Branch, h: Poly, g: Poly) -> bool:
        """Whether h = g = 0 has no point allowed by the assumptions, shown by their
        resultant in a parameter both contain: its factors are units on the branch or
        polynomials in one parameter with no allowed real root."""
        both = [i for i, (a, b) in enumerate(zip(h.degrees(), g.degrees(), strict=True)) if a and b]
        for i in sorted(both, key=lambda i: max(h.degrees()[i], g.degrees()[i])):
            r = h.resultant(g, self.region.names[i])
            if r.is_zero():
                continue
            if all(self.is_unit(f, branch) for f in self.factor(r)):
                return True
        return False

    def _full_at_points(self, branch: Branch, equations: list[Poly]) -> bool:
        """``_full_at_points_exactly``; False (undecided) where sympy cannot do it."""
        try:
            return self._full_at_points_exactly(branch, equations)
        except (NotImplementedError, ValueError, sp.PolynomialError, sp.CoercionFailed):
            return False  # sympy could not do the algebra: undecided, never assumed

    def _full_at_points_exactly(self, branch: Branch, equations: list[Poly]) -> bool:
        """Whether the rows keep the rank ``need`` at every allowed point of the finite
        set the equations define, decided exactly over each number field Q(alpha):
        the lex Groebner basis in shape position (x = f(t), r(t) = 0), one irreducible
        factor of r at a time (conjugate points have equal ranks). False when it
        cannot tell (not finite, not in shape position, symbolic parameters)."""
        used = sorted({i for e in equations for i, d in enumerate(e.degrees()) if d})
        rows_used = {
            i for r in branch.rows for v in r.values() for i, d in enumerate(v.degrees()) if d
        }
        if any(i >= self.region.free for i in set(used) | rows_used) or len(used) > 3:
            return False
        symbols = [self.symbols[i] for i in used]
        if rows_used - set(used):
            return False
        basis = sp.groebner([self.expr(e) for e in equations], *symbols, order="lex")
        t = symbols[-1]
        last = basis.exprs[-1]
        shape = {}
        for g in basis.exprs[:-1]:
            x = next((s for s in symbols[:-1] if sp.Poly(g, *symbols).degree(s) == 1), None)
            if x is None or x in shape or (g.free_symbols - {x, t}):
                return False
            shape[x] = sp.solve(g, x)[0]
        if last.free_symbols != {t} or len(shape) != len(symbols) - 1:
            return False
        for f, _ in sp.factor_list(last, t)[1]:
            roots = sp.Poly(f, t).real_roots()
            if not roots:
                continue
            alpha = roots[0]
            field = sp.QQ.algebraic_field(alpha)
            point = {t: alpha, **{x: e.subs(t, alpha) for x, e in shape.items()}}
            values = {s: field.from_sympy(v) for s, v in point.items()}
            if any(i in self.region.positive and not (point[self.symbols[i]] > 0) for i in used):
                continue
            if any(self._at(u, values, field) == field.zero for u in branch.units.values()):
                continue
            cols = sorted({k for r in branch.rows for k in r})
            dense = [
                [self._at(r[k], values, field) if k in r else field.zero for k in cols]
                for r in branch.rows
            ]
            rank = DomainMatrix(dense, (len(dense), len(cols)), field).rank()
            if rank < branch.need:
                return False
        return True

    def _at(self, poly: Poly, values: dict, field) -> object:
        """poly at the point ``values`` (symbols -> elements of ``field``)."""
        total = field.zero
        for exps, c in poly.terms():
            term = field.convert(int(c))
            for s, e in zip(self.symbols, exps, strict=True):
                if e:
                    term *= values[s] ** int(e)
            total += term
        return total

    def _no_real_point(self, poly: Poly) -> bool:
        """Whether an irreducible polynomial has no real zero where the assumptions hold:
        one in a single parameter by its real roots, one quadratic in a parameter (with a
        leading coefficient of one sign) by a discriminant negative everywhere. False
        when it cannot tell."""
        used = [i for i, d in enumerate(poly.degrees()) if d]
        if len(used) == 1:
            (i,) = used
            return not _real_roots_allowed(
                poly, i, i in self.region.positive, i in self.region.nonzero
            )
        for i in used:
            if poly.degrees()[i] != 2:
                continue
            parts = _coefficients(poly, i)
            a, b = parts[2], parts.get(1, self.ctx.constant(0))
            c = parts.get(0, self.ctx.constant(0))
            if self._sign(a) is None:
                continue
            if self._sign(b * b - 4 * a * c) is False:
                return True
        return False


#: Factorisations (by the polynomials' ring) and nowhere-zero decisions (by the region,
#: whose assumptions they depend on), shared by every block of a search: the blocks of
#: one ansatz meet the same factors again and again.
_FACTORS: dict[flint.fmpz_mpoly_ctx, dict[str, list[Poly]]] = {}
_NOWHERE_ZERO: dict[Region, dict[str, bool]] = {}


def _memo(store: dict, key) -> dict:
    """The memo of ``key`` in ``store``, emptied once it holds MEMO_SIZE entries."""
    memo = store.setdefault(key, {})
    if len(memo) >= MEMO_SIZE:
        memo.clear()
    return memo


def _real_roots_allowed(poly: Poly, i: int, positive: bool, nonzero: bool) -> int:
    """How many real roots the irreducible ``poly``, a polynomial in its variable ``i``
    alone, has where the assumptions allow them (x > 0 if ``positive``, x != 0 if
    ``nonzero``), from its integer coefficients (no expressions built). Being
    irreducible, its roots are simple and 0 is one only for the polynomial c x.

    FLINT isolates the roots in certified balls, the real ones with an imaginary part
    exactly 0; a real root whose ball meets 0 (sign not certified) falls back to
    Sturm sequences, which are exact but some 30 times slower."""
    coeffs: dict[int, int] = {}
    for exps, c in poly.terms():
        coeffs[int(exps[i])] = int(c)
    degree = max(coeffs)
    if degree == 1:
        root = QQ(-coeffs.get(0, 0), coeffs[1])
        return int(not ((positive and root <= 0) or (nonzero and root == 0)))
    ascending = [coeffs.get(k, 0) for k in range(degree + 1)]
    # (root ball, multiplicity) pairs; python-flint's stubs type them as acb alone
    roots = cast(list[tuple[Any, int]], flint.fmpz_poly(ascending).complex_roots())
    real = [z.real for z, _ in roots if z.imag == 0]
    if not positive:
        return len(real)
    if all(x > 0 or x < 0 for x in real):
        return sum(1 for x in real if x > 0)
    dense = [ZZ(c) for c in reversed(ascending)]
    return dup_count_real_roots(dense, ZZ, inf=QQ(0))


def _divides(h: Poly, v: Poly) -> bool:
    """Whether h divides v ({h} is a Groebner basis of (h): the remainder decides)."""
    return v.is_zero() or divmod(v, h)[1].is_zero()


def _coefficients(poly: Poly, v: int) -> dict[int, Poly]:
    """poly as a polynomial in variable v: power -> coefficient (free of v)."""
    ctx = poly.context()
    out: dict[int, dict] = {}
    for exps, c in poly.terms():
        rest = list(exps)
        rest[v] = 0
        out.setdefault(exps[v], {})[tuple(rest)] = c
    return {k: ctx.from_dict(d) for k, d in out.items()}


def _put(poly: Poly, v: int, numer: Poly, denom: Poly, top: int) -> Poly:
    """denom**top * poly(v = numer/denom), with top >= the degree of poly in v."""
    ctx = poly.context()
    total = ctx.constant(0)
    for k, c in _coefficients(poly, v).items():
        total += c * numer**k * denom ** (top - k)
    return total


def _components(rows: list[Row]) -> list[list[Row]]:
    """The rows grouped into independent parts (no column shared between parts)."""
    parent: dict[int, int] = {}

    def find(a: int) -> int:
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for row in rows:
        keys = list(row)
        for k in keys[1:]:
            a, b = find(keys[0]), find(k)
            if a != b:
                parent[a] = b
    groups: dict[int, list[Row]] = {}
    for row in rows:
        groups.setdefault(find(next(iter(row))), []).append(row)
    return list(groups.values())


#: Runs a function on each item elsewhere: the outcomes in the items' order, a failed
#: call as the text of why it failed.
Spread = Callable[[Callable[[Any], "Split"], list[Any]], list["Split | str"]]


def drop_sets(
    rows: list[Row],
    need: int,
    region: Region,
    rnd: random.Random,
    spread: Spread | None = None,
) -> Split:
    """The candidate sets where ``rows`` (entries in ``region.context``, generic rank
    ``need``) lose rank (module docstring); ``spread`` explores open branches elsewhere."""
    if need <= 0 or not rows:
        return Split()
    return _Splitter(region, rnd).run([Branch([dict(r) for r in rows], need)], spread)


def _explored(work: tuple[Region, int, tuple, int]) -> Split:
    """One branch and all its sub-branches, in a process of its own (``spread``)."""
    region, seed, packed, limit = work
    return _Splitter(region, random.Random(seed), limit).run([_unpacked(packed, region)])


def _packed(branch: Branch) -> tuple:
    """A branch as plain data (FLINT's polynomials do not pickle): each polynomial as its
    terms."""

    def terms(p: Poly) -> tuple:
        return tuple((tuple(int(e) for e in exps), int(c)) for exps, c in p.terms())

    return (
        [{k: terms(v) for k, v in row.items()} for row in branch.rows],
        branch.need,
        {key: terms(u) for key, u in branch.units.items()},
        tuple((st.variable, terms(st.numerator), terms(st.denominator)) for st in branch.steps),
        tuple(terms(h) for h in branch.pending),
    )


def _unpacked(packed: tuple, region: Region) -> Branch:
    """The branch ``_packed`` wrote, in the region's ring."""
    ctx = region.context

    def poly(terms: tuple) -> Poly:
        return ctx.from_dict(dict(terms))

    rows, need, units, steps, pending = packed
    return Branch(
        [{k: poly(v) for k, v in row.items()} for row in rows],
        need,
        {key: poly(u) for key, u in units.items()},
        tuple(Step(v, poly(n), poly(d)) for v, n, d in steps),
        tuple(poly(h) for h in pending),
    )
