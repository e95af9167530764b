"""Elements of Q(p) cross to FLINT's polynomials over Z and back unchanged: numerators
over the lcm of the denominators, and the quotient rebuilt in sympy's field."""

from __future__ import annotations

import flint
import sympy as sp

from registry.mathematics.flint_polys import integral, numerators, to_ring

a, b = sp.symbols("a b")
K = sp.QQ.frac_field(a, b)
CTX = flint.fmpz_mpoly_ctx.get(("p0", "p1"), "lex")


def back(poly):
    return to_ring(K.field.ring, poly)


def test_numerators_over_the_lcm_rebuild_every_element():
    entries = [K.convert(e) for e in (a / 2 + b, 3 / (a * b), (a - b) / (6 * a**2), 0)]
    flat, common = numerators(CTX, entries)
    assert back(common).as_expr() == 6 * a**2 * b
    for entry, numerator in zip(entries, flat, strict=True):
        assert K.field.new(back(numerator), back(common)) == entry


def test_an_extra_variable_is_appended_and_left_at_degree_zero():
    ctx = flint.fmpz_mpoly_ctx.get(("p0", "p1", "u"), "lex")
    num, den = integral(ctx, K.convert(a**2 / 3).numer, K.convert(a**2 / 3).denom, extra=1)
    assert num.to_dict() == {(2, 0, 0): 1} and den.to_dict() == {(0, 0, 0): 3}
