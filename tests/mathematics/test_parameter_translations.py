"""Translations of the parameters that keep a field: found exactly, one parameter set to 0
for each, and the reduced parameters written back as the combinations they stand for."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.parameter_translations import reduction, translations

x, y, t = sp.symbols("x y t")


def kirchhoff_field(a1, a2, a3):
    """Kirchhoff's equations, moments (1, 2, 3), potential sum a_i gamma_i**2 / 2."""
    m = sp.Matrix(sp.symbols("M1:4"))
    g = sp.Matrix(sp.symbols("gamma1:4"))
    omega = sp.Matrix([m[0], m[1] / 2, m[2] / 3])
    grad = sp.Matrix([a1 * g[0], a2 * g[1], a3 * g[2]])
    return [sp.expand(e) for e in (*m.cross(omega) + g.cross(grad), *g.cross(omega))]


def along(field, parameters, v):
    """The field's derivative along v, each component simplified: zero for a translation."""
    return [
        sp.cancel(sum((c * f.diff(p) for c, p in zip(v, parameters, strict=True)), 0))
        for f in field
    ]


def test_a_potential_that_enters_through_differences_is_reduced_by_one_parameter():
    a1, a2, a3 = sp.symbols("a1 a2 a3", positive=True)
    field = kirchhoff_field(a1, a2, a3)
    assert translations(field, (a1, a2, a3)) == [[1, 1, 1]]
    r = reduction(field, (a1, a2, a3))
    assert r is not None and r.removed == (a3,)
    assert {str(k): v for k, v in r.back.items()} == {"a1": a1 - a3, "a2": a2 - a3}
    # the reduced parameters carry no sign: a1 - a3 may be negative
    assert all(p.is_positive is None for p in r.parameters)
    # the reduced field written back is the field itself
    assert [sp.expand(r.written_back(f) - g) for f, g in zip(r.field, field, strict=True)] == [
        0
    ] * 6


def test_two_independent_translations_remove_two_parameters():
    a, b, c, d = sp.symbols("a b c d")
    field = [(a - b) * x**2 + x * y / (c - d), (c - d) * y**2]
    basis = translations(field, (a, b, c, d))
    assert sorted(basis) == [[0, 0, 1, 1], [1, 1, 0, 0]]
    for v in basis:
        assert along(field, (a, b, c, d), v) == [0, 0]
    r = reduction(field, (a, b, c, d))
    assert set(r.removed) == {b, d}
    assert {str(k): v for k, v in r.back.items()} == {"a": a - b, "c": c - d}


def test_a_field_with_no_translation_is_left_alone():
    # the heavy top's centre of mass enters through gamma x (x0, y0, z0): no translation
    x0, y0, z0 = sp.symbols("x0 y0 z0")
    g1, g2, g3 = sp.symbols("gamma1:4")
    field = [y0 * g3 - z0 * g2, z0 * g1 - x0 * g3, x0 * g2 - y0 * g1]
    assert translations(field, (x0, y0, z0)) == []
    assert reduction(field, (x0, y0, z0)) is None


def test_a_translation_along_a_combination_with_rational_weights():
    # (a + 2b) enters alone: v = (2, -1) keeps it; b is the parameter set to 0
    a, b = sp.symbols("a b")
    field = [(a + 2 * b) * x**2, x * y]
    assert translations(field, (a, b)) == [[-2, 1]]
    r = reduction(field, (a, b))
    assert r.removed == (b,) and {str(k): v for k, v in r.back.items()} == {"a": a + 2 * b}
    assert sp.expand(r.written_back(r.field[0]) - field[0]) == 0
