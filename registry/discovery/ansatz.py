"""The linear system of an integral search: unknown coefficients of a polynomial ansatz.

F = sum_k c_k m_k over the monomials m_k = M^a gamma^b of weighted degree 1..K
(constants are trivially conserved). dF/dt = grad F . X is linear in the c_k; with
the vector field X = Y / D (Y polynomial, D a common denominator) every monomial
coefficient of grad F . Y must vanish: a sparse linear system A(p) c = 0 whose
entries are polynomials in the parameters p. On a level set the system is taken
modulo the set's ideal: F and grad F . Y are reduced to normal form by a Groebner
basis of the ideal, and F ranges over the standard monomials only, so that F is
counted modulo the ideal.

The columns of A fall into connected blocks (two columns are connected when some
row holds both); for a weighted-homogeneous vector field the blocks never mix
weighted degrees, so the system splits by degree without being told.
"""

from __future__ import annotations

import heapq
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp
from sympy import QQ
from sympy.polys.orderings import ProductOrder, grevlex
from sympy.polys.rings import PolyElement, PolyRing

from ..errors import DiscoveryError
from ..mathematics import mechanics as mech
from ..mathematics.factoring import factor
from .ring import NotInRingError, SystemRing
from .symmetry import Decomposition, decompose

#: Exponents of the ring's variables (the adjoined ones, then the state variables).
Monomial = tuple[int, ...]
#: A polynomial in the parameters: exponents (in the system's parameter order) -> rational.
ParamPoly = Mapping[tuple[int, ...], "object"]


#: The size of the largest block of the sparsity from which symmetries are sought: below
#: it, finding and using them costs more than it saves (bench_discover.py, measured).
SPLIT_FROM = 24

#: Largest system a search builds: unknowns times equations (about 8 bytes of sparse
#: bookkeeping each in the worst case, so the default stays within a few hundred MB).
MAX_SYSTEM_SIZE = 20_000_000


class NotPolynomialError(DiscoveryError):
    """The vector field, a known integral or a level set is not polynomial (after
    clearing denominators) in the state variables."""


def count_monomials(max_weight: int, weights: Sequence[int]) -> int:
    """How many monomials of variables of these weights have weighted degree <= max_weight."""
    counts = [1] + [0] * max_weight  # counts[w]: monomials of weight exactly w so far
    for w in weights:
        for total in range(w, max_weight + 1):
            counts[total] += counts[total - w]
    return sum(counts)


def weighted_monomials(
    degree: int, weights: Sequence[int], bounds: Sequence[int | None] | None = None
) -> list[Monomial]:
    """Every monomial of variables of these weights of exactly this weighted degree; a
    variable of weight 0 takes the exponents 0..its bound."""
    n = len(weights)
    bounds = bounds or (None,) * n
    found: list[Monomial] = []
    exps = [0] * n

    def place(i: int, left: int) -> None:
        if i == n:
            if left == 0:
                found.append(tuple(exps))
            return
        top = (bounds[i] or 0) if weights[i] == 0 else left // weights[i]
        for a in range(top + 1):
            exps[i] = a
            place(i + 1, left - a * weights[i])
        exps[i] = 0

    place(0, degree)
    return found


@dataclass(frozen=True)
class Block:
    """One connected block of the system: its columns (indices into the system's
    columns), how many rows, and the entries (row, column-in-block) -> parameter
    polynomial (exponent tuple -> rational). Split along a symmetry, a column of the
    block is a combination of the system's columns (``basis``: (column, rational)
    pairs for each; ``columns`` then lists every system column they use)."""

    columns: tuple[int, ...]
    rows: int
    entries: Mapping[tuple[int, int], ParamPoly]
    weights: tuple[int, ...] = ()
    basis: tuple[tuple[tuple[int, Any], ...], ...] | None = None

    @property
    def size(self) -> int:
        """How many columns (unknowns) the block has."""
        return len(self.weights)

    def combination(self, k: int) -> tuple[tuple[int, Any], ...]:
        """The block's column k as (system column, coefficient) pairs."""
        return ((self.columns[k], 1),) if self.basis is None else self.basis[k]


