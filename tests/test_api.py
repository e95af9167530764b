"""The Python API: ``registry.open`` and the ``Registry`` it returns
(docs/getting-started.md, "From a notebook").

One database with two seed cases is audited once per module (fixture ``audited``);
tests that need their own history (versions, failing cases) use a fresh database.
The module runs on SQLite and on PostgreSQL (fixture ``backend``); the tests of SQLite
files and in-memory databases are SQLite's own.
"""

from __future__ import annotations

import doctest
import json
import re
import tomllib
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest
from click.testing import CliRunner

import registry
import registry.api
import registry.store.database
from registry import AddResult, AuditReport, CaseFormatError, Registry
from registry.cli import main
from registry.model import VerdictChange
from tests.helpers.samples import UNDECLARED, case_file

ROOT = Path(registry.__file__).resolve().parent.parent
CASES = ROOT / "data" / "cases"
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"
VERDICT_COLUMNS = {"case", "claim", "check", "verdict", "method", "run"}


def toml(case_id: str) -> dict:
    return tomllib.loads(case_file(case_id).read_text(encoding="utf-8"))


def verdict_of(frame: pd.DataFrame, case: str, claim: str | None, check: str) -> list[str]:
    """The verdicts in ``frame`` for one (case, claim or None for case checks, check)."""
    rows = frame[(frame["case"] == case) & (frame["check"] == check)]
    rows = rows[rows["claim"].isna()] if claim is None else rows[rows["claim"] == claim]
    return rows["verdict"].tolist()


@pytest.fixture(scope="module")
def audited(module_databases):
    path = module_databases.new("api")
    reg = registry.open(path)
    added = reg.add(case_file(YEHIA_B), case_file(ZHUKOVSKY))
    report = reg.audit()
    yield SimpleNamespace(path=path, reg=reg, added=added, report=report)
    reg.close()


# --------------------------------------------------------------------------- open


# SQLite only: files and folders (a server's database is created by its administrator)
def test_open_creates_the_file(tmp_path):
    path = tmp_path / "r.sqlite"
    assert not path.exists()
    with registry.open(path) as reg:
        assert isinstance(reg, Registry)
        assert path.exists()
        assert reg.cases().empty
        assert reg.runs().empty
    nested = tmp_path / "a" / "b" / "r.sqlite"
    registry.open(str(nested)).close()
    assert nested.exists()


# SQLite only: an in-memory database
def test_open_in_memory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with registry.open(":memory:") as reg:
        assert [r.status for r in reg.add(case_file(ZHUKOVSKY))] == ["added"]
        report = reg.audit()
        frame = reg.verdicts()
        assert verdict_of(frame, ZHUKOVSKY, "area", "casimir") == ["verified"]
        assert set(frame["run"]) == {report.run}
    assert list(tmp_path.iterdir()) == []  # nothing written to disk
    with registry.open(":memory:") as fresh:  # each in-memory registry is its own
        assert fresh.cases().empty


def test_open_sqlalchemy_url(db_target, backend):
    path = db_target
    url = f"sqlite:///{path}" if backend == "sqlite" else path
    with registry.open(url) as reg:
        (result,) = reg.add(case_file(ZHUKOVSKY))
        assert (result.status, result.case, result.version) == ("added", ZHUKOVSKY, 1)
        report = reg.audit()
    assert backend != "sqlite" or Path(path).exists()
    with registry.open(path) as same:  # the URL named this very database
        assert list(same.cases()["case"]) == [ZHUKOVSKY]
        assert verdict_of(same.verdicts(), ZHUKOVSKY, "area", "integral") == ["verified"]
        assert list(same.runs()["run"]) == [report.run]


# ---------------------------------------------------------------------------- add


def test_add_returns_results(audited):
    assert all(isinstance(r, AddResult) for r in audited.added)
    assert [(r.status, r.case, r.version, r.error) for r in audited.added] == [
        ("added", YEHIA_B, 1, None),
        ("added", ZHUKOVSKY, 1, None),
    ]
    assert [Path(r.path).name for r in audited.added] == [
        f"{YEHIA_B}.toml",
        f"{ZHUKOVSKY}.toml",
    ]
    again = audited.reg.add(case_file(ZHUKOVSKY))
    assert [(r.status, r.case, r.version) for r in again] == [("unchanged", ZHUKOVSKY, 1)]


