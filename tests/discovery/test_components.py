"""An algebraic candidate set split into components: rational ones become candidate sets,
points without real points go, the rest are pieces to decide at their points."""

from __future__ import annotations

import sympy as sp

from registry.discovery.components import NEW, resolve
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


c22, n3, m2, b31, b32 = sp.symbols("c22 n3 m2 b31 b32", real=True)


def _vanishes(equation, values) -> bool:
    return sp.cancel(sp.together(sp.sympify(equation).xreplace(values))) == 0


def test_a_quadric_whose_discriminant_is_linear_is_parametrised_by_a_new_parameter():
    # quadratic in m2 with discriminant c22 - 1/4: c22 = w**2 + 1/4, m2 = 2 c22 n3 + 2 w
    # (Wolf and Efimovskaya's e(3) family, at the Kovalevskaya ratio, has this slice)
    f = m2**2 / 4 - c22 * n3 * m2 + c22**2 * n3**2 - c22 + sp.Rational(1, 4)
    found = resolve(AlgebraicSet({}, (f,)), [c22, n3, m2])
    assert not found.pieces and not found.undecided
    (values,) = found.sets
    assert NEW in values[c22].free_symbols and _vanishes(f, values)
    # a polynomial parametrisation is preferred where there is one: nothing is missed
    assert not any(sp.denom(sp.together(v)).free_symbols for v in values.values())
    # every real point is reached: both real m2 at c22 = 5/4, n3 = 1 have a real w
    ws = sp.solve(values[c22] - sp.Rational(5, 4), NEW)
    reached = {values[m2].xreplace({NEW: w, n3: 1}) for w in ws}
    assert all(w.is_real for w in ws)
    assert reached == set(sp.solve(f.xreplace({c22: sp.Rational(5, 4), n3: 1}), m2))


def test_a_parametrisation_misses_no_point_where_its_denominators_vanish():
    # n3**2 c22**2 = c22 - 1/4: c22 = (w**2 + 1)/4, n3 = 2w/(w**2 + 1); the point
    # c22 = 1/4, n3 = 0 (w = 0) is reached, nothing is left undecided
    g = n3**2 * c22**2 - c22 + sp.Rational(1, 4)
    found = resolve(AlgebraicSet({}, (g,)), [c22, n3])
    assert not found.pieces and not found.undecided
    (values,) = found.sets
    assert _vanishes(g, values) and values[c22].xreplace({NEW: 0}) == sp.Rational(1, 4)


def test_a_parameter_the_parametrisation_equals_stays_free_instead_of_a_new_one():
    # the component of the Wolf family where b32 = 2 c22 n3/m2: its parametrisation's w
    # is -b32 itself, so the set is rational in b31, b32, m2 (Sokolov's case)
    f = b31**2 * m2**2 / 4 + c22**2 * n3**2 - c22 * m2**2
    solved = {b32: 2 * c22 * n3 / m2}
    found = resolve(AlgebraicSet(solved, (f,), (m2,)), [b31, b32, c22, n3, m2])
    assert not found.pieces and not found.undecided
    (sokolov,) = [v for v in found.sets if n3 in v]
    assert b32 not in sokolov and not any(NEW in e.free_symbols for e in sokolov.values())
    assert sp.expand(sokolov[c22] - (b31**2 + b32**2) / 4) == 0
    assert _vanishes(f, sokolov) and _vanishes(b32 - 2 * c22 * n3 / m2, sokolov)


def test_a_conic_with_no_linear_discriminant_stays_a_piece():
    # c22**2 + n3**2 = 3 m2**2: every discriminant is a quadratic form
    found = resolve(AlgebraicSet({}, (c22**2 + n3**2 - 3 * m2**2,)), [c22, n3, m2])
    assert found.sets == [] and len(found.pieces) == 1


def test_a_conic_through_a_rational_point_is_parametrised_by_the_lines_through_it():
    # x0^2 = z0^2 (p^2 + 2 p): t^2 = p^2 + 2 p has the point at infinity t = p (its
    # leading coefficient a square), and every real point has a real line through it
    p = sp.Symbol("p", positive=True)
    f = p**2 * z0**2 + 2 * p * z0**2 - x0**2
    found = resolve(AlgebraicSet({}, (f,)), [p, x0, z0])
    assert not found.pieces and not found.undecided
    (values,) = [v for v in found.sets if NEW in set().union(*(e.free_symbols for e in v.values()))]
    assert _vanishes(f, values) and set(values) == {p, x0}
    # both real points at p = 1, z0 = 1 (x0 = +-sqrt(3)) are reached by real lines
    ws = sp.solve(values[p].xreplace({z0: 1}) - 1, NEW)
    assert len(ws) == 2 and all(w.is_real for w in ws)
    reached = {sp.simplify(values[x0].xreplace({z0: 1, NEW: w})) for w in ws}
    assert reached == {sp.sqrt(3), -sp.sqrt(3)}


def test_a_conic_without_a_rational_point_stays_a_piece():
    # t^2 = 2 p^2 + 3 has no rational point (2 is not a square modulo 3): no line
    p = sp.Symbol("p", positive=True)
    found = resolve(AlgebraicSet({}, (x0**2 - z0**2 * (2 * p**2 + 3),)), [p, x0, z0])
    assert len(found.pieces) == 1 and not any(
        NEW in set().union(*(e.free_symbols for e in v.values())) for v in found.sets
    )
