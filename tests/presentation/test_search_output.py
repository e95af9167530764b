"""The output of a search: the JSON document of docs/json-output.md (Search output), the text
summary and the one-sentence statement."""

from __future__ import annotations

from pathlib import Path

import pytest

from registry.api import discover_file
from registry.presentation.search_output import search_document, search_text, statement

FAMILIES = Path(__file__).resolve().parents[1] / "data" / "families"


@pytest.fixture(scope="module")
def kovalevskaya():
    return discover_file(FAMILIES / "heavy-top-lam.toml", degree=4, free=["lam"]).search


def test_the_document_has_the_contracts_keys_and_values(kovalevskaya):
    doc = search_document(kovalevskaya)
    for key in ("case", "degree", "weights", "on", "free", "known", "generic", "special",
                "complete", "seconds"):  # fmt: skip
        assert key in doc
    assert doc["case"] == "family-heavy-top-lam"
    assert doc["degree"] == 4 and doc["weights"] == {"M": 1, "gamma": 2}
    assert doc["free"] == ["lam"] and doc["on"] == []
    assert doc["known"] == ["H", "gamma1**2 + gamma2**2 + gamma3**2", "s"]
    assert doc["generic"] == {
        "extra": 0,
        "integrals": [],
        "casimir": [],
        "new": 0,
        "rediscovered": 0,
        "same_as": [],
    }
    assert [s["when"] for s in doc["special"]] == [["lam = 1"], ["lam = 2"]]
    assert doc["special"][0]["integrals"] == ["M1"] and doc["special"][0]["extra"] == 1
    assert doc["complete"] is True


def test_the_statement_says_what_exists_and_what_is_ruled_out(kovalevskaya):
    text = statement(kovalevskaya)
    assert text.startswith("No extra integral of weighted degree <= 4")
    assert "lam = 1; or lam = 2" in text and "no other values carry more" in text


def test_the_text_lists_each_set_with_its_integrals(kovalevskaya):
    text = search_text(kovalevskaya)
    assert "lam = 2: 1 extra integral(s)" in text
    assert "    M1    (integral verified; casimir refuted)" in text
    assert "complete: yes" in text


def test_the_text_lists_invariant_relations_with_their_cofactor():
    """A search for relations (Hess's, under his condition): each set lists F = 0 and its
    cofactor K; a relation has no Casimir verdict (the text once failed on that)."""
    hess = FAMILIES.parents[2] / "data" / "cases" / "heavy-top" / "hess-1890-heavy-top.toml"
    search = discover_file(hess, degree=1, relations=True).search
    lines = search_text(search).splitlines()
    assert "generic: no invariant relation" in lines
    (where,) = [x for x in lines if "1 invariant relation(s), cofactor " in x]
    assert where.startswith("K_M1 = 0, K_M3 = 0, K_M2 = ") and "cofactor M2*b*x0*z0**3/" in where
    assert "    M1*x0 + M3*z0 = 0    (dF/dt = K F verified)" in lines


def test_a_relation_that_is_a_first_integral_is_named_so_in_the_statement():
    """Suslov's problem: the energy's level sets are invariant relations with cofactor 0
    (the statement once printed "(cofactor )"), and I13 w1 + I23 w2 = 0 has its own."""
    suslov = FAMILIES.parent / "any-form" / "suslov-problem.toml"
    search = discover_file(suslov, degree=2, relations=True).search
    text = statement(search)
    assert "I11*w1**2 + I22*w2**2 = 0 (cofactor 0: first integral)" in text
    assert "I13*w1 + I23*w2 = 0 (cofactor (I11*I23*w1 - I13*I22*w2)/(I11*I22))" in text
    assert "(cofactor )" not in text


def test_claims_that_span_the_integrals_of_a_system_with_nothing_known():
    """Toda's lattice in Flaschka's variables has no known integral (no Hamiltonian, no
    bracket): its three traces span every integral of degree <= 3, said without the
    "beyond" of nothing (the statement once ended "beyond .")."""
    toda = FAMILIES.parent / "any-form" / "toda-flaschka.toml"
    search = discover_file(toda, degree=3).search
    assert search.known == () and search.generic.extra == 3
    text = statement(search)
    assert "the claims trace, trace-2, trace-3 span every integral of weighted degree <= 3." in text
    assert "beyond" not in text


def test_the_text_says_which_symmetries_split_the_ansatz():
    """Lagrange's top at degree 8: turning about axis 3 and the reflections swapping axes
    1 and 2 keep the field, and split its ansatz; the text says so."""
    search = discover_file(FAMILIES / "lagrange-lam.toml", degree=8).search
    (line,) = [x for x in search_text(search).splitlines() if x.startswith("symmetries: ")]
    assert line.startswith("symmetries: the group (Z/2)^") and "split into" in line
    assert "M1 -> M2, M2 -> M1, gamma1 -> gamma2, gamma2 -> gamma1" in line
    assert "rotation about axis 3" in line
