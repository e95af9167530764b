"""Elements of Q(p) to polynomials over Z in FLINT and back: the fraction-free
computations (Gröbner bases, Bareiss elimination, determinants) work on FLINT's
``fmpz_mpoly`` and hand their results back to sympy's rings once.

Exponents and coefficients cross as Python integers both ways: sympy's elements and
FLINT's do not convert into each other under sympy's pure-Python ground types.
"""

from __future__ import annotations

import math
from typing import Any

import flint
import sympy as sp
from sympy.polys.rings import PolyRing


def numerators(ctx, entries: list, extra: int = 0) -> tuple[list, flint.fmpz_mpoly]:
    """Elements of Q(p) (sympy's fraction field over Q) as numerators in ``ctx`` over one
    common denominator (the lcm), and that denominator; ``extra``: as for ``integral``.

    >>> a = sp.Symbol("a")
    >>> K = sp.QQ.frac_field(a)
    >>> ctx = flint.fmpz_mpoly_ctx.get(("p0",), "lex")
    >>> numerators(ctx, [K.convert(a / 2), K.convert(1 / (3 * a))])
    ([3*p0^2, 2], 6*p0)
    """
    parts = [integral(ctx, e.numer, e.denom, extra) for e in entries]
    common = ctx.from_dict({(0,) * ctx.nvars(): 1})
    for _, den in parts:
        common = common * den / common.gcd(den)
    return [num * (common / den) for num, den in parts], common


def integral(
    ctx, numer, denom, extra: int = 0, before: int = 0
) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """numer/denom (polynomials of sympy's ring Q[p]) as a quotient of polynomials over Z
    in ``ctx``, a context with ``extra`` more variables after p's (``before``: before
    them)."""
    n_scale, numer = numer.clear_denoms()
    d_scale, denom = denom.clear_denoms()

    def whole(q) -> int:
        # an integer of QQ, whatever sympy's ground types (gmpy, flint or pure Python)
        return int(sp.QQ.numer(q))

    def poly(p, scale):
        pad, tail = (0,) * before, (0,) * extra
        return ctx.from_dict({(*pad, *m, *tail): whole(c) * scale for m, c in p.items()})

    return poly(numer, whole(d_scale)), poly(denom, whole(n_scale))


def to_ring(ring: PolyRing, poly: flint.fmpz_mpoly):
    """A FLINT polynomial over Z as an element of sympy's ``ring`` (same variables, same
    order)."""
    return ring.from_dict(
        {tuple(int(e) for e in m): ring.domain.convert(int(c)) for m, c in poly.to_dict().items()}
    )


def fraction(field, numer: flint.fmpz_mpoly, denom: flint.fmpz_mpoly, back=None):
    """numer/denom (FLINT polynomials over Z in the variables of ``field``'s ring, in
    the same order, or brought to that ring by ``back``) as an element of sympy's
    fraction field ``field``, in lowest terms by FLINT's gcd: the element ``field.new``
    gives, without sympy's own gcd, which dominated the shape lemma over Q(p) on the
    heavy top's balances.

    >>> a, b = sp.symbols("a b")
    >>> K = sp.QQ.frac_field(a, b)
    >>> ctx = flint.fmpz_mpoly_ctx.get(("p0", "p1"), "lex")
    >>> p0, p1 = ctx.gens()
    >>> fraction(K.field, 2 * p0**2 - 2 * p1**2, -4 * p0 - 4 * p1)
    (-a + b)/2
    """
    common = numer.gcd(denom)
    if not common.is_one():
        numer, denom = numer / common, denom / common
    if back is None:
        top, bottom = to_ring(field.ring, numer), to_ring(field.ring, denom)
    else:
        top, bottom = back(numer), back(denom)
    if bottom.LC < 0:  # sympy's canonical sign: the denominator's leading coefficient
        top, bottom = -top, -bottom
    return field.raw_new(top, bottom)


def resultant(f: sp.Poly, g: sp.Poly) -> sp.Expr:
    """Res_x(f, g) (Sylvester's determinant) of two polynomials in one variable x over Q
    or Q(p), by FLINT's
    ``fmpz_mpoly`` on their numerators: with f = F/D and g = G/E (F, G over Z[p, x], D, E
    in Z[p]), Res(f, g) = Res(F, G) / (D^deg g E^deg f). sympy's subresultants over Q(p)
    swell in its fraction arithmetic (a degree-8 discriminant over Q(B, C, gamma3): over
    two minutes); over Z[p] FLINT takes a fraction of a second.

    >>> x, a = sp.symbols("x a")
    >>> K = sp.QQ.frac_field(a)
    >>> resultant(sp.Poly(x**2 - a, x, domain=K), sp.Poly(x / a - 1, x, domain=K))
    (a - 1)/a
    """
    if f.gen != g.gen or f.domain != g.domain:
        raise ValueError("the resultant needs two polynomials in one variable over one domain")
    field, ctx = _context(f)
    (big_f, d), (big_g, e) = (_over_z(ctx, field, p) for p in (f, g))
    value = big_f.resultant(big_g, "x")
    return _quotient(value, d ** g.degree() * e ** f.degree(), _symbols(field))


