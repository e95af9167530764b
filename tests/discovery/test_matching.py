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