def test_add_refused_file(tmp_path, db_target):
    bad = tmp_path / "bad.toml"
    bad.write_text(UNDECLARED, encoding="utf-8")
    with registry.open(db_target) as reg:
        results = reg.add(bad, case_file(ZHUKOVSKY))
        assert [r.status for r in results] == ["refused", "added"]
        refused = results[0]
        assert refused.case is None and refused.version is None
        assert isinstance(refused.error, CaseFormatError)
        (problem,) = refused.error.problems
        assert problem.field == "claims[0].expression"
        assert problem.text == "M1 + bogus*gamma1"
        assert str(bad) in str(refused.error)
        assert list(reg.cases()["case"]) == [ZHUKOVSKY]


def test_add_folder(tmp_path, db_target):
    folder = tmp_path / "cases"
    folder.mkdir()
    for case_id in (YEHIA_B, ZHUKOVSKY):
        (folder / f"{case_id}.toml").write_text(
            case_file(case_id).read_text(encoding="utf-8"), encoding="utf-8"
        )
    with registry.open(db_target) as reg:
        results = reg.add(folder)
        assert sorted((r.status, r.case) for r in results) == [
            ("added", YEHIA_B),
            ("added", ZHUKOVSKY),
        ]


# -------------------------------------------------------------------------- audit


def test_audit_report(audited):
    report = audited.report
    assert isinstance(report, AuditReport)
    assert report.run == 1
    document = report.document()
    json.dumps(document)  # the document is plain JSON
    assert document["run"] == report.run
    assert [entry["case"] for entry in document["cases"]] == sorted([YEHIA_B, ZHUKOVSKY])
    (i2,) = [
        claim
        for entry in document["cases"]
        if entry["case"] == YEHIA_B
        for claim in entry["claims"]
    ]
    assert (i2["label"], i2["integral"], i2["casimir"]) == ("I2", "refuted", "refuted")


def test_verdicts_frame(audited):
    frame = audited.reg.verdicts()
    assert isinstance(frame, pd.DataFrame)
    assert VERDICT_COLUMNS <= set(frame.columns)
    assert verdict_of(frame, YEHIA_B, "I2", "integral") == ["refuted"]
    assert verdict_of(frame, YEHIA_B, "I2", "casimir") == ["refuted"]
    assert verdict_of(frame, ZHUKOVSKY, "area", "integral") == ["verified"]
    assert verdict_of(frame, ZHUKOVSKY, "area", "casimir") == ["verified"]
    for case in (YEHIA_B, ZHUKOVSKY):
        for check in ("jacobi", "energy", "c1"):
            assert verdict_of(frame, case, None, check) == ["verified"]
    assert set(frame["run"]) == {audited.report.run}
    assert (frame["method"].str.len() > 0).all()

    of_run = audited.reg.verdicts(run=audited.report.run)
    assert VERDICT_COLUMNS <= set(of_run.columns)
    assert verdict_of(of_run, YEHIA_B, "I2", "casimir") == ["refuted"]
    assert len(of_run) == len(frame)


def test_verdicts_of_an_unknown_run(audited):
    with pytest.raises(registry.UnknownRunError):
        audited.reg.verdicts(run=999)


def test_cases_frame(audited):
    frame = audited.reg.cases()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame["case"]) == sorted([YEHIA_B, ZHUKOVSKY])
    rows = frame.set_index("case")
    for case_id in (YEHIA_B, ZHUKOVSKY):
        data = toml(case_id)
        assert rows.loc[case_id, "title"] == data["title"]
        assert rows.loc[case_id, "citation"] == data["source"]["citation"]
        assert rows.loc[case_id, "version"] == 1
        assert rows.loc[case_id, "n_claims"] == len(data["claims"])


def test_claims_frame(audited):
    frame = audited.reg.claims()
    assert isinstance(frame, pd.DataFrame)
    got = sorted(
        zip(frame["case"], frame["label"], frame["kind"], frame["expression"], strict=True)
    )
    expected = sorted(
        (case_id, c["label"], c["kind"], c["expression"])
        for case_id in (YEHIA_B, ZHUKOVSKY)
        for c in toml(case_id)["claims"]
    )
    assert got == expected
    merged = audited.reg.cases().merge(frame, on="case")  # the join of docs/getting-started.md
    assert len(merged) == len(expected)


def test_runs_frame(audited):
    frame = audited.reg.runs()
    assert isinstance(frame, pd.DataFrame)
    (row,) = frame.to_dict("records")
    assert row["run"] == audited.report.run
    assert row["status"] == "complete"
    assert row["finished_at"] >= row["started_at"]
    assert row["n_cases"] == 2
    assert row["n_error"] == 0
    assert row["n_refuted"] == len(audited.reg.verdicts().query("verdict == 'refuted'"))


