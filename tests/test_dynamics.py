"""The system of a case, whatever its form (``registry/dynamics.py``): weights named by
vector, shorthands written out, one equation per variable."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.dynamics import Dynamics, Vector, as_weights
from registry.language.casefile import load_case
from registry.mathematics import mechanics as mech
from tests.helpers.samples import CASES


def test_weights_come_as_pairs_from_numbers_pairs_or_a_mapping():
    assert as_weights((1, 2)) == (("M", 1), ("gamma", 2))
    assert as_weights({"omega": 1, "gamma": 2}) == (("omega", 1), ("gamma", 2))
    assert as_weights((("alpha", 2),)) == (("alpha", 2),)
    with pytest.raises(ValueError, match="positive integer"):
        as_weights({"M": 0})
    with pytest.raises(ValueError, match="two weights"):
        as_weights((("M", 1), ("M", 2)))


def test_each_variable_weighs_what_its_vector_is_given_or_its_default():
    x, y, z = sp.symbols("x y z", real=True)
    d = Dynamics(
        variables=(x, y, z),
        vectors=(Vector("x", (x,), 3), Vector("v", (y, z), 1)),
        field=(y, z, x),
    )
    assert d.weights() == (3, 1, 1)
    assert d.weights({"v": 2}) == (3, 2, 2)
    assert d.dimension == 3 and d.torque_exprs is None and d.bracket is None


def test_a_field_must_give_one_equation_per_variable():
    x, y = sp.symbols("x y", real=True)
    with pytest.raises(ValueError, match="1 equations of motion for 2 variables"):
        Dynamics(variables=(x, y), vectors=(Vector("x", (x,)), Vector("y", (y,))), field=(y,))


def test_the_papers_shorthand_s_is_written_out():
    case = load_case(CASES / "borisov-mamaev-1997.toml")
    d = case.dynamics
    assert d.variables == mech.STATE and [v.name for v in d.vectors] == ["M", "gamma"]
    assert d.expanded(mech.s * mech.gamma3) == sp.expand(mech.S_VALUE) * mech.gamma3
    assert d.torque_exprs[2] == case.system.torque[2].expr
