"""``registry discover`` and ``Registry.discover``: searches recorded, reused, queried
as DataFrames, their integrals added as claims that the next audit decides; on SQLite
and on PostgreSQL (fixture ``backend``)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from tests.helpers.databases import rows

FAMILIES = Path(__file__).resolve().parent / "data" / "families"
HEAVY = FAMILIES / "heavy-top-lam.toml"


def test_record_then_audit_verifies_every_discovered_claim(db_target):
    with registry.open(db_target) as reg:
        report = reg.discover(HEAVY, degree=3, free=["lam"], on=["s = 0"], record=True)
        assert report.number == 1 and not report.reused
        assert report.derived == (
            "family-heavy-top-lam-where-lam-1",
            "family-heavy-top-lam-where-lam-4",
        )
        reg.audit(jobs=1)
        claims = reg.claims()
        found = claims[claims.provenance == "discovered"]
        assert set(found.case) == set(report.derived)
        v = reg.verdicts()
        integral = v[(v.check == "integral") & v.case.isin(report.derived)]
        assert list(integral.verdict) == ["verified", "verified"]
        assert reg.verify_db().problems == ()


def test_a_derived_case_s_level_set_holds_the_set_s_values(tmp_path):
    # The gyrostat's Casimir s + k.gamma holds the free parameters: the derived case at
    # k1 = k2 = 0 declares neither, so its claims' level set must not name them either.
    with registry.open(tmp_path / "r.sqlite") as reg:
        on = "M1*gamma1 + M2*gamma2 + M3*gamma3 + k1*gamma1 + k2*gamma2 + k3*gamma3 = 0"
        report = reg.discover(
            FAMILIES / "goryachev-chaplygin-gyrostat.toml",
            degree=3,
            weights={"M": 1, "gamma": 2},
            on=[on],
            free=["k1", "k2", "k3"],
            record=True,
            jobs=1,
        )
        (derived,) = report.derived
        reg.audit(jobs=1)
        claims = reg.claims()
        (level,) = claims[claims.case == derived].on
        assert level == ["M1*gamma1 + M2*gamma2 + M3*gamma3 + gamma3*k3 = 0"]
        v = reg.verdicts()
        assert list(v[(v.check == "integral") & (v.case == derived)].verdict) == ["verified"]


def test_generic_integrals_become_claims_of_the_searched_version(db_target):
    with registry.open(db_target) as reg:
        reg.add(FAMILIES / "lagrange-lam.toml")
        reg.discover("family-lagrange-lam", degree=2, free=["lam"], record=True)
        case = reg.case("family-lagrange-lam")
        (discovered,) = [c for c in case.claims if c.provenance == "discovered"]
        assert discovered.expression.text == "M3"
        run = reg.audit(jobs=1)
        outcome = [o for o in run.outcomes() if o.case_id == "family-lagrange-lam"][0]
        (claim,) = [c for c in outcome.claims if c.label == discovered.label]
        assert str(claim.integral.verdict) == "verified"
        assert reg.verify_db().problems == ()
        # the file added again is unchanged: the discovered claim stays with its version
        (again,) = reg.add(FAMILIES / "lagrange-lam.toml")
        assert again.status == "unchanged"


def test_an_identical_search_reuses_the_stored_one_unless_fresh(db_target):
    with registry.open(db_target) as reg:
        first = reg.discover(HEAVY, degree=4, free=["lam"], record=True)
        again = reg.discover("family-heavy-top-lam", degree=4, free=["lam"])
        assert again.reused and again.number == first.number
        assert again.search.special == first.search.special
        assert again.search.generic == first.search.generic
        other = reg.discover("family-heavy-top-lam", degree=3, free=["lam"])
        assert not other.reused
        fresh = reg.discover("family-heavy-top-lam", degree=4, free=["lam"], fresh=True)
        assert not fresh.reused


def test_a_search_that_ran_out_of_time_is_reused_only_for_no_more_time(tmp_path):
    with registry.open(tmp_path / "r.sqlite") as reg:
        short = reg.discover(HEAVY, degree=4, free=["lam"], record=True, budget=0.01)
        assert not short.search.complete
        assert short.search.coverage[0].startswith("time budget exceeded (0.01 s)")
        again = reg.discover("family-heavy-top-lam", degree=4, free=["lam"], budget=0.01)
        assert again.reused and again.number == short.number
        longer = reg.discover("family-heavy-top-lam", degree=4, free=["lam"], record=True)
        assert not longer.reused and longer.search.complete
        assert [s.when for s in longer.search.special] == [("lam = 1",), ("lam = 2",)]
        assert reg.discover("family-heavy-top-lam", degree=4, free=["lam"]).reused


def test_searches_and_discoveries_frames_hold_negative_results_too(db_target):
    with registry.open(db_target) as reg:
        reg.discover(FAMILIES / "asymmetric-heavy-top.toml", degree=4, record=True)
        reg.discover(HEAVY, degree=4, free=["lam"], record=True)
        searches = reg.searches()
        assert list(searches.case) == ["family-asymmetric-heavy-top", "family-heavy-top-lam"]
        assert list(searches.complete) == [True, True]
        assert list(searches.generic_extra) == [0, 0]
        assert list(searches.n_special) == [0, 2]
        assert searches.statement[0].startswith("No extra integral of weighted degree <= 4")
        found = reg.discoveries()
        assert [list(w) for w in found.when] == [[], [], ["lam = 1"], ["lam = 2"]]


def test_the_cli_prints_the_json_of_the_contract(db_target, databases):
    result = CliRunner().invoke(
        main, ["--db", db_target, "discover", str(HEAVY), "--free", "lam", "--json"]
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert [s["when"] for s in doc["special"]] == [["lam = 1"], ["lam = 2"]]
    assert doc["complete"] is True
    # a file searched without --record creates no database, nor tables in an empty one
    if databases.backend == "sqlite":
        assert not Path(db_target).exists()
    else:
        assert rows(db_target, "SELECT count(*) FROM information_schema.tables "
                    "WHERE table_schema = 'public'") == [(0,)]  # fmt: skip


def test_the_cli_records_and_says_so(db_target):
    db = db_target
    args = ["--db", str(db), "discover", str(HEAVY), "--free", "lam", "--degree", "3",
            "--on", "s = 0", "--record"]  # fmt: skip
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "lam = 4: 1 extra integral(s)" in result.stdout
    assert "recorded as search 1" in result.stdout
    again = CliRunner().invoke(main, args)
    assert "(reused stored search 1; --fresh searches again)" in again.stdout


@pytest.mark.parametrize(
    "args,message",
    [
        (["--free", "mu"], "Error: --free names 'mu', which the case does not declare"),
        (
            ["--weights", "omega=1"],
            "Error: --weights names 'omega', which the case's state does not have "
            "(its vectors: M, gamma)",
        ),
        (["--on", "M1 = 0", "--degree", "2"], "Error: the flow does not keep the level set"),
        (["--on", "bogus = 0"], "Error: unknown name 'bogus'"),
    ],
)
def test_the_cli_refuses_what_it_cannot_search_in_one_line(db_target, args, message):
    result = CliRunner().invoke(main, ["--db", db_target, "discover", str(HEAVY), *args])
    assert result.exit_code == 1, result.output
    assert result.stderr.startswith(message), result.stderr
    assert "Traceback" not in result.output


SURVEYED = [
    Path(__file__).resolve().parents[1] / "data" / "cases" / sub
    for sub in (
        "heavy-top/goryachev-1916-heavy-top.toml",
        "heavy-top/lagrange-1788-heavy-top.toml",
        "gyroscopic-torque/birtea-2011-radial-torque.toml",
    )
]


def test_survey_records_a_search_of_every_case_and_reuses_it(db_target):
    with registry.open(db_target) as reg:
        reg.add(*SURVEYED)
        reports = reg.survey(jobs=1)
        searched = [(r.search.case, [e.text for e in r.search.options.on]) for r in reports]
        assert searched == [
            ("birtea-2011-radial-torque", []),
            ("goryachev-1916-heavy-top", []),
            ("goryachev-1916-heavy-top", ["s = 0"]),
            ("lagrange-1788-heavy-top", []),
        ]
        assert not any(r.reused for r in reports)
        radial, *_, lagrange = reports
        # an arbitrary function in the torque: recorded, with the reason, deciding nothing
        assert not radial.search.decided and "not rational" in radial.search.coverage[0]
        assert lagrange.search.complete and lagrange.search.generic.integrals == ("M3",)
        frame = reg.searches()
        assert sorted(frame["search"]) == sorted(r.number for r in reports)
        assert set(frame["case"]) == {p.stem for p in SURVEYED}
        again = reg.survey(jobs=1)
        assert all(r.reused for r in again)
        assert [r.number for r in again] == [r.number for r in reports]
        assert len(reg.searches()) == len(reports)
        # Lagrange's M3 is his own claim again: named, not added as a claim a second time
        (status,) = lagrange.search.generic.status
        assert (status.status, status.equals, status.relation) == ("rediscovered", ("M3",), "M3")
        assert lagrange.search.claims_complete
        row = frame[frame.case == "lagrange-1788-heavy-top"].iloc[0]
        assert (row.generic_new, row.rediscovered, row.claims_complete) == (0, 1, True)
        claims = reg.claims()
        assert not len(claims[claims.provenance == "discovered"])
        assert reg.verify_db().problems == ()


def test_registry_survey_and_searches_commands(db_target):
    db = db_target
    runner = CliRunner()
    assert runner.invoke(main, ["--db", str(db), "add", *map(str, SURVEYED[:2])]).exit_code == 0
    result = runner.invoke(main, ["--db", str(db), "survey", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.strip().splitlines()
    assert lines[-1] == "3 search(es): 3 recorded, 0 reused; 0 not decided (see their statements)"
    assert max(map(len, lines)) <= 80
    searched = [line for line in lines if not line.startswith(" ")]  # wrapped under 4 spaces
    assert searched[0].startswith("goryachev-1916-heavy-top: No extra integral of weighted")
    assert searched[2].startswith("lagrange-1788-heavy-top: 1 extra integral(s)")
    lagrange = ["--db", str(db), "searches", "--case", "lagrange-1788-heavy-top"]
    listed = runner.invoke(main, lagrange)
    assert listed.exit_code == 0, listed.output
    assert listed.stdout.splitlines() == [
        "case",
        "  search  ansatz                 complete  result",
        "  ------  ---------------------  --------  ----------------------",
        "lagrange-1788-heavy-top",
        "  3       degree 2; M=1,gamma=2  yes       1 extra (rediscovered)",
    ]
    every = runner.invoke(main, ["--db", str(db), "searches"]).stdout.splitlines()
    assert [line.split() for line in every[3:6]] == [
        ["goryachev-1916-heavy-top"],  # its two searches under it, newest last
        ["1", "degree", "3;", "M=1,gamma=2", "yes", "no", "extra", "integral"],
        [
            "2",
            "degree",
            "3;",
            "M=1,gamma=2;",
            "on",
            "s",
            "=",
            "0",
            "yes",
            "1",
            "extra",
            "(rediscovered)",
        ],
    ]
    long = runner.invoke(main, [*lagrange, "--long"])
    assert long.exit_code == 0, long.output
    head, *said = long.stdout.splitlines()
    assert head == "search 3: lagrange-1788-heavy-top, degree 2; M=1,gamma=2"
    with registry.open(db) as reg:
        stored = reg.searches()
    statement = stored[stored.search == 3].statement.iloc[0]
    assert " ".join(line.strip() for line in said) == statement
    assert all(len(line) <= 80 and line.startswith("  ") for line in said)
    as_json = runner.invoke(main, [*lagrange, "--json"])
    assert as_json.exit_code == 0, as_json.output
    (document,) = json.loads(as_json.stdout)
    assert (document["search"], document["version"]) == (3, 1)
    assert document["case"] == "lagrange-1788-heavy-top"
    assert document["statement"] == statement
    assert document["generic"]["rediscovered"] == 1
    unknown = runner.invoke(main, ["--db", str(db), "searches", "--case", "lagrange-1788"])
    assert unknown.exit_code == 1
    assert unknown.stderr.startswith("Error: no case with id 'lagrange-1788' in the registry")


def test_an_invariant_relation_is_recorded_and_its_claim_verified_by_the_audit(db_target):
    """discover --relations --record: Hess's relation becomes a derived case whose claim
    is the relation on its own level set, which the audit verifies."""
    hess = Path(__file__).resolve().parents[1] / "data/cases/heavy-top/hess-1890-heavy-top.toml"
    with registry.open(db_target) as reg:
        report = reg.discover(hess, degree=1, relations=True, record=True)
        (derived,) = report.derived
        frame = reg.searches()
        assert list(frame.n_special) == [1]
        reg.audit(jobs=1)
        claims = reg.claims()
        (claim,) = claims[claims.case == derived].itertuples()
        assert claim.expression == "M1*x0 + M3*z0"
        v = reg.verdicts()
        verdict = v[(v.case == derived) & (v.check == "integral")].verdict
        assert list(verdict) == ["verified"]
        again = reg.discover(hess, degree=1, relations=True)
        assert again.reused and again.search.options.relations


KOVALEVSKAYA = Path(__file__).resolve().parents[1] / "data" / "cases" / "heavy-top"


def test_a_special_set_is_named_as_the_catalog_case_it_is_and_recorded_so(db_target):
    # issue 33's example: Kovalevskaya's body with the torque (t1 g1, t2 g2, t3 g3)
    family = FAMILIES / "kovalevskaya-diagonal-torque.toml"
    with registry.open(db_target) as reg:
        reg.add(KOVALEVSKAYA / "kovalevskaya-1889-heavy-top.toml")
        report = reg.discover(family, degree=4, free=["t1", "t2", "t3"], record=True)
        (point,) = report.search.special
        (same,) = point.same_as
        assert same.case == "kovalevskaya-1889-heavy-top" and same.claims == ("K",)
        assert dict(same.values) == {"C": "1", "a": "1"}
        assert point.new == () and point.status[0].equals == ("kovalevskaya-1889-heavy-top:K",)
        again = reg.discover(
            "family-kovalevskaya-diagonal-torque", degree=4, free=["t1", "t2", "t3"]
        )
        assert again.reused and again.search.special[0].same_as == point.same_as
        found = reg.discoveries()
        (row,) = found[found.case == "family-kovalevskaya-diagonal-torque"].same_as.iloc[1:]
        assert [s["case"] for s in row] == ["kovalevskaya-1889-heavy-top"]


def test_the_cli_names_the_catalog_case_in_its_json_and_statement(db_target):
    family = FAMILIES / "kovalevskaya-diagonal-torque.toml"
    runner = CliRunner()
    added = runner.invoke(
        main, ["--db", db_target, "add", str(KOVALEVSKAYA / "kovalevskaya-1889-heavy-top.toml")]
    )
    assert added.exit_code == 0, added.output
    result = runner.invoke(
        main,
        ["--db", db_target, "discover", str(family), "--free", "t1,t2,t3", "--json"],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    (point,) = doc["special"]
    assert point["when"] == ["t1 = 0", "t2 = 0", "t3 = 0"]
    assert point["new"] == 0 and point["rediscovered"] == 1
    assert [(s["case"], s["claims"]) for s in point["same_as"]] == [
        ("kovalevskaya-1889-heavy-top", ["K"])
    ]
    assert point["same_as"][0]["transformation"]["t"] == "t"
    text = runner.invoke(main, ["--db", db_target, "discover", str(family), "--free", "t1,t2,t3"])
    said = " ".join(text.output.split())  # the text is wrapped to the terminal
    assert "t1 = 0, t2 = 0, t3 = 0 (kovalevskaya-1889-heavy-top); no other values" in said
    assert "same system as kovalevskaya-1889-heavy-top (C = 1, a = 1" in said


def test_a_survey_s_analysis_that_ran_out_is_made_again_with_more_time(tmp_path):
    """The main job gives each Kovalevskaya analysis a short budget; a later survey with
    more time makes again the analyses that ran out (and reuses the searches)."""
    lagrange = SURVEYED[1]
    with registry.open(tmp_path / "r.sqlite") as reg:
        reg.add(lagrange)
        (short,) = reg.survey(jobs=1, exponent_budget=1e-3)
        assert short.exponents is not None and not short.exponents.decided
        (again,) = reg.survey(jobs=1)
        assert again.reused and again.number == short.number
        assert again.exponents is not None and again.exponents.decided
        assert again.exponents.all_integer and again.exponents.passes
        (kept,) = reg.survey(jobs=1, exponent_budget=1e-3)  # decided: kept, not redone
        assert kept.exponents.decided


NORMALISATIONS = [
    Path(__file__).resolve().parents[1] / "data" / "cases" / "heavy-top" / f"{name}.toml"
    for name in (
        "kovalevskaya-1889-heavy-top",
        "kovalevskaya-1889-heavy-top-normalised",
        "goryachev-1916-heavy-top",
    )
]


def test_registry_identify_records_the_same_systems_and_cases_shows_them(db_target):
    runner = CliRunner()
    db = ["--db", str(db_target)]
    assert runner.invoke(main, [*db, "add", *map(str, NORMALISATIONS)]).exit_code == 0
    result = runner.invoke(main, [*db, "identify", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.strip().splitlines()
    assert max(map(len, lines)) <= 80
    assert lines[-1] == (
        "3 case(s): 2 the same system as some other case; 0 not compared with every case"
    )
    # Goryachev's field has s in a denominator: no normal form, compared with no case
    goryachev = "goryachev-1916-heavy-top: its field is not polynomial in (M, gamma)"
    assert any(line.startswith(goryachev) for line in lines)
    kovalevskaya = ["--case", "kovalevskaya-1889-heavy-top"]
    as_json = runner.invoke(main, [*db, "identify", "--json", *kovalevskaya])
    assert as_json.exit_code == 0, as_json.output
    (found,) = json.loads(as_json.stdout)
    assert found["reused"] and found["complete"]
    (same,) = found["same_as"]
    assert same["case"] == "kovalevskaya-1889-heavy-top-normalised"
    assert same["values"] == {"c0": "C*a"} and same["transformation"]["t"] == "t/C"
    with registry.open(db_target) as reg:
        table = reg.cases().set_index("case")
        assert table.loc["kovalevskaya-1889-heavy-top", "equivalent"] == [
            "kovalevskaya-1889-heavy-top-normalised"
        ]
        assert table.loc["goryachev-1916-heavy-top", "same_as"] == []
        assert len(reg.identifications()) == 2
    unknown = runner.invoke(main, [*db, "identify", "--case", "no-such-case"])
    assert unknown.exit_code != 0 and "no-such-case" in unknown.stderr
