"""``registry copy``: a registry copied whole (every table, ids and history) into a new
or empty database, from either backend to either (fixture ``backend``), verified
before it is committed, and all or nothing: a target that holds rows is refused
unchanged, a copy that does not verify is rolled back, and a copy killed (SIGKILL) at
random points leaves its target empty or complete, never half.

Rows are compared as data, read through the registry's column types: JSON as the values
it holds, times as aware UTC datetimes, booleans as booleans (``registry_rows``).
"""

from __future__ import annotations

import random
import shutil
import signal
import sqlite3
import subprocess
import time
from pathlib import Path

import pytest
from click.testing import CliRunner
from sqlalchemy import func, inspect, select

import registry
from registry.cli import main
from registry.errors import (
    CopySameDatabaseError,
    CopyTargetNotEmptyError,
    CopyVerificationError,
    ServerDatabaseMissingError,
)
from registry.language.casefile import parse_case_text
from registry.store import migrate
from registry.store.copying import copy_registry, rows_named
from registry.store.database import Store
from registry.store.integrity import verify
from registry.store.tables import Base
from tests.helpers.clocks import HANG
from tests.helpers.databases import POSTGRES, connection, database_name, execute, is_url
from tests.helpers.processes import registry_command
from tests.helpers.registries import registry_rows
from tests.helpers.samples import ZHUKOVSKY, case_file

# ---------------------------------------------------------------------- helpers


@pytest.fixture
def source(full_registry_file, tmp_path) -> Path:
    """A copy of the full registry for one test (a test may damage it)."""
    copy = tmp_path / "source.sqlite"
    shutil.copyfile(full_registry_file, copy)
    return copy


def held_rows(target: str | Path) -> dict[str, int] | None:
    """Rows per registry table (``meta`` left out), or None when the target has no
    registry tables (or, for a file, does not exist)."""
    if not is_url(target) and not Path(target).exists():
        return None
    with connection(target) as conn:
        present = set(inspect(conn).get_table_names()) & set(Base.metadata.tables)
        if not present:
            return None
        return {
            t: conn.scalar(select(func.count()).select_from(Base.metadata.tables[t])) or 0
            for t in sorted(present - {"meta"})
        }


def test_the_source_has_rows_in_every_table(full_registry_file):
    rows = registry_rows(full_registry_file)
    assert all(rows[t.name] for t in Base.metadata.sorted_tables), {
        name: len(found) for name, found in rows.items()
    }


# ------------------------------------------------------------------------ copies


def test_a_registry_is_copied_whole_into_a_new_database(source, databases):
    target = databases.new("copy")
    with Store(source) as store:
        report = copy_registry(store, target)
    assert report.created and report.verification.ok
    assert report.target == target and report.source == str(source)
    expected = registry_rows(source)
    assert dict(report.rows) == {name: len(rows) for name, rows in expected.items()}
    assert registry_rows(target) == expected
    assert not list(source.parent.glob(".*.tmp*"))  # no temporary file left beside it

    with registry.open(target) as copy, registry.open(source) as original:
        assert copy.verify_db().ok
        assert copy.verdicts().equals(original.verdicts())
        assert copy.cases().equals(original.cases())
        # the ids go on after the copied ones (PostgreSQL's sequences were moved)
        added = copy.store.add_case(parse_case_text(_renamed(ZHUKOVSKY, "after-copy")))
        assert added.pk == max(r["id"] for r in expected["cases"]) + 1
        run = copy.store.start_run({}, "test")
        assert run == max(r["id"] for r in expected["audit_runs"]) + 1


def _renamed(case_id: str, new_id: str) -> str:
    text = case_file(case_id).read_text(encoding="utf-8")
    return text.replace(f'id = "{case_id}"', f'id = "{new_id}"', 1)


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_sqlite_to_postgresql_and_back_keeps_every_row(source, databases, tmp_path):
    """The round trip SQLite -> PostgreSQL -> SQLite: every table's rows equal as data.
    As text they differ only in representation: PostgreSQL's json and SQLite's JSON text
    (spaces, key order), timestamptz and SQLite's naive UTC text, booleans and 0/1."""
    server = databases.new("server")
    back = tmp_path / "back.sqlite"
    with Store(source) as store:
        copy_registry(store, server)
    with Store(server, create=False) as store:
        report = copy_registry(store, back)
    assert report.verification.ok
    before = registry_rows(source)
    assert registry_rows(server) == before
    assert registry_rows(back) == before
    with Store(back, create=False) as store:
        assert verify(store).ok


def test_an_empty_registry_is_filled(source, databases):
    target = databases.new("empty")
    Store(target).close()  # a registry with its tables and no rows
    with Store(source) as store:
        report = copy_registry(store, target)
    assert not report.created
    assert registry_rows(target) == registry_rows(source)


