"""The normal form of the zero test: radicals and transcendental terms as new symbols,
numerators reduced modulo the radical relations (and a level set's equations)."""

import random

import sympy as sp

from registry.mathematics.mechanics import S_VALUE, gamma1, gamma2, gamma3, s
from registry.mathematics.normal_form import Atoms, numerator, prove_zero, reduce_radical

SPHERE = gamma1**2 + gamma2**2 + gamma3**2 - 1


def test_radical_identity_needs_the_relation():
    x, y = gamma1, gamma2
    product = sp.sqrt((x + y) ** 2 + 1) * sp.sqrt(x**2 + 2 * x * y + y**2 + 1)
    assert prove_zero(product - (x + y) ** 2 - 1) == "algebraic normal form"
    assert prove_zero(product - (x + y) ** 2) is None


def test_radicals_and_functions_become_symbols_with_their_relations():
    atoms = Atoms()
    root = sp.sqrt(gamma1**2 + 1)
    rewritten = atoms.rewrite(root**3 + sp.sin(gamma2) + root)
    ((rho, q, base),) = atoms.relations()
    assert (q, base) == (2, gamma1**2 + 1)
    assert rewritten.free_symbols == {rho, *atoms.others.values()}
    # rho**3 = base * rho modulo rho**2 = base
    reduced = reduce_radical(numerator(rho**3), rho, q, base)
    assert sp.expand(reduced - base * rho) == 0


def test_s_is_replaced_by_m_gamma_in_the_numerator():
    assert numerator(s - S_VALUE) == 0
    assert numerator(1 / s) == 1  # 1/(M . gamma)


def test_a_claim_that_holds_on_a_level_set_is_proven_there_only():
    residual = gamma1**2 + gamma2**2 + gamma3**2 - 1
    assert prove_zero(residual) is None
    assert prove_zero(residual, on=[SPHERE]) == "level-set reduction"
    rng = random.Random(0)
    noise = sum(rng.randint(1, 5) * g for g in (gamma1, gamma2))
    assert prove_zero(residual + noise, on=[SPHERE]) is None
