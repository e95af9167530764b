"""Greatest common divisors of sympy's sparse polynomials over Z computed by FLINT.

sympy cancels every rational function of parameters (its ``FracField`` over Q(p), the
ground field of balances, exponents and series with parameters) by a gcd in Z[p] that
its heuristic algorithm (``heugcd``: big integer evaluations, in Python) computes;
in the Kovalevskaya analysis of a case with parameters nearly all the time went there.
``flint_gcd()`` has FLINT's multivariate gcd (``fmpz_mpoly``) do it instead, with the
same result: the gcd in Z[p] is unique up to its sign, which is chosen as sympy's
(a positive leading coefficient in the ring's order, and the gcd of the contents as
content), and the cofactors are the exact quotients.

The replacement is installed for the duration of a ``with flint_gcd():`` block (it
nests; the Kovalevskaya analysis uses it, ``exponent_analysis.exponents``); outside,
sympy's own algorithm runs. Being the same function of its arguments, it changes no
result anywhere, whichever thread meets it.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

import flint
from sympy.polys.rings import PolyElement

_ORIGINAL = PolyElement._gcd_ZZ
_LOCK = threading.Lock()
_DEPTH = 0


def _flint_gcd_ZZ(f: PolyElement, g: PolyElement):  # noqa: N802 - sympy's name
    """(h, f/h, g/h) with h = gcd(f, g) in Z[x] normalised as sympy's ``heugcd`` does."""
    ring = f.ring
    ctx = flint.fmpz_mpoly_ctx.get(tuple(f"x{i}" for i in range(ring.ngens)), "lex")
    # Python integers both ways: sympy's elements and FLINT's do not convert into each
    # other under sympy's pure-Python ground types
    ff, gg = (ctx.from_dict({m: int(c) for m, c in p.items()}) for p in (f, g))
    h = ff.gcd(gg)
    cff, cfg = ff / h, gg / h  # exact divisions
    back = (
        ring.from_dict(
            {
                tuple(int(e) for e in m): ring.domain.convert(int(c))
                for m, c in zip(p.monoms(), p.coeffs(), strict=True)
            }
        )
        for p in (h, cff, cfg)
    )
    h_, cff_, cfg_ = back
    if h_.LC < 0:  # sympy's sign: a positive leading coefficient in the ring's order
        return -h_, -cff_, -cfg_
    return h_, cff_, cfg_


@contextmanager
def flint_gcd() -> Iterator[None]:
    """sympy's gcd over Z[x] (and so its rational functions' cancellation) by FLINT in
    this block (module doc)."""
    global _DEPTH
    with _LOCK:
        _DEPTH += 1
        PolyElement._gcd_ZZ = _flint_gcd_ZZ
    try:
        yield
    finally:
        with _LOCK:
            _DEPTH -= 1
            if _DEPTH == 0:
                PolyElement._gcd_ZZ = _ORIGINAL
