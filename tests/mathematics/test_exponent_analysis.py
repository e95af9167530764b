"""The analysis as a whole: the JSON document of CASE_FORMAT.md, the notes for a field
that is not homogeneous, the statement, and the time for Kovalevskaya's top."""

from __future__ import annotations

import json

import sympy as sp

from registry.mathematics.exponent_analysis import exponents
from tests.helpers.clocks import cpu_bound
from tests.helpers.tops import HEAVY_WEIGHTS, STATE, heavy_top

x, y = sp.symbols("x y")


def test_the_document_has_the_keys_of_the_contract_and_is_json():
    result = exponents(STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    document = json.loads(json.dumps(result.as_dict()))
    assert {"weights", "homogeneous", "free", "balances", "all_integer", "degrees"} <= set(document)
    assert {"painleve", "statement", "seconds"} <= set(document)
    assert document["weights"] == {"M1": 1, "M2": 1, "M3": 1, "gamma1": 2, "gamma2": 2, "gamma3": 2}
    first = document["balances"][0]
    assert {"point", "exponents", "integer", "rational"} <= set(first)
    assert first["point"] == {
        "M1": "I*M2", "M2": "M2", "M3": "-2*I", "gamma1": "2", "gamma2": "-2*I", "gamma3": "0"
    }  # fmt: skip
    assert first["exponents"] == ["-1", "0", "1", "2", "3", "4"]
    assert first["dimension"] == 1 and first["free"] == ["M2"]
    assert document["all_integer"] is True and document["degrees"] == [1, 2, 3, 4]
    assert document["painleve"] == {"passes": True, "compatible": True, "conditions": []}


def test_kovalevskaya_top_takes_well_under_two_seconds():
    with cpu_bound(2.0) as used:
        exponents(STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    assert used.seconds < 2.0


def test_a_field_that_is_not_homogeneous_is_analysed_through_its_leading_part_and_says_so():
    result = exponents([x, y], [y + x**2 + x, x * y + 1], [1, 2])
    assert not result.homogeneous and result.leading == (x**2 + y, x * y)
    assert any("not weighted-homogeneous" in n and "leading part" in n for n in result.notes)
    assert result.as_dict()["homogeneous"] is False


def test_the_statement_names_the_theorems_and_claims_no_more():
    passing = exponents(STATE, heavy_top((2, 2, 1), (1, 0, 0)), HEAVY_WEIGHTS)
    assert "Yoshida" in passing.statement and "not a proof" in passing.statement
    failing = exponents([x, y], [-(x**2), x * y + 1], [1, 1])
    assert "Ablowitz, Ramani and Segur" in failing.statement
    assert "does not have the Painlevé property" in failing.statement


def test_a_field_without_balances_says_so():
    # x' = y^2, y' = 0: -c_y = 0 and then -c_x = 0
    result = exponents([x, y], [y**2, 0], [1, 1])
    assert result.balances == ()
    assert "the leading part has no balance: no Laurent solution x = c t^(-w)" in result.notes
    assert result.statement == ""


def test_balances_without_closed_forms_are_given_through_a_root_theta():
    """Over Q(a) three balances are the roots of a cubic: one entry, written with theta."""
    a = sp.Symbol("a")
    result = exponents([x, y], [a * y**2 + 2 * x**2, 2 * x**2 - 2 * x * y + y**2], [1, 1])
    (balance,) = result.balances
    document = balance.as_dict()
    assert document["point"]["y"] == "theta" and "theta" in document["point"]["x"]
    assert document["root_of"].startswith("theta**3 + ") and document["root_of"].endswith("= 0")
    assert document["exponents"][0] == "-1" and "theta" in document["exponents"][1]
    assert not balance.exponents.rational and not result.all_rational


def test_a_top_with_three_symbolic_parameters_agrees_with_its_members():
    """Bobylev's top: moments (2C, B, C), centre of mass (a, 0, 0), analysed over
    Q(B, C, a); specialised at two members it gives the exponents those members' own
    analyses over Q give, balance by balance (8 balances: 2 integer with 0, 4 with a
    double 2 and 2 with the pair 1/2 +- sqrt(8B^2 - 16BC + 9C^2)/(2C))."""
    b, c, a = sp.symbols("B C a", positive=True)
    with cpu_bound(60.0):
        generic = exponents(
            STATE, heavy_top((2 * c, b, c), (a, 0, 0)), HEAVY_WEIGHTS, parameters=[b, c, a]
        )
    assert len(generic.balances) == 8

    def texts(analysis, values=None):
        return sorted(
            tuple(sorted(str(sp.radsimp(sp.sympify(v).subs(values or {}))) for v in e))
            for e in (r.exponents.values for r in analysis.balances)
        )

    for member in ({b: 3, c: 1, a: 5}, {b: 2, c: 3, a: -1}):
        inertia = (2 * member[c], member[b], member[c])
        own = exponents(STATE, heavy_top(inertia, (member[a], 0, 0)), HEAVY_WEIGHTS)
        assert texts(generic, member) == texts(own)


def test_an_exponent_0_that_no_family_of_balances_carries_fails_the_test():
    """Hénon and Heiles's x²y + 2y³/3 (Chang, Tabor and Weiss's C/D = -2) under
    (x, y, px, py) = (2, 2, 3, 3): the balances with x != 0 need x² = 9(2 - 2) = 0, so
    the one balance left, x = 0, y = -3, is a double root with exponents -1, 0, 5, 6
    (x'' = 6x/t² there: t^3 and t^-2). No family of balances carries the exponent 0,
    so the general solution misses a constant and the test fails; its compatibility
    conditions at 5 and 6 all hold, so only the exponent 0 can decide it."""
    px, py = sp.symbols("px py")
    field = [px, py, -x - 2 * x * y, -3 * y - x**2 - 2 * y**2]
    result = exponents([x, y, px, py], field, [2, 2, 3, 3])
    (balance,) = result.balances
    assert dict(balance.balance.point) == {x: 0, y: -3, px: 0, py: 6}
    assert sorted(balance.exponents.values) == [-1, 0, 5, 6]
    assert result.all_integer and not result.painleve_passes
    (leading, *others) = balance.painleve.resonances
    assert (leading.order, leading.multiplicity, leading.missing) == (0, 1, 1)
    assert all(r.holds for r in others) and [r.order for r in others] == [5, 6]
    assert "exponent 0 has multiplicity 1 but the balance is isolated" in result.conditions[0]


def test_an_exponent_0_along_a_family_of_balances_is_its_free_coordinate():
    """Lagrange's top (1, 1, 2) with the centre on its axis: rotations about the axis
    make each balance with gamma != 0 a family of dimension 1, whose exponent 0 is that
    family's free coordinate, and the test passes."""
    result = exponents(STATE, heavy_top((1, 1, 2), (0, 0, 1)), HEAVY_WEIGHTS)
    families = [b for b in result.balances if b.balance.dimension]
    assert families and result.painleve_passes
    for b in families:
        (leading,) = [r for r in b.painleve.resonances if r.order == 0]
        assert leading.multiplicity == b.balance.dimension == len(leading.free)


def test_without_the_series_the_verdict_is_known_only_where_an_exponent_is_not_an_integer():
    """Kovalevskaya's top has integer exponents: without its series the test is not
    decided (None), and ``painleve_passes`` never says it passes; with the series it
    passes. A top with moments (1, 2, 3) has an irrational exponent: it fails either way."""
    fields = {
        "kovalevskaya": heavy_top((2, 2, 1), (1, 0, 0)),
        "distinct": heavy_top((1, 2, 3), (1, 1, 1)),
    }
    bare = {k: exponents(STATE, f, HEAVY_WEIGHTS, painleve=False) for k, f in fields.items()}
    assert bare["kovalevskaya"].painleve_verdict is None
    assert not bare["kovalevskaya"].painleve_passes
    tested = exponents(STATE, fields["kovalevskaya"], HEAVY_WEIGHTS)
    assert tested.painleve_verdict is True and tested.painleve_passes
    assert bare["distinct"].painleve_verdict is False
