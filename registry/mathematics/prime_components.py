"""The irreducible components of a polynomial system's zero set, away from the origin,
each in shape position: the balances of Kovalevskaya's method.

The system is solved by Groebner bases over k = Q (or Q(p) for parameters p), never by
``sympy.solve``. A *finite* system is decomposed at once: from one graded (grevlex)
basis, the multiplication matrices of the algebra k[x]/I give the powers of a linear
form u = l(x) by linear algebra (as in FGLM); when they span the algebra,
k[x]/I = k[u]/(g) (the shape lemma), so x_i = h_i(u), and each irreducible factor of g
over k is one prime component: a field k[u]/(g_j) whose roots are its points.

Over Q(p) a system is first split on a coordinate hyperplane where it has points both
on and off it: into I + (x) and the saturation I : x^oo (two Groebner bases, which stay
small where the determinants and lexicographic bases over Q(p) swell with the number of
points); the balances with a vanishing coordinate come apart from the others so.
Each basis is kept as polynomials and extended by the equations added to it (its own
pairs not formed again). One integer value of p decides cheaply what needs no proof
over Q(p): a variable whose multiplication matrix has a non-zero determinant there has
no point on its hyperplane, and a characteristic polynomial irreducible there is
irreducible over Q(p) (no split by its values).

Otherwise a basis element that factors splits the system into one branch per factor.
An irreducible branch of dimension d has a maximal independent set S of d variables
(no leading monomial lies in k[S]); over the field k(S) it is zero-dimensional and a
linear form puts it in shape position, {x_i - h_i(u), g(u)} with g irreducible over
k(S) (where g factors, the branch splits again): a family of balances with free
coordinates S. Components on which S is not independent are not seen over k(S): with a
lexicographic basis in which the other variables precede S, they lie where a leading
coefficient h(S) vanishes (Gianni, Trager and Zacharias, J. Symb. Comput. 6 (1988),
Prop. 3.7), so the branch I + (h) is decomposed too. Components contained in others
(a point of a family) are dropped at the end, and so is the origin.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import flint
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from .algebraic import Extension
from .factoring import factor_list, factor_mpoly
from .flint_polys import bareiss, fraction, numerators
from .groebner import NormalForms, elimination, groebner

#: The most systems a decomposition visits before it gives up (each a Groebner basis).
MAX_BRANCHES = 400
#: Linear forms tried for shape position before a branch is given up.
MAX_FORMS = 12
#: The most points over Q(p), p two or more symbols, for which shape position is sought
#: by linear algebra in k[x]/I (its Krylov matrix's degrees grow with the size).
SMALL_ALGEBRA = 8


class DecompositionLimit(Exception):
    """The decomposition would exceed ``MAX_BRANCHES`` systems or find no shape position."""


@dataclass(frozen=True)
class Component:
    """One irreducible component over k: its free variables S (dimension len(S)) and its
    generic point x_i = h_i(u) (``coordinates``, rational in S and the parameters),
    where u = ``element`` is a root of the irreducible ``minimal`` polynomial over k(S).

    ``ideal`` generates its prime ideal in k[x] (for containment tests)."""

    variables: tuple[sp.Symbol, ...]
    parameters: tuple[sp.Symbol, ...]
    free: tuple[sp.Symbol, ...]
    symbol: sp.Symbol
    element: sp.Expr
    minimal: sp.Poly
    coordinates: Mapping[sp.Symbol, sp.Expr]
    ideal: tuple[sp.Expr, ...]
    #: the coordinates as polynomials in u over k(S) where the decomposition had them so
    #: (``point`` then need not read the expressions back, which over Q(p) costs seconds)
    polynomials: Mapping[sp.Symbol, sp.Poly] | None = dataclasses.field(
        default=None, compare=False, repr=False
    )

    @property
    def dimension(self) -> int:
        return len(self.free)

    @property
    def degree(self) -> int:
        """The number of points (or families) over the algebraic closure of k(S) it holds."""
        return self.minimal.degree()

    @property
    def domain(self) -> sp.polys.domains.Domain:
        """k(S): Q, or the rational functions of the parameters and free variables."""
        return self.minimal.domain

    def vanishes(self, expr: sp.Expr) -> bool:
        """Whether a polynomial (or the numerator of a rational function) in the variables
        vanishes on the component: at its generic point, modulo the minimal polynomial (by
        arithmetic on polynomials in u, ``evaluate``: no expanded expressions)."""
        expr = sp.sympify(expr)
        try:
            return self.evaluate(expr).is_zero
        except (sp.PolynomialError, sp.CoercionFailed):  # a denominator in the variables
            return self.evaluate(sp.fraction(sp.together(expr))[0]).is_zero

    @functools.cached_property
    def point(self) -> tuple[sp.Poly, ...]:
        """The generic point's coordinates other than the free ones, as polynomials in u
        over k(S)."""
        known = self.polynomials or {}

        def coordinate(x: sp.Symbol) -> sp.Poly:
            if x in known:
                return known[x]
            return sp.Poly(self.coordinates[x], self.symbol, domain=self.domain)

        return tuple(coordinate(x) for x in self.variables if x not in self.free)

    def evaluate(self, expr: sp.Expr) -> sp.Poly:
        """A polynomial in the variables (coefficients in k) at the generic point, as a
        polynomial in u reduced modulo the minimal polynomial; remembered, since the
        Kovalevskaya matrix's entries are asked for by the exponents and by the series."""
        if expr not in self._values:
            self._values[expr] = self._evaluated(expr)
        return self._values[expr]

    @functools.cached_property
    def _values(self) -> dict[sp.Expr, sp.Poly]:
        return {}

    def _evaluated(self, expr: sp.Expr) -> sp.Poly:
        bound = [x for x in self.variables if x not in self.free]
        if not bound:
            return sp.Poly(expr, self.symbol, domain=self.domain)
        poly = sp.Poly(expr, *bound, domain=self.domain)
        return Extension(self.symbol, self.minimal).evaluate(poly, self.point)

    def equations(self) -> tuple[sp.Expr, ...]:
        """Generators of its prime ideal: g(l(x)) and x - h(l(x)) for an isolated
        component in shape position (short), else the stored ``ideal``."""
        if self.free:
            return self.ideal
        u, element = self.symbol, self.element
        return (
            self.minimal.as_expr().subs(u, element),
            *(x - h.subs(u, element) for x, h in self.coordinates.items() if x != element),
        )


