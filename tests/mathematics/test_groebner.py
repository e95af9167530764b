"""The fraction-free Gröbner bases are sympy's reduced bases: compared with
``sympy.groebner`` on random systems over Q and Q(a, b) in both orders, on systems with
the parameters in denominators, and on the balances of a heavy top with a parameter; a
basis given back as polynomials gives the same bases; normal forms are sympy's."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from registry.mathematics import mechanics as mech
from registry.mathematics.balances import balance_equations
from registry.mathematics.groebner import NormalForms, elimination, groebner
from registry.mathematics.weighted import split_field

x, y, z, a, b = sp.symbols("x y z a b")
Q_AB = sp.QQ.frac_field(a, b)


def random_system(rng: random.Random, gens, parameters, count: int = 3) -> list[sp.Expr]:
    """``count`` polynomials of degree <= 2 in the gens with small integer coefficients,
    some of them multiplied by a parameter or divided by one."""
    monomials = [sp.Integer(1), *gens, *(p * q for p in gens for q in gens)]
    system = []
    for _ in range(count):
        terms = rng.sample(monomials, 3)
        coefficients = [rng.choice([-2, -1, 1, 3]) for _ in terms]
        if parameters:
            coefficients[0] *= rng.choice(parameters)
            coefficients[-1] /= rng.choice([*parameters, 1 + parameters[0]])
        system.append(sp.expand(sum(c * t for c, t in zip(coefficients, terms, strict=True))))
    return system


@pytest.mark.parametrize("order", ["grevlex", "lex"])
@pytest.mark.parametrize("seed", range(6))
def test_random_systems_give_sympy_s_reduced_basis(order, seed):
    rng = random.Random(seed)
    for gens, parameters, domain in (([x, y, z], [], sp.QQ), ([x, y], [a, b], Q_AB)):
        system = random_system(rng, gens, parameters, count=len(gens))
        ours = groebner(system, gens, domain, order)
        theirs = sp.groebner(system, *gens, order=order, domain=domain)
        assert ours.exprs == theirs.exprs, system
        assert ours.is_zero_dimensional == theirs.is_zero_dimensional


@pytest.mark.parametrize("seed", range(6))
def test_an_elimination_ideal_is_sympy_s_from_a_lex_basis(seed):
    """(I) ∩ k[rest] from the block order equals the lex basis's elements free of the
    eliminated variable, as a reduced grevlex basis (its elements' leading terms are
    grevlex ones: sympy's basis of those elements again)."""
    rng = random.Random(100 + seed)
    for gens, parameters, domain in (([x, y, z], [], sp.QQ), ([x, y, z], [a, b], Q_AB)):
        system = random_system(rng, gens, parameters, count=3)
        ours = elimination(system, gens[:1], gens[1:], domain)
        lex = sp.groebner(system, *gens, order="lex", domain=domain)
        kept = [e for e in lex.exprs if not e.has(gens[0])]
        theirs = sp.groebner(kept, *gens[1:], order="grevlex", domain=domain) if kept else []
        assert ours.exprs == list(theirs), system
        assert ours.gens == tuple(gens[1:])


@pytest.mark.parametrize("seed", range(4))
def test_a_basis_given_back_as_polynomials_gives_the_bases_of_its_expressions(seed):
    """Polynomials over the domain (a basis found before, in the gens or some of them,
    in another order) are read as they are: the same bases as from their expressions,
    mixed with expressions, in both orders and in an elimination."""
    rng = random.Random(200 + seed)
    system = random_system(rng, [x, y, z], [a, b], count=3)
    first = groebner(system[:2], [x, y, z], Q_AB)
    mixed = [*first.polys, system[2]]
    for order in ("grevlex", "lex"):
        for gens in ([x, y, z], [z, x, y]):
            ours = groebner(mixed, gens, Q_AB, order)
            theirs = groebner([*first.exprs, system[2]], gens, Q_AB, order)
            assert (
                ours.exprs
                == theirs.exprs
                == list(sp.groebner([*first.exprs, system[2]], *gens, order=order, domain=Q_AB))
            )
    for order in ("grevlex", "lex"):  # added to a known basis: no pairs of its own formed
        known = groebner(system[:2], [x, y, z], Q_AB, order)
        added = groebner([system[2]], [x, y, z], Q_AB, order, known=known)
        assert added.exprs == groebner(system, [x, y, z], Q_AB, order).exprs
        other = groebner([system[2]], [x, y, z], Q_AB, "lex" if order == "grevlex" else order)
        assert groebner([z], [x, y, z], Q_AB, order, known=other).exprs == list(
            sp.groebner([*other.exprs, z], x, y, z, order=order, domain=Q_AB)
        )
    t = sp.Symbol("t")
    h = first.polys[-1].as_expr() - 1
    ours = elimination([*first.polys, 1 - t * h], [t], [x, y, z], Q_AB)
    assert ours.exprs == elimination([*first.exprs, 1 - t * h], [t], [x, y, z], Q_AB).exprs
    in_xy = groebner([p for p in system if not p.has(z)] or [x * y - a], [x, y], Q_AB)
    assert groebner([*in_xy.polys, z - b], [x, y, z], Q_AB).exprs == list(
        sp.groebner([*in_xy.exprs, z - b], x, y, z, order="grevlex", domain=Q_AB)
    )


@pytest.mark.parametrize("seed", range(6))
def test_normal_forms_are_sympy_s_remainders(seed):
    """The normal form of a monomial modulo a reduced grevlex basis, by pseudo-division
    over Z[p] with one scale, equals sympy's remainder over Q(a, b) (and over Q)."""
    rng = random.Random(300 + seed)
    for gens, parameters, domain in (([x, y, z], [], sp.QQ), ([x, y, z], [a, b], Q_AB)):
        basis = groebner(random_system(rng, gens, parameters, count=3), gens, domain)
        if basis.exprs == [1]:
            continue
        forms = NormalForms(basis, domain)
        for monomial in [(2, 1, 0), (0, 3, 1), (1, 1, 2), (0, 0, 0), (4, 0, 1)]:
            term = sp.Mul(*(g**e for g, e in zip(gens, monomial, strict=True)))
            _, theirs = sp.reduced(term, basis.exprs, *gens, order="grevlex", domain=domain)
            ours = sp.Add(
                *(
                    domain.to_sympy(c) * sp.Mul(*(g**e for g, e in zip(gens, m, strict=True)))
                    for m, c in forms.of_monomial(monomial).items()
                )
            )
            assert sp.expand(ours - theirs) == 0, (basis.exprs, monomial)
    lex = groebner([x**2 - a * y, y**2 - b], [x, y], Q_AB, "lex")  # the basis's own order
    assert NormalForms(lex, Q_AB).of_monomial((0, 3)) == {(0, 1): Q_AB.convert(b)}


def test_a_saturation_by_elimination_drops_the_component_on_the_hyperplane():
    """I : x^oo as (I + (1 - t x)) ∩ k[x, y]: of the points (0, b) and (a, 1) of
    I = (x (x - a), (x - a)(y - b) + x (y - 1)) only the one off x = 0 is left; by
    x - a, only the other."""
    t = sp.Symbol("t")
    ideal = [x * (x - a), (x - a) * (y - b) + x * (y - 1)]
    saturated = elimination([*ideal, 1 - t * x], [t], [x, y], Q_AB)
    assert saturated.exprs == [x - a, y - 1]
    mutated = elimination([*ideal, 1 - t * (x - a)], [t], [x, y], Q_AB)
    assert mutated.exprs == [x, y - b]
    root = sp.QQ.algebraic_field(sp.sqrt(2))  # another domain: sympy's lex basis, filtered
    over = elimination([x**2 - 2, x * (y - 1), 1 - t * x], [t], [x, y], root)
    assert over.exprs == [x**2 - 2, y - 1]


def test_the_unit_ideal_and_a_point():
    assert groebner([x - 1, x - 2], [x], sp.QQ).exprs == [1]
    point = groebner([x * y - a, x - b / a], [x, y], Q_AB)
    assert point.exprs == [x - b / a, y - a**2 / b]


def test_a_basis_keeps_working_as_sympy_s():
    """fglm and the zero-dimensional test act on the returned basis as on sympy's."""
    system = [x**2 + a * y - 1, y**2 - b * x]
    ours = groebner(system, [x, y], Q_AB)
    assert ours.is_zero_dimensional
    assert ours.fglm("lex").exprs == sp.groebner(system, x, y, order="lex", domain=Q_AB).exprs


def test_a_denominator_in_the_variables_is_refused_and_a_float_converted_as_by_sympy():
    """A denominator in the variables is left to sympy (which refuses it); a float
    becomes the rational sympy makes of it."""
    with pytest.raises(sp.PolynomialError):
        groebner([1 / x - a], [x], Q_AB)
    system = [0.5 * x - y, x**2 - 1]
    assert (
        groebner(system, [x, y], sp.QQ).exprs
        == sp.groebner(system, x, y, order="grevlex", domain=sp.QQ).exprs
        == [y**2 - sp.Rational(1, 4), x - 2 * y]
    )


def test_the_balances_of_a_heavy_top_with_a_parameter():
    """Moments (1, B, C), centre of mass (a, 0, 0): the balance equations over Q(B, C, a)."""
    B, C, c = sp.symbols("B C a")
    field = mech.vector_field((1, B, C), c * mech.AXIS[0], (0, 0, 0))
    split = split_field(mech.STATE, [sp.expand(v) for v in field], (1, 1, 1, 2, 2, 2),
                        parameters=(B, C, c))  # fmt: skip
    equations = balance_equations(split)
    domain = sp.QQ.frac_field(B, C, c)
    ours = groebner(equations, mech.STATE, domain)
    assert ours.exprs == sp.groebner(equations, *mech.STATE, order="grevlex", domain=domain).exprs
