"""Potentials of the tangential part of a field: found where a polynomial potential
exists, refused for a rotation field, which has none."""

import random

import pytest
import sympy as sp

from registry.mathematics import mechanics as mech
from registry.mathematics import potentials
from registry.mathematics.domain import Domain


def _random_polynomial(rng: random.Random, degree: int) -> sp.Expr:
    g, p = mech.AXIS, sp.Symbol("p", real=True)
    return sp.Add(
        *(
            sp.Rational(rng.randint(-7, 7), rng.randint(1, 4))
            * (p if rng.random() < 0.3 else 1)
            * sp.Mul(*(rng.choice(g) for _ in range(rng.randint(0, degree))))
            for _ in range(6)
        )
    )


@pytest.mark.parametrize("seed", range(8))
def test_polynomial_ansatz_finds_phi_of_a_random_psi_gamma_plus_grad_phi(seed):
    rng = random.Random(seed)
    phi, psi = _random_polynomial(rng, 4), _random_polynomial(rng, 2)
    nu = tuple(sp.expand(psi * g + sp.diff(phi, g)) for g in mech.AXIS)
    found = potentials._polynomial_ansatz(nu, Domain())
    assert found is not None
    # the tangential parts agree: gamma x (nu - grad found) = 0 identically
    tangential = [n - sp.diff(found, g) for n, g in zip(nu, mech.AXIS, strict=True)]
    rest = mech.cross(mech.AXIS, tangential)
    assert all(sp.expand(r) == 0 for r in rest)


def test_a_rotation_field_has_no_tangential_potential():
    g1, g2, g3 = mech.AXIS
    k = sp.Symbol("k", positive=True)
    domain = Domain(parameters=(k,))
    assert potentials.tangential_potential((-k * g2, k * g1, sp.Integer(0)), domain) is None
    assert potentials.tangential_potential((g3 - g2, g1, g1 * g2), domain) is None