def ground_domain(symbols: Sequence[sp.Symbol]) -> sp.polys.domains.Domain:
    """Q, or the field of rational functions over Q of ``symbols``."""
    return sp.QQ.frac_field(*symbols) if symbols else sp.QQ


def components(
    equations: Sequence[sp.Expr],
    variables: Sequence[sp.Symbol],
    parameters: Sequence[sp.Symbol] = (),
    *,
    origin: Sequence[sp.Symbol] | None = None,
    seed: int = 0,
    hyperplanes: bool = True,
) -> tuple[Component, ...]:
    """The irreducible components of ``equations = 0`` on which the ``origin`` variables
    (default: all) are not all zero, none contained in another, largest dimension first
    (module doc for the method); ``origin=()`` keeps every component. ``hyperplanes=False``
    leaves out the splits on coordinate hyperplanes over Q(p) (the same components,
    found more slowly: a benchmark's baseline).

    >>> x, y = sp.symbols("x y")
    >>> [(c.free, c.minimal.as_expr()) for c in components([x * (x**2 - 2), x * y], [x, y])]
    [((y,), x), ((), x**2 - 2)]
    """
    decomposition = _Decomposition(
        tuple(variables), tuple(parameters), random.Random(seed), hyperplanes=hyperplanes
    )
    found = decomposition.run([sp.expand(e) for e in equations])
    zero = tuple(variables) if origin is None else tuple(origin)
    return _maximal([c for c in found if not zero or not all(c.vanishes(x) for x in zero)])


@dataclass(frozen=True)
class _Shape:
    symbol: sp.Symbol
    element: sp.Expr
    minimal: sp.Poly
    coordinates: dict[sp.Symbol, sp.Expr]
    polynomials: dict[sp.Symbol, sp.Poly] | None = None  # the coordinates, where known so


#: A system to decompose: equations added to a reduced basis (None: to none), so that
#: the basis's own pairs are not formed again (``groebner``'s ``known``).
_System = tuple[sp.GroebnerBasis | None, tuple]


@dataclass(frozen=True)
class _Split:
    """Systems whose points together are those of a system I, each a proper part (none
    of them is I again, so none is dropped as a system already seen)."""

    systems: tuple[_System, ...]


