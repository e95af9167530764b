"""The field F = k[u]/(g) of a component of balances (k = Q or Q(p)), with symbols f
adjoined, computed over Z[p] by FLINT.

The Kovalevskaya matrix's characteristic polynomial and the Laurent series of a
component over several parameters spent nearly all their time in sympy's fractions
of Q(p): a gcd in Z[p] after every product of coefficients (Clebsch's curve of
Kirchhoff balances, eight points over Q(B, C, gamma3): minutes). Here an element is one
fraction N/D: with g = G/c, G over Z[p] of leading coefficient l, the element v = l u
is a root of the monic G~(v) = l^(d-1) G(v/l) over Z[p], and every element of F[f] is
N(v, f)/D with N over Z[p] of degree < d in v and D in Z[p]. Sums and products are
FLINT's; ``reduce`` divides by the monic G~ (exact over Z) and cancels gcd(N, D); an
inverse solves N's multiplication matrix by fraction-free elimination. Elements go
back to sympy's k[u, f] (``exported``) only where a result leaves the computation.
"""

from __future__ import annotations

from collections.abc import Sequence

import flint
import sympy as sp
from sympy.polys.orderings import lex
from sympy.polys.rings import PolyElement, PolyRing

from .flint_polys import bareiss, fraction, integral


class Element:
    """N/D in F[f] (module doc): ``numer`` over Z[p] in v and f, ``denom`` in Z[p]. The
    arithmetic is exact but does not reduce; ``IntegralAlgebra.reduce`` does."""

    __slots__ = ("denom", "numer")

    def __init__(self, numer: flint.fmpz_mpoly, denom: flint.fmpz_mpoly):
        self.numer, self.denom = numer, denom

    @property
    def is_zero(self) -> bool:
        """Zero in F when reduced (every value the algebra hands out is)."""
        return self.numer.is_zero()

    def _other(self, other) -> Element:
        if isinstance(other, Element):
            return other
        zero = self.denom.context().from_dict({})
        return Element(zero + int(other), zero + 1)  # an integer n as n/1

    def __add__(self, other) -> Element:
        other = self._other(other)
        if self.denom == other.denom:
            return Element(self.numer + other.numer, self.denom)
        common = self.denom.gcd(other.denom)
        a, b = self.denom / common, other.denom / common
        return Element(self.numer * b + other.numer * a, self.denom * b)

    __radd__ = __add__

    def __neg__(self) -> Element:
        return Element(-self.numer, self.denom)

    def __sub__(self, other) -> Element:
        return self + (-self._other(other))

    def __rsub__(self, other) -> Element:
        return self._other(other) - self

    def __mul__(self, other) -> Element:
        if isinstance(other, int):
            return Element(self.numer * other, self.denom)
        other = self._other(other)
        return Element(self.numer * other.numer, self.denom * other.denom)

    __rmul__ = __mul__