def resultant_in(f: sp.Expr, g: sp.Expr, x: sp.Symbol) -> sp.Expr:
    """Res_x(f, g) of two expressions, polynomial in x and rational in their other
    symbols (``resultant`` over Q of those symbols)."""
    others = sorted((sp.sympify(f).free_symbols | sp.sympify(g).free_symbols) - {x}, key=str)
    domain = sp.QQ.frac_field(*others) if others else sp.QQ
    return resultant(sp.Poly(f, x, domain=domain), sp.Poly(g, x, domain=domain))


def discriminant(f: sp.Poly) -> sp.Expr:
    """The discriminant of a polynomial in one variable over Q or Q(p) (sympy's
    convention), by FLINT as ``resultant``: disc(F/D) = disc(F) / D^(2n - 2)."""
    if f.degree() < 1:
        return sp.discriminant(f)
    field, ctx = _context(f)
    big_f, d = _over_z(ctx, field, f)
    return _quotient(big_f.discriminant("x"), d ** (2 * f.degree() - 2), _symbols(field))


def _symbols(field) -> tuple:
    return field.symbols if field.is_FractionField else ()


def _context(f: sp.Poly):
    """f's field (Q or Q(p)) and a FLINT context for Z[p, x]."""
    field = f.domain.get_field() if f.domain.is_PolynomialRing else f.domain
    if not (field.is_QQ or field.is_ZZ or field.is_FractionField):
        raise ValueError(f"a polynomial over Q or Q(p) is needed, not over {field}")
    symbols = field.symbols if field.is_FractionField else ()
    names = (*(f"p{i}" for i in range(len(symbols))), "x")
    return field, flint.fmpz_mpoly_ctx.get(names, "lex")


def _over_z(ctx, field, f: sp.Poly) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """f over Q(p) as F/D: F over Z[p, x] (x the last variable of ``ctx``), D in Z[p]."""
    if field.is_FractionField:
        coefficients = [field.convert(c, f.domain) for c in f.rep.to_list()]
        nums, denominator = numerators(ctx, coefficients, extra=1)
    else:  # over Q: integers over the lcm of the denominators
        values = [sp.Rational(f.domain.to_sympy(c)) for c in f.rep.to_list()]
        common = math.lcm(*(int(v.q) for v in values))
        one = ctx.from_dict({}) + 1
        nums, denominator = [one * int(v * common) for v in values], one * common
    x = ctx.gens()[-1]
    n = len(nums) - 1
    total = ctx.from_dict({})
    for i, num in enumerate(nums):
        total += num * x ** (n - i)
    return total, denominator


def _quotient(numer: flint.fmpz_mpoly, denom: flint.fmpz_mpoly, symbols) -> sp.Expr:
    """numer/denom in lowest terms (their gcd divided out in FLINT), as an expression."""
    common = numer.gcd(denom)
    numer, denom = numer / common, denom / common
    if denom.leading_coefficient() < 0:
        numer, denom = -numer, -denom
    return _expr(numer, symbols) / _expr(denom, symbols)


def _expr(poly: flint.fmpz_mpoly, symbols) -> sp.Expr:
    """A FLINT polynomial over Z in the parameters (its last variable unused) as an
    expanded expression."""
    terms = []
    for monomial, c in poly.to_dict().items():
        term = sp.Integer(int(c))
        for s, e in zip(symbols, monomial, strict=False):
            if e:
                term *= s ** int(e)
        terms.append(term)
    return sp.Add(*terms)


def bareiss(rows: list[list], size: int) -> tuple[list[list], Any] | None:
    """The solutions of A y = b for the augmented rows [A | b_1 ... b_m] (A square, of
    ``size``, entries in an integral domain with exact division): per right side, the
    numerators of y over the common denominator det, by fraction-free elimination with
    fraction-free back substitution; None when A is singular."""
    previous = None
    for col in range(size):
        pivot = next((i for i in range(col, size) if not rows[i][col].is_zero()), None)
        if pivot is None:
            return None
        rows[col], rows[pivot] = rows[pivot], rows[col]
        top = rows[col]
        for i in range(col + 1, size):
            row = rows[i]
            factor = row[col]
            row[col] = top[col] * 0
            for j in range(col + 1, len(row)):
                value = top[col] * row[j] - factor * top[j]
                row[j] = value if previous is None else value / previous
        previous = top[col]
    det = rows[size - 1][size - 1]
    found = []
    for b in range(size, len(rows[0])):
        y = [None] * size
        for i in reversed(range(size)):
            value = det * rows[i][b]
            for j in range(i + 1, size):
                value -= rows[i][j] * y[j]
            y[i] = value / rows[i][i]
        found.append(y)
    return found, det