def test_a_target_that_holds_rows_is_refused_unchanged(source, databases, sample_case):
    target = databases.new("busy")
    with Store(target) as store:
        store.add_case(sample_case)
    before = registry_rows(target)
    with Store(source) as store, pytest.raises(CopyTargetNotEmptyError) as info:
        copy_registry(store, target)
    assert str(info.value) == (
        f"the target {target!r} is not empty (it holds 1 source, 1 case version, 2 claims); "
        "registry copy fills only a new file or an empty database, so nothing was changed: "
        "name a new file, or an empty database on the server (createdb NAME)"
    )
    assert registry_rows(target) == before


def test_a_registry_is_not_copied_into_itself(source):
    with Store(source) as store, pytest.raises(CopySameDatabaseError) as info:
        copy_registry(store, source.parent / "." / source.name)
    assert str(info.value) == (
        f"source and target of the copy are the same database {str(source.parent / source.name)!r}"
        "; name another target (a new file, or an empty database on the server)"
    )


@POSTGRES
@pytest.mark.parametrize("backend", ["postgres"], indirect=True)
def test_a_database_the_server_does_not_have_is_named_as_the_target(source, databases):
    target = databases.missing("nowhere")
    with Store(source) as store, pytest.raises(ServerDatabaseMissingError) as info:
        copy_registry(store, target)
    assert str(info.value) == databases.missing_message(target)
    assert not databases.exists(target)  # the registry never creates a server's database


@pytest.mark.parametrize("empty_registry", [False, True], ids=["new", "empty-registry"])
def test_a_copy_that_does_not_verify_is_rolled_back(source, databases, empty_registry):
    """A source whose stored hash does not match its text (a damaged registry): the copy
    finds it before the commit, and the target is left as it was."""
    execute(source, "UPDATE cases SET content_hash = 'damaged' WHERE id = 1")
    target = databases.new("refused")
    if empty_registry:
        Store(target).close()
    with Store(source) as store, pytest.raises(CopyVerificationError) as info:
        copy_registry(store, target)
    (line,) = str(info.value).splitlines()
    assert line == (
        f"the copy into {target!r} was not committed (nothing was written): case "
        "yehia-2003-kovalevskaya-b version 1: the stored hash does not match the stored text"
    )
    expected = {t: 0 for t in Base.metadata.tables if t != "meta"} if empty_registry else None
    assert held_rows(target) == expected
    folder = source.parent
    assert not list(folder.glob(".*.copy-*"))  # the temporary file is gone too


# --------------------------------------------------------------------------- CLI


def test_the_command_copies_to_and_from(source, databases):
    first, second = databases.new("first"), databases.new("second")
    to = CliRunner().invoke(main, ["--db", str(source), "copy", "--to", first])
    assert to.exit_code == 0, to.output
    head, checked = to.stdout.splitlines()
    described = ", ".join(
        rows_named(table, len(rows))
        for table, rows in registry_rows(source).items()
        if table != "meta"
    )
    assert head.startswith(f"copied {str(source)!r} into {first!r} in ")
    assert head.endswith(f" s: {described}")
    versions = len(registry_rows(source)["cases"])
    assert checked == (
        f"verified before the commit: schema revision {migrate.head()}, integrity, foreign "
        "keys, hashes "
        f"and every stored expression; the rows of every table and the hashes of the {versions} "
        "case versions equal the source's"
    )
    back = CliRunner().invoke(main, ["--db", second, "copy", "--from", first])
    assert back.exit_code == 0, back.output
    assert registry_rows(second) == registry_rows(source)

    again = CliRunner().invoke(main, ["--db", str(source), "copy", "--to", first])
    assert again.exit_code == 1
    assert again.stderr.startswith(f"Error: the target {first!r} is not empty (it holds ")
    assert len(again.stderr.splitlines()) == 1


@pytest.mark.parametrize("options", [[], ["--to", "a.sqlite", "--from", "b.sqlite"]])
def test_the_command_takes_exactly_one_direction(options):
    result = CliRunner().invoke(main, ["copy", *options])
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        "Error: give exactly one of --to DB and --from DB (see: registry copy --help)"
    ]


# ------------------------------------------------------------------ interrupted

#: Kills of each kind of target: at a random moment of the command's life, and at a
#: random moment after its transaction is seen open.
RANDOM_KILLS, TRIGGERED_KILLS = 3, 3


def grown(source: Path) -> Path:
    """The source with many more check results (copies of its own, 22k rows), so that
    the copy's transaction lasts long enough (seconds) to be killed in its middle."""
    columns = (
        'run_id, case_pk, claim_id, "check", verdict, method, reason, residual, witness, '
        "seconds, reused"
    )
    execute(
        source,
        *[f"INSERT INTO check_results ({columns}) SELECT {columns} FROM check_results"] * 8,
    )
    return source


def target_state(target: str, expected: dict[str, list[dict]]) -> str:
    """'empty' (no file, no registry tables, or tables without rows) or 'complete'
    (verified and equal to the source); anything else fails the test."""
    held = held_rows(target)
    if held is None or not any(held.values()):
        return "empty"
    with Store(target, create=False) as store:
        found = verify(store)
    assert found.ok, found.problems
    assert registry_rows(target) == expected
    return "complete"


