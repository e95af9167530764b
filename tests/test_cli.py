"""The ``registry`` command line (docs/cli.md; its JSON: docs/json-output.md).

Most tests drive ``registry.cli.main`` through click's CliRunner; a few start real
processes (``python -m registry`` and the ``registry`` console script). One database
with three seed cases is audited twice per module (fixture ``audited``) and shared.
The module runs on SQLite and on PostgreSQL (fixture ``backend``).
"""

from __future__ import annotations

import io
import json
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.store.database import Store
from tests.helpers.clocks import PATIENT_OPTIONS
from tests.helpers.samples import (
    AFFINE,
    CASES,
    CLASSICAL,
    SEED,
    UNDECLARED,
    YEHIA_B,
    ZHUKOVSKY,
    case_file,
)

ROOT = Path(registry.__file__).resolve().parent.parent
COMMANDS = ("add", "audit", "cases", "verdicts", "runs", "corrections", "export-case", "copy")
VERDICTS = {"verified", "refuted", "inconclusive"}

#: One line of ``registry add`` for a stored file: status, case id, version, path.
ADD_LINE = re.compile(r"^(added|unchanged|new version)\s+(\S+) \(version (\d+)\)\s+(.+)$")
TALLY = re.compile(r"^\d+ file\(s\): \d+ added, \d+ new version, \d+ unchanged, \d+ refused$")


ZERO_INERTIA = """\
id = "bad-zero-inertia"
title = "A body with a vanishing moment of inertia"

[source]
citation = "Nobody, Nowhere (2024)"

[parameters]
C = "positive"

[system]
inertia = ["C", "0", "2*C"]

[[claims]]
label = "I1"
kind = "casimir"
expression = "gamma1**2 + gamma2**2 + gamma3**2"
"""


def invoke(db: Path | str | None, *args: str, **kwargs) -> object:
    """Run ``registry [--db DB] ARGS`` in-process; never lets an exception escape."""
    prefix = [] if db is None else ["--db", str(db)]
    return CliRunner().invoke(main, [*prefix, *args], **kwargs)


def grouped_rows(text: str) -> list[tuple[str, list[str]]]:
    """(heading, words of the row) of each row of a grouped listing (``cases``,
    ``verdicts``, ``corrections``, ``searches``): a row is indented under the heading
    before it; the header and its rule (the first three lines) are skipped."""
    rows = []
    heading = ""
    for line in text.splitlines()[3:]:
        if line.startswith("  "):
            rows.append((heading, line.split()))
        elif line:
            heading = line.split()[0]
    return rows


def error_lines(result) -> list[str]:
    return result.stderr.strip().splitlines()


def add_lines(result) -> list[tuple[str, str, int, str]]:
    """The stored-file lines of ``registry add`` as (status, case, version, path)."""
    parsed = []
    *lines, tally = result.stdout.strip().splitlines()
    assert TALLY.match(tally), tally
    for line in lines:
        match = ADD_LINE.match(line)
        assert match, f"unexpected line from add: {line!r}"
        status, case, version, path = match.groups()
        parsed.append((status, case, int(version), path.strip()))
    return parsed


def by_case(document: dict) -> dict[str, dict]:
    return {entry["case"]: entry for entry in document["cases"]}


def claim_of(document: dict, case_id: str, label: str) -> dict:
    (claim,) = [c for c in by_case(document)[case_id]["claims"] if c["label"] == label]
    return claim


@pytest.fixture(scope="module")
def audited(module_databases) -> SimpleNamespace:
    """A database with three seed cases, audited twice (JSON, then table).

    The outputs of ``runs`` and ``verdicts`` are taken right after the two audits,
    so later tests may audit this database again without changing them.
    """
    db = module_databases.new("cli")
    added = invoke(db, "add", *(str(case_file(c)) for c in SEED))
    # budgets only a hang exceeds: a busy machine must not turn a verdict inconclusive
    as_json = invoke(db, "audit", "--json", *PATIENT_OPTIONS)
    table = invoke(db, "audit", *PATIENT_OPTIONS)
    runs = invoke(db, "runs")
    verdicts = invoke(db, "verdicts")
    return SimpleNamespace(
        db=db, added=added, json=as_json, table=table, runs=runs, verdicts=verdicts
    )