class _Decomposition:
    def __init__(self, variables, parameters, rng: random.Random, *, hyperplanes: bool = True):
        self.variables = variables
        self.parameters = parameters
        self.k = ground_domain(parameters)
        self.rng = rng
        self.hyperplanes = hyperplanes and self.k.is_FractionField

    def run(self, equations: list[sp.Expr]) -> list[Component]:
        found: list[Component] = []
        seen: set[frozenset] = set()
        stack: list[_System] = [(None, tuple(equations))]
        while stack:
            known, more = stack.pop()
            basis = groebner(more, self.variables, self.k, known=known)
            key = frozenset(basis.polys)
            if key in seen:
                continue
            seen.add(key)
            if len(seen) > MAX_BRANCHES:
                raise DecompositionLimit(f"more than {MAX_BRANCHES} branches")
            if _no_point(basis):
                continue
            if basis.is_zero_dimensional:
                points = self._zero_dimensional(basis)
                if isinstance(points, _Split):
                    stack.extend(points.systems)
                    continue
                if points is not None:
                    found.extend(points)
                    continue
            branches = self._split(basis)
            if branches is None and self.hyperplanes:
                parts = self._hyperplane_parts(basis)
                branches = None if parts is None else list(parts.systems)
            if branches is None:
                branches, component = self._branch(basis)
                if component is not None:
                    found.append(component)
            stack.extend(branches)
        return found

    def _zero_dimensional(self, basis: sp.GroebnerBasis) -> list[Component] | _Split | None:
        """The components of a finite system at once: when a linear form u generates the
        algebra k[x]/I (``_cyclic``), k[x]/I = k[u]/(g) and each irreducible factor of g
        is one component, with no further basis. None when no form does (a multiple point
        of embedding dimension 2 or more): the system is then split on factors. Over
        Q(p), a system of more than two points is first split on a coordinate hyperplane
        (``_hyperplane_split``), then by the values of a variable, the last first
        (``_Algebra.value_split``), where they fall into several factors."""
        algebra = _Algebra(basis, self.variables, self.k)
        if self.k.is_FractionField and algebra.size > 2:
            parts = self._hyperplane_parts(basis, algebra) if self.hyperplanes else None
            if parts is not None:
                return parts
            for x in reversed(self.variables):
                factors = algebra.value_split(x)
                if factors is not None:
                    return _Split(tuple((basis, (f,)) for f in factors))
        for element in self._forms(list(self.variables), pairs=True):
            u = element if element in self.variables else sp.Dummy("u")
            cyclic = algebra.cyclic(element, u)
            if cyclic is None:
                continue
            eliminant, solved = cyclic
            found = []
            for f, _ in self._factors(eliminant.as_expr(), [u]):
                minimal = sp.Poly(f, u, domain=self.k).monic()
                polynomials, coordinates = _reduced(solved, minimal)
                ideal = (*basis.exprs, sp.fraction(sp.together(f.subs(u, element)))[0])
                found.append(
                    Component(
                        self.variables,
                        self.parameters,
                        (),
                        u,
                        element,
                        minimal,
                        coordinates,
                        ideal,
                        polynomials,
                    )
                )
            return found
        return None

    def _hyperplane_parts(
        self, basis: sp.GroebnerBasis, algebra: _Algebra | None = None
    ) -> _Split | None:
        """The first proper split of the system on a coordinate hyperplane, the last
        variable first (``_hyperplane_split``), or None. With the finite ``algebra``
        k[x]/I, a variable shown to be a unit there (``_Algebra.is_unit``) is passed
        over: no point lies on its hyperplane, which Buchberger's algorithm would prove
        only by reaching I + (x) = (1), at great cost over several parameters."""
        for x in reversed(self.variables):
            if algebra is not None and algebra.is_unit(x):
                continue
            parts = self._hyperplane_split(basis, x)
            if parts is not None:
                return parts
        return None

    def _hyperplane_split(self, basis: sp.GroebnerBasis, x: sp.Symbol) -> _Split | None:
        """The points where x = 0 (I + (x)) and those where it is not (I : x^oo), when
        both are proper parts: two Groebner bases, where over Q(p) the determinant of
        ``value_split`` and the shape position's coefficients grow with the size of the
        system (balances split so at once into those on a coordinate hyperplane and the
        rest). None where x lies in I, or where I : x^oo = I (x is no zero divisor
        modulo I: in a finite algebra, a unit)."""
        on = groebner([x], self.variables, self.k, known=basis)
        if _no_point(on) or on.polys == basis.polys:
            return None
        off = _saturate(basis.polys, x, self.variables, self.k)
        if off.polys == basis.polys:
            return None
        return _Split(((on, ()), (off, ())))

    def _factors(self, expr: sp.Expr, wrt: Sequence[sp.Symbol]) -> list[tuple[sp.Expr, int]]:
        """The factors of ``expr`` that are not units: those involving ``wrt``."""
        gens = [*wrt, *sorted(sp.sympify(expr).free_symbols - set(wrt), key=str)]
        return [(f, e) for f, e in factor_list(expr, gens) if f.free_symbols & set(wrt)]

    def _split(self, basis: sp.GroebnerBasis) -> list[_System] | None:
        """One branch per factor of the first element that is not irreducible."""
        for element in basis.exprs:
            factors = self._factors(element, self.variables)
            if len(factors) > 1 or factors[0][1] > 1:
                return [(basis, (f,)) for f, _ in factors]
        return None

    def _branch(self, basis: sp.GroebnerBasis) -> tuple[list[_System], Component | None]:
        """The branches an irreducible system splits into, or its component (and the
        branches where a leading coefficient of its free variables vanishes)."""
        free = _independent_set(basis.exprs, self.variables)
        others = [x for x in self.variables if x not in free]
        generators = list(basis.exprs)
        remainder: list[_System] = []
        if free:
            lex = groebner(basis.polys, [*others, *free], self.k, "lex")
            generators = list(lex.exprs)
            leading = [sp.Poly(e, *others).LC() for e in generators]
            for f, _ in self._factors(sp.Mul(*leading), free):
                remainder.append((basis, (f,)))
        field = ground_domain([*self.parameters, *free])
        shape = self._shape(generators, others, field, None if free else basis)
        if isinstance(shape, list):
            return [(basis, (b,)) for b in shape] + remainder, None
        ideal = tuple(basis.exprs)
        if remainder:  # the prime ideal is the branch's saturation by the leading coefficients
            h = sp.Mul(*(f for _, (f,) in remainder))
            ideal = tuple(_saturate(basis.polys, h, self.variables, self.k).exprs)
        coordinates = {x: shape.coordinates.get(x, x) for x in self.variables}
        component = Component(
            self.variables,
            self.parameters,
            tuple(free),
            shape.symbol,
            shape.element,
            shape.minimal,
            coordinates,
            ideal,
            shape.polynomials,
        )
        return remainder, component

    def _shape(self, generators, gens, field, known=None) -> _Shape | list[sp.Expr]:
        """Shape position over ``field`` through a linear form, or the polynomials (in the
        variables) whose vanishing splits the system, when the form's eliminant factors.
        ``known``: the generators' graded basis in ``gens``. Over Q or Q(one symbol) the
        forms are tried on the algebra of one graded basis (``_Algebra.cyclic``: linear
        algebra, no basis per form); over more symbols only on an algebra of at most
        ``SMALL_ALGEBRA`` points, the sums of two variables first: beyond it the Krylov
        matrix's degrees grow too fast (and FLINT's long steps would overrun a time
        budget, which cannot interrupt them), while for a few points the lexicographic
        basis of each form is the slower (its coefficients over Q(p) swell). Where no
        form generates the algebra (a multiple point), each form gets its own basis."""
        if not gens:  # every variable is free: the component is the whole space
            u = sp.Dummy("u")
            return _Shape(u, sp.Integer(0), sp.Poly(u, u, domain=field), {})
        graded = known
        if graded is None:
            graded = groebner(generators, gens, field)
        symbols = field.symbols if field.is_FractionField else ()
        if graded.is_zero_dimensional and (
            len(symbols) <= 1 or len(standard_monomials(graded, gens)) <= SMALL_ALGEBRA
        ):
            algebra = _Algebra(graded, gens, field)
            for element in self._forms(gens, pairs=len(symbols) > 1):
                u = element if element in gens else sp.Dummy("u")
                cyclic = algebra.cyclic(element, u)
                if cyclic is not None:
                    eliminant, solved = cyclic
                    return self._shaped(eliminant, u, element, solved, field)
        for element in self._forms(gens):
            if element in gens:
                u, order = element, [x for x in gens if x != element] + [element]
                system = list(generators)
            else:
                u = sp.Dummy("u")
                order, system = [*gens, u], [*generators, u - element]
            if order == list(gens):
                graded_u = graded
            else:
                graded_u = groebner(system, order, field)
            lex = graded_u.fglm("lex")
            solved = _solved(lex.exprs[:-1], order[:-1])
            shaped = self._shaped(lex.exprs[-1], u, element, solved, field)
            if isinstance(shaped, list) or solved is not None:
                return shaped
        raise DecompositionLimit(f"no shape position found in {MAX_FORMS} linear forms")

    def _shaped(self, eliminant, u, element, coordinates, field) -> _Shape | list[sp.Expr]:
        """The shape position x = h_x(u), g(u) = 0 where the eliminant g is irreducible,
        else the numerators of its factors at u = ``element`` (the system splits on them).
        The eliminant and the coordinates come as expressions, or as polynomials in u over
        ``field`` (kept so: reading them back from expressions costs seconds over Q(p))."""
        polynomial = isinstance(eliminant, sp.Poly)
        factors = self._factors(eliminant.as_expr() if polynomial else eliminant, [u])
        if len(factors) > 1 or factors[0][1] > 1:
            return [sp.fraction(sp.together(f.subs(u, element)))[0] for f, _ in factors]
        minimal = (eliminant if polynomial else sp.Poly(eliminant, u, domain=field)).monic()
        polynomials = None
        if polynomial:
            polynomials, coordinates = _reduced(coordinates, minimal)
        coordinates = dict(coordinates or {})
        if element in self.variables:  # u is that variable itself
            coordinates[element] = element
        return _Shape(u, element, minimal, coordinates, polynomials)

    def _forms(self, gens: Sequence[sp.Symbol], *, pairs: bool = False):
        """The variables, last first, then (with ``pairs``, where a try costs one cheap
        test) the sums of two of them, whose shape positions are the sparsest after the
        variables', then random small combinations of them."""
        yield from reversed(gens)
        if pairs:
            ordered = list(reversed(gens))
            yield from (a + b for a, b in itertools.combinations(ordered, 2))
        for _ in range(MAX_FORMS - len(gens)):
            yield sp.Add(*(self.rng.randint(-3, 3) * x for x in gens[:-1]), gens[-1])


