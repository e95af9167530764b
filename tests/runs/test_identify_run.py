"""An identification run (``registry/runs/identify_run.py``): each case against the
latest version of every other case, recorded and reused for the same catalog and code
version, made again when the catalog changes or the run is fresh; history kept; the
frames and ``reg.cases()`` show what was found."""

from __future__ import annotations

from registry.execution.executor import InProcess
from registry.runs.identify_run import identify_run
from registry.store import frames
from registry.store.database import Store
from tests.helpers.samples import CASES

HEAVY = CASES / "heavy-top"
KOVALEVSKAYA = "kovalevskaya-1889-heavy-top"
NORMALISED = "kovalevskaya-1889-heavy-top-normalised"
LAGRANGE = "lagrange-1788-heavy-top"


def _store(tmp_path, *names: str) -> Store:
    store = Store(tmp_path / "r.sqlite")
    for name in names:
        store.add_case(_load(name))
    return store


def _load(name: str):
    from registry.language.casefile import load_case

    return load_case(HEAVY / f"{name}.toml")


def test_normalisations_are_one_system_both_ways_and_a_family_contains_its_member(tmp_path):
    store = _store(tmp_path, KOVALEVSKAYA, NORMALISED, LAGRANGE, "hess-1890-heavy-top")
    found = {f.case: f for f in identify_run(store, None, InProcess())}
    assert {s.case for s in found[KOVALEVSKAYA].same_as} == {NORMALISED}
    assert {s.case for s in found[NORMALISED].same_as} == {KOVALEVSKAYA}
    (same,) = found[KOVALEVSKAYA].same_as
    assert dict(same.values) == {"c0": "C*a"}  # the normalised top's c0, time scaled by C
    assert dict(same.transformation)["t"] == "t/C"
    assert not found[LAGRANGE].same_as  # neither a normalisation of Kovalevskaya's nor Hess's
    assert all(f.complete and not f.reused for f in found.values())
    table = frames.case_table(store).set_index("case")
    assert table.loc[KOVALEVSKAYA, "same_as"] == [NORMALISED]
    assert table.loc[KOVALEVSKAYA, "equivalent"] == [NORMALISED]
    pairs = frames.identifications_frame(store)
    assert set(zip(pairs["case"], pairs["same_as"], pairs["equivalent"], strict=True)) == {
        (KOVALEVSKAYA, NORMALISED, True),
        (NORMALISED, KOVALEVSKAYA, True),
    }
    store.close()


def test_a_member_is_the_general_case_one_way_only(tmp_path):
    general = "kovalevskaya-1889-heavy-top-classical-integrals"
    store = _store(tmp_path, LAGRANGE, general)
    found = {f.case: f for f in identify_run(store, None, InProcess())}
    (same,) = found[LAGRANGE].same_as  # Lagrange's top: A = B, centre on the axis
    assert same.case == general
    assert dict(same.values) == {"A": "A", "B": "A", "C": "C", "x0": "0", "y0": "0", "z0": "a"}
    assert not found[general].same_as  # the general top is no Lagrange top
    table = frames.case_table(store).set_index("case")
    assert table.loc[LAGRANGE, "same_as"] == [general]
    assert table.loc[LAGRANGE, "equivalent"] == []
    assert table.loc[general, "same_as"] == []  # identified: none, not unknown
    store.close()


def test_a_recorded_identification_is_reused_until_the_catalog_changes(tmp_path):
    store = _store(tmp_path, KOVALEVSKAYA, NORMALISED)
    here = InProcess()
    (first,) = identify_run(store, [KOVALEVSKAYA], here)
    (again,) = identify_run(store, [KOVALEVSKAYA], here)
    assert again.reused and again.same_as == first.same_as and again.catalog == first.catalog
    (fresh,) = identify_run(store, [KOVALEVSKAYA], here, fresh=True)
    assert not fresh.reused
    store.add_case(_load("kovalevskaya-1889-heavy-top-equatorial"))
    (grown,) = identify_run(store, [KOVALEVSKAYA], here)
    assert not grown.reused and grown.catalog != first.catalog
    assert {s.case for s in grown.same_as} == {NORMALISED, "kovalevskaya-1889-heavy-top-equatorial"}
    assert store.catalog_digest() == grown.catalog
    table = frames.case_table(store).set_index("case")
    assert table.loc[KOVALEVSKAYA, "identification_current"]
    assert not table.loc[NORMALISED, "identification_current"]  # against the older catalog
    with store.read() as session:
        from sqlalchemy import func, select

        from registry.store.tables import IdentificationRow

        assert session.scalar(select(func.count()).select_from(IdentificationRow)) == 3
    store.close()


def test_cases_never_identified_are_unknown_not_none(tmp_path):
    store = _store(tmp_path, KOVALEVSKAYA)
    table = frames.case_table(store)
    assert table.loc[0, "same_as"] is None and table.loc[0, "equivalent"] is None
    store.close()


def test_the_main_job_says_whether_the_catalog_was_identified(tmp_path):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "scripts" / "audit.py"
    spec = importlib.util.spec_from_file_location("main_job", path)
    main_job = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(main_job)
    store = _store(tmp_path, KOVALEVSKAYA, NORMALISED, LAGRANGE)
    assert main_job.identification_line(frames.case_table(store)).startswith(
        "Same systems: not identified yet; registry identify compares every case"
    )
    identify_run(store, None, InProcess())
    assert main_job.identification_line(frames.case_table(store)) == (
        "Same systems: 2 of 3 identified cases are the same system as another case; "
        "see reg.identifications()"
    )
    store.close()
