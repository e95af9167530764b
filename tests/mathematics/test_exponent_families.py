"""Special parameter values of a family of fields, each confirmed by its own analysis.

The symmetric heavy top A = B = 1, C = c, centre of mass (1, 0, 0) in the equatorial
plane: Kowalevski (Acta Math. 12 (1889) 177-232, as reviewed in JFM 21.0935.01) found
that, besides the known cases, the Laurent series carry five arbitrary constants when
two moments are equal and twice the third with the centre of gravity in the plane of
the equal moments: here c = 1/2. The search finds exactly c = 1/2 and the sphere c = 1,
and says that the search is complete; and, as the only value where every exponent is
half an integer without all being integers, Goryachev and Chaplygin's c = 1/4.
"""

from __future__ import annotations

import json

import pytest
import sympy as sp

from registry.errors import WeightedFieldError
from registry.mathematics.exponent_families import exponent_family
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, heavy_top

x, y, p, q = sp.symbols("x y p q")
c = sp.Symbol("c")


def test_the_symmetric_heavy_top_is_integral_exactly_for_kovalevskaya_and_the_sphere():
    family = exponent_family(STATE, heavy_top((1, 1, c), (1, 0, 0)), HEAVY_WEIGHTS, [c])
    assert [s.values for s in family.integer] == [{c: sp.Rational(1, 2)}, {c: 1}]
    assert family.complete_integer and family.complete_rational
    (goryachev,) = family.half_integer
    assert goryachev.values == {c: sp.Rational(1, 4)} and family.complete_half_integer
    assert {v for b in goryachev.analysis.balances for v in b.exponents.values} >= {
        -sp.Rational(1, 2),
        sp.Rational(3, 2),
    }
    kovalevskaya = family.integer[0].analysis
    assert kovalevskaya.all_integer and kovalevskaya.painleve_passes
    assert [list(b.exponents.values) for b in kovalevskaya.balances][0] == [-1, 0, 1, 2, 3, 4]
    # the generic exponents: 2c - 1 and 2 - 2c, and the roots of c l^2 - c l + 2c - 2
    factors = {f for f, _ in family.factors}
    assert {2 * c + sp.Symbol("lambda") - 2, -2 * c + sp.Symbol("lambda") + 1} <= factors
    (conic,) = [s for s in family.rational if s.index is not None]
    t = conic.index
    assert sp.simplify(conic.values[c] - 8 / (t**2 + 7)) == 0
    # the sphere and Kovalevskaya's case are exceptional: families of balances appear there
    assert all(s.notes for s in family.integer)
    json.dumps(family.as_dict())


def test_a_lotka_volterra_family_has_finitely_many_integral_members():
    """x' = x (-x + p y), y' = y (3x - 2y): exponents 4, 1 + p/2 and (4p + 8)/(3p - 2):
    p = 2m - 2 with 3m - 4 dividing 16, so p in {-10, -2, 0, 2, 6}."""
    family = exponent_family([x, y], [x * (-x + p * y), y * (3 * x - 2 * y)], [1, 1], [p])
    assert [s.values[p] for s in family.integer] == [-10, -2, 0, 2, 6]
    assert family.complete_integer
    assert all(s.analysis.all_integer for s in family.integer)
    document = family.as_dict()
    assert document["free"] == ["p"] and document["complete"]["integer"] is True
    assert {"values": {"p": "6"}}.items() <= document["special"][4].items()


def test_several_free_parameters_are_searched_and_not_claimed_complete():
    family = exponent_family([x, y], [x * (-x + p * y), y * (q * x - 2 * y)], [1, 1], [p, q])
    assert not family.complete_integer and not family.complete_rational
    assert family.integer and all(s.analysis.all_integer for s in family.integer)
    assert "not complete" in family.coverage[-1]


def test_the_analyses_at_candidate_values_run_through_the_mapper_given():
    """Each candidate's exact analysis is one call of the mapper (a worker pool's map),
    and the result is the same as in process."""
    calls: list[int] = []

    def mapper(fn, items):
        calls.append(len(items))
        return [fn(item) for item in items]

    field = [x * (-x + p * y), y * (3 * x - 2 * y)]
    mapped = exponent_family([x, y], field, [1, 1], [p], mapper=mapper)
    assert sum(calls) >= 5
    assert [s.values for s in mapped.special] == [
        s.values for s in exponent_family([x, y], field, [1, 1], [p]).special
    ]


def test_a_compatibility_condition_with_radicals_is_named_not_a_crash():
    """Wolf's set S4 with m1 free: at one balance the compatibility condition holds a
    square root of the free coefficients, so it cannot be split by their coefficients;
    the values where the Painlevé test passes are then not sought, and the coverage
    says so (this raised PolynomialError before)."""
    import registry
    from tests.helpers.samples import FAMILIES

    report = registry.analyse_exponents(
        FAMILIES / "wolf-s4-m1.toml", free=["m1"], weights={"M": 1, "gamma": 1}
    )
    assert report.result.decided
    assert any(
        "not polynomial in the free coefficients" in line
        for line in report.result.document["coverage"]
    )


def test_a_pole_that_holds_a_coordinate_of_a_family_of_balances_is_no_crash():
    """Kovalevskaya's top with its axes exchanged, c free, under weights M: 1, gamma: 1:
    a family of balances keeps a free coordinate (gamma3) in a pole of its exponents; the
    parameter equations are the factors in c alone (this raised CoercionFailed)."""
    import registry
    from tests.helpers.samples import FAMILIES

    report = registry.analyse_exponents(
        FAMILIES / "kovalevskaya-transformed.toml",
        free=["c"],
        weights={"M": 1, "gamma": 1},
        budget=60,
    )
    assert report.result.decided or "time budget" in report.result.statement


def test_a_family_of_divided_fields_is_refused_not_misread():
    """Special values are sought for polynomial fields only: the balance equations of a
    divided field are multiplied by its denominators, and their components where one
    vanishes are not balances."""
    x, y, a = sp.symbols("x y a")
    with pytest.raises(WeightedFieldError, match="polynomial fields only"):
        exponent_family([x, y], [x**2, a * y**3 / x], [1, 1], [a])
