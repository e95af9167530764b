"""A witness that the Painlevé test fails for generic parameter values, found by one
exact analysis at rational parameter values, where the analysis over Q(p) is too slow.

At a value p0 the balance equations F(c, p) = v(c, p) + w c = 0 of the leading part are
the specialisation of the generic ones, and their Jacobian in c is the Kovalevskaya
matrix K(c, p). A balance c0 at p0 none of whose exponents is 0 is therefore a simple
root: K(c0, p0) is invertible, and by the implicit function theorem c0 continues to a
balance c(p) of every nearby p, whose exponents (the eigenvalues of K(c(p), p)) move
continuously. An exponent of c0 that is not an integer lies at a distance d > 0 from
every integer, so the continued exponent is not an integer on a neighbourhood of p0.
(Where the field divides by polynomials D of the state, the equations solved are
multiplied by them, and their Jacobian at a balance off D = 0 is D K: the same.)

Globally: let V be the irreducible component of F = 0 through the simple point
(c0, p0); it projects onto a dense subset of the parameter space. For each tuple of
integers, the points of V where det(lambda - K) is the product of the lambda - n_i form
a closed subset, proper since it misses (c0, p0); so do the points where c = 0 or a
denominator vanishes. Their images are countably many proper algebraic subsets, a set
of measure zero, real points included (a proper complex algebraic set meets R^n in a
proper real one). At every other value some balance has an exponent that is not an
integer: the ARS test fails at generic values, as the analysis over Q(p) would have said.
That needs parameters that range over a set of positive measure: a parameter declared
integer gets no witness.

The components at p0 are taken smallest first, and each is decided from its
characteristic polynomial over Q(u)/(g) split as G H (``kovalevskaya``): its rational
exponents are G's roots, H's roots are not rational at any balance. So no balance's
exponents need be written out, and the first component that fails ends the search.
Nothing else carries over from one value: exponents that are integers at p0 may not be
elsewhere, and Yoshida's degrees need every balance of the generic system.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import flint
import sympy as sp

from . import algebraic
from .balances import Balance, balance_equations
from .exponent_analysis import BalanceResult, Painleve
from .flint_gcd import flint_gcd
from .kovalevskaya import (
    LAMBDA,
    balance_exponents,
    characteristic_polynomial,
    kovalevskaya_matrix,
)
from .prime_components import DecompositionLimit, components
from .weighted import WeightedField, WeightedFieldError, split_field

#: Parameter values tried: each costs one decomposition over Q, and a generic failure
#: shows at the first value (a second guards against a value that happens to be special).
TRIES = 2


@dataclass(frozen=True)
class Witness:
    """A simple balance with an exponent that is not an integer, at rational parameter
    ``values``: the test fails for generic values (module doc). The balance is given
    through a root of its component's minimal polynomial, its exponents as the rational
    ones and factors whose roots are not rational (``Exponents.implicit``)."""

    values: Mapping[sp.Symbol, sp.Rational]
    balance: BalanceResult


def witness(split: WeightedField, *, seed: int = 0, tries: int = TRIES) -> Witness | None:
    """A witness that the test fails at generic values of the split field's parameters
    (module doc), sought at ``tries`` values; None where none was found there, which
    proves nothing (the test may pass, or fail only at balances that are not simple)."""
    if not split.parameters or any(p.is_integer for p in split.parameters):
        return None  # none, or integers: "outside a set of measure zero" says nothing
    rng = random.Random(seed)
    for _ in range(tries):
        values = _values(split.parameters, rng)
        at = [f.xreplace(values) for f in split.field]  # split_field expands as it reads
        if any(f.has(sp.zoo, sp.nan, sp.oo) for f in at):
            continue  # a coefficient's denominator vanishes there: not a specialisation
        try:
            special = split_field(split.variables, at, split.weights, parameters=())
        except WeightedFieldError:  # the leading part vanishes there
            continue
        try:
            with flint_gcd():
                found = _failing_balance(special)
        except DecompositionLimit:  # too many branches at this value: try another
            continue
        if found is not None:
            return Witness(values, found)
    return None


def approximate(found: Witness) -> list[complex]:
    """The witness's exponents that are not rational, numerically, at one root theta of
    its component's minimal polynomial: for a reader, never for the verdict (which the
    factors over Q decide exactly). Empty where FLINT cannot isolate them."""
    component = found.balance.balance.component
    e = found.balance.exponents
    try:
        with algebraic.precision():
            theta = algebraic.flint_roots(component.minimal)[0]
            at = {component.symbol: theta}
            values = [algebraic.evaluate(v, at) for v in e.values if not v.is_rational]
            for factor, multiplicity in e.implicit:
                poly = sp.Poly(factor, LAMBDA)
                coeffs = [algebraic.evaluate(c, at) for c in reversed(poly.all_coeffs())]
                values += [r for r in flint.acb_poly(coeffs).roots() for _ in range(multiplicity)]
    except (ValueError, ZeroDivisionError):  # Unidentified is a ValueError
        return []
    numbers = [complex(float(v.real.mid()), float(v.imag.mid())) for v in values]
    return sorted(numbers, key=lambda z: (round(z.real, 9), round(z.imag, 9)))


def _values(parameters: Sequence[sp.Symbol], rng: random.Random) -> dict:
    """Distinct positive rationals m/q, small (short algebraic numbers) and not integers,
    so that an exponent such as 1 - a, an integer at every integer a, is seen to vary,
    and ratios such as 1, 2 or 4, where classical cases lie, are unlikely."""
    while True:
        numerators = rng.sample(range(3, 3 + 4 * len(parameters)), len(parameters))
        values = [sp.Rational(m, rng.choice((2, 3, 5, 7))) for m in numerators]
        if len(set(values)) == len(values) and not any(v.is_integer for v in values):
            return dict(zip(parameters, values, strict=True))


def _failing_balance(split: WeightedField) -> BalanceResult | None:
    """A simple balance of a field over Q with an exponent that is not an integer, from
    the first component, smallest first, whose characteristic polynomial shows one."""
    matrix = kovalevskaya_matrix(split)
    found = components(balance_equations(split), split.variables, ())
    for component in sorted(found, key=lambda c: c.minimal.degree()):
        if component.free or any(component.vanishes(d) for d, _ in split.denominators):
            continue  # a family (exponent 0), or no balance where the field is defined
        polynomial = characteristic_polynomial(component, matrix, norm=False)
        if any(sp.expand(f.subs(LAMBDA, 0)) == 0 for f, _ in polynomial.common):
            continue  # 0 is an exponent: not a simple root
        balance = Balance(dict(component.coordinates), component, None)
        exponents = balance_exponents(balance, polynomial)  # H's roots left implicit
        if not exponents.integer:
            return BalanceResult(balance, exponents, Painleve(()))
    return None
