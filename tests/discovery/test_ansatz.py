"""The ansatz's linear system: monomials by weighted degree, the level set's normal
form, the blocks, and the limits that keep a search bounded."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.discovery.ansatz import PolynomialSystem, count_monomials, weighted_monomials
from registry.errors import DiscoveryError
from registry.mathematics import mechanics as mech

LAM = sp.Symbol("lam", positive=True)
FIELD = mech.vector_field((1, 1, 1 / LAM), mech.gamma1, (0, 0, 0))
WEIGHTS = (1, 1, 1, 2, 2, 2)


@pytest.mark.parametrize("degree", range(0, 7))
def test_monomials_of_each_weighted_degree_are_all_there_and_counted(degree):
    found = weighted_monomials(degree, WEIGHTS)
    assert len(set(found)) == len(found)
    assert all(sum(a * w for a, w in zip(e, WEIGHTS, strict=True)) == degree for e in found)
    brute = sum(
        1
        for e in __import__("itertools").product(range(degree + 1), repeat=6)
        if sum(a * w for a, w in zip(e, WEIGHTS, strict=True)) == degree
    )
    assert len(found) == brute
    assert count_monomials(degree, WEIGHTS) == sum(
        len(weighted_monomials(d, WEIGHTS)) for d in range(degree + 1)
    )


def test_a_weighted_homogeneous_field_splits_the_system_by_degree():
    system = PolynomialSystem(FIELD, [LAM], WEIGHTS, 4)
    for block in system.blocks:
        assert len({system.columns[j][1] for j in block.columns}) == 1
    assert len(system.columns) == sum(len(weighted_monomials(d, WEIGHTS)) for d in (1, 2, 3, 4))


def test_entries_are_the_coefficients_of_df_dt():
    system = PolynomialSystem(FIELD, [LAM], WEIGHTS, 2)
    j = system.column_index[(0, 0, 1, 0, 0, 0)]  # F = M3
    (block,) = [b for b in system.blocks if j in b.columns]
    column = block.columns.index(j)
    entries = {(r, c): v for (r, c), v in block.entries.items() if c == column}
    # dM3/dt = (1/A - 1/B) M1 M2 + (gamma x grad U)_3 = -gamma2 here: one entry, -1
    assert list(entries.values()) == [{(0,): -1}]


def test_on_a_level_set_the_ansatz_drops_the_multiples_of_its_leading_monomial():
    system = PolynomialSystem(FIELD, [LAM], WEIGHTS, 3, [mech.S_VALUE])
    (lead,) = system.leading
    assert all(not all(a >= b for a, b in zip(e, lead, strict=True)) for e, _ in system.columns)
    assert system.reduce(system.polynomial(mech.S_VALUE)) == 0


def test_a_field_with_a_transcendental_function_or_a_cube_root_is_refused():
    for potential in (sp.sin(mech.gamma1), sp.cbrt(mech.gamma1)):
        field = mech.vector_field((1, 2, 3), potential, (0, 0, 0))
        with pytest.raises(DiscoveryError, match="not rational in the state variables|root"):
            PolynomialSystem(field, [], WEIGHTS, 2, hamiltonian=potential)


def test_a_square_root_and_a_denominator_become_variables_of_the_ring():
    """rho = sqrt(gamma1), r = 1/rho and u = 1/(1 + gamma3^2), with their relations: the
    field is polynomial in them, and rho^2 reduces to gamma1."""
    potential = sp.sqrt(mech.gamma1) + 1 / (1 + mech.gamma3**2)
    field = mech.vector_field((1, 2, 3), potential, (0, 0, 0))
    system = PolynomialSystem(field, [], WEIGHTS, 2, hamiltonian=potential)
    kinds = sorted(a.kind for a in system.space.adjoined)
    assert kinds == ["inverse", "root", "root_inverse"]
    assert all(y.ring.ngens == 9 for y in system.field)
    rho = sp.sqrt(mech.gamma1)
    assert system.polynomial(rho**2) == system.polynomial(mech.gamma1)
    assert (
        system.polynomial((1 + mech.gamma3**2) / (1 + mech.gamma3**2) ** 2 * (1 + mech.gamma3**2))
        == system.ring.one
    )
    # the normal form of rho^3 is gamma1 * rho: no power of rho above the first survives
    (monomial,) = system.polynomial(rho**3).monoms()
    assert max(monomial[: system.n]) == 1
    with pytest.raises(DiscoveryError, match="not in the system's ring"):
        system.polynomial(1 / (1 + mech.gamma2))


def test_the_size_limit_is_checked_before_the_system_is_built():
    with pytest.raises(DiscoveryError, match="more than the limit of 1,000"):
        PolynomialSystem(FIELD, [LAM], WEIGHTS, 6, max_size=1000)


def test_the_normal_form_is_the_remainder_sympy_gives():
    """``normal_form`` (a heap, each monomial placed once) leaves the same remainder as
    ``PolyElement.rem`` by a monic basis, in grevlex and in the product order the search
    uses when a parameter stands for an inverse."""
    import random

    from sympy import QQ
    from sympy.polys.orderings import ProductOrder, grevlex
    from sympy.polys.rings import PolyRing

    from registry.discovery.ansatz import normal_form

    rnd = random.Random(1)
    n = 4
    for product in (False, True):
        order = ProductOrder((grevlex, lambda m: m[:n]), (grevlex, lambda m: m[n:]))
        ring = PolyRing("x1 x2 x3 u p q".split(), QQ, order if product else grevlex)
        x1, x2, x3, u, p, q = ring.gens
        basis = [u * (x1**2 + p * x2**2 + x3) - 1, x1 * x2 * x3 - q * x2 - 1]
        basis = [g if g.LC == 1 else g.monic() for g in basis]
        for _ in range(40):
            f = sum(
                (
                    rnd.randint(-3, 3)
                    * x1 ** rnd.randint(0, 3)
                    * x2 ** rnd.randint(0, 3)
                    * x3 ** rnd.randint(0, 2)
                    * u ** rnd.randint(0, 2)
                    * p ** rnd.randint(0, 2)
                    * q ** rnd.randint(0, 1)
                    for _ in range(12)
                ),
                ring.zero,
            )
            assert normal_form(f, basis, n, product) == f.rem(basis)
