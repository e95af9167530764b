"""The registry as DataFrames: cases, claims and verdicts (the newest per check and
claim, or one run's), across runs and case versions."""

from __future__ import annotations

import pandas as pd

from registry.language.casefile import load_case
from registry.model import Verdict
from registry.store import frames
from registry.store.tables import ResultRow
from tests.helpers.samples import CASES
from tests.helpers.stores import audit_of, count


def test_cases_and_claims_frames(store, sample_case, other_case, case_factory):
    store.add_case(sample_case)
    store.add_case(other_case)
    store.add_case(case_factory(text="v2"))
    cases = frames.cases_frame(store)
    assert list(cases.columns) == [
        "case", "version", "title", "citation", "locator", "doi", "content_hash", "n_claims",
        "added_at", "topic", "inertia", "potential", "torque", "form", "variables",
        "hamiltonian", "kappa", "authors", "year", "source_title", "journal", "booktitle",
        "publisher", "volume", "issue", "pages", "url", "aliases",
    ]  # fmt: skip
    assert set(cases["form"]) <= {"inertia", "hamiltonian"}
    assert all(v == [] for v in cases["variables"])
    assert cases.set_index("case")["version"].to_dict() == {other_case.id: 1, sample_case.id: 2}
    assert cases.set_index("case")["n_claims"].to_dict() == {other_case.id: 0, sample_case.id: 2}

    claims = frames.claims_frame(store)
    assert list(claims.columns) == [
        "case", "version", "label", "kind", "expression", "on", "locator", "provenance",
        "notes", "search",
    ]  # fmt: skip
    assert claims["label"].tolist() == ["I1", "I2"]
    assert set(claims["version"]) == {2}
    assert claims["on"].tolist()[1] == ["gamma1**2 + gamma2**2 + gamma3**2 = 1"]


def test_the_cases_frame_shows_each_system_as_its_file_writes_it(store, sample_case):
    """Inertia form: A, B, C, U and kappa "0"; Hamiltonian form: H and kappa as written
    (so a notebook can select the so(4) cases without parsing anything)."""
    komarov = load_case(CASES / "so4" / "komarov-1981-so4-kovalevskaya.toml")
    store.add_case(sample_case)
    store.add_case(komarov)
    rows = frames.cases_frame(store).set_index("case")
    ours = rows.loc[sample_case.id]
    assert list(ours["inertia"]) == [e.text for e in sample_case.system.inertia]
    assert ours["potential"] == sample_case.system.potential.text
    assert pd.isna(ours["hamiltonian"]) and ours["kappa"] == "0"
    theirs = rows.loc[komarov.id]
    assert theirs["hamiltonian"] == "M1**2 + M2**2 + 2*M3**2 + 2*gamma1"
    assert theirs["kappa"] == "1" and list(theirs["inertia"]) == []
    assert rows.index[rows["kappa"] != "0"].tolist() == [komarov.id]


def test_latest_verdicts_follow_the_newest_run_and_keep_history(store, sample_case):
    store.add_case(sample_case)
    (stored,) = store.case_versions()
    first = store.start_run({}, code_version="x")
    store.record_case(first, stored.pk, audit_of(sample_case, stored, Verdict.VERIFIED))
    store.finish_run(first)
    second = store.start_run({}, code_version="x")
    store.record_case(
        second, stored.pk, audit_of(sample_case, stored, Verdict.REFUTED), reused=False
    )
    store.finish_run(second)

    latest = frames.verdicts_frame(store)
    assert list(latest.columns)[:10] == [
        "case", "version", "claim", "check", "verdict", "method", "reason", "run", "seconds",
        "witness",
    ]  # fmt: skip
    # one row per (case, claim or none, check): NULL claims form one partition per check
    assert len(latest) == 4
    assert set(latest["run"]) == {second}
    # missing labels are None or, with pandas' string dtype, NaN
    by_key = {(None if pd.isna(r.claim) else r.claim, r.check): r for r in latest.itertuples()}
    assert by_key[("I1", "integral")].verdict == "refuted"
    assert by_key[("I1", "integral")].witness["point"] == {"gamma1": "1", "N": "1/2"}
    assert by_key[(None, "jacobi")].verdict == "verified"
    assert by_key[(None, "jacobi")].witness is None

    assert count(store, ResultRow) == 8  # both runs kept
    assert frames.verdicts_frame(store, first)["verdict"].tolist() == ["verified"] * 4
    history = frames.runs_frame(store)
    assert history["n_refuted"].tolist() == [0, 2]


