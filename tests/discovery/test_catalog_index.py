"""The catalog's index: forms and numeric kinetic ratios, computed once per case."""

from __future__ import annotations

from registry.discovery.identification.catalog_index import compatible, entry, ratio_orders
from tests.helpers.catalog import catalog_case


def test_ratios_that_do_not_depend_on_the_parameters_rule_bodies_out():
    kovalevskaya = entry(catalog_case("kovalevskaya-1889-heavy-top"))
    chaplygin = entry(catalog_case("goryachev-chaplygin-1900"))
    general = entry(catalog_case("pleshakov-2007-generalized-grioli"))
    assert kovalevskaya.ratios[0] == 1  # 2C : 2C
    assert not compatible(kovalevskaya.ratios, chaplygin.ratios)
    assert compatible(kovalevskaya.ratios, general.ratios)
    assert len(ratio_orders(kovalevskaya.ratios, kovalevskaya.ratios)) == 2


def test_an_entry_is_computed_once_per_case_version(tmp_path, monkeypatch):
    monkeypatch.setenv("REGISTRY_CACHE", str(tmp_path))
    case = catalog_case("lagrange-1788-heavy-top")
    first = entry(case)
    assert entry(case) is first
    assert first.form is not None and first.size == len(case.parameters)


def test_every_catalog_case_is_indexed_or_named_with_the_reason_it_is_not():
    from tests.helpers.catalog import catalog_cases, catalog_index

    index = catalog_index()
    assert len(index.entries) == len(catalog_cases())
    unindexed = index.unindexed()
    assert all(reason for reason in unindexed.values())
    # systems in their own variables (a nonholonomic sleigh, the (omega, gamma) form)
    assert (
        "its state (v, omega) is not (M, gamma)"
        in unindexed["bloch-2015-chaplygin-sleigh-as-quoted"]
    )
    assert (
        "(p, q, r, gamma1, gamma2, gamma3)"
        in unindexed["kovalevskaya-1889-heavy-top-omega-equations"]
    )
    # a field with s over a denominator has no polynomial normal form
    assert "not polynomial" in unindexed["goryachev-1916-heavy-top"]
    assert "kovalevskaya-1889-heavy-top" not in unindexed
