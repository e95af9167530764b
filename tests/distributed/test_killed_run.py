"""A test run killed with SIGKILL (or SIGTERM, which ends pytest as abruptly: no
fixture teardown, no exit handler) leaves no process behind: neither the PostgreSQL server
of its session, nor the ``dask scheduler`` and ``dask worker`` processes of a fixture,
nor the processes of a LocalCluster, nor the server's folder.

The killed run is a real ``python -m pytest`` of a few PostgreSQL and Dask tests and of
``test_services_held_until_the_run_is_killed``, which holds every kind of service up
until the run is killed (it runs only there). Its processes carry the mark
``REGISTRY_TEST_RUN=<its pid>`` (``tests/helpers/watchdog.py``), by which they are found.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from tests.helpers.clocks import HANG
from tests.helpers.watchdog import clean_up, marked

#: The environment variable naming the file that the held services are described in.
HOLD = "REGISTRY_TEST_HOLD"

ROOT = Path(__file__).resolve().parents[2]

#: Real tests of the PostgreSQL server and of the Dask clusters, run before the hold.
SELECTION = [
    "tests/store/test_database.py::test_reopening_a_database_keeps_its_content[postgres]",
    "tests/distributed/test_cluster_calls.py::test_every_index_comes_once_with_its_result",
]

#: Seconds within which nothing of the killed run may be left.
BOUND = HANG


def command_line(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return "(gone)"


@pytest.mark.skipif(
    HOLD not in os.environ, reason="holds the services of the run that the killed-run test kills"
)
def test_services_held_until_the_run_is_killed(
    postgres_server, separate_processes, process_cluster
):
    url = postgres_server.create_database("held")
    from sqlalchemy import create_engine, text

    engine = create_engine(url)
    with engine.connect() as conn:  # a backend of the server, busy with this session
        assert conn.execute(text("SELECT 1")).scalar() == 1
        held = {
            "postmaster": int((postgres_server.data / "postmaster.pid").read_text().split()[0]),
            "postgres_root": str(postgres_server.root),
            "dask": [p.pid for p in (separate_processes.scheduler, *separate_processes.workers)],
            "local_cluster": sorted(process_cluster.run(os.getpid).values()),
        }
        ready = Path(os.environ[HOLD])
        aside = ready.with_suffix(".part")
        aside.write_text(json.dumps(held), encoding="utf-8")
        os.replace(aside, ready)  # the killing test reads it whole
        time.sleep(10 * HANG)
    pytest.fail("the run was not killed")


@pytest.mark.slow
@pytest.mark.serial  # kills a whole test run: not beside the workers of another
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.skipif(HOLD in os.environ, reason="the killed run itself")
@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_a_killed_run_leaves_nothing_behind(tmp_path, how):
    ready = tmp_path / "held.json"
    log = tmp_path / "run.log"
    held_test = f"{Path(__file__).relative_to(ROOT)}::test_services_held_until_the_run_is_killed"
    with open(log, "wb") as out:
        run = subprocess.Popen(
            # -n 0: the held services are this pytest's own, marked with its pid
            [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-x", "-n", "0"]
            + [*SELECTION, held_test],
            cwd=ROOT,
            env={**os.environ, HOLD: str(ready)},
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
    try:
        deadline = time.monotonic() + 10 * HANG  # a few tests and three clusters, busy machine
        while not ready.exists():
            assert run.poll() is None, log.read_text(errors="replace")
            assert time.monotonic() < deadline, "the services did not come up"
            time.sleep(0.1)
        held = json.loads(ready.read_text(encoding="utf-8"))
        up = set(marked(str(run.pid)))
        services = {held["postmaster"], *held["dask"], *held["local_cluster"]}
        assert services <= up, f"not marked: {services - up}"
        assert Path(held["postgres_root"]).is_dir()

        os.kill(run.pid, how)  # the test process only, as a CI time limit does
        run.wait(timeout=HANG)
        assert run.returncode == -how  # killed, not a pytest that cleaned up and ended
        deadline = time.monotonic() + BOUND
        while (left := marked(str(run.pid))) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert left == [], "left running: " + "; ".join(f"{p}: {command_line(p)}" for p in left)
        assert not Path(held["postgres_root"]).exists(), "the server's folder was left"
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGKILL)
            run.wait()
        # what a failing run left: stopped as its watchdog would have
        for folder in Path(tempfile.gettempdir()).glob(f"registry-test-run-{run.pid}-*"):
            clean_up(run.pid, folder)