def _reduced(
    solved: Mapping[sp.Symbol, sp.Poly], minimal: sp.Poly
) -> tuple[dict[sp.Symbol, sp.Poly], dict[sp.Symbol, sp.Expr]]:
    """The coordinates h_x(u) reduced modulo the minimal polynomial: as polynomials in u
    (a component's ``polynomials``) and as expressions (its ``coordinates``)."""
    polynomials = {x: h.rem(minimal) for x, h in solved.items()}
    return polynomials, {x: h.as_expr() for x, h in polynomials.items()}


class _Algebra:
    """k[x]/I for a zero-dimensional I: its standard monomials (a basis) and the matrices
    of multiplication by each variable, from one graded basis; any linear form's powers
    then cost matrix products, no further reduction (the idea of FGLM)."""

    def __init__(self, basis: sp.GroebnerBasis, gens, k):
        self.k, self.gens = k, tuple(gens)
        self.monomials = standard_monomials(basis, gens)
        self.index = {m: i for i, m in enumerate(self.monomials)}
        self.forms = NormalForms(basis, k)
        self.times = [self._multiplication(i) for i in range(len(self.gens))]

    @property
    def size(self) -> int:
        return len(self.monomials)

    def _coordinates(self, monomial: tuple[int, ...]) -> list:
        if monomial in self.index:
            column = [self.k.zero] * self.size
            column[self.index[monomial]] = self.k.one
            return column
        remainder = self.forms.of_monomial(monomial)
        column = [self.k.zero] * self.size
        for m, c in remainder.items():
            column[self.index[m]] = c
        return column

    def _multiplication(self, i: int) -> DomainMatrix:
        columns = [
            self._coordinates(tuple(e + (j == i) for j, e in enumerate(m))) for m in self.monomials
        ]
        return DomainMatrix([list(r) for r in zip(*columns, strict=True)], (self.size,) * 2, self.k)

    def is_unit(self, x: sp.Symbol, tries: int = 2) -> bool:
        """Whether x is shown invertible in k[x]/I, k = Q(p): the determinant of its
        multiplication matrix, over one common denominator, is not zero at a random
        integer value of p, hence not zero as a polynomial in p (no point of I has
        x = 0). False where no value showed it (not a proof of the contrary). The
        values are drawn from their own generator, seeded by x (``_values``)."""
        entries = [e for row in self.times[self.gens.index(x)].to_list() for e in row]
        count = len(self.k.symbols)
        ctx = flint.fmpz_mpoly_ctx.get(tuple(f"p{i}" for i in range(count)), "lex")
        flat, _ = numerators(ctx, entries)
        return any(self._at(flat, value).det() != 0 for value in self._values(str(x), tries))

    def _values(self, seed: str, tries: int):
        """``tries`` random integer values of the parameters, from their own generator
        seeded by ``seed`` (the same every run; the decomposition's choices unmoved)."""
        rng = random.Random(seed)
        for _ in range(tries):
            yield [flint.fmpz(rng.randint(-1000, 1000)) for _ in self.k.symbols]

    def _at(self, flat: list, value: list) -> flint.fmpz_mat:
        """The matrix of the ``flat`` entries (polynomials over Z) at ``value``."""
        n = self.size
        return flint.fmpz_mat([[flat[i * n + j](*value) for j in range(n)] for i in range(n)])

    def multiplication_by(self, element: sp.Expr) -> DomainMatrix:
        """The matrix of multiplication by a linear form in the variables."""
        form = sp.Poly(element, *self.gens, domain=self.k)
        times = DomainMatrix.zeros((self.size, self.size), self.k)
        for i, x in enumerate(self.gens):
            c = form.coeff_monomial(x)
            if c:
                times += self.times[i] * self.k.convert(c)
        return times

    def value_split(self, element: sp.Expr) -> list[sp.Expr] | None:
        """The powers f_j^m_j of the distinct irreducible factors of the characteristic
        polynomial of multiplication by ``element`` (a linear form l), each as
        f_j^m_j(l(x)), when there are two or more: k[x]/I is the direct sum of the
        k[x]/(I + f_j^m_j(l)) (its generalised eigenspaces), so the points of I are split
        by the value of l at them and a part is cyclic wherever the whole is. None when
        it is a power of one factor. Over k = Q(p) this costs one
        fraction-free determinant det(d u - N) of polynomials whose degree grows like
        its minors, where solving for the shape position grows like the Krylov matrix's
        (far higher): splitting first keeps each solve small."""
        ring = self.k.field.ring
        ctx = flint.fmpz_mpoly_ctx.get((*(f"p{i}" for i in range(ring.ngens)), "u"), "lex")
        entries = [e for row in self.multiplication_by(element).to_list() for e in row]
        flat, d = numerators(ctx, entries, extra=1)
        if self._irreducible_at_a_value(flat, d, str(element)):
            return None  # one factor: no split
        u = ctx.gens()[-1]
        rows = [
            [d * u * int(i == j) - flat[i * self.size + j] for j in range(self.size)]
            for i in range(self.size)
        ]
        solved = bareiss(rows, self.size)  # never singular: monic in u up to d^size
        if solved is None:
            return None
        _, factors = factor_mpoly(solved[1])  # its sign is not kept: no matter here
        powers = [f**m for f, m in factors if f.degrees()[-1] > 0]
        if len(powers) < 2:
            return None
        u_symbol = sp.Dummy("u")
        gens = (*ring.symbols, u_symbol)
        return [
            sp.expand(
                sp.Poly.from_dict({m: int(c) for m, c in f.to_dict().items()}, *gens)
                .as_expr()
                .subs(u_symbol, element)
            )
            for f in powers
        ]

    def _irreducible_at_a_value(self, flat: list, d, seed: str, tries: int = 2) -> bool:
        """Whether det(d u - N) (N the ``flat`` numerators over the common denominator
        d, in Z[p, u]) is shown irreducible over Q(p): at a random integer value p0 with
        d(p0) != 0 the characteristic polynomial of N(p0) is irreducible over Q. Its
        monic factors over Q(p) have coefficients defined wherever its own are (Q[p]
        localised at p0 is integrally closed), so a factorization would specialise to
        one at p0. False where no value showed it (``_values``, seeded by ``seed``)."""
        for value in self._values(seed, tries):
            if d(*value, 0) == 0:
                continue
            _, factors = self._at(flat, [*value, 0]).charpoly().factor()
            if len(factors) == 1 and factors[0][1] == 1:
                return True
        return False

    def cyclic(self, element: sp.Expr, u: sp.Symbol):
        """(g, {x: h_x}) with g(u) = 0 and x = h_x(u) in k[x]/I for u = ``element`` (a linear
        form), when 1, u, ..., u^(D-1) span the algebra: then k[x]/I = k[u]/(g), the shape
        lemma by linear algebra. None when they do not."""
        k, size = self.k, self.size
        times = self.multiplication_by(element)
        unit = [tuple(int(j == i) for j in range(len(self.gens))) for i in range(len(self.gens))]
        if k.is_FractionField and k.domain.is_QQ:
            return _cyclic_fraction_free(
                times.to_list(),
                [self._coordinates(m) for m in [(0,) * len(self.gens), *unit]],
                k,
                u,
                self.gens,
            )
        vector = DomainMatrix([[c] for c in self._coordinates((0,) * len(self.gens))], (size, 1), k)
        powers = [vector]
        for _ in range(size):
            powers.append(times * powers[-1])
        square = DomainMatrix.hstack(*powers[:size])
        if square.rank() < size:
            return None
        targets = [powers[size]] + [
            DomainMatrix([[c] for c in self._coordinates(m)], (size, 1), k) for m in unit
        ]
        solution = square.lu_solve(DomainMatrix.hstack(*targets)).to_list()
        eliminant = sp.Poly.from_list(
            [k.one, *(-solution[i][0] for i in reversed(range(size)))], u, domain=k
        )
        solved = {
            x: sp.Poly.from_list([solution[i][j + 1] for i in reversed(range(size))], u, domain=k)
            for j, x in enumerate(self.gens)
        }
        return eliminant, solved


