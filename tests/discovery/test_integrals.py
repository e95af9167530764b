"""Extra integrals are counted modulo the algebra of the known ones, degree by degree."""

from __future__ import annotations

import sympy as sp
from sympy import QQ

from registry.discovery.ansatz import PolynomialSystem
from registry.discovery.integrals import Generator, analyse, products
from registry.discovery.linear import GF_PRIME, Field
from registry.mathematics import mechanics as mech

WEIGHTS = (1, 1, 1, 2, 2, 2)


def system_of(inertia, potential, degree=4):
    return PolynomialSystem(mech.vector_field(inertia, potential, (0, 0, 0)), [], WEIGHTS, degree)


def known(system, inertia, potential):
    exprs = [mech.hamiltonian(inertia, potential), 2 * mech.C1, mech.S_VALUE]
    polys = [system.polynomial(e) for e in exprs]
    return [Generator(p, system.weight(p)) for p in polys]


def test_products_of_generators_stay_within_the_degree():
    system = system_of((1, 2, 3), mech.gamma1, 4)
    gens = known(system, (1, 2, 3), mech.gamma1)
    found = products(system, gens, 4)
    assert len(found) == 4  # H, s, H**2, |gamma|**2
    assert all(system.weight(p) <= 4 for p in found)


def test_an_asymmetric_top_has_only_trivial_integrals_and_the_counts_say_so():
    inertia, potential = (1, 2, 3), mech.gamma1 + mech.gamma2
    system = system_of(inertia, potential)
    result = analyse(system, known(system, inertia, potential), Field(QQ, (), {}))
    assert result.extra == 0
    assert all(kernel == trivial for kernel, trivial, _ in result.counts.values())


def test_kovalevskayas_integral_is_one_extra_at_degree_four_also_modulo_a_prime():
    inertia, potential = (1, 1, sp.Rational(1, 2)), mech.gamma1
    system = system_of(inertia, potential)
    gens = known(system, inertia, potential)
    exact = analyse(system, gens, Field(QQ, (), {}))
    modular = analyse(system, gens, Field(GF_PRIME, (), {}))
    assert [d for _, d in exact.extras] == [4]
    assert exact.counts == modular.counts


def test_an_extra_integral_of_low_degree_makes_its_powers_trivial():
    inertia, potential = (1, 1, 1), mech.gamma1  # the spherical top: M1 at degree 1
    system = system_of(inertia, potential)
    result = analyse(
        system,
        known(system, inertia, potential),
        Field(QQ, (), {}),
        to_poly=lambda v: system.polynomial(
            sp.Add(
                *(
                    QQ.to_sympy(c)
                    * sp.Mul(*(x**e for x, e in zip(mech.STATE, system.columns[j][0], strict=True)))
                    for j, c in enumerate(v)
                    if c
                )
            )
        ),
    )
    assert [d for _, d in result.extras] == [1]  # M1**2, M1*H, ... are not counted again