@pytest.fixture(scope="module")
def document(audited) -> dict:
    assert audited.added.exit_code == 0, audited.added.output
    assert audited.json.exit_code == 0, audited.json.output
    return json.loads(audited.json.stdout)


# ----------------------------------------------------------------------------- help


def test_all_commands_are_registered():
    assert set(COMMANDS) <= set(main.commands)


@pytest.mark.parametrize("command", sorted(main.commands))
def test_every_command_documents_itself(command):
    result = invoke(None, command, "--help")
    assert result.exit_code == 0, result.output
    assert "Example:" in result.stdout
    usage = result.stdout.splitlines()[0]
    assert usage.startswith("Usage:") and f" {command} " in f"{usage} "


def test_main_help_lists_commands():
    result = invoke(None, "--help")
    assert result.exit_code == 0, result.output
    assert "Example:" in result.stdout
    for command in COMMANDS:
        assert command in result.stdout


def _registry_script() -> str:
    script = Path(sys.executable).with_name("registry")
    if script.exists():
        return str(script)
    found = shutil.which("registry")
    if found is None:
        pytest.fail("the 'registry' console script is not installed next to the interpreter")
    return found


@pytest.mark.parametrize("how", ["python -m registry", "console script"])
def test_help_in_a_real_process(how, tmp_path):
    command = (
        [sys.executable, "-m", "registry"] if how == "python -m registry" else [_registry_script()]
    )
    done = subprocess.run(
        [*command, "--help"], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    assert "Example:" in done.stdout
    for name in COMMANDS:
        assert name in done.stdout
    assert not (tmp_path / "data").exists()  # --help opens no database


def test_user_error_in_a_real_process(db_target):
    db = db_target
    Store(db).close()
    done = subprocess.run(
        [_registry_script(), "--db", str(db), "audit", "--case", "no-such-case"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error:"), done.stderr
    assert "no-such-case" in lines[0]
    assert "Traceback" not in done.stderr + done.stdout


# ------------------------------------------------------------------------------ add


def test_add_catalog_then_unchanged(db_target, monkeypatch):
    monkeypatch.chdir(ROOT)
    db = db_target
    files = sorted(str(p.relative_to(ROOT)) for p in CASES.rglob("*.toml"))
    assert len(files) >= 3

    first = invoke(db, "add", "data/cases")
    assert first.exit_code == 0, first.output
    lines = add_lines(first)
    assert sorted(path for *_, path in lines) == files
    assert {status for status, *_ in lines} == {"added"}
    assert {version for _, _, version, _ in lines} == {1}
    ids = {case for _, case, _, _ in lines}
    assert len(ids) == len(files)
    assert first.stderr == ""

    again = invoke(db, "add", "data/cases")
    assert again.exit_code == 0, again.output
    relines = add_lines(again)
    assert sorted(path for *_, path in relines) == files
    assert {status for status, *_ in relines} == {"unchanged"}
    assert {case for _, case, _, _ in relines} == ids

    with registry.open(db) as reg:
        cases = reg.cases()
    assert set(cases["case"]) == ids
    assert set(cases["version"]) == {1}


def test_add_refuses_bad_files_and_keeps_good_ones(tmp_path, db_target):
    undeclared = tmp_path / "undeclared.toml"
    undeclared.write_text(UNDECLARED, encoding="utf-8")
    zero = tmp_path / "zero.toml"
    zero.write_text(ZERO_INERTIA, encoding="utf-8")
    db = db_target

    result = invoke(db, "add", str(undeclared), str(case_file(ZHUKOVSKY)), str(zero))
    assert result.exit_code == 1
    assert "Traceback" not in result.output

    stored = add_lines(result)
    assert [(s, c, v) for s, c, v, _ in stored] == [("added", ZHUKOVSKY, 1)]
    tally = result.stdout.strip().splitlines()[-1]
    assert tally == "3 file(s): 1 added, 0 new version, 0 unchanged, 2 refused"

    errors = error_lines(result)
    assert len(errors) == 2, result.stderr
    assert all(line.startswith("Error:") for line in errors)
    (about_name,) = [line for line in errors if str(undeclared) in line]
    assert "claims[0].expression" in about_name
    assert "bogus" in about_name
    assert "'M1 + bogus*gamma1'" in about_name
    (about_zero,) = [line for line in errors if str(zero) in line]
    assert "system.inertia[1]" in about_zero
    assert "'0'" in about_zero

    listed = invoke(db, "cases")
    assert listed.exit_code == 0, listed.output
    assert ZHUKOVSKY in listed.stdout
    assert "bad-undeclared-name" not in listed.stdout
    assert "bad-zero-inertia" not in listed.stdout
    with registry.open(db) as reg:
        assert list(reg.cases()["case"]) == [ZHUKOVSKY]
        assert set(reg.claims()["case"]) == {ZHUKOVSKY}


def test_add_prints_one_error_line_per_problem(tmp_path, db_target):
    both = tmp_path / "both.toml"
    both.write_text(ZERO_INERTIA.replace('"gamma1**2', '"bogus + gamma1**2'), encoding="utf-8")
    result = invoke(db_target, "add", str(both))
    assert result.exit_code == 1
    errors = error_lines(result)
    assert len(errors) == 2, result.stderr
    assert all(line.startswith("Error:") for line in errors), result.stderr


# ---------------------------------------------------------------------------- audit


def test_add_of_the_audited_cases(audited):
    assert audited.added.exit_code == 0, audited.added.output
    assert sorted((s, c, v) for s, c, v, _ in add_lines(audited.added)) == sorted(
        ("added", c, 1) for c in SEED
    )


def test_audit_json_has_the_contract_shape(document):
    assert set(document) >= {"run", "cases"}
    assert isinstance(document["run"], int) and not isinstance(document["run"], bool)
    assert isinstance(document["cases"], list)
    assert sorted(entry["case"] for entry in document["cases"]) == sorted(SEED)
    for entry in document["cases"]:
        assert set(entry["checks"]) >= {"jacobi", "energy", "c1"}
        assert {entry["checks"][k] for k in ("jacobi", "energy", "c1")} <= VERDICTS
        assert isinstance(entry["claims"], list) and entry["claims"]
        for claim in entry["claims"]:
            assert set(claim) >= {"label", "kind", "integral", "casimir", "verdict"}
            assert claim["kind"] in {"integral", "casimir"}
            assert {claim["integral"], claim["casimir"], claim["verdict"]} <= VERDICTS
            # A claim's overall verdict is that of the property its kind names.
            assert claim["verdict"] == claim[claim["kind"]]


def test_audit_json_verdicts(document):
    cases = by_case(document)
    i2 = claim_of(document, YEHIA_B, "I2")
    assert (i2["kind"], i2["integral"], i2["casimir"], i2["verdict"]) == (
        "casimir",
        "refuted",
        "refuted",
        "refuted",
    )
    area = claim_of(document, ZHUKOVSKY, "area")
    assert (area["integral"], area["casimir"], area["verdict"]) == ("verified",) * 3
    assert cases[AFFINE]["checks"]["jacobi"] == "refuted"
    assert cases[YEHIA_B]["checks"]["jacobi"] == "verified"
    zhukovsky = cases[ZHUKOVSKY]["checks"]
    assert [zhukovsky[k] for k in ("jacobi", "energy", "c1")] == ["verified"] * 3


def test_audit_json_corrections(document):
    i2 = claim_of(document, YEHIA_B, "I2")
    corrections = i2["corrections"]
    assert sorted(c["kind"] for c in corrections) == ["casimir", "torque"]
    (casimir,) = [c for c in corrections if c["kind"] == "casimir"]
    (torque,) = [c for c in corrections if c["kind"] == "torque"]
    assert isinstance(casimir["expression"], str) and casimir["expression"].strip()
    assert isinstance(torque["torque"], list) and len(torque["torque"]) == 3
    assert all(isinstance(mu, str) and mu.strip() for mu in torque["torque"])
    assert i2["holds_when"] == ["N = 0"]

    affine = by_case(document)[AFFINE]
    assert affine["conditions"]["jacobi"] == ["T12 = T21", "T13 = T31", "T23 = T32"]
    assert "conditions" not in by_case(document)[ZHUKOVSKY]
    assert "corrections" not in claim_of(document, ZHUKOVSKY, "area")


def test_audit_json_expressions_paste_back_into_a_case_file(document):
    """Corrections are written in the input language: they parse as case-file fields."""
    i2 = claim_of(document, YEHIA_B, "I2")
    (casimir,) = [c for c in i2["corrections"] if c["kind"] == "casimir"]
    (torque,) = [c for c in i2["corrections"] if c["kind"] == "torque"]
    text = case_file(YEHIA_B).read_text(encoding="utf-8")
    data = tomllib.loads(text)
    original = data["claims"][0]["expression"]
    assert original != casimir["expression"]

    import tomli_w

    data["claims"][0]["expression"] = casimir["expression"]
    data["system"]["torque"] = torque["torque"]
    case = registry.parse_case_text(tomli_w.dumps(data), "pasted.toml")
    assert [e.text for e in case.system.torque] == torque["torque"]
    assert case.claims[0].expression.text == casimir["expression"]


def test_audit_table(audited, document):
    """Each case heads the rows of its claims, under the header of the claims' columns."""
    assert audited.table.exit_code == 0, audited.table.output
    lines = audited.table.stdout.splitlines()
    assert lines[0].split()[0] == "case"
    assert lines[1].split() == ["claim", "kind", "integral", "casimir", "verdict"]
    assert max(map(len, lines)) <= 80
    for case_id, entry in by_case(document).items():
        (heading,) = [i for i, line in enumerate(lines) if line.split()[:1] == [case_id]]
        rows = [line.split() for line in lines[heading + 1 : heading + 1 + len(entry["claims"])]]
        for row, claim in zip(rows, entry["claims"], strict=True):
            assert row[0] == claim["label"]
            assert row[-4:] == [
                claim["kind"],
                claim["integral"],
                claim["casimir"],
                claim["verdict"],
            ]
    assert re.search(
        r"^run 2: 3 cases, 3 claims \(2 refuted, 1 verified\)$", audited.table.stdout, re.M
    )


def test_each_audit_is_stored_as_a_run(audited, document):
    assert document["run"] == 1
    assert audited.runs.exit_code == 0, audited.runs.output
    lines = audited.runs.stdout.strip().splitlines()
    header = lines[0].split()
    assert header[0] == "run" and "status" in header
    rows = [line.split() for line in lines[2:] if not line.startswith(" ")]
    assert [int(row[0]) for row in rows] == [1, 2]
    assert all("complete" in row for row in rows)
    assert max(map(len, lines)) <= 80


def test_verdicts_lists_case_claim_check_verdict(audited):
    assert audited.verdicts.exit_code == 0, audited.verdicts.output
    lines = audited.verdicts.stdout.strip().splitlines()
    assert lines[0] == "case (version)"
    assert lines[1].split() == ["claim", "check", "verdict", "method", "run"]
    assert max(map(len, lines)) <= 80
    rows = {}
    for case, (claim, check, verdict, *_method, run) in grouped_rows(audited.verdicts.stdout):
        rows[case, claim, check] = (verdict, int(run))
    assert rows[YEHIA_B, "I2", "integral"] == ("refuted", 2)
    assert rows[YEHIA_B, "I2", "casimir"] == ("refuted", 2)
    assert rows[ZHUKOVSKY, "area", "casimir"] == ("verified", 2)
    jacobi = [v for (case, _, check), v in rows.items() if case == AFFINE and check == "jacobi"]
    assert jacobi == [("refuted", 2)]


@pytest.mark.parametrize("columns", [80, 100])
@pytest.mark.parametrize(
    "args",
    [
        ("cases",),
        ("verdicts",),
        ("runs",),
        ("corrections",),
        ("list-checks",),
        ("report", "--diff", "1", "2"),
    ],
    ids=lambda a: " ".join(a),
)
def test_every_listing_fits_the_terminal_in_plain_text(audited, args, columns):
    done = invoke(audited.db, *args, env={"COLUMNS": str(columns)})
    assert done.exit_code == 0, done.output
    lines = done.stdout.splitlines()
    assert lines and max(map(len, lines)) <= columns
    assert "\x1b" not in done.stdout


def test_audit_unknown_case_is_a_one_line_error(audited, document):
    with registry.open(audited.db) as reg:
        runs_before = len(reg.runs())
    result = invoke(audited.db, "audit", "--case", "no-such-case")
    assert result.exit_code == 1
    assert isinstance(result.exception, SystemExit)
    errors = error_lines(result)
    assert len(errors) == 1 and errors[0].startswith("Error:"), result.stderr
    assert "no-such-case" in errors[0]
    assert "Traceback" not in result.output
    assert result.stdout == ""

    mixed = invoke(audited.db, "audit", "--case", ZHUKOVSKY, "--case", "no-such-case", "--json")
    assert mixed.exit_code == 1
    assert error_lines(mixed)[0].startswith("Error:")
    with registry.open(audited.db) as reg:
        assert len(reg.runs()) == runs_before


def test_audit_case_restricts_the_run(audited, document):
    result = invoke(audited.db, "audit", "--case", ZHUKOVSKY, "--json")
    assert result.exit_code == 0, result.output
    restricted = json.loads(result.stdout)
    assert [entry["case"] for entry in restricted["cases"]] == [ZHUKOVSKY]
    assert restricted["run"] > document["run"]
    with registry.open(audited.db) as reg:
        stored = reg.verdicts(run=restricted["run"])
        (run_row,) = reg.runs().query(f"run == {restricted['run']}").to_dict("records")
    assert set(stored["case"]) == {ZHUKOVSKY}
    assert run_row["status"] == "complete"


# ------------------------------------------------------------------------- database


def test_db_from_environment(audited, document, databases, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the default data/registry.sqlite would land here
    monkeypatch.setenv("REGISTRY_DB", str(audited.db))
    result = invoke(None, "cases")
    assert result.exit_code == 0, result.output
    for case_id in SEED:
        assert case_id in result.stdout

    other = databases.missing("other")
    missing = invoke(None, "cases", env={"REGISTRY_DB": other})
    assert missing.exit_code == 1
    assert error_lines(missing) == [f"Error: {databases.missing_message(other)}"]
    assert not databases.exists(other)  # reading never creates a database
    other = databases.new("other")
    Store(other).close()
    empty = invoke(None, "cases", env={"REGISTRY_DB": str(other)})
    assert empty.exit_code == 0, empty.output
    assert empty.stdout.strip() == "(none)"

    explicit = invoke(audited.db, "cases", env={"REGISTRY_DB": str(other)})
    assert explicit.exit_code == 0, explicit.output
    assert all(case_id in explicit.stdout for case_id in SEED)
    assert not (tmp_path / "data").exists()


def test_db_accepts_a_sqlalchemy_url(db_target, backend):
    path = db_target
    url = f"sqlite:///{path}" if backend == "sqlite" else path
    result = invoke(url, "add", str(case_file(ZHUKOVSKY)))
    assert result.exit_code == 0, result.output
    assert [(s, c) for s, c, _, _ in add_lines(result)] == [("added", ZHUKOVSKY)]
    assert backend != "sqlite" or Path(path).exists()
    listed = invoke(path, "cases")
    assert ZHUKOVSKY in listed.stdout


# --------------------------------------------------------------------------- export


def test_export_case_round_trip(audited, document, tmp_path, databases):
    out = tmp_path / "out.toml"
    result = invoke(audited.db, "export-case", YEHIA_B, "--claim", "I2", "-o", str(out))
    assert result.exit_code == 0, result.output
    data = tomllib.loads(out.read_text(encoding="utf-8"))
    original = tomllib.loads(case_file(YEHIA_B).read_text(encoding="utf-8"))
    assert data["id"] != YEHIA_B
    assert data["claims"][0]["expression"] == original["claims"][0]["expression"]
    (torque,) = [
        c for c in claim_of(document, YEHIA_B, "I2")["corrections"] if c["kind"] == "torque"
    ]
    assert data["system"]["torque"] == torque["torque"]
    assert data["system"]["torque"] != original["system"]["torque"]

    db = databases.new("exported")
    added = invoke(db, "add", str(out))
    assert added.exit_code == 0, added.output
    assert [(s, c) for s, c, _, _ in add_lines(added)] == [("added", data["id"])]
    checked = invoke(db, "audit", "--json")
    assert checked.exit_code == 0, checked.output
    redone = json.loads(checked.stdout)
    i2 = claim_of(redone, data["id"], "I2")
    assert i2["casimir"] == "verified"
    assert i2["verdict"] == "verified"
    assert by_case(redone)[data["id"]]["checks"]["jacobi"] == "verified"


def test_export_case_to_stdout(audited, document):
    result = invoke(audited.db, "export-case", YEHIA_B, "--claim", "I2", "--kind", "casimir")
    assert result.exit_code == 0, result.output
    data = tomllib.loads(result.stdout)
    (casimir,) = [
        c for c in claim_of(document, YEHIA_B, "I2")["corrections"] if c["kind"] == "casimir"
    ]
    assert [c["expression"] for c in data["claims"]] == [casimir["expression"]]


def test_export_case_before_any_audit(tmp_path, db_target):
    db = db_target
    assert invoke(db, "add", str(case_file(ZHUKOVSKY))).exit_code == 0
    out = tmp_path / "out.toml"
    result = invoke(db, "export-case", ZHUKOVSKY, "-o", str(out))
    assert result.exit_code == 1
    errors = error_lines(result)
    assert len(errors) == 1 and errors[0].startswith("Error:"), result.stderr
    assert ZHUKOVSKY in errors[0]
    assert "Traceback" not in result.output
    assert not out.exists()


def test_export_unknown_case(db_target):
    Store(db_target).close()
    result = invoke(db_target, "export-case", "no-such-case")
    assert result.exit_code == 1
    errors = error_lines(result)
    assert len(errors) == 1 and errors[0].startswith("Error:")
    assert "no-such-case" in errors[0]


def test_checks_lists_every_registered_check_with_its_statement():
    from registry.audit.checks import CHECKS

    result = invoke(None, "list-checks")
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["check", "runs", "cost", "statement"]
    assert max(map(len, lines)) <= 80
    column = lines[0].index("statement")
    rows: list[list[str]] = []
    for line in lines[2:]:  # a row, or the next line of its wrapped statement
        if not line.startswith(" "):
            rows.append([line[:column], line[column:]])
        else:
            rows[-1][1] += " " + line[column:]
    assert [row[0].split()[0] for row in rows] == list(CHECKS)
    assert any("Jacobi identity" in statement for _, statement in rows)
    for (fields, statement), spec in zip(rows, CHECKS.values(), strict=True):
        found = re.fullmatch(r"(\S+) +(per claim|per case) +(\S+) *", fields)
        assert found, fields
        name, scope, cost = found.groups()
        assert name == spec.name
        assert scope == ("per claim" if spec.per_claim else "per case")
        assert cost == spec.cost
        assert statement.replace("- ", "-") == spec.statement != ""


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["add", "/no/such/file.toml"],
            "Invalid value for 'PATHS...': Path "
            "'/no/such/file.toml' does not exist. (see: registry add --help)",
        ),
        (["bogus"], "No such command 'bogus'. (see: registry --help)"),
        (
            ["audit", "--jobs", "-1"],
            "Invalid value for '--jobs': -1 is not in the range x>=1. (see: registry audit --help)",
        ),
        (
            ["verdicts", "--run", "x"],
            "Invalid value for '--run': 'x' is not a valid "
            "integer. (see: registry verdicts --help)",
        ),
    ],
)
def test_usage_mistakes_are_one_error_line_and_exit_1(tmp_path, args, message):
    result = invoke(tmp_path / "r.sqlite", *args)
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [f"Error: {message}"]
    assert result.stdout == ""


def test_a_file_that_cannot_be_written_is_one_error_line(tmp_path, db_target):
    db = db_target
    invoke(db, "add", str(case_file(ZHUKOVSKY)))
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = invoke(db, "export", "--format", "csv", "-o", str(blocker / "out"))
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        f"Error: cannot use {str(blocker / 'out')!r}: Not a directory"
    ]


