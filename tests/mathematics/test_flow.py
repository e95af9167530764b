"""The calculus of a flow on any state (``registry/mathematics/flow.py``): derivatives with
shorthands, the Jacobi identity, Casimirs, and Liouville's divergence."""

from __future__ import annotations

import sympy as sp

from registry.dynamics import Dynamics, Vector
from registry.language.casefile import load_case
from registry.mathematics import flow
from registry.mathematics import mechanics as mech
from tests.helpers.samples import CASES

M1, M2, M3 = mech.MOMENTUM
g1, g2, g3 = mech.AXIS


def test_a_shorthand_is_differentiated_by_the_chain_rule():
    assert flow.total_diff(mech.s**2, M1, mech.SHORTHANDS) == 2 * mech.s * g1
    assert flow.total_diff(mech.s**2, M1) == 0  # no shorthand: s is a constant


def test_the_brackets_of_e3_are_poisson_and_keep_their_casimirs():
    case = load_case(CASES / "zhukovsky-gyrostat.toml")
    d = case.dynamics
    assert all(sp.expand(v) == 0 for v in flow.jacobiator(d).values())
    assert len(flow.jacobiator(d)) == 20
    assert all(sp.expand(v) == 0 for v in flow.bracket_gradient(d, g1**2 + g2**2 + g3**2))
    assert sp.expand(flow.time_derivative(d, d.hamiltonian)) == 0


def test_a_bracket_that_is_not_poisson_has_a_nonzero_jacobiator():
    x, y, z = sp.symbols("x y z", real=True)
    # {y, z} = y, {z, x} = z, {x, y} = x: in three dimensions Jacobi holds exactly when
    # P . curl P = 0 for P = (y, z, x), and here P . curl P = -(x + y + z)
    pi = sp.ImmutableMatrix([[0, x, -z], [-x, 0, y], [z, -y, 0]])
    d = Dynamics(
        variables=(x, y, z),
        vectors=(Vector("x", (x,)), Vector("y", (y,)), Vector("z", (z,))),
        field=(0, 0, 0),
        bracket=pi,
    )
    ((_, value),) = flow.jacobiator(d).items()
    assert sp.expand(value) == -(x + y + z)


def test_liouvilles_equation_tells_an_invariant_measure_from_another():
    x, y = sp.symbols("x y", real=True)
    # dx/dt = x, dy/dt = -y keeps dx dy; dx/dt = x, dy/dt = y keeps dx dy / (x y)
    keeps = Dynamics((x, y), (Vector("x", (x,)), Vector("y", (y,))), (x, -y))
    grows = Dynamics((x, y), (Vector("x", (x,)), Vector("y", (y,))), (x, y))
    assert sp.simplify(flow.divergence(keeps)) == 0
    assert sp.simplify(flow.divergence(grows)) == 2
    assert sp.simplify(flow.divergence(grows, 1 / (x * y))) == 0
    assert sp.simplify(flow.divergence(grows, 1 / (x * y) ** 2)) == -2 / (x * y) ** 2