def test_corrections_frame(audited):
    frame = audited.reg.corrections()
    assert isinstance(frame, pd.DataFrame)
    assert set(frame["run"]) == {audited.report.run}
    i2 = frame[(frame["case"] == YEHIA_B) & (frame["claim"] == "I2")]
    corrections = i2[i2["kind"].isin(["casimir", "torque"])]
    assert sorted(corrections["kind"]) == ["casimir", "torque"]
    assert set(corrections["verdict"]) == {"verified"}
    (casimir,) = corrections[corrections["kind"] == "casimir"]["expression"]
    document = audited.report.document()
    (claim,) = [c for e in document["cases"] if e["case"] == YEHIA_B for c in e["claims"]]
    assert casimir in [c.get("expression") for c in claim["corrections"]]
    conditions = i2[i2["kind"] == "conditions"]
    assert [p["branches"] for p in conditions["payload"]] == [[["N = 0"]]]
    assert set(frame[frame["case"] == ZHUKOVSKY]["kind"]) >= {"family"}
    assert audited.reg.corrections(run=audited.report.run).equals(frame)


def test_export_case(audited):
    text = audited.reg.export_case(YEHIA_B, "I2")
    case = registry.parse_case_text(text, "exported.toml")
    assert case.id == f"{YEHIA_B}-corrected-torque"
    assert [c.expression.text for c in case.claims] == [toml(YEHIA_B)["claims"][0]["expression"]]


# ------------------------------------------------------------------------ history


def test_history_of_a_changed_case(tmp_path, db_target):
    path = tmp_path / "zhukovsky.toml"
    original = case_file(ZHUKOVSKY).read_text(encoding="utf-8")
    path.write_text(original, encoding="utf-8")
    with registry.open(db_target) as reg:
        assert [(r.status, r.version) for r in reg.add(path)] == [("added", 1)]
        first = reg.audit()

        changed = original.replace('"(M1 + k1)*gamma1', '"(M1 + 2*k1)*gamma1')
        assert changed != original
        path.write_text(changed, encoding="utf-8")
        assert [(r.status, r.version) for r in reg.add(path)] == [("new version", 2)]
        assert [r.status for r in reg.add(path)] == ["unchanged"]
        second = reg.audit()

        runs = reg.runs()
        assert list(runs["run"]) == [first.run, second.run] == [1, 2]
        assert set(runs["status"]) == {"complete"}

        old = reg.verdicts(run=1)
        assert set(old["version"]) == {1}
        assert verdict_of(old, ZHUKOVSKY, "area", "integral") == ["verified"]
        assert verdict_of(old, ZHUKOVSKY, "area", "casimir") == ["verified"]

        new = reg.verdicts(run=2)
        assert set(new["version"]) == {2}
        assert verdict_of(new, ZHUKOVSKY, "area", "casimir") == ["refuted"]

        latest = reg.verdicts()
        assert set(latest["run"]) == {2} and set(latest["version"]) == {2}
        assert verdict_of(latest, ZHUKOVSKY, "area", "casimir") == ["refuted"]

        assert list(reg.cases()["version"]) == [2]
        assert list(reg.claims()["expression"]) == [
            "(M1 + 2*k1)*gamma1 + (M2 + k2)*gamma2 + (M3 + k3)*gamma3"
        ]


# ------------------------------------------------------------------ broken cases


def test_audit_goes_on_when_a_stored_case_cannot_be_parsed(db_target, monkeypatch):
    real_parse = registry.store.database.parse_case_text

    def parse(text, *args, **kwargs):
        if tomllib.loads(text)["id"] == YEHIA_B:
            raise ValueError("simulated: stored text no longer parses")
        return real_parse(text, *args, **kwargs)

    with registry.open(db_target) as reg:
        reg.add(case_file(YEHIA_B), case_file(ZHUKOVSKY))
        monkeypatch.setattr(registry.store.database, "parse_case_text", parse)
        report = reg.audit()
        monkeypatch.undo()

        entries = {e["case"]: e for e in report.document()["cases"]}
        assert set(entries) == {YEHIA_B, ZHUKOVSKY}
        assert "simulated" in entries[YEHIA_B]["error"]
        assert set(entries[YEHIA_B]["checks"].values()) == {"error"}
        assert "error" not in entries[ZHUKOVSKY]
        (area,) = entries[ZHUKOVSKY]["claims"]
        assert area["verdict"] == "verified"

        stored = reg.verdicts(run=report.run)
        broken = stored[stored["case"] == YEHIA_B]
        assert broken["verdict"].tolist() == ["error"]
        assert "simulated" in broken["reason"].iloc[0]
        assert verdict_of(stored, ZHUKOVSKY, "area", "casimir") == ["verified"]

        (run,) = reg.runs().to_dict("records")
        assert run["status"] == "complete"
        assert run["n_cases"] == 2
        assert run["n_error"] == 1


