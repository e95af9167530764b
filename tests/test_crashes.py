"""Audits killed at random moments, in real processes (issue "Trust").

An audit killed with SIGKILL at any moment must leave a database that passes
``PRAGMA integrity_check``, keeps every earlier run byte for byte, and shows
the killed run as ``interrupted`` (once a process opens the database again),
never as ``complete``. SIGTERM ends an audit like Ctrl-C: the process itself
records the run as ``interrupted`` and leaves no worker behind.

Each audit is a real ``python -m registry ... audit --fresh`` started in its own
session, so that ``os.killpg`` kills it together with its worker processes. The
kill moments are drawn from a seeded random generator; some are times after the
start, some wait until the run has committed a number of cases first, so that
start-up, "run started, nothing committed" and "some cases committed" are all
covered whatever the load of the machine.
"""

from __future__ import annotations

import os
import random
import signal
import sqlite3
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import closing, contextmanager
from pathlib import Path

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from tests.helpers.clocks import PATIENT_OPTIONS
from tests.helpers.processes import group_members, kill_group, registry_command, wait_until_gone
from tests.helpers.samples import SEED_FILES

#: Seconds a killed or finishing process may take before the test calls it a hang.
WAIT = 120.0

#: A fresh audit of the 16 seed cases takes about this long on two cores (start-up included).
TYPICAL = 4.5

#: Tables whose rows belong to one run (column ``run_id``).
RUN_TABLES = ("check_results", "corrections", "evidence", "drift_curves")


# ------------------------------------------------------------------- processes


