"""The equivalences as one change of variables: the field pushed forward, an integral
pulled back."""

from __future__ import annotations

import sympy as sp

from registry.discovery.identification.field_form import field_form
from registry.discovery.identification.transformations import Transformation, axes_matrix
from registry.mathematics import mechanics as mech
from tests.helpers.catalog import catalog_case


def test_a_signed_permutation_moves_the_axes_and_keeps_the_signs():
    p = axes_matrix((2, 1, 0), (1, -1, 1))
    assert p * sp.Matrix([1, 2, 3]) == sp.Matrix([3, -2, 1])


def test_the_identity_pulls_an_integral_back_unchanged():
    form = field_form(catalog_case("kovalevskaya-1889-heavy-top").dynamics)
    one = sp.Integer(1)
    identity = Transformation(one, one, one, sp.ImmutableMatrix(sp.eye(3)), (0, 0, 0))
    assert identity.is_identity()
    k = (mech.M1**2 - mech.M2**2) ** 2
    assert sp.expand(identity.pullback(k, form, form) - k) == 0
    assert identity.pushed(form) == identity.pulled(form)
    assert identity.description(form, form, {})["t"] == "t"