def transaction_open(databases, target: str) -> bool:
    """Whether the copy's transaction into ``target`` has begun: on SQLite, its
    temporary file exists (a new target) or some connection holds the target's write
    lock (an existing one); on PostgreSQL, a connection of the registry is in a
    transaction there."""
    if not is_url(target):
        if list(Path(target).parent.glob(f".{Path(target).name}.copy-*.tmp")):
            return True
        return Path(target).exists() and write_locked(Path(target))
    with databases.server.connect() as conn:
        found = conn.execute(
            "SELECT 1 FROM pg_stat_activity WHERE datname = %s AND "
            "application_name = 'registry' AND xact_start IS NOT NULL",
            (database_name(target),),
        )
        return found.fetchone() is not None


def write_locked(file: Path) -> bool:
    """Whether a connection holds ``file``'s one write lock (a write transaction is
    open there): BEGIN IMMEDIATE without waiting fails exactly then. A probe that gets
    the lock gives it back at once; the copy's busy timeout covers that instant."""
    probe = sqlite3.connect(file, timeout=0, isolation_level=None)
    try:
        probe.execute("BEGIN IMMEDIATE")
    except sqlite3.OperationalError as err:
        if "locked" in str(err) or "busy" in str(err):
            return True
        raise
    else:
        probe.execute("ROLLBACK")
        return False
    finally:
        probe.close()


def wait_for_server_sessions(databases, target: str) -> None:
    """Wait until the server has ended every session of the killed copy (it rolls back
    their transaction): only then is the target's state final."""
    if not is_url(target):
        return
    deadline = time.monotonic() + HANG
    while time.monotonic() < deadline:
        with databases.server.connect() as conn:
            found = conn.execute(
                "SELECT count(*) FROM pg_stat_activity WHERE datname = %s "
                "AND pid <> pg_backend_pid()",
                (database_name(target),),
            ).fetchone()
        if not found[0]:
            return
        time.sleep(0.05)
    pytest.fail(f"the killed copy's session on {target} did not end within {HANG:g} s")


@pytest.mark.slow
@pytest.mark.parametrize("empty_registry", [False, True], ids=["new", "empty-registry"])
def test_a_copy_killed_at_any_point_leaves_its_target_empty_or_complete(
    source, databases, empty_registry
):
    """SIGKILL at a random moment of the command's life (from its start to past its
    end), and at a random moment within a second of its transaction being seen open:
    each target is then empty or complete and verified; and a new copy into a target a
    killed copy left empty succeeds (on SQLite it removes the dead copy's temporary file)."""
    grown(source)
    expected = registry_rows(source)
    chance = random.Random()  # a new draw each run: the kill test explores
    outcomes: list[tuple[str, float, str]] = []
    targets = (databases.new(f"killed{i}") for i in range(1000))

    def run(delay: float, triggered: bool) -> None:
        target = next(targets)
        if empty_registry:
            Store(target).close()
        process = subprocess.Popen(
            registry_command(source, "copy", "--to", target),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        started = time.monotonic()
        try:
            while triggered and process.poll() is None and not transaction_open(databases, target):
                assert time.monotonic() - started < HANG, "the copy never began"
                time.sleep(0.01)
            time.sleep(delay)
            finished = process.poll() is not None
            process.send_signal(signal.SIGKILL)
            process.wait(HANG)
        finally:
            if process.poll() is None:
                process.kill()
        wait_for_server_sessions(databases, target)
        state = target_state(target, expected)
        kind = f"{'finished' if finished else 'killed'}, {state}"
        outcomes.append((kind, round(time.monotonic() - started, 2), target))

    started = time.monotonic()
    whole = subprocess.run(
        registry_command(source, "copy", "--to", next(targets)), capture_output=True, text=True
    )
    assert whole.returncode == 0, whole.stderr
    lifetime = time.monotonic() - started
    run(0.0, triggered=True)  # as soon as its transaction is seen open: before the commit
    for _ in range(RANDOM_KILLS):
        run(chance.uniform(0, 1.1 * lifetime), triggered=False)
    for _ in range(TRIGGERED_KILLS):
        run(chance.uniform(0, 1.0), triggered=True)

    tally = {kind: sum(1 for k, _, _ in outcomes if k == kind) for kind, _, _ in outcomes}
    print(f"\nkills, {'an empty registry' if empty_registry else 'a new'} target: {tally}")
    for kind, seconds, target in outcomes:
        print(f"  {kind:18} after {seconds:5.2f} s  {target}")
    assert "killed, empty" in tally, outcomes  # some kills landed before the commit

    # a killed copy's target takes a new copy; its dead temporary files are removed
    target = next(t for k, _, t in reversed(outcomes) if k == "killed, empty")
    with Store(source) as store:
        copy_registry(store, target)
    assert registry_rows(target) == expected
    assert not list(source.parent.glob(f".{Path(target).name}.copy-*"))