def start_audit(db: Path, *args: str) -> subprocess.Popen:
    """``registry audit --fresh`` in a new session (its process group holds its workers)."""
    return subprocess.Popen(
        registry_command(db, "audit", "--fresh", *PATIENT_OPTIONS, *args),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


@contextmanager
def reaped(proc: subprocess.Popen) -> Iterator[subprocess.Popen]:
    """Kill the process group of ``proc`` when the test leaves, whatever happened."""
    try:
        yield proc
    finally:
        if proc.poll() is None or group_members(proc.pid):
            kill_group(proc.pid)
        proc.communicate(timeout=WAIT)


# -------------------------------------------------------------------- database


def connect(db: Path) -> sqlite3.Connection:
    """A plain sqlite3 connection, for looking at the file exactly as it was left."""
    return sqlite3.connect(db, timeout=30)


def sqlite_checks(db: Path) -> tuple[list[str], list[tuple]]:
    """(PRAGMA integrity_check, PRAGMA foreign_key_check) of the file."""
    with closing(connect(db)) as conn:
        integrity = [row[0] for row in conn.execute("PRAGMA integrity_check")]
        foreign = conn.execute("PRAGMA foreign_key_check").fetchall()
    return integrity, foreign


def snapshot(db: Path, up_to_run: int) -> dict[str, list[tuple]]:
    """Every row of every table, except those of runs after ``up_to_run``."""
    rows = {}
    with closing(connect(db)) as conn:
        tables = [
            name
            for (name,) in conn.execute(
                "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'"
            )
        ]
        for table in tables:
            if table == "audit_runs":
                where = f"WHERE id <= {up_to_run}"
            elif table in RUN_TABLES:
                where = f"WHERE run_id <= {up_to_run}"
            else:
                where = ""
            rows[table] = conn.execute(f"SELECT * FROM {table} {where} ORDER BY 1").fetchall()
    assert {"audit_runs", "cases", *RUN_TABLES} <= rows.keys()
    return rows


def runs(db: Path) -> dict[int, tuple[str, str | None]]:
    """run -> (status, finished_at), read straight from the file (no Store opened)."""
    with closing(connect(db)) as conn:
        found = conn.execute("SELECT id, status, finished_at FROM audit_runs ORDER BY id")
        return {run: (status, finished) for run, status, finished in found}


def committed_cases(conn: sqlite3.Connection, after_run: int) -> tuple[int | None, int]:
    """(the newest run after ``after_run`` or None, how many cases it has committed)."""
    run = conn.execute("SELECT max(id) FROM audit_runs WHERE id > ?", (after_run,)).fetchone()[0]
    if run is None:
        return None, 0
    (n,) = conn.execute(
        "SELECT count(DISTINCT case_pk) FROM check_results WHERE run_id = ?", (run,)
    ).fetchone()
    return run, n


def result_keys(db: Path, run: int) -> dict[int, set[tuple]]:
    """case_pk -> the (claim, check) of each of its results in ``run``."""
    keys: dict[int, set[tuple]] = {}
    with closing(connect(db)) as conn:
        for case_pk, claim, check in conn.execute(
            'SELECT case_pk, claim_id, "check" FROM check_results WHERE run_id = ?', (run,)
        ):
            keys.setdefault(case_pk, set()).add((claim, check))
    return keys


def wait_for_cases(
    proc: subprocess.Popen, db: Path, after_run: int, cases: int, timeout: float = WAIT
) -> bool:
    """Poll the file until the run started after ``after_run`` has committed ``cases``
    cases (0: until the run exists). False if the audit ended first."""
    deadline = time.monotonic() + timeout
    with closing(connect(db)) as conn:
        while time.monotonic() < deadline:
            if proc.poll() is not None:
                return False
            run, n = committed_cases(conn, after_run)
            if run is not None and n >= cases:
                return True
            time.sleep(0.01)
    pytest.fail(f"no run committed {cases} case(s) within {timeout:.0f} s")


def check_command(db: Path) -> object:
    """``registry check`` in this process."""
    return CliRunner().invoke(main, ["--db", str(db), "verify-db"])


# ---------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def audited(tmp_path_factory) -> tuple[Path, int]:
    """A database with the 16 seed cases and one complete fresh audit, in real processes;
    returns (file, number of cases). Tests work on copies of it."""
    db = tmp_path_factory.mktemp("crashes") / "audited.sqlite"
    added = subprocess.run(
        registry_command(db, "add", *map(str, SEED_FILES)),
        capture_output=True,
        text=True,
        timeout=WAIT,
    )
    assert added.returncode == 0, added.stderr
    done = subprocess.run(
        registry_command(db, "audit", "--fresh", *PATIENT_OPTIONS),
        capture_output=True,
        text=True,
        timeout=WAIT,
    )
    assert done.returncode == 0, done.stderr
    assert [status for status, _ in runs(db).values()] == ["complete"]
    n_cases = len(SEED_FILES)
    return db, n_cases


@pytest.fixture
def db(audited, tmp_path) -> Path:
    """A copy of the audited database (with SQLite's backup API: WAL content included)."""
    source, _ = audited
    copy = tmp_path / "registry.sqlite"
    with closing(connect(source)) as src, closing(connect(copy)) as dst:
        src.backup(dst)
        dst.execute("PRAGMA journal_mode=WAL")
    return copy


# ------------------------------------------------------------------------ SIGKILL


def kill_plan(rng: random.Random, n_cases: int) -> list[tuple[str, float]]:
    """When to kill each audit: ("time", seconds after start) or ("cases", n committed).

    Drawn from ``rng``, but always including kills during the interpreter's start-up,
    right after the run is recorded, after some cases are committed, and right after
    the last one is (before or just after the run is marked complete).
    """
    return [
        ("time", rng.uniform(0.0, 0.25)),  # the interpreter starting
        ("time", rng.uniform(0.25, 1.2)),  # imports, opening the database
        ("cases", 0),  # the run row committed, no case yet
        ("cases", rng.randint(1, n_cases // 2)),  # some cases committed
        ("time", rng.uniform(1.2, TYPICAL)),
        ("time", rng.uniform(0.0, TYPICAL)),
        ("cases", n_cases),  # every case committed
    ]


@pytest.mark.slow  # seven audits killed, then one complete: about 20 s on two cores
def test_audits_killed_at_random_moments_leave_a_sound_database(db, audited, capsys):
    _, n_cases = audited
    rng = random.Random(20240613)
    reference = result_keys(db, 1)  # the results of each case in a complete fresh run
    assert len(reference) == n_cases
    landed = []
    outcomes = []  # (trigger, value, where the kill landed, cases committed)
    for trigger, value in kill_plan(rng, n_cases):
        before = runs(db)
        earlier = max(before)
        kept = snapshot(db, earlier)

        proc = start_audit(db)
        with reaped(proc):
            t0 = time.monotonic()
            if trigger == "time":
                time.sleep(value)
            elif wait_for_cases(proc, db, earlier, int(value)):
                time.sleep(rng.uniform(0.0, 0.03))
            elapsed = time.monotonic() - t0
            kill_group(proc.pid)
            proc.communicate(timeout=WAIT)
            assert wait_until_gone(proc.pid) == [], "worker processes outlived the kill"

        # the file exactly as the kill left it: sound, earlier runs untouched
        integrity, foreign = sqlite_checks(db)
        assert integrity == ["ok"]
        assert foreign == []
        assert snapshot(db, earlier) == kept
        left = runs(db)
        new = sorted(set(left) - set(before))
        assert len(new) <= 1, f"one audit recorded runs {new}"
        killed = new[0] if new else None
        where, category, committed = "before start_run", "before start_run", 0
        if killed is not None:
            keys = result_keys(db, killed)
            # each case's results are committed together or not at all
            for case_pk, found in keys.items():
                assert found == reference[case_pk], f"case {case_pk} committed partly"
            status = left[killed][0]
            committed = len(keys)
            if status == "complete":
                assert len(keys) == n_cases
                where = category = "after finish_run (complete)"
            else:
                assert status == "running", f"killed run {killed} is {status}"
                where = f"mid-run, {len(keys)}/{n_cases} cases committed"
                category = "mid-run"
        outcomes.append((trigger, value, category, committed))
        landed.append(
            f"{trigger}={value:g}: killed after {elapsed:.2f} s (exit {proc.returncode}), {where}"
        )

        # opening the registry again marks the run of the dead process interrupted
        with registry.open(db) as reg:
            frame = reg.runs()
        statuses = dict(zip(frame["run"], frame["status"], strict=True))
        assert "running" not in statuses.values()
        assert statuses == {
            run: status if status != "running" else "interrupted"
            for run, (status, _) in left.items()
        }
        if killed is not None and statuses[killed] == "complete":
            assert proc.returncode in (0, -signal.SIGKILL)
            assert frame.set_index("run").loc[killed, "n_cases"] == n_cases
        assert snapshot(db, earlier) == kept
        checked = check_command(db)
        assert checked.exit_code == 0, checked.output

    with capsys.disabled():
        print("\nSIGKILL moments:\n  " + "\n  ".join(landed))
    # the plan's moments were really hit: a kill during the interpreter's start-up (the
    # first moment, < 0.25 s) came before the run was recorded, and every kill that
    # waited for a run to commit fewer than all its cases landed in the middle of it
    categories = [category for _, _, category, _ in outcomes]
    assert "before start_run" in categories, landed
    assert "mid-run" in categories, landed
    assert outcomes[0][2] == "before start_run", landed
    for trigger, value, category, committed in outcomes:
        if trigger == "cases" and value < n_cases:
            assert category == "mid-run" and committed >= value, landed

    # the next audit, in a real process, completes normally
    done = subprocess.run(
        registry_command(db, "audit", "--fresh", *PATIENT_OPTIONS),
        capture_output=True,
        text=True,
        timeout=WAIT,
    )
    assert done.returncode == 0, done.stderr
    final = runs(db)
    last = max(final)
    assert final[last][0] == "complete"
    assert result_keys(db, last) == reference
    assert "running" not in {status for status, _ in final.values()}
    checked = subprocess.run(
        registry_command(db, "verify-db"), capture_output=True, text=True, timeout=WAIT
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert sqlite_checks(db) == (["ok"], [])


# ------------------------------------------------------------------------ SIGTERM


@pytest.mark.slow  # audits stopped by SIGTERM, then re-run: about a minute when loaded
@pytest.mark.parametrize("cases", [0, 3], ids=["run-recorded", "3-cases-committed"])
def test_sigterm_records_the_run_as_interrupted_and_stops_the_workers(db, audited, cases):
    _, n_cases = audited
    kept = snapshot(db, 1)
    proc = start_audit(db, "--jobs", "2")
    with reaped(proc):
        assert wait_for_cases(proc, db, 1, cases), "the audit ended before it could be stopped"
        os.kill(proc.pid, signal.SIGTERM)  # the audit process only, not its group
        _, stderr = proc.communicate(timeout=WAIT)
        assert wait_until_gone(proc.pid) == [], "worker processes outlived the audit"
    assert proc.returncode > 0, stderr  # it ended itself, not by SIGTERM's default action
    assert "Traceback" not in stderr, stderr

    # recorded by the audit process itself, before any other process opens the file
    left = runs(db)
    assert sorted(left) == [1, 2]
    status, finished = left[2]
    assert status == "interrupted"
    assert finished is not None
    assert len(result_keys(db, 2)) >= cases
    assert len(result_keys(db, 2)) < n_cases
    assert sqlite_checks(db) == (["ok"], [])
    assert snapshot(db, 1) == kept
    checked = check_command(db)
    assert checked.exit_code == 0, checked.output


#: A ``registry`` command line that sends itself SIGTERM while SQLAlchemy flushes the
#: results of the first case audited. A random SIGTERM landing there used to hang the
#: audit for ever: the workers' generator stayed open, multiprocessing's exit handler
#: sent SIGTERM to the workers, and a busy worker (with the parent's SIGTERM handler)
#: caught the KeyboardInterrupt and waited for a next case that never came.
SIGTERM_IN_FLUSH = """\
import os, signal, sys
from sqlalchemy import event
from sqlalchemy.orm import Session
from registry.cli import main
from registry.store.tables import ResultRow

sent = []

@event.listens_for(Session, "before_flush")
def terminate_once(session, *args):
    if not sent and any(isinstance(row, ResultRow) for row in session.new):
        sent.append(True)
        os.kill(os.getpid(), signal.SIGTERM)

main(sys.argv[1:])
"""

#: Seconds an audit may take to end after SIGTERM before the test calls it a hang.
HANG = 20.0


def test_sigterm_while_a_case_is_committed_ends_the_audit(db, audited, tmp_path):
    _, n_cases = audited
    driver = tmp_path / "sigterm_in_flush.py"
    driver.write_text(SIGTERM_IN_FLUSH, encoding="utf-8")
    proc = subprocess.Popen(
        [
            sys.executable,
            str(driver),
            "--db",
            str(db),
            "audit",
            "--fresh",
            "--jobs",
            "2",
            *PATIENT_OPTIONS,
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    with reaped(proc):
        try:
            _, stderr = proc.communicate(timeout=HANG)
        except subprocess.TimeoutExpired:
            alive = group_members(proc.pid)
            pytest.fail(f"the audit did not end within {HANG:.0f} s of SIGTERM; alive: {alive}")
        assert wait_until_gone(proc.pid) == [], "worker processes outlived the audit"
    assert proc.returncode > 0, stderr
    assert "Traceback" not in stderr, stderr
    status, finished = runs(db)[2]
    assert status == "interrupted" and finished is not None
    reference, committed = result_keys(db, 1), result_keys(db, 2)
    assert len(committed) < n_cases
    assert all(keys == reference[case_pk] for case_pk, keys in committed.items())
    assert sqlite_checks(db) == (["ok"], [])
