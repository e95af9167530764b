"""A match: the case's parameter values and a transformation, checked exactly."""

from __future__ import annotations

from registry.discovery.identification.field_form import field_form
from registry.discovery.identification.matching import match
from tests.helpers.catalog import catalog_case


def test_the_normalised_case_is_the_general_one_at_c_1():
    mine = field_form(catalog_case("kovalevskaya-1889-heavy-top-normalised").dynamics)
    theirs = catalog_case("kovalevskaya-1889-heavy-top")
    found = match(mine, field_form(theirs.dynamics), assumptions={"C": "positive"})
    assert {str(k): str(v) for k, v in found.values.items()} == {"C": "1", "a": "c0"}
    assert found.transformation.is_identity()


def test_goryachev_chaplygins_body_is_not_kovalevskayas():
    mine = field_form(catalog_case("kovalevskaya-1889-heavy-top-normalised").dynamics)
    theirs = field_form(catalog_case("goryachev-chaplygin-1900").dynamics)
    assert match(mine, theirs, assumptions={"C": "positive"}) is None


def test_the_probe_point_is_fixed_positive_and_leaves_no_parameter():
    from registry.discovery.identification.matching import specialised

    form = field_form(catalog_case("kovalevskaya-1889-heavy-top").dynamics)
    point = specialised(form)
    assert point == specialised(form)  # the same values in every run
    assert point.parameters == ()
    assert not any(f.free_symbols & set(form.parameters) for f in point.field)
    c = point.kinetic[2, 2]  # 1/C at the point: a positive rational
    assert c.is_Rational and c > 0


def test_a_match_with_parameters_is_found_through_the_probe_and_then_generically():
    from registry.discovery.identification import matching

    mine = field_form(catalog_case("kovalevskaya-1889-heavy-top").dynamics)
    theirs = field_form(catalog_case("kovalevskaya-1889-heavy-top-normalised").dynamics)
    found = match(mine, theirs)
    assert {str(k): str(v) for k, v in found.values.items()} == {"c0": "C*a"}  # generic
    probed = matching._attempts(matching.specialised(mine), theirs, {}, [((0, 1, 2), None)])
    assert probed is not None and probed.values[next(iter(probed.values))].is_Rational


def test_the_zero_test_of_a_match_proves_only_what_holds_for_every_sign():
    """Radicals of a real parameter b, which may be negative: each identity below fails
    at b = c = -1, so none may be proven zero; those that hold for every b are."""
    import sympy as sp

    from registry.discovery.identification.matching import _is_zero

    b, c = sp.symbols("b c", real=True)
    false = [
        sp.sqrt(b * c) - sp.sqrt(b) * sp.sqrt(c),
        sp.sqrt(-b) - sp.I * sp.sqrt(b),
        sp.sqrt(1 / b) - 1 / sp.sqrt(b),
        sp.sqrt(b**3) - b ** sp.Rational(3, 2),
        sp.sqrt(b) * sp.Abs(b) - b ** sp.Rational(3, 2),
    ]
    for d in false:
        assert not _is_zero(sp.expand(d)), d
        assert sp.N(d.subs({b: -1, c: -1})) != 0
    true = [
        sp.sqrt(b) ** 3 - b * sp.sqrt(b),
        b ** sp.Rational(11, 2) * sp.sqrt(b + c) - b**5 * sp.sqrt(b) * sp.sqrt(b + c),
        (sp.sqrt(b + 1) + 1) * (sp.sqrt(b + 1) - 1) - b,
    ]
    for d in true:
        assert _is_zero(sp.expand(d)), d


def test_a_value_with_an_even_root_of_a_base_of_either_sign_is_not_allowed():
    import sympy as sp

    from registry.discovery.identification.matching import _allowed

    c1, c2 = sp.symbols("c1 c2", real=True)
    a, e = sp.symbols("a e", positive=True)
    x = sp.Symbol("x")
    assert not _allowed({x: sp.sqrt(c2 - c1)}, {"x": "real"})  # real only where c2 >= c1
    assert _allowed({x: sp.sqrt(a + e)}, {"x": "real"})
    assert _allowed({x: sp.sqrt(c2 - c1)}, {"x": "real"}, probe=True)  # a probe is lenient
    assert not _allowed({x: sp.zoo}, {}, probe=True)
