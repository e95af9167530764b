"""The searches recorded for every case: the degree, weights and level sets follow the
case's own claims and potential; a system the method refuses is recorded as not searched,
with the reason; searching in worker processes changes nothing."""

from __future__ import annotations

from dataclasses import replace

import pytest

from registry.discovery.survey import not_searched, searched, stated_options
from registry.execution.executor import LocalPool
from registry.language.casefile import parse_case_text
from registry.model import Provenance, SearchOptions
from registry.presentation.search_output import search_document, statement

HEADER = """
id = "survey-test"
title = "t"
[source]
citation = "a test"
[parameters]
a = "real"
b = "real"
"""


def case(potential: str, *claims: tuple[str, str], inertia=("2", "2", "1")):
    """A case with this potential and these (expression, on) claims, all integrals."""
    text = HEADER + f'[system]\ninertia = {list(inertia)!r}\npotential = "{potential}"\n'
    for i, (expression, on) in enumerate(claims):
        text += f'[[claims]]\nlabel = "I{i}"\nkind = "integral"\nexpression = "{expression}"\n'
        text += f'on = ["{on}"]\n' if on else ""
    return parse_case_text(text.replace("'", '"'), "<test>")


def test_the_degree_is_the_largest_weighted_degree_of_the_claims():
    kovalevskaya = "(M1**2 - M2**2 - 4*a*gamma1)**2 + (2*M1*M2 - 4*a*gamma2)**2"
    (options,) = stated_options(case("a*gamma1", (kovalevskaya, ""), ("M3", "")))
    assert options == SearchOptions(4, (1, 2), (), ())
    (options,) = stated_options(case("a*gamma1", ("M3*gamma1**2", "")))
    assert options.degree == 5  # weights M: 1, gamma: 2


def test_a_quadratic_potential_takes_equal_weights():
    (options,) = stated_options(case("a*gamma1**2 + b*gamma2**2", ("M1*gamma1**2", "")))
    assert options.weights == (("M", 1), ("gamma", 1)) and options.degree == 3
    (options,) = stated_options(case("a*gamma1 + b*gamma2", ("M1*gamma1**2", "")))
    assert options.weights == (("M", 1), ("gamma", 2)) and options.degree == 5


def test_at_least_degree_two_and_non_polynomial_claims_set_no_degree():
    (options,) = stated_options(case("a*gamma1", ("M3", ""), ("M3/gamma3**5", "")))
    assert options.degree == 2
    (options,) = stated_options(case("a*gamma1"))
    assert options.degree == 2


def test_each_level_set_of_the_claims_is_searched_once():
    c = case("a*gamma1", ("M3", "s = 0"), ("M3**3", "s = 0"), ("M1", "M2 = 0"))
    found = stated_options(c)
    assert [[e.text for e in o.on] for o in found] == [[], ["s = 0"], ["M2 = 0"]]
    assert {o.degree for o in found} == {3}


def test_discovered_claims_do_not_raise_the_degree():
    c = case("a*gamma1", ("M3", ""), ("M3**6", ""))
    discovered = replace(c.claims[1], provenance=Provenance.DISCOVERED)
    c = replace(c, claims=(c.claims[0], discovered))
    assert [o.degree for o in stated_options(c)] == [2]


def test_a_refused_search_establishes_nothing_and_says_why():
    c = case("a*gamma1")
    options = stated_options(c)[0]
    record = not_searched(c, options, "the potential is not polynomial")
    assert not record.decided and not record.complete
    assert record.coverage == ("not searched: the potential is not polynomial",)
    sentence = statement(record)
    assert sentence.startswith("Nothing is established")
    assert "exists" not in sentence and "the potential is not polynomial" in sentence
    assert search_document(record)["decided"] is False


def test_searched_refuses_a_non_polynomial_system_and_decides_the_others():
    lagrange = case("a*gamma3", ("M3", ""))
    singular = case("a*gamma1 + b*exp(gamma3)", ("M3", ""))
    work = [(c, stated_options(c)[0]) for c in (lagrange, singular)]
    first, second = searched(work, budget=60)
    assert first.decided and first.complete and first.generic.integrals == ("M3",)
    assert not second.decided and "not rational" in second.coverage[0]


@pytest.mark.parametrize("jobs", [2])
def test_worker_processes_find_the_same(jobs):
    cases = [case("a*gamma3", ("M3", "")), case("a*gamma1", ("M3", "s = 0"))]
    work = [(c, o) for c in cases for o in stated_options(c)]
    here = list(searched(work, budget=60))
    apart = list(searched(work, budget=60, executor=LocalPool(jobs)))
    assert [s.generic for s in apart] == [s.generic for s in here]
    assert [s.options for s in apart] == [o for _, o in work]


def test_a_search_cut_short_by_its_budget_in_a_worker_says_so_and_establishes_nothing():
    # Kovalevskaya's top at degree 4 takes far more than a millisecond: the budget runs
    # out in the worker processes before the generic values are decided, and the record
    # says so: not decided, never "no integral exists"
    kovalevskaya = "(M1**2 - M2**2 - 4*a*gamma1)**2 + (2*M1*M2 - 4*a*gamma2)**2"
    c = case("a*gamma1", (kovalevskaya, ""), ("M3", ""))
    work = [(c, stated_options(c)[0])] * 2
    for cut in searched(work, budget=1e-3, executor=LocalPool(2)):
        assert not cut.decided and not cut.complete
        assert any("time budget exceeded (0.001 s)" in line for line in cut.coverage)
        sentence = statement(cut)
        assert sentence.startswith("Nothing is established") and "exists" not in sentence
        assert search_document(cut)["decided"] is False