def _cyclic_fraction_free(times: list[list], columns: list[list], k, u: sp.Symbol, gens):
    """``_Algebra.cyclic`` over k = Q(p), the same (g, {x: h_x}), without a gcd on the
    way: the multiplication matrix T = N/d and the coordinates of 1 and of the variables
    with common denominators, the powers N^j w of the unit's numerator w in Z[p] and the
    system [w, N w, ..., N^(D-1) w] y = (N^D w, the variables) solved by fraction-free
    (Bareiss) elimination, all in FLINT's multivariate polynomials; the solution brought
    back to k once (T^j (w/e) = N^j w / (d^j e)). None when the powers do not span."""
    ring = k.field.ring
    ctx = flint.fmpz_mpoly_ctx.get(tuple(f"p{i}" for i in range(ring.ngens)), "lex")
    size = len(times)
    flat, d = numerators(ctx, [e for row in times for e in row])
    matrix = [flat[i * size : (i + 1) * size] for i in range(size)]
    (w, e), *targets = (numerators(ctx, c) for c in columns)
    if not _spans_somewhere(matrix, w, ctx.nvars()):
        return None  # decided on integers, before the powers grow in the parameters
    powers = [w]
    for _ in range(size):
        last = powers[-1]
        powers.append([sum((a * b for a, b in zip(row, last, strict=True)), ctx.from_dict({}))
                       for row in matrix])  # fmt: skip
    rows = [
        [powers[j][i] for j in range(size)] + [powers[size][i]] + [t[i] for t, _ in targets]
        for i in range(size)
    ]
    solved = bareiss(rows, size)
    if solved is None:
        return None
    numerators_, det = solved

    def element(num, den):
        return fraction(k.field, num, den)

    d_powers = [ctx.from_dict({(0,) * ring.ngens: 1})]
    for _ in range(size):
        d_powers.append(d_powers[-1] * d)
    # T^D (w/e) = sum_j x_j T^j (w/e): x_j = y_j d^j / d^D for N^D w = sum_j y_j N^j w
    eliminant = sp.Poly.from_list(
        [k.one, *(-element(numerators_[0][j], det * d_powers[size - j])
                  for j in reversed(range(size)))],
        u,
        domain=k,
    )  # fmt: skip
    # c/t = sum_j x_j T^j (w/e): x_j = y_j d^j e / t
    found = {
        x: sp.Poly.from_list(
            [
                element(numerators_[i + 1][j] * d_powers[j] * e, det * t)
                for j in reversed(range(size))
            ],
            u,
            domain=k,
        )  # fmt: skip
        for i, (x, (_, t)) in enumerate(zip(gens, targets, strict=True))
    }
    return eliminant, found


