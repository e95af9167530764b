"""Several processes on one database at once, in real processes (issues "Trust" and
"Beyond one machine"), on an SQLite file and on a PostgreSQL database (``backend``).

Two audits and two adds of the same files running at the same time on one database
all finish (SQLite: WAL journal, busy timeout, BEGIN IMMEDIATE, retries on "database
is locked"; PostgreSQL: advisory locks around "read the next version and insert it",
lock timeouts, retries), and pandas queries in another process work while the
audits write. The adds start once both audits have recorded their runs, so that
their new case versions are written while the audits commit results. Nothing is
lost or duplicated: each case content is stored once, each run is complete with
every check of every case once, and ``registry check`` is clean afterwards. Two
processes adding the same new files (to a registry, or to a database that has no
tables yet) store each case once.
"""

from __future__ import annotations

import re
import sqlite3
import subprocess
import sys
import time
from contextlib import closing
from pathlib import Path

import pandas as pd
import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.store.tables import RUN_STATUSES
from tests.helpers.databases import is_url, rows
from tests.helpers.samples import CASES

#: Seconds a process may take before the test calls it a hang.
WAIT = 180.0

#: One line of ``registry add`` for a stored file: status, case id, version, path.
ADD_LINE = re.compile(r"^(added|unchanged|new version)\s+(\S+) \(version (\d+)\)\s+(.+)$")

#: The closing tally of ``registry add``: "4 file(s): 1 added, 3 new version, ...".
ADD_TALLY = re.compile(r"^(\d+) file\(s\): ")

#: Seed cases given a new title (a new version) in the folder added during the audits.
RETITLED = ("axis-torque", "grioli-1957-charged-body", "zhukovsky-gyrostat")

#: Seed cases copied under new ids, for the new-case folders.
COPIED = ("zhukovsky-gyrostat", "axis-torque", "yehia-2003-cyclic", "goryachev-chaplygin-1900")


# ------------------------------------------------------------------- helpers


def copy_case(source_id: str, folder: Path, *, new_id: str | None = None, title: str) -> Path:
    """Write a seed case file into ``folder``, with a new title (and id, if given)."""
    text = (CASES / f"{source_id}.toml").read_text(encoding="utf-8")
    text, n = re.subn(r'(?m)^title = ".*"$', f'title = "{title}"', text, count=1)
    assert n == 1, source_id
    if new_id is not None:
        text, n = re.subn(r'(?m)^id = ".*"$', f'id = "{new_id}"', text, count=1)
        assert n == 1, source_id
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{new_id or source_id}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def new_cases(folder: Path) -> list[str]:
    """Copies of seed cases under new ids; returns the ids."""
    ids = []
    for source in COPIED:
        new_id = f"{source}-copy"
        copy_case(source, folder, new_id=new_id, title=f"Copy of {source}")
        ids.append(new_id)
    return ids


def start(command: list[str], out: Path) -> subprocess.Popen:
    """A registry process whose output goes to files (no pipe can fill up and block it)."""
    with out.with_suffix(".out").open("w") as stdout, out.with_suffix(".err").open("w") as stderr:
        return subprocess.Popen(
            [sys.executable, "-m", "registry", *command],
            stdout=stdout,
            stderr=stderr,
            start_new_session=True,
        )


