"""Weights under which every component of a polynomial field keeps a leading term, found
by a mixed-integer program; checked against the weights the literature uses."""

from __future__ import annotations

import sympy as sp

from registry.dynamics import Vector
from registry.mathematics import mechanics as mech
from registry.mathematics.leading_weights import leading_weights
from registry.mathematics.weighted import split_field
from tests.helpers.tops import heavy_top

x, y, px, py, a, b, e = sp.symbols("x y px py A B e")


def scalars(*symbols):
    return [Vector(str(s), (s,)) for s in symbols]


def test_henon_heiles_gets_the_weights_of_its_cubic_part():
    """x, y: 2 and px, py: 3 (x = c t^-2, the classical balance). (1, 2, 2, 3) also
    keeps a leading term everywhere but drops x² from dpy/dt: fewer leading terms."""
    state = [x, y, px, py]
    field = [px, py, -a * x - 2 * x * y, -b * y - x**2 - e * y**2]
    weights = leading_weights(field, scalars(*state), state)
    assert weights == (("x", 2), ("y", 2), ("px", 3), ("py", 3))
    split = split_field(state, field, [w for _, w in weights], parameters=[a, b, e])
    assert split.leading == (px, py, -2 * x * y, -(x**2) - e * y**2)
    other = split_field(state, field, [1, 2, 2, 3], parameters=[a, b, e])
    assert all(v != 0 for v in other.leading)  # admissible, with one term less
    assert other.leading[3] == -e * y**2


def test_lorenz_and_the_heavy_top_get_their_usual_weights():
    """Lorenz's system: x ~ t^-1, y, z ~ t^-2 (the weights of its Painlevé analysis);
    the heavy top's state: M: 1, gamma: 2."""
    s, r, beta = sp.symbols("sigma r beta")
    lorenz = [s * (y - x), r * x - y - x * e, x * y - beta * e]
    assert leading_weights(lorenz, scalars(x, y, e), [x, y, e]) == (
        ("x", 1),
        ("y", 2),
        ("e", 2),
    )
    top = heavy_top((1, 2, 3), (1, 0, 0))
    assert leading_weights(top, mech.VECTORS, list(mech.STATE)) == (("M", 1), ("gamma", 2))


def test_no_weights_where_a_component_can_never_lead_or_the_field_divides():
    # dx/dt = x has weight w_x for every w: never w_x + 1
    assert leading_weights([x, x * y], scalars(x, y), [x, y]) is None
    assert leading_weights([x**2 / y, y**2], scalars(x, y), [x, y]) is None
    assert leading_weights([0, 0], scalars(x, y), [x, y]) is None


def test_where_no_weights_keep_every_component_most_keeps_as_many_as_possible():
    """Rössler's dx/dt = -y - z, dy/dt = x + a y, dz/dt = b + z (x - c): dy/dt leads only
    if w_x = w_y + 1, and dz/dt only if w_x = 1, so no weights keep all three; x: 1,
    y, z: 2 keep dx/dt (both terms) and dz/dt."""
    z, c = sp.symbols("z c")
    field = [-y - z, x + a * y, b + z * (x - c)]
    state = [x, y, z]
    assert leading_weights(field, scalars(*state), state) is None
    weights = leading_weights(field, scalars(*state), state, most=True)
    assert weights == (("x", 1), ("y", 2), ("z", 2))
    split = split_field(state, field, [w for _, w in weights], parameters=[a, b, c])
    assert split.leading == (-y - z, 0, x * z)
    # where weights keep every component, most gives the same
    hh = [px, py, -a * x - 2 * x * y, -b * y - x**2 - e * y**2]
    both = [leading_weights(hh, scalars(x, y, px, py), [x, y, px, py], most=m) for m in (0, 1)]
    assert both[0] == both[1] == (("x", 2), ("y", 2), ("px", 3), ("py", 3))
