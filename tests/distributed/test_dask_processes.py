"""The command line against a real cluster: a ``dask scheduler`` and two ``dask worker``
processes started here, the audit and the search run by ``registry`` processes.

The results are the local pool's, verdict by verdict; a worker killed (SIGKILL) in the
middle of an audit takes no results with it: the run finishes complete, every case
has its results, and the run records the loss and the retry on the other worker.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import registry
from registry.language.casefile import load_case
from tests.helpers.clocks import PATIENT_OPTIONS
from tests.helpers.dask_clusters import registry_run, source_environment, verdicts

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "data" / "cases"
FAMILY = ROOT / "tests" / "data" / "families" / "heavy-top-lam-z0.toml"

pytestmark = [
    pytest.mark.skipif(not sys.platform.startswith("linux"), reason="POSIX processes"),
    # whole audits and searches through a scheduler and workers of their own, each run
    # locally too for comparison: 1.5 to 8 min each on a loaded 2-core machine
    pytest.mark.slow,
]


def catalog(db: Path, *paths: Path) -> Path:
    added = registry_run(db, "add", *map(str, paths))
    assert added.returncode == 0, added.stderr
    return db


def last_run(db: Path) -> dict:
    return registry.open(db).runs().to_dict("records")[-1]


def test_an_audit_on_separate_dask_processes_gives_the_local_pools_verdicts(
    tmp_path, separate_processes
):
    local = catalog(tmp_path / "local.sqlite", SEED)
    by_option = catalog(tmp_path / "option.sqlite", SEED)
    by_variable = catalog(tmp_path / "variable.sqlite", SEED)
    address = separate_processes.address

    expected = registry_run(local, "audit", "--jobs", "2", *PATIENT_OPTIONS)
    assert expected.returncode == 0, expected.stderr
    got = registry_run(by_option, "audit", "--scheduler", address, *PATIENT_OPTIONS)
    assert got.returncode == 0, got.stderr + separate_processes.log()
    by_env = registry_run(
        by_variable, "audit", *PATIENT_OPTIONS, env={"REGISTRY_SCHEDULER": address}
    )
    assert by_env.returncode == 0, by_env.stderr

    table = verdicts(local)
    assert len(table) > 300 and set(table.verdict) >= {"verified", "refuted"}
    assert verdicts(by_option).equals(table)
    assert verdicts(by_variable).equals(table)
    assert got.stdout.splitlines()[2:] == expected.stdout.splitlines()[2:]  # the table
    for db in (by_option, by_variable):
        run = last_run(db)
        assert run["status"] == "complete"
        assert run["options"]["scheduler"] == address
        assert run["options"]["cluster"]["workers"] == 2
        assert run["options"]["events"] == []


def test_a_search_on_separate_dask_processes_is_the_local_search(tmp_path, separate_processes):
    """The cluster named by its scheduler file, as the jobs of a batch system find it."""
    args = ["discover", str(FAMILY), "--degree", "4", "--free", "lam,z0", "--json"]
    db = tmp_path / "none.sqlite"
    local = registry_run(db, *args, "--jobs", "2")
    assert local.returncode == 0, local.stderr
    remote = registry_run(db, *args, "--scheduler", str(separate_processes.file))
    assert remote.returncode == 0, remote.stderr + separate_processes.log()
    expected, got = json.loads(local.stdout), json.loads(remote.stdout)
    for document in (expected, got):
        document.pop("seconds")
    assert got == expected
    assert got["complete"] is True and len(got["special"]) == 2
    assert not db.exists()  # a search of a file without --record writes nothing


def worker_busy_with_the_audit(address: str, timeout: float = 120.0) -> str:
    """The address of a worker executing a task of the audit (asked of the scheduler)."""
    from distributed import Client

    with Client(address, timeout=30) as observer:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for worker, keys in observer.processing().items():
                if any(str(k).startswith("registry-audit") for k in keys):
                    return worker
            time.sleep(0.05)
    raise AssertionError("no worker started the audit")


def test_a_worker_killed_mid_audit_takes_no_results_with_it(tmp_path, separate_processes):
    local = catalog(tmp_path / "local.sqlite", SEED)
    remote = catalog(tmp_path / "remote.sqlite", SEED)
    expected = registry_run(local, "audit", "--jobs", "2", *PATIENT_OPTIONS)
    assert expected.returncode == 0, expected.stderr

    audit = subprocess.Popen(
        [sys.executable, "-m", "registry", "--db", str(remote), "audit"]
        + ["--scheduler", separate_processes.address, *PATIENT_OPTIONS],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=source_environment(),
    )
    try:
        victim = worker_busy_with_the_audit(separate_processes.address)
        pids = {p.pid: p for p in separate_processes.workers}
        from distributed import Client

        with Client(separate_processes.address, timeout=30) as observer:
            pid = observer.run(os.getpid, workers=[victim])[victim]
        assert pid in pids, "the worker is one of the processes started here"
        time.sleep(0.5)  # well inside its task
        os.kill(pid, signal.SIGKILL)
        pids[pid].wait(timeout=10)
        out, err = audit.communicate(timeout=600)
    finally:
        if audit.poll() is None:
            audit.kill()
            audit.communicate()
    assert audit.returncode == 0, err + separate_processes.log()

    run = last_run(remote)
    assert run["status"] == "complete"
    seed = [load_case(p) for p in SEED.rglob("*.toml")]
    decided = [c for c in seed if c.claims or c.system.form != "equations"]
    assert run["n_cases"] == last_run(local)["n_cases"] == len(decided)
    assert run["n_error"] == 0
    assert verdicts(remote).equals(verdicts(local))  # complete, and the local pool's
    events = run["options"]["events"]
    lost = [e for e in events if f"worker {victim} lost while holding" in e]
    retried = [e for e in events if f"after losing {victim}" in e]
    assert lost and retried, events
    assert all(e.endswith("; rescheduled") for e in lost)
    survivor = next(w for w in observer_addresses(separate_processes) if w != victim)
    assert all(f"done on worker {survivor} after losing {victim}" in e for e in retried)
    assert all(f"note: {e}" in err for e in events)  # said on the command line too


def observer_addresses(cluster) -> list[str]:
    """The addresses of the workers still connected to the scheduler."""
    from distributed import Client

    with Client(cluster.address, timeout=30) as observer:
        return list(observer.scheduler_info()["workers"])