class IntegralAlgebra:
    """F[f] = (k[u]/(g))[f] for the minimal polynomial ``minimal`` of ``symbol`` over k
    (Q or sympy's Q(p)) and ``symbols`` f (module doc)."""

    def __init__(self, symbol: sp.Symbol, minimal: sp.Poly, symbols: Sequence[sp.Symbol] = ()):
        domain = minimal.domain
        self.field = domain.get_field() if domain.is_PolynomialRing else domain
        if not (self.field.is_QQ or self.field.is_FractionField):
            raise ValueError(f"the algebra needs g over Q or Q(p), not over {self.field}")
        self.symbol, self.symbols = symbol, tuple(symbols)
        self.parameters = self.field.symbols if self.field.is_FractionField else ()
        self.degree = minimal.degree()
        self._offset = 1 + len(self.symbols)  # v, f..., then the parameters
        names = ("v", *(f"f{i}" for i in range(len(self.symbols))))
        names += tuple(f"p{i}" for i in range(len(self.parameters)))
        self.ctx = flint.fmpz_mpoly_ctx.get(names, "lex")
        self._one = self.ctx.from_dict({}) + 1
        self.zero = Element(self.ctx.from_dict({}), self._one)
        self.one = Element(self._one, self._one)
        # G = sum G_i u^i over Z[p] (one common denominator), G~ = sum G_i l^(d-1-i) v^i
        terms = [self._coefficient(c) for c in reversed(minimal.rep.to_list())]
        common = self._one
        for _, den in terms:
            common = common * den / common.gcd(den)
        big = [num * (common / den) for num, den in terms]
        self.lead = big[-1]
        v = self.ctx.gens()[0]
        self.modulus = sum(
            (big[i] * self.lead ** (self.degree - 1 - i) * v**i for i in range(self.degree)),
            v**self.degree,
        )
        self._export_ring = PolyRing([symbol, *self.symbols], self.field, lex)

    # -- into the algebra ----------------------------------------------------------------

    def _coefficient(self, c) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
        """An element of k as (numerator, denominator) over Z[p] in this context."""
        if self.field.is_QQ:
            q = self.field.convert(c)
            return self._one * int(sp.QQ.numer(q)), self._one * int(sp.QQ.denom(q))
        e = self.field.convert(c)
        return integral(self.ctx, e.numer, e.denom, before=self._offset)

    def lift(self, poly: sp.Poly) -> Element:
        """A polynomial in u over k (sympy's Poly) as a reduced element: u = v / l."""
        v = self.ctx.gens()[0]
        total = self.zero
        for (i,), c in poly.as_dict(native=True).items():
            num, den = self._coefficient(c)
            total = total + Element(num * v**i, den * self.lead**i)
        return self.reduce(total)

    def variable(self, symbol: sp.Symbol) -> Element:
        """One of the adjoined symbols f."""
        return Element(self.ctx.gens()[1 + self.symbols.index(symbol)], self._one)

    # -- arithmetic ------------------------------------------------------------------------

    def reduce(self, x: Element) -> Element:
        """x with its numerator reduced modulo G~ (degree < d in v) and in lowest terms."""
        numer = x.numer
        if numer.degrees()[0] >= self.degree:
            numer = divmod(numer, self.modulus)[1]
        if numer.is_zero():
            return self.zero
        common = numer.gcd(x.denom)
        if common.leading_coefficient() < 0:
            common = -common
        numer, denom = numer / common, x.denom / common
        if denom.leading_coefficient() < 0:
            numer, denom = -numer, -denom
        return Element(numer, denom)

    def inverse(self, x: Element) -> Element:
        """1/x in F, for x free of the symbols f: y with N y = det e_0 for N's
        multiplication matrix (fraction-free elimination), 1/x = D y / det."""
        degrees = x.numer.degrees()
        if any(d for d in degrees[1 : self._offset]):
            raise ValueError("only an element free of the adjoined symbols has an inverse here")
        if x.numer.is_zero():
            raise ZeroDivisionError("the element is zero in the component's field")
        if degrees[0] == 0:  # an element of k
            return self.reduce(Element(x.denom, x.numer))
        v = self.ctx.gens()[0]
        columns = []
        power = x.numer
        for j in range(self.degree):
            if j:
                power = divmod(power * v, self.modulus)[1]
            columns.append(self._in_v(power))
        rows = [
            [columns[j][i] for j in range(self.degree)] + [self._one if i == 0 else self.zero.numer]
            for i in range(self.degree)
        ]
        solved = bareiss(rows, self.degree)
        if solved is None:
            raise ZeroDivisionError("the element is zero in the component's field")
        (y,), det = solved
        numer = sum((y[i] * v**i for i in range(self.degree)), self.zero.numer)
        return self.reduce(Element(numer * x.denom, det))

    def in_ground(self, x: Element) -> bool:
        """Whether x lies in k (free of u and of the symbols f): its inverse is cheap."""
        return not any(x.numer.degrees()[: self._offset])

    def _in_v(self, numer: flint.fmpz_mpoly) -> list[flint.fmpz_mpoly]:
        """The coefficients of v^0, ..., v^(d-1) of a numerator free of f, over Z[p]."""
        parts: list[dict] = [{} for _ in range(self.degree)]
        for monomial, c in numer.to_dict().items():
            parts[monomial[0]][(0, *monomial[1:])] = c
        return [self.ctx.from_dict(p) for p in parts]

    # -- out of the algebra ----------------------------------------------------------------

    def exported(self, x: Element) -> PolyElement:
        """x as an element of sympy's k[u, f] (v^i = l^i u^i), coefficients in lowest
        terms."""
        ring = self._export_ring
        powers = [self._one]
        terms: dict[tuple[int, ...], flint.fmpz_mpoly] = {}
        for monomial, c in x.numer.to_dict().items():
            i = monomial[0]
            while len(powers) <= i:
                powers.append(powers[-1] * self.lead)
            head = tuple(int(e) for e in monomial[: self._offset])
            tail = tuple(int(e) for e in monomial[self._offset :])
            piece = self.ctx.from_dict({(0,) * self._offset + tail: int(c)})
            terms[head] = terms.get(head, self.zero.numer) + piece * powers[i]
        return ring.from_dict({m: self._to_field(num, x.denom) for m, num in terms.items()})

    def poly(self, x: Element) -> sp.Poly:
        """An element free of the symbols f as a polynomial in u over k."""
        element = self.exported(x)
        coefficients = {(m[0],): c for m, c in element.items()} or {(0,): self.field.zero}
        return sp.Poly.from_dict(coefficients, self.symbol, domain=self.field)

    def _to_field(self, numer: flint.fmpz_mpoly, denom: flint.fmpz_mpoly):
        """numer/denom (both in the parameters only) as an element of k."""
        if self.field.is_QQ:
            constant = (0,) * self.ctx.nvars()
            value = sp.Rational(
                int(numer.to_dict().get(constant, 0)), int(denom.to_dict()[constant])
            )
            return self.field.convert(value)
        ring = self.field.field.ring
        offset = self._offset

        def back(p):
            return ring.from_dict(
                {
                    tuple(int(e) for e in m[offset:]): ring.domain.convert(int(c))
                    for m, c in p.to_dict().items()
                }
            )

        return fraction(self.field.field, numer, denom, back)