class _RecordingBar:
    """Stands in for tqdm: records how it was made and what it was told."""

    made: list[_RecordingBar] = []

    def __init__(self, **kwargs):
        self.kwargs, self.postfixes, self.updates, self.closed = kwargs, [], 0, False
        _RecordingBar.made.append(self)

    def set_postfix_str(self, text, refresh=True):
        self.postfixes.append(text)

    def update(self, n=1):
        self.updates += n

    def close(self):
        self.closed = True


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.fixture
def recording_bar(monkeypatch):
    import tqdm

    _RecordingBar.made = []
    monkeypatch.setattr(tqdm, "tqdm", _RecordingBar)
    return _RecordingBar.made


def test_audit_json_is_quiet_and_parsable(audited, recording_bar):
    result = CliRunner().invoke(main, ["--db", str(audited.db), "audit", "--json", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["cases"]
    (bar,) = recording_bar
    assert bar.kwargs["disable"] is True and bar.closed


def test_audit_json_with_the_real_bar_prints_only_json(audited):
    result = CliRunner().invoke(main, ["--db", str(audited.db), "audit", "--json", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["run"] > 0
    assert result.stderr == ""


def test_audit_on_a_terminal_shows_each_case(db_target, monkeypatch, recording_bar):
    db = db_target
    runner = CliRunner()
    assert runner.invoke(main, ["--db", db, "add", str(CASES / f"{ZHUKOVSKY}.toml")]).exit_code == 0
    monkeypatch.setattr("registry.cli.sys", SimpleNamespace(stderr=_Tty(), exit=sys.exit))
    result = runner.invoke(main, ["--db", db, "audit", "--fresh", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    (bar,) = recording_bar
    assert bar.kwargs["disable"] is False and bar.kwargs["total"] == 1
    assert bar.postfixes == [ZHUKOVSKY] and bar.updates == 1 and bar.closed
    assert ZHUKOVSKY in result.stdout


@pytest.mark.parametrize(("old", "new"), [("checks", "list-checks"), ("check", "verify-db")])
def test_renamed_commands_are_gone_under_their_old_names(old, new):
    """No hidden aliases: the old name is an unknown command, the new one is listed."""
    assert old not in main.commands and new in main.commands
    result = invoke(None, old)
    assert result.exit_code != 0
    assert "No such command" in result.output + result.stderr


def test_every_branch_of_a_condition_reaches_the_json_the_table_and_corrections(db_target):
    # the Zhukovsky-Volterra gyrostat's |M|^2 holds on five components: A = B = C (any
    # gyrostatic moment), and a moment along a principal axis of a body symmetric about it
    path = CLASSICAL / "zhukovsky-volterra-gyrostat.toml"
    assert invoke(db_target, "add", str(path)).exit_code == 0
    done = invoke(db_target, "audit", "--json")
    (case,) = json.loads(done.stdout)["cases"]
    claim = [c for c in case["claims"] if c["label"] == "M-false"][0]
    assert claim["holds_when"] == ["A = C", "B = C"]
    assert claim["holds_when_branches"] == [
        ["A = B", "k1 = 0", "k2 = 0"],
        ["A = C", "k1 = 0", "k3 = 0"],
        ["B = C", "k2 = 0", "k3 = 0"],
        ["k1 = 0", "k2 = 0", "k3 = 0"],
    ]
    table = invoke(db_target, "audit").stdout  # the stored results, reused
    words = " ".join(table.split())  # the line is wrapped at 80 columns
    assert "M-false: holds when A = C, B = C or A = B, k1 = 0, k2 = 0 or " in words
    listing = invoke(db_target, "corrections", env={"COLUMNS": "200"}).stdout
    rows = [words for _, words in grouped_rows(listing.split("\n", 1)[1])]
    branches = [" ".join(r[2:]) for r in rows if r[:2] == ["M-false", "conditions"]]
    assert branches[:2] == ["A = C, B = C verified", "A = B, k1 = 0, k2 = 0 verified"]
    assert len(branches) == 5


def test_the_corrections_budget_bounds_the_corrections_alone(module_databases):
    """``--corrections-budget``: the corrections of a case with a wrong torque claim run
    out of it (and say so), the checks keep theirs and their verdicts."""
    case = "yehia-2003-kovalevskaya-b"
    db = module_databases.new("corrections-budget")
    assert invoke(db, "add", str(case_file(case))).exit_code == 0
    args = ("audit", "--case", case, "--json", "--fresh", "--jobs", "1", *PATIENT_OPTIONS)
    patient = json.loads(invoke(db, *args).stdout)
    cut = invoke(db, *args, "--corrections-budget", "1e-9")
    assert cut.exit_code == 0, cut.output
    hurried = json.loads(cut.stdout)
    (entry,) = hurried["cases"]
    (before,) = patient["cases"]
    assert entry["family"] == {
        "name": "none",
        "reason": "corrections: time budget exceeded (1e-09 s)",
    }
    assert before["family"]["name"] == "psi-gamma-grad-phi"  # found with time to do it
    (claim,) = entry["claims"]
    (claim_before,) = before["claims"]
    assert claim_before["corrections"] and "corrections" not in claim
    keep = ("label", "integral", "casimir", "verdict")
    assert {k: claim[k] for k in keep} == {k: claim_before[k] for k in keep}
    assert entry["checks"] == before["checks"]


def test_a_bad_budget_in_the_environment_is_one_line_naming_it(module_databases, monkeypatch):
    db = module_databases.new("bad-budget")
    assert invoke(db, "add", str(case_file("zhukovsky-gyrostat"))).exit_code == 0
    monkeypatch.setenv("REGISTRY_BUDGET", "soon")
    result = invoke(db, "audit")
    assert result.exit_code != 0
    assert error_lines(result) == [
        "Error: $REGISTRY_BUDGET must be a positive number of seconds, not 'soon' "
        "(unset it for the built-in default)"
    ]
    monkeypatch.delenv("REGISTRY_BUDGET")
    assert registry.open(db).runs().empty  # refused before any run was started


def test_a_bad_lock_wait_in_the_environment_is_one_line_naming_it(tmp_path, monkeypatch):
    monkeypatch.setenv("REGISTRY_LOCK_TIMEOUT", "soon")
    result = invoke(tmp_path / "registry.sqlite", "add", str(case_file(ZHUKOVSKY)))
    assert result.exit_code != 0
    assert error_lines(result) == [
        "Error: $REGISTRY_LOCK_TIMEOUT must be a positive number of seconds, not 'soon' "
        "(unset it for the built-in default)"
    ]


def test_the_audit_forks_its_workers_where_no_other_thread_of_the_command_runs(
    tmp_path, monkeypatch
):
    # A fork copies the locks other threads hold, without the threads that would
    # release them: the local pool's workers are forked from this process, so the
    # command starts no thread of its own before it (tqdm's monitor thread did).
    import threading

    from registry.execution import local

    before = set(threading.enumerate())
    started: list[str] = []
    original = local._Worker.__init__

    def watching(self, *args, **kwargs):
        started.extend(t.name for t in threading.enumerate() if t not in before)
        original(self, *args, **kwargs)

    monkeypatch.setattr(local._Worker, "__init__", watching)
    db = tmp_path / "registry.sqlite"
    assert invoke(db, "add", str(case_file(ZHUKOVSKY))).exit_code == 0
    result = invoke(db, "audit", "--jobs", "2", *PATIENT_OPTIONS)
    assert result.exit_code == 0, result.output
    assert started == []