def _spans_somewhere(matrix: list[list], w: list, nvars: int, tries: int = 2) -> bool:
    """Whether w, N w, ..., N^(D-1) w (N a D x D ``matrix`` and w a vector of polynomials
    over Z in the parameters) are independent at one of a few fixed pseudo-random integer
    points: then they are over Q(p) (a minor that is not zero at a point is not zero).
    The powers are taken at the point, in integers, so that a linear form that does not
    span costs no power in the parameters. False means that they are dependent at every
    point tried, so over Q(p) too but for a chance smaller than deg/range per point;
    the caller then takes another linear form, or splits the system, which finds the
    same components (the exact elimination it saves fails on every dependent form)."""
    size = len(w)
    rng = random.Random(size)  # fixed: the same answer on every run
    for _ in range(tries):
        point = [rng.randint(-(10**12), 10**12) for _ in range(nvars)]
        at = flint.fmpz_mat([[int(entry(*point)) for entry in row] for row in matrix])
        column = flint.fmpz_mat([[int(entry(*point))] for entry in w])
        powers = [column]
        for _ in range(size - 1):
            powers.append(at * powers[-1])
        krylov = flint.fmpz_mat([[int(p[i, 0]) for p in powers] for i in range(size)])
        if krylov.rank() == size:
            return True
    return False