class PolynomialSystem:
    """A(p) c = 0 for an ansatz of weighted degree <= ``degree`` (see module docstring).

    ``field`` is the vector field (one sympy expression per variable of ``state``, in
    the state, its ``shorthands`` and the parameters; by default the reference paper's
    six variables and s = M.gamma); ``ideal`` the level-set equations (expressions
    vanishing on the set); ``weights`` the weight of each state variable.
    """

    def __init__(
        self,
        field: Sequence[sp.Expr],
        params: Sequence[sp.Symbol],
        weights: Sequence[int],
        degree: int,
        ideal: Sequence[sp.Expr] = (),
        max_size: int = MAX_SYSTEM_SIZE,
        *,
        hamiltonian: sp.Expr | None = None,
        cofactor: sp.Expr | None = None,
        symmetries: bool = True,
        state: Sequence[sp.Symbol] = mech.STATE,
        shorthands: Mapping[sp.Symbol, sp.Expr] = mech.SHORTHANDS,
    ):
        self.params = tuple(params)
        self.degree = degree
        self.state = tuple(state)
        self.shorthands = dict(shorthands)
        around = [] if hamiltonian is None else [hamiltonian]
        try:
            self.space = SystemRing(
                [*field, *around],
                weights,
                state=self.state,
                shorthands=self.shorthands,
                bound_from=around,
            )
        except NotInRingError as err:
            raise NotPolynomialError(str(err)) from None
        self.variables = self.space.variables
        self.n = len(self.variables)
        self.weights = self.space.weights
        self.bounds = self.space.bounds
        self._plain = {g: sp.Symbol(str(g)) for g in (*self.variables, *self.params)}
        # the level set's basis over Q(p); a leading coefficient c(p) that is not constant
        # is divided by through a parameter iota = 1/c(p) of its own (``divisors``)
        self.contents: list[sp.Expr] = []
        basis = self._basis([*self.space.relations(), *ideal])
        self.divisors: dict[sp.Symbol, sp.Expr] = {}
        monic = [self._monic(numer, lead) for numer, lead in basis]
        self.params = (*self.params, *self.divisors)
        self._plain.update({i: sp.Symbol(str(i)) for i in self.divisors})
        names = [str(v) for v in (*self.variables, *self.params)]
        order: Any = "grevlex"
        if self.divisors:  # the state's grevlex first: iota's degree must not lead
            n = self.n
            order = ProductOrder((grevlex, lambda m: m[:n]), (grevlex, lambda m: m[n:]))
        self.ring = PolyRing(names, QQ, order)
        rates = self.space.rates(field) if self.space.extended else field
        self.field = self._polynomial_field(rates)
        # Darboux polynomials: X F = K F, i.e. Y F = D K F for Y = D X (D the parameter
        # denominator cleared from the field); the cofactor's coefficients are parameters
        # (a cofactor with parameter denominators: both sides times its denominator)
        self.cofactor, self.cofactor_scale = self.ring.zero, self.ring.one
        if cofactor is not None:
            scaled = self.space.lift(cofactor) if self.space.extended else cofactor
            numer, denom = sp.fraction(sp.together(sp.expand(scaled * self.denominator)))
            plain = self._plain
            self.cofactor = self.ring.from_expr(sp.expand(numer).xreplace(plain))
            self.cofactor_scale = self.ring.from_expr(sp.expand(denom).xreplace(plain))
        self.ideal = [self.ring.from_expr(g) for g in monic]
        self.leading = [g.LM[: self.n] for g in self.ideal]
        # the field in normal form (u gamma3^3 u^3 is u^0 where u gamma3 = 1): what d/dt
        # does modulo the ideal is unchanged, and its degrees are the true ones
        self.field = [self.reduce(y) for y in self.field]
        self._check_size(max_size)
        # (a monomial of weight 0, in inverse variables only, counts with degree 1)
        self.columns: list[tuple[Monomial, int]] = [
            (e, max(d, 1))
            for d in range(0 if self.space.extended else 1, degree + 1)
            for e in weighted_monomials(d, self.weights, self.bounds)
            if any(e)
            and not any(all(a >= b for a, b in zip(e, lm, strict=True)) for lm in self.leading)
        ]
        self.column_index = {e: j for j, (e, _) in enumerate(self.columns)}
        self.decomposition: Decomposition | None = None
        self.symmetry_note = "not used"
        self.symmetries = symmetries
        self.blocks = self._blocks()

    def _check_size(self, limit: int) -> None:
        """Refuse, before building it, a system larger than ``limit`` (unknowns times
        equations, the equations counted as the monomials dF/dt can reach)."""
        shift = max(
            (
                self.weight_of(m) - self.weights[i]
                for i, y in enumerate(self.field)
                for m in y.monoms()
            ),
            default=0,
        )
        positive = [w for w in self.weights if w]
        times = 1
        for w, b in zip(self.weights, self.bounds, strict=True):
            times *= 1 if w else (b or 0) + 1
        unknowns = count_monomials(self.degree, positive) * times - 1
        equations = count_monomials(self.degree + max(shift, 0), positive) * times
        if unknowns * equations > limit:
            raise DiscoveryError(
                f"the ansatz of weighted degree <= {self.degree} has {unknowns} unknowns and "
                f"up to {equations} equations ({unknowns * equations:,} entries, more than "
                f"the limit of {limit:,}); search at a lower --degree"
            )

    def shift(self) -> int:
        """How much the field raises the weighted degree of polynomials in the state
        (the weight of a cofactor, a polynomial in it: the rates of adjoined inverses
        and roots, whose weight 0 is a convention, do not count)."""
        state = set(self.state)
        return max(
            (
                self.weight_of(m) - self.weights[i]
                for i, y in enumerate(self.field)
                if self.variables[i] in state
                for m in y.monoms()
            ),
            default=0,
        )

    def weight_of(self, monomial: tuple[int, ...]) -> int:
        """The weighted degree of a ring monomial (its state part)."""
        return sum(a * w for a, w in zip(monomial[: self.n], self.weights, strict=True))

    # ------------------------------------------------------------ conversion

    def polynomial(self, expr: sp.Expr, *, what: str = "expression") -> PolyElement:
        """``expr`` as an element of the system's ring (s expanded; parameter denominators
        cleared; in an extended ring, inverses and roots written with its variables),
        reduced modulo the level set. NotPolynomialError if it is not in the ring."""
        return self.reduce(self.fraction(expr, what=what)[0])

    def fraction(self, expr: sp.Expr, *, what: str = "expression") -> tuple[PolyElement, sp.Expr]:
        """``expr`` as (numerator in the system's ring, not reduced; the parameter
        denominator cleared from it): expr = numerator / denominator in the ring.
        NotPolynomialError if it is not in the ring."""
        expr = self.expanded(expr)
        if self.space.extended:
            try:
                expr = self.space.lift(expr)
            except NotInRingError as err:
                raise NotPolynomialError(f"the {what} is not in the system's ring: {err}") from None
        numer, denom = sp.fraction(sp.together(sp.expand(expr)))
        if denom.free_symbols & set(self.variables):
            raise NotPolynomialError(f"the {what} is not polynomial in the state variables")
        try:
            poly = self.ring.from_expr(sp.expand(numer).xreplace(self._plain))
        except (ValueError, sp.PolynomialError, sp.CoercionFailed) as err:
            raise NotPolynomialError(f"the {what} is not polynomial: {err}") from None
        return poly, denom

    def expression(self, poly: PolyElement) -> sp.Expr:
        """A ring element as a sympy expression in the state and the parameters."""
        plain = {v: k for k, v in self._plain.items()}
        return sp.sympify(poly.as_expr()).xreplace(plain)

    def expanded(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with the shorthands written out (s as M.gamma)."""
        expr = sp.sympify(expr)
        return expr.subs(self.shorthands) if self.shorthands else expr

    def _polynomial_field(self, field: Sequence[sp.Expr]) -> list[PolyElement]:
        """Y = D X with one denominator D for all components (dropping D changes no
        conserved quantity where X is defined)."""
        numers, denoms = [], []
        for x in field:
            n, d = sp.fraction(sp.together(sp.expand(self.expanded(x))))
            numers.append(n)
            denoms.append(d)
        common = sp.lcm_list(denoms)
        self.denominator = common
        out = []
        for n, d in zip(numers, denoms, strict=True):
            scaled = sp.expand(n * sp.cancel(common / d))
            try:
                out.append(self.ring.from_expr(scaled.xreplace(self._plain)))
            except (ValueError, sp.PolynomialError, sp.CoercionFailed):
                raise NotPolynomialError(
                    "the equations of motion are not rational in the state variables "
                    "(radicals or transcendental functions); the ansatz needs polynomials"
                ) from None
        return out

    def _basis(self, ideal: Sequence[sp.Expr]) -> list[tuple[sp.Expr, sp.Expr]]:
        """A Groebner basis of the level set (and the ring's relations) over Q(p), each
        element as (numerator, leading coefficient), in plain symbols."""
        if not ideal:
            return []
        polys = []
        for g in ideal:
            numer, denom = sp.fraction(sp.together(sp.expand(self.expanded(g))))
            if denom.free_symbols & set(self.variables):
                raise NotPolynomialError("a level-set equation is not polynomial")
            polys.append(sp.expand(numer).xreplace(self._plain))
        state = [self._plain[v] for v in self.variables]
        params = [self._plain[p] for p in self.params]
        plain = {v: k for k, v in self._plain.items()}
        for g in polys:  # a parameter factor common to an equation's terms is divided out
            content = factor(sp.Poly(g, *state).content()) if g != 0 else sp.Integer(1)
            if content.free_symbols:
                c = content.xreplace(plain)
                if c not in self.contents:
                    self.contents.append(c)
        domain = QQ.frac_field(*params) if params else QQ
        basis = sp.groebner(polys, *state, order="grevlex", domain=domain)
        out = []
        for g in basis.exprs:
            numer, _ = sp.fraction(sp.together(g))
            poly = sp.Poly(sp.expand(numer), *state)
            out.append((poly.as_expr(), poly.LC(order="grevlex")))
        return out

    def _monic(self, numer: sp.Expr, lead: sp.Expr) -> sp.Expr:
        """A basis element divided by its leading coefficient: by the number, or, for a
        coefficient c(p) that depends on the parameters, times a parameter iota standing
        for 1/c(p) (the search then holds where c(p) != 0; ``divisors``)."""
        if not lead.free_symbols:
            return sp.expand(numer / lead)
        plain = {v: k for k, v in self._plain.items()}
        c = factor(lead.xreplace(plain))
        iota = next((i for i, d in self.divisors.items() if d == c), None)
        if iota is None:
            iota = sp.Symbol(f"ring_iota{len(self.divisors) + 1}")
            self.divisors[iota] = c
        state = [self._plain[v] for v in self.variables]
        poly = sp.Poly(numer, *state)
        head = sp.Mul(
            *(x**e for x, e in zip(state, poly.LM(order="grevlex").exponents, strict=True))
        )
        rest = sp.expand(numer - lead * head)
        return sp.expand(head + sp.Symbol(str(iota)) * rest)

    # --------------------------------------------------------------- algebra

    @property
    def divided_by(self) -> list[sp.Expr]:
        """The parameter polynomials c(p) the level set's basis divides by: the search
        holds where none vanishes."""
        return list(dict.fromkeys([*self.contents, *self.divisors.values()]))

    @property
    def inverses(self) -> dict[int, sp.Expr]:
        """Parameter index -> c(p), for each parameter that stands for 1/c(p)."""
        return {self.params.index(i): c for i, c in self.divisors.items()}

    def reduce(self, poly: PolyElement) -> PolyElement:
        """The normal form of ``poly`` modulo the level set's ideal (``normal_form``: what
        ``poly.rem(self.ideal)`` gives, without re-sorting ``poly`` at every step)."""
        return normal_form(poly, self.ideal, self.n, bool(self.divisors)) if self.ideal else poly

    def weight(self, poly: PolyElement) -> int:
        """The largest weighted degree of the state monomials of ``poly``."""
        return max((self.weight_of(m) for m in poly.monoms()), default=0)

    def derivative(self, exps: Monomial) -> PolyElement:
        """D d(x^exps)/dt reduced modulo the level set."""
        total = self.ring.zero
        pad = (0,) * len(self.params)
        for i in range(self.n):
            if exps[i]:
                lower = list(exps)
                lower[i] -= 1
                total += self.ring({(*lower, *pad): QQ(exps[i])}) * self.field[i]
        if self.cofactor:
            total = total * self.cofactor_scale - self.ring({(*exps, *pad): QQ(1)}) * self.cofactor
        return self.reduce(total)

    def coordinates(self, poly: PolyElement) -> dict[int, dict[tuple[int, ...], object]]:
        """The coefficients of ``poly`` on the ansatz columns (constants dropped), each a
        parameter polynomial; ValueError for a monomial outside the ansatz."""
        coords: dict[int, dict[tuple[int, ...], object]] = {}
        for m, c in poly.items():
            state = m[: self.n]
            if not any(state):
                continue
            j = self.column_index.get(state)
            if j is None:
                raise ValueError(f"monomial {state} is outside the ansatz")
            coords.setdefault(j, {})[m[self.n :]] = c
        return coords

    def _blocks(self, splits: Sequence[Decomposition] | None = None) -> list[Block]:
        """The connected blocks of the system: columns joined when some row holds both.
        Split along symmetries (``splits``: given, or the ways ``decompose`` finds where
        the sparsity leaves a block of SPLIT_FROM unknowns or more: smaller ones cost
        less than looking), the columns are the eigenvectors of each class, and a block
        never joins two classes (d/dt maps them into independent subspaces); the split
        whose blocks cost least to eliminate is kept, if it costs less than the blocks
        of the sparsity alone."""
        derivatives = [self.derivative(e) for e, _ in self.columns]
        plain = self._connected([{j: 1} for j in range(len(self.columns))], derivatives)
        best, cost = plain, _cost(plain)
        if splits is None:
            largest = max((b.size for b in plain), default=0)
            if not self.symmetries:
                splits = []
            elif largest < SPLIT_FROM:
                self.symmetry_note = (
                    f"not sought (the sparsity's largest block has {largest} unknowns)"
                )
                return plain
            else:
                found_splits, self.symmetry_note = decompose(self, cofactor=bool(self.cofactor))
                splits = found_splits
        found = self.symmetry_note
        for split in splits:
            row = split.representatives()
            blocks = [b for c in split.classes for b in self._connected(c, derivatives, row)]
            if _cost(blocks) < cost:
                best, cost, self.decomposition = blocks, _cost(blocks), split
        if splits:
            used = self.decomposition.note if self.decomposition else "none used"
            if self.decomposition is None:
                found += " (no split cheaper than the blocks of the sparsity)"
            self.symmetry_note = f"{used} (found: {found})"
        elif self.symmetry_note != "not used":
            self.symmetry_note = f"none used (found: {found})"
        return best

    def _connected(self, combos, derivatives, row=None) -> list[Block]:
        """The blocks of one class of columns (each a combination of system columns);
        ``row`` keeps the monomials that determine an image (orbit representatives)."""
        unit = all(len(c) == 1 and next(iter(c.values())) == 1 for c in combos)
        rows: dict[tuple, int] = {}
        entries: dict[tuple[int, int], dict] = {}
        for k, combo in enumerate(combos):
            if unit:
                image = derivatives[next(iter(combo))]
            else:
                image = self.ring.zero
                for j, c in combo.items():
                    image += derivatives[j] * c
            for m, c in image.items():
                if row is not None and not row(m[: self.n]):
                    continue
                r = rows.setdefault(m[: self.n], len(rows))
                entries.setdefault((r, k), {})[m[self.n :]] = c
        parent = list(range(len(combos)))

        def find(a: int) -> int:
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        first: dict[int, int] = {}
        for r, k in entries:
            if r in first:
                a, b = find(first[r]), find(k)
                if a != b:
                    parent[a] = b
            else:
                first[r] = k
        groups: dict[int, list[int]] = {}
        for k in range(len(combos)):
            groups.setdefault(find(k), []).append(k)
        blocks = []
        for cols in groups.values():
            index = {k: i for i, k in enumerate(cols)}
            local_rows: dict[int, int] = {}
            local = {}
            for (r, k), v in entries.items():
                if k in index:
                    local[(local_rows.setdefault(r, len(local_rows)), index[k])] = v
            weights = tuple(self.columns[next(iter(combos[k]))][1] for k in cols)
            if unit:
                used = tuple(next(iter(combos[k])) for k in cols)
                blocks.append(Block(used, len(local_rows), local, weights))
            else:
                basis = tuple(tuple(sorted(combos[k].items())) for k in cols)
                used = tuple(sorted({j for b in basis for j, _ in b}))
                blocks.append(Block(used, len(local_rows), local, weights, basis))
        return blocks

    @property
    def size(self) -> int:
        """Unknowns times equations, the measure of the work the system asks for."""
        return len(self.columns) * sum(b.rows for b in self.blocks)


def _cost(blocks: Sequence[Block]) -> int:
    """The work of eliminating the blocks (unknowns times equations times the smaller),
    to choose between ways of splitting the system."""
    return sum(b.size * b.rows * min(b.size, b.rows) for b in blocks)


def normal_form(
    poly: PolyElement, basis: Sequence[PolyElement], n: int, product: bool
) -> PolyElement:
    """The remainder of ``poly`` on division by the monic ``basis`` in the ring's order
    (grevlex; with ``product``, grevlex on the first ``n`` variables, then on the rest):
    the same terms as ``poly.rem(basis)``, the divisor tried first where several divide,
    but with each monomial's place in the order computed once (a heap), where ``rem``
    looks for the leading term of the whole rest at every step."""

    def place(m: tuple[int, ...]) -> tuple[int, ...]:
        # negated grevlex keys: the largest monomial comes first out of a min-heap
        if product:
            head, tail = m[:n], m[n:]
            return (-sum(head), *reversed(head), -sum(tail), *reversed(tail))
        return (-sum(m), *reversed(m))

    ring = poly.ring
    divisors = []
    for g in basis:
        if g.LC != 1:
            return poly.rem(list(basis))  # only monic bases are divided here
        lead = g.LM
        divisors.append((lead, [(m, c) for m, c in g.items() if m != lead]))
    terms = dict(poly)
    heap = [(place(m), m) for m in terms]
    heapq.heapify(heap)
    rest: dict[tuple[int, ...], Any] = {}
    while heap:
        _, m = heapq.heappop(heap)
        c = terms.pop(m, None)
        if c is None:
            continue  # cancelled, or met before
        for lead, tail in divisors:
            q = tuple(a - b for a, b in zip(m, lead, strict=True))
            if min(q) < 0:
                continue
            for mg, cg in tail:  # m - c q g: the leading term cancels
                m1 = tuple(a + b for a, b in zip(mg, q, strict=True))
                value = terms.get(m1)
                if value is None:
                    terms[m1] = -c * cg
                    heapq.heappush(heap, (place(m1), m1))
                elif value == c * cg:
                    del terms[m1]
                else:
                    terms[m1] = value - c * cg
            break
        else:
            rest[m] = c
    return ring.from_dict(rest) if rest else ring.zero
