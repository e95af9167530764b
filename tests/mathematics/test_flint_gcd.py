"""``flint_gcd``: sympy's gcd over Z[x] by FLINT, the same result, only inside its block."""

from __future__ import annotations

import random

from sympy import ZZ
from sympy.polys.rings import PolyElement, ring

from registry.mathematics.flint_gcd import flint_gcd


def test_the_gcd_and_cofactors_are_sympys_own_and_the_original_comes_back():
    r, x, y, p = ring("x, y, p", ZZ)
    rnd = random.Random(7)

    def term():
        return (
            rnd.randint(-9, 9)
            * x ** rnd.randint(0, 3)
            * y ** rnd.randint(0, 2)
            * p ** rnd.randint(0, 2)
        )

    def random_poly():
        return sum((term() for _ in range(5)), r.zero)

    pairs = []
    for _ in range(40):
        common = random_poly() or r.one
        pairs.append((common * random_poly(), common * random_poly()))
    original = PolyElement._gcd_ZZ
    expected = [f.cofactors(g) for f, g in pairs]
    with flint_gcd():
        assert PolyElement._gcd_ZZ is not original
        with flint_gcd():  # nested blocks
            pass
        assert PolyElement._gcd_ZZ is not original
        assert [f.cofactors(g) for f, g in pairs] == expected
    assert PolyElement._gcd_ZZ is original
