"""An algebraic candidate set split into components: rational ones become candidate sets,
points without real points go, the rest are pieces to decide at their points."""

from __future__ import annotations

import sympy as sp

from registry.discovery.components import resolve
from registry.discovery.splitting import AlgebraicSet

c = sp.Symbol("c", positive=True)
x0, y0, z0 = sp.symbols("x0 y0 z0", real=True)


def test_a_product_of_two_rational_lines_gives_two_candidate_sets():
    found = resolve(AlgebraicSet({y0: 0}, (x0**2 - 4 * z0**2,)), [c, x0, y0, z0])
    assert not found.pieces and not found.undecided
    assert sorted(found.sets, key=str) == sorted(
        [{y0: 0, x0: 2 * z0}, {y0: 0, x0: -2 * z0}], key=str
    )


def test_a_sum_of_squares_keeps_only_its_real_points():
    # x0^2 + z0^2 = 0 has the one real point x0 = z0 = 0
    found = resolve(AlgebraicSet({}, (x0**2 + 4 * z0**2,)), [c, x0, z0])
    assert found.sets == [{x0: 0, z0: 0}] and not found.pieces
    # where the branch assumed z0 != 0, nothing is left
    gone = resolve(AlgebraicSet({}, (x0**2 + 4 * z0**2,), (z0,)), [c, x0, z0])
    assert gone.sets == [] and gone.pieces == []


def test_lines_over_an_algebraic_extension_are_a_piece():
    # 49 x0^2 = 30 z0^2: two real lines, defined over Q(sqrt(30)) only
    found = resolve(AlgebraicSet({c: sp.Rational(10, 7)}, (49 * x0**2 - 30 * z0**2,)), [c, x0, z0])
    assert found.sets == []
    (piece,) = found.pieces
    assert piece.component.degree == 2 and piece.component.dimension == 1
    assert "c = 10/7" in piece.text and piece.values == {c: sp.Rational(10, 7)}


def test_a_component_that_breaks_an_assumption_is_dropped():
    found = resolve(AlgebraicSet({}, ((c + 1) * (x0**2 - 2),)), [c, x0])
    # c = -1 is not allowed (c positive); x0^2 = 2 is a piece
    assert found.sets == [] and len(found.pieces) == 1
