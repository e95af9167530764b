"""The suite runs in parallel (pytest-xdist: the README's test command has ``-n auto``),
and its workers share nothing: each is a test session of its own, with its own
PostgreSQL server, Dask scratch folder, temporary folders and watchdog, and the
environment that ``tests/conftest.py`` sets (the audits' budgets, the wait for a lock)
reaches every worker and the processes it starts. A real ``pytest -n 2`` of the probe
below shows it: the probe runs once in each worker (``--dist each``) and reports what it
sees; the run starts from an environment without those variables. A test that hangs is
ended with its stacks reported, and the run goes on (another probe).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import watchdog
from tests.helpers.clocks import HANG, PATIENT

#: The environment variable naming the folder the probes report to.
PROBE = "REGISTRY_TEST_PROBE"

ROOT = Path(__file__).resolve().parents[1]

#: What tests/conftest.py sets for every process of a run, and the values it sets.
ENVIRONMENT = {
    "REGISTRY_BUDGET": f"{PATIENT.check:g}",
    "REGISTRY_CORRECTIONS_BUDGET": f"{PATIENT.corrections:g}",
    "REGISTRY_LOCK_TIMEOUT": f"{HANG / 2:g}",
}

#: Shows the environment a process started by a test sees.
CHILD = "import json, os, sys; print(json.dumps({k: os.environ.get(k) for k in sys.argv[1:]}))"


@pytest.mark.skipif(PROBE not in os.environ, reason="the probe of the run the test below starts")
def test_probe_of_a_worker(postgres_server, tmp_path):
    import dask.config

    names = [*ENVIRONMENT, "DASK_TEMPORARY_DIRECTORY"]
    child = subprocess.run(
        [sys.executable, "-c", CHILD, *names], capture_output=True, text=True, check=True
    )
    report = {
        "worker": os.environ.get("PYTEST_XDIST_WORKER"),
        "pid": os.getpid(),
        "environment": {k: os.environ.get(k) for k in names},
        "child": json.loads(child.stdout),
        "dask": dask.config.get("temporary-directory"),
        "server": str(postgres_server.root),
        "database": postgres_server.create_database("probe"),
        "tmp": str(tmp_path),
        "watch": os.environ.get(watchdog.FOLDER),
    }
    folder = Path(os.environ[PROBE])
    aside = folder / f".{os.getpid()}.part"
    aside.write_text(json.dumps(report), encoding="utf-8")
    aside.rename(folder / f"{os.getpid()}.json")  # the test reads it whole


def test_each_worker_has_its_own_server_folders_and_the_suites_environment(tmp_path):
    reports = tmp_path / "reports"
    reports.mkdir()
    unset = {*ENVIRONMENT, "DASK_TEMPORARY_DIRECTORY", watchdog.MARK, watchdog.FOLDER}
    env = {
        k: v for k, v in os.environ.items() if k not in unset and not k.startswith("PYTEST_XDIST")
    }
    probe = f"{Path(__file__).relative_to(ROOT)}::test_probe_of_a_worker"
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-n", "2", "--dist", "each", "-p", "no:cacheprovider"]
        + ["-q", "-rs", "--basetemp", str(tmp_path / "base"), probe],
        cwd=ROOT,
        env={**env, PROBE: str(reports)},
        capture_output=True,
        text=True,
        timeout=10 * HANG,
    )
    seen = [json.loads(p.read_text(encoding="utf-8")) for p in sorted(reports.glob("*.json"))]
    if not seen and done.returncode == 0 and "skipped" in done.stdout:
        pytest.skip(f"the probes were skipped: {done.stdout.strip().splitlines()[-2:]}")
    assert done.returncode == 0, done.stdout + done.stderr
    assert sorted(r["worker"] for r in seen) == ["gw0", "gw1"]
    assert len({r["pid"] for r in seen}) == 2

    for report in seen:
        # the conftest's environment, in the worker and in what it starts
        wanted = {**ENVIRONMENT, "DASK_TEMPORARY_DIRECTORY": report["dask"]}
        assert report["environment"] == wanted
        assert report["child"] == wanted
    for key in ("server", "dask", "tmp", "watch", "database"):
        values = [r[key] for r in seen]
        assert None not in values and len(set(values)) == 2, f"{key} shared: {values}"
    for report in seen:
        assert Path(report["server"]).name.startswith(f"registry-pg-{report['worker']}-")
        assert Path(report["dask"]).name.startswith(f"registry-dask-{report['worker']}-")
        assert Path(report["tmp"]).is_relative_to(tmp_path / "base" / f"popen-{report['worker']}")
        # stopped and removed when the worker's session ended
        assert not Path(report["server"]).exists()
        assert not Path(report["dask"]).exists()


#: The environment variable that makes the probe below hang.
HANG_PROBE = "REGISTRY_TEST_HANG_PROBE"


@pytest.mark.skipif(
    HANG_PROBE not in os.environ, reason="the probe of the run the test below starts"
)
def test_probe_that_hangs():
    import time

    time.sleep(10 * HANG)


def test_a_test_that_hangs_is_reported_with_its_stacks_and_the_run_goes_on(tmp_path):
    probe = f"{Path(__file__).relative_to(ROOT)}::test_probe_that_hangs"
    neighbour = f"{Path(__file__).relative_to(ROOT)}::test_probe_of_a_worker"  # skipped
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_XDIST")}
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-n", "2", "-p", "no:cacheprovider", "-q"]
        + ["--basetemp", str(tmp_path / "base"), probe, neighbour],
        cwd=ROOT,
        env={**env, HANG_PROBE: "1", "REGISTRY_TEST_HANG": "3"},
        capture_output=True,
        text=True,
        timeout=10 * HANG,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    report = done.stdout
    assert f"crashed while running '{probe}': it hung for over 3 s" in report
    # the hung test's stacks: the line it hung on, in the test's own file
    assert re.search(r'File ".*test_xdist_workers\.py", line \d+ in test_probe_that_hangs', report)
    assert "1 skipped" in report  # the other test still ran
