"""Elements of Q(p) to polynomials over Z in FLINT and back: the fraction-free
computations (Gröbner bases, Bareiss elimination, determinants) work on FLINT's
``fmpz_mpoly`` and hand their results back to sympy's rings once.

Exponents and coefficients cross as Python integers both ways: sympy's elements and
FLINT's do not convert into each other under sympy's pure-Python ground types.
"""

from __future__ import annotations

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


def integral(ctx, numer, denom, extra: int = 0) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """numer/denom (polynomials of sympy's ring Q[p]) as a quotient of polynomials over Z
    in ``ctx``, a context with ``extra`` more variables after p's."""
    n_scale, numer = numer.clear_denoms()
    d_scale, denom = denom.clear_denoms()

    def whole(q) -> int:
        # an integer of QQ, whatever sympy's ground types (gmpy, flint or pure Python)
        return int(sp.QQ.numer(q))

    def poly(p, scale):
        return ctx.from_dict({(*m, *(0,) * extra): whole(c) * scale for m, c in p.items()})

    return poly(numer, whole(d_scale)), poly(denom, whole(n_scale))


def to_ring(ring: PolyRing, poly: flint.fmpz_mpoly):
    """A FLINT polynomial over Z as an element of sympy's ``ring`` (same variables, same
    order)."""
    return ring.from_dict(
        {tuple(int(e) for e in m): ring.domain.convert(int(c)) for m, c in poly.to_dict().items()}
    )
