"""Identification with the catalog: each normalisation of one system is found to be the
others, with the values and the transformation that carry one into the other."""

from __future__ import annotations

import pytest
import sympy as sp

from registry.discovery.identification.identify import identify
from registry.language.forms import with_values
from tests.helpers.catalog import catalog_case, catalog_index
from tests.helpers.samples import family

KOVALEVSKAYA = (
    "kovalevskaya-1889-heavy-top",
    "kovalevskaya-1889-heavy-top-normalised",
    "kovalevskaya-1889-heavy-top-equatorial",
)


@pytest.mark.parametrize("case_id", KOVALEVSKAYA)
def test_each_normalisation_of_kovalevskayas_top_is_identified_with_the_others(case_id):
    found = identify(catalog_case(case_id).dynamics, catalog_index(), exclude=(case_id,))
    same = {s.case: s for s in found.same}
    assert set(KOVALEVSKAYA) - {case_id} <= set(same)
    assert not found.skipped


def test_the_general_case_is_the_normalised_one_with_time_scaled_by_c():
    found = identify(
        catalog_case("kovalevskaya-1889-heavy-top").dynamics,
        catalog_index(),
        exclude=("kovalevskaya-1889-heavy-top",),
    )
    same = {s.case: s for s in found.same}
    normalised = same["kovalevskaya-1889-heavy-top-normalised"]
    assert normalised.values == {"c0": "C*a"}
    assert normalised.transformation["t"] == "t/C"


def test_the_equatorial_case_is_the_general_one_after_a_rotation_about_the_axis():
    found = identify(
        catalog_case("kovalevskaya-1889-heavy-top-equatorial").dynamics,
        catalog_index(),
        exclude=("kovalevskaya-1889-heavy-top-equatorial",),
    )
    general = {s.case: s for s in found.same}["kovalevskaya-1889-heavy-top"]
    a = sp.sympify(general.values["a"])
    assert sp.simplify(a**2 - sp.sympify("a**2 + b**2")) == 0  # |a| = sqrt(a^2 + b^2)
    assert "sqrt(a**2 + b**2)" in general.transformation["gamma1"]
    assert not general.identity


def test_a_point_of_a_family_with_axes_exchanged_is_identified_with_the_permutation():
    case = family("kovalevskaya-transformed")
    point = with_values(case, {case.parameters["c"]: sp.Integer(1)})
    found = identify(point.dynamics, catalog_index())
    general = {s.case: s for s in found.same}["kovalevskaya-1889-heavy-top"]
    # axes 1 and 3 exchanged (up to a sign change of axes, which time reversal allows)
    assert general.transformation["M1"].lstrip("-") == "M3"
    assert general.transformation["gamma3"].lstrip("-") == "gamma1"
    assert found.seconds < 60


def test_a_heavy_top_is_the_general_heavy_top_at_its_values_and_no_special_case():
    case = family("asymmetric-heavy-top")  # moments 1, 2, 3, centre (1, 1, 1)
    found = identify(case.dynamics, catalog_index())
    same = {s.case: s for s in found.same}
    general = same["kovalevskaya-1889-heavy-top-classical-integrals"]
    values = {"A": "1", "B": "2", "C": "3", "x0": "1", "y0": "1", "z0": "1"}
    assert general.values == values
    assert general.identity
    assert not set(KOVALEVSKAYA) & set(same)
    assert "lagrange-1788-heavy-top" not in same


def test_a_comparison_that_fails_is_named_and_the_others_still_made(monkeypatch):
    from registry.discovery.identification import identify as module

    real = module.match

    def failing(mine, theirs, **options):
        if theirs is broken.form:
            raise ArithmeticError("planted")
        return real(mine, theirs, **options)

    broken = next(e for e in catalog_index().entries if e.id == "kovalevskaya-1889-heavy-top")
    monkeypatch.setattr(module, "match", failing)
    case_id = "kovalevskaya-1889-heavy-top-normalised"
    found = identify(catalog_case(case_id).dynamics, catalog_index(), exclude=(case_id,))
    assert found.failed == (("kovalevskaya-1889-heavy-top", "ArithmeticError: planted"),)
    same = {s.case for s in found.same}
    assert "kovalevskaya-1889-heavy-top" not in same
    assert "kovalevskaya-1889-heavy-top-equatorial" in same