def finish(proc: subprocess.Popen, out: Path) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of a process started by ``start``."""
    try:
        proc.wait(timeout=WAIT)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        pytest.fail(f"{proc.args} did not finish within {WAIT:.0f} s")
    return (
        proc.returncode,
        out.with_suffix(".out").read_text(),
        out.with_suffix(".err").read_text(),
    )


def add_lines(stdout: str) -> list[tuple[str, str, int]]:
    """The stored-file lines of ``registry add`` as (status, case, version)."""
    parsed = []
    lines = stdout.strip().splitlines()
    tally = ADD_TALLY.match(lines[-1]) if lines else None
    if tally:
        lines.pop()
        assert int(tally.group(1)) == len(lines), stdout
    for line in lines:
        match = ADD_LINE.match(line)
        assert match, f"unexpected line from add: {line!r}"
        status, case, version, _ = match.groups()
        parsed.append((status, case, int(version)))
    return parsed


def assert_clean(name: str, code: int, stdout: str, stderr: str) -> None:
    assert code == 0, f"{name} exited with {code}:\n{stderr}"
    assert "Error:" not in stderr, f"{name}:\n{stderr}"
    assert "Traceback" not in stderr + stdout, f"{name}:\n{stderr}"


def assert_sound(db: str) -> None:
    """SQLite's own checks (on a file), ``registry check``, and every case content
    stored once."""
    if not is_url(db):
        with closing(sqlite3.connect(db, timeout=30)) as conn:
            assert [r[0] for r in conn.execute("PRAGMA integrity_check")] == ["ok"]
            assert conn.execute("PRAGMA foreign_key_check").fetchall() == []
    checked = CliRunner().invoke(main, ["--db", str(db), "verify-db"])
    assert checked.exit_code == 0, checked.output
    assert "problem:" not in checked.output
    twice = rows(
        db,
        "SELECT case_id, content_hash FROM cases GROUP BY case_id, content_hash "
        "HAVING count(*) > 1",
    )
    assert twice == [], "a case content stored more than once"


# ---------------------------------------------------------------------- tests


@pytest.mark.slow  # four registry commands at once on the catalog: over a minute per backend loaded
def test_two_audits_and_two_adds_at_once_all_finish_while_pandas_reads(tmp_path, db_target, capsys):
    db = db_target
    with registry.open(db) as reg:
        seeded = {r.case: r.version for r in reg.add(CASES)}
    assert len(seeded) == len(list(CASES.rglob("*.toml"))) and set(seeded.values()) == {1}
    incoming = tmp_path / "incoming"
    for case_id in RETITLED:
        copy_case(case_id, incoming, title=f"Retitled {case_id}")
    new_id = "zhukovsky-gyrostat-copy"
    copy_case("zhukovsky-gyrostat", incoming, new_id=new_id, title="A copy, added during audits")

    names = ("audit-1", "audit-2", "add-1", "add-2")
    commands = {
        "audit-1": ["--db", str(db), "audit", "--fresh", "--jobs", "1"],
        "audit-2": ["--db", str(db), "audit", "--fresh", "--jobs", "1"],
        "add-1": ["--db", str(db), "add", str(incoming)],
        "add-2": ["--db", str(db), "add", str(incoming)],
    }
    # the audits start together; the adds as soon as both runs are recorded, so that
    # their writes meet the audits' (each commits a case every fraction of a second)
    # and each other's (the same files, at the same time)
    procs = {name: start(commands[name], tmp_path / name) for name in names[:2]}

    # meanwhile, this process reads with pandas, through the API and with plain SQL
    queries, failures, seen_running = 0, [], 0
    deadline = time.monotonic() + WAIT
    with registry.open(db) as reader:
        while "add-1" not in procs or any(p.poll() is None for p in procs.values()):
            assert time.monotonic() < deadline, "the processes did not finish"
            for query in (
                reader.verdicts,
                reader.runs,
                lambda: pd.read_sql(
                    "SELECT run_id, count(*) AS n FROM check_results GROUP BY run_id",
                    reader.store.engine,
                ),
            ):
                try:
                    frame = query()
                except Exception as err:  # every failure is reported below
                    failures.append(f"{type(err).__name__}: {err}")
                    continue
                queries += 1
                assert isinstance(frame, pd.DataFrame)
                if "status" in frame:
                    assert set(frame["status"]) <= set(RUN_STATUSES)
                    seen_running = max(seen_running, int((frame["status"] == "running").sum()))
            if "add-1" not in procs and (
                seen_running == 2 or all(p.poll() is not None for p in procs.values())
            ):
                for name in names[2:]:
                    procs[name] = start(commands[name], tmp_path / name)
            time.sleep(0.02)
    outcomes = {name: finish(procs[name], tmp_path / name) for name in names}

    for name, (code, stdout, stderr) in outcomes.items():
        assert_clean(name, code, stdout, stderr)
    assert failures == []
    assert queries > 0
    assert seen_running == 2, "no query saw both audits at work"

    # each file stored by one add; the other found it unchanged
    added = add_lines(outcomes["add-1"][1]) + add_lines(outcomes["add-2"][1])
    expected = [("new version", case_id, 2) for case_id in RETITLED] + [("added", new_id, 1)]
    expected += [("unchanged", case_id, version) for _, case_id, version in expected]
    assert sorted(added) == sorted(expected)

    with registry.open(db) as reg:
        runs = reg.runs()
        assert list(runs["status"]) == ["complete", "complete"]
        cases = reg.cases()
        assert set(cases["case"]) == set(seeded) | {new_id}
        # both runs read the case list before the add began: each audited every seed
        # case in its first version, with the same checks
        # a system given by its equations has no bracket to check: without claims, its
        # audit records nothing
        form = dict(zip(cases["case"], cases["form"], strict=True))
        claims = reg.claims()
        decided = {c for c in seeded if form[c] != "equations" or c in set(claims["case"])}
        assert len(decided) < len(seeded), "the catalog holds equations without claims"
        checks = []
        for run in runs["run"]:
            verdicts = reg.verdicts(run)
            assert dict(verdicts.groupby("case")["version"].unique().map(list)) == {
                case_id: [1] for case_id in decided
            }
            keys = verdicts.fillna({"claim": ""})[["case", "claim", "check"]]
            assert not keys.duplicated().any(), f"run {run} recorded a check twice"
            checks.append(sorted(keys.itertuples(index=False, name=None)))
        assert checks[0] == checks[1]
        # every check of every case: one per claim (a retitled case's new version has
        # the same claims), and the case checks
        case_checks = {  # C1 is the reference paper's Casimir condition
            "inertia": {"jacobi", "energy", "c1"},
            "hamiltonian": {"jacobi", "energy", "c1"},
            "bracket": {"jacobi", "energy"},
            "equations": set(),
        }
        for case_id in seeded:
            labels = set(claims.loc[claims["case"] == case_id, "label"])
            for found in checks:
                mine = [(claim, check) for case, claim, check in found if case == case_id]
                assert {claim for claim, _ in mine if claim} == labels, case_id
                done = {check for claim, check in mine if not claim}
                assert done >= case_checks[form[case_id]], case_id
        added_at = cases.set_index("case").loc[new_id, "added_at"]
        overlap = [
            f"run {r.run}: {r.started_at:%H:%M:%S.%f} to {r.finished_at:%H:%M:%S.%f}"
            for r in runs.itertuples()
        ]
    with capsys.disabled():
        print(f"\n{queries} queries; {new_id} added at {added_at:%H:%M:%S.%f}", *overlap, sep="; ")
    assert_sound(db)


@pytest.mark.parametrize("database", ["existing", "new"])
def test_two_adds_of_the_same_new_files_store_each_case_once(tmp_path, db_target, database):
    db = db_target  # "new": no file yet, or a server database without tables
    if database == "existing":
        with registry.open(db) as reg:
            reg.add(CASES / "borisov-mamaev-1997.toml")
    folder = tmp_path / "new"
    ids = new_cases(folder)

    procs = [start(["--db", str(db), "add", str(folder)], tmp_path / f"add-{i}") for i in (1, 2)]
    outcomes = [finish(p, tmp_path / f"add-{i}") for i, p in zip((1, 2), procs, strict=True)]

    reports = []
    for i, (code, stdout, stderr) in enumerate(outcomes, start=1):
        assert_clean(f"add-{i}", code, stdout, stderr)
        reports.append(add_lines(stdout))
    for case_id in ids:
        said = sorted(
            (status, version) for lines in reports for status, case, version in lines
            if case == case_id
        )  # fmt: skip
        assert said == [("added", 1), ("unchanged", 1)], case_id

    stored = rows(
        db, "SELECT case_id, version FROM cases WHERE case_id LIKE '%-copy' ORDER BY case_id"
    )
    assert stored == sorted((case_id, 1) for case_id in ids)
    assert_sound(db)