def standard_monomials(basis: sp.GroebnerBasis, gens) -> list[tuple[int, ...]]:
    """The exponents of the monomials no leading monomial divides (finitely many for a
    zero-dimensional ideal): a basis of k[x]/I."""
    leading = [sp.Poly(f, *gens).monoms(order=basis.order)[0] for f in basis.polys]
    found: set[tuple[int, ...]] = set()
    frontier = [(0,) * len(gens)]
    while frontier:
        monomial = frontier.pop()
        if monomial in found or any(
            all(a >= b for a, b in zip(monomial, lm, strict=True)) for lm in leading
        ):
            continue
        found.add(monomial)
        frontier += [tuple(e + (j == i) for j, e in enumerate(monomial)) for i in range(len(gens))]
    return sorted(found)


def _solved(basis: Sequence[sp.Expr], gens: Sequence[sp.Symbol]) -> dict | None:
    """{x: h(u)} when ``basis`` is {x - h(u) for x in gens} (shape position), else None."""
    if len(basis) != len(gens):
        return None
    solved = {}
    for e, x in zip(basis, gens, strict=True):
        h = sp.expand(x - e)
        if h.free_symbols & set(gens):
            return None
        solved[x] = h
    return solved


def _independent_set(basis: list[sp.Expr], variables: Sequence[sp.Symbol]) -> tuple:
    """A maximal set S of variables independent modulo the ideal: no leading monomial of
    the (graded reverse lexicographic) basis lies in k[S]; its size is the dimension."""
    supports = []
    for e in basis:
        monomial = sp.Poly(e, *variables).monoms(order="grevlex")[0]
        supports.append({x for x, m in zip(variables, monomial, strict=True) if m})
    for size in range(len(variables), -1, -1):
        for subset in itertools.combinations(variables, size):
            if not any(s <= set(subset) for s in supports):
                return subset
    return ()  # pragma: no cover - the empty set is always independent