def test_latest_verdicts_span_case_versions(store, sample_case, case_factory):
    store.add_case(sample_case)
    (v1,) = store.case_versions()
    run1 = store.start_run({}, code_version="x")
    store.record_case(run1, v1.pk, audit_of(sample_case, v1))
    v2_case = case_factory(text="v2")
    store.add_case(v2_case)
    (v2,) = store.case_versions()
    run2 = store.start_run({}, code_version="x")
    store.record_case(run2, v2.pk, audit_of(v2_case, v2, Verdict.REFUTED), reused=True)
    latest = frames.verdicts_frame(store)
    assert set(zip(latest["version"], latest["run"], strict=True)) == {(2, run2)}
    assert latest["reused"].all()
    assert frames.runs_frame(store)["n_reused"].tolist() == [0, 4]


def test_every_kovalevskaya_analysis_is_a_row_and_none_is_overwritten(store, sample_case):
    """Two analyses of one case version (a later code version, say) are two rows, oldest
    first; the newest is what ``stored_exponents`` returns for those options."""
    from registry.model import ExponentOptions, ExponentResult

    store.add_case(sample_case)
    (stored,) = store.case_versions()
    options = ExponentOptions((("M", 1), ("gamma", 2)))
    first = ExponentResult(
        sample_case.id,
        sample_case.content_hash,
        options,
        {"decided": True, "homogeneous": True, "all_integer": False, "all_rational": True,
         "degrees": [2, 4], "balances": [{}, {}], "painleve": {"passes": False},
         "statement": "first"},
        1.5,
    )  # fmt: skip
    second = ExponentResult(
        first.case, first.content_hash, options, {**first.document, "statement": "second"}
    )
    a = store.record_exponents(stored.pk, first, "code-1")
    b = store.record_exponents(stored.pk, second, "code-2")
    frame = frames.exponents_frame(store)
    assert list(frame.columns) == [
        "analysis", "case", "version", "weights", "free", "decided", "homogeneous", "balances",
        "all_integer", "all_rational", "degrees", "painleve", "n_special", "statement",
        "code_version", "started_at", "seconds",
    ]  # fmt: skip
    assert frame["analysis"].tolist() == [a, b]
    assert frame["statement"].tolist() == ["first", "second"]
    assert frame.loc[0, "degrees"] == [2, 4] and frame.loc[0, "balances"] == 2
    assert frame.loc[0, "weights"] == {"M": 1, "gamma": 2} and frame.loc[0, "free"] == []
    assert store.stored_exponents(stored.pk, options, "code-1") == (a, first)
    assert store.stored_exponents(stored.pk, options)[0] == b  # the newest, any code
    assert store.newest_exponents()[sample_case.id][0] == b


def test_the_painleve_column_holds_passes_fails_and_not_made(store, sample_case):
    """The frame's ``painleve`` is true, false, or null where the test was not made: an
    analysis that computed no series, or one that was not decided (it once held false,
    which read as "fails")."""
    from registry.model import ExponentOptions, ExponentResult

    store.add_case(sample_case)
    (stored,) = store.case_versions()
    options = ExponentOptions((("M", 1), ("gamma", 2)))
    documents = [
        {"painleve": {"passes": True}},
        {"painleve": {"passes": False}},
        {"painleve": {"passes": None}},
        {"decided": False, "reason": "time budget exceeded", "painleve": {"passes": True}},
    ]
    for document in documents:
        result = ExponentResult(sample_case.id, sample_case.content_hash, options, document)
        store.record_exponents(stored.pk, result, "code")
    frame = frames.exponents_frame(store)
    assert frame["painleve"].tolist() == [True, False, None, None]
    assert frame["decided"].tolist() == [True, True, True, False]
