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


def test_a_field_with_a_radical_is_not_polynomial():
    field = mech.vector_field((1, 2, 3), sp.sqrt(mech.gamma1), (0, 0, 0))
    with pytest.raises(DiscoveryError, match="not rational in the state variables"):
        PolynomialSystem(field, [], WEIGHTS, 2)


def test_a_rational_field_is_cleared_of_its_denominator():
    field = mech.vector_field((1, 2, 3), 1 / (1 + mech.gamma1**2), (0, 0, 0))
    system = PolynomialSystem(field, [], WEIGHTS, 2)
    assert all(y.is_zero or y.ring.ngens == 6 for y in system.field)


def test_the_size_limit_is_checked_before_the_system_is_built():
    with pytest.raises(DiscoveryError, match="more than the limit of 1,000"):
        PolynomialSystem(FIELD, [LAM], WEIGHTS, 6, max_size=1000)