# ------------------------------------------------------------------------ doctest


def test_module_doctest(monkeypatch):
    monkeypatch.chdir(ROOT)  # the example adds data/cases/... by a relative path
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    out: list[str] = []
    tests = [t for t in finder.find(registry.api) if t.examples]
    assert tests, "registry/api.py has no doctest"
    for test in tests:
        runner.run(test, out=out.append)
    failed, attempted = runner.summarize(verbose=False)
    assert failed == 0, "".join(out)
    assert attempted >= 5


def test_unchanged_cases_are_reused_and_fresh_recomputes(db_target):
    reg = registry.open(db_target)
    reg.add(CASES / "yehia-2003-kovalevskaya-b.toml", CASES / "zhukovsky-gyrostat.toml")
    first = reg.audit(jobs=1)
    second = reg.audit(jobs=1)
    third = reg.audit(jobs=1, fresh=True)
    runs = reg.runs().set_index("run")
    assert runs.loc[first.run, "n_reused"] == 0
    assert runs.loc[second.run, "n_reused"] == runs.loc[second.run, "n_results"] > 0
    assert runs.loc[third.run, "n_reused"] == 0
    assert first.document()["cases"] == second.document()["cases"]
    assert _without_timings(third.document()["cases"]) == _without_timings(
        first.document()["cases"]
    )


def _without_timings(cases):
    """Timings differ between fresh runs; everything else must be identical."""
    for case in cases:
        for detail in case["details"].values():
            detail.pop("seconds", None)
        for claim in case["claims"]:
            for detail in claim["details"].values():
                detail.pop("seconds", None)
    return cases


# --------------------------------------------------------------------------- diff


CHANGED_TITLE = 'title = "Zhukovsky & Co.: k_i at 100% #1"'


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory, module_databases) -> str:
    """A one-case database audited twice: the original claim, then a sign flipped in it."""
    folder = tmp_path_factory.mktemp("diff")
    target = module_databases.new("diff")
    original = (CASES / f"{ZHUKOVSKY}.toml").read_text(encoding="utf-8")
    original = re.sub(r"^title = .*$", CHANGED_TITLE, original, count=1, flags=re.M)
    changed = original.replace('expression = "(M1 + k1)*gamma1', 'expression = "(M1 - k1)*gamma1')
    assert changed != original
    with registry.open(target) as reg:
        for text in (original, changed):
            path = folder / f"{ZHUKOVSKY}.toml"
            path.write_text(text, encoding="utf-8")
            reg.add(path)
            reg.audit(jobs=1)
    return target


def test_diff_of_a_run_with_itself_is_empty(two_runs):
    db = two_runs
    with registry.open(db) as reg:
        assert reg.diff(1, 1) == []
    result = CliRunner().invoke(main, ["--db", str(db), "report", "--diff", "1", "1"])
    assert result.exit_code == 0, result.output
    assert "no changes" in result.output


def test_diff_lists_the_changed_verdicts(two_runs):
    with registry.open(two_runs) as reg:
        changes = reg.diff(1, 2)
    expected = {"case": ZHUKOVSKY, "claim": "area", "before": "verified", "after": "refuted"}
    assert VerdictChange(**expected, check="casimir") in changes
    assert all(c.case == ZHUKOVSKY and c.claim == "area" for c in changes)
    result = CliRunner().invoke(main, ["--db", str(two_runs), "report", "--diff", "1", "2"])
    assert result.exit_code == 0, result.output
    assert "no changes" not in result.output
    lines = result.output.splitlines()
    assert lines[:2] == ["case", "  claim  check     run 1     run 2"]
    assert lines[3] == ZHUKOVSKY  # the case heads its changed verdicts
    row = next(line for line in lines if "casimir" in line)
    assert row.split() == ["area", "casimir", "verified", "refuted"]


def test_diff_of_an_unknown_run_is_an_error(two_runs):
    result = CliRunner().invoke(main, ["--db", str(two_runs), "report", "--diff", "1", "7"])
    assert result.exit_code == 1
    assert "Error:" in result.output