def _no_point(basis: sp.GroebnerBasis) -> bool:
    """Whether a reduced basis is (1): its equations have no common zero."""
    return any(p.is_ground and not p.is_zero for p in basis.polys)


def _saturate(ideal, h: sp.Expr, variables, k) -> sp.GroebnerBasis:
    """The reduced basis of I : h^oo, by eliminating y from I + (1 - y h)."""
    y = sp.Dummy("y")
    return elimination([*ideal, 1 - y * h], [y], variables, k)


def same_components(ours: Sequence[Component], theirs: Sequence[Component]) -> bool:
    """Whether two decompositions found the same components, whatever linear forms put
    them in shape position: as many, and each lies in one of the other's (that one's
    equations vanish at its generic point), both ways."""

    def inside(c: Component, others: Sequence[Component]) -> bool:
        return any(all(c.vanishes(q) for q in d.equations()) for d in others)

    return (
        len(ours) == len(theirs)
        and all(inside(c, theirs) for c in ours)
        and all(inside(c, ours) for c in theirs)
    )


def _maximal(found: list[Component]) -> tuple[Component, ...]:
    """The components contained in no other (a duplicate kept once), largest first
    (``_inside``)."""
    ordered = sorted(found, key=lambda c: -c.dimension)
    kept: list[Component] = []
    for c in ordered:
        if not any(_inside(c, other) for other in kept):
            kept.append(c)
    return tuple(kept)


def _inside(c: Component, other: Component) -> bool:
    """Whether the component c lies in ``other``, of dimension at least c's. Of one
    dimension, one lies in the other only if they are the same set: over the same free
    variables, a different degree, or a different minimal polynomial of the same linear
    form, tells them apart without evaluating anything."""
    if (c.dimension, c.free) == (other.dimension, other.free):
        if c.degree != other.degree:
            return False
        if c.element == other.element and _coefficients(c) != _coefficients(other):
            return False  # the same form, another minimal polynomial: another set
    # the short equations first: one that does not vanish settles it
    return all(c.vanishes(q) for q in sorted(other.equations(), key=sp.count_ops))


def _coefficients(c: Component) -> list:
    """The coefficients of the component's (monic) minimal polynomial, highest first."""
    return c.minimal.monic().all_coeffs()
