"""Dask clusters for the tests of ``tests/distributed``: in this process (workers as
threads, so that a monkeypatched check reaches the child processes they fork), in
processes of a LocalCluster, or as separate ``dask scheduler`` and ``dask worker``
processes. ``tests/distributed/conftest.py`` makes the fixtures available there."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import dask
import distributed  # noqa: F401 - its config defaults, before any dask.config.set
import pytest

from tests.helpers.clocks import HANG
from tests.helpers.processes import dying_with_this_process


@pytest.fixture
def thread_cluster() -> Iterator[object]:
    """A client of a LocalCluster whose one worker (one thread) runs in this process,
    connected in-process (no network); its HTTP endpoints on free ports of 127.0.0.1."""
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=False,
            dashboard_address=None,
            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
            worker_dashboard_address="127.0.0.1:0",  # the worker's HTTP endpoint
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client


@pytest.fixture(scope="module")
def process_cluster():
    """A client of a LocalCluster of two worker processes (one thread each), restarted
    by their nannies when they die; the scheduler gives a task up when the second worker
    running it dies (``allowed-failures`` 1, to keep the tests short)."""
    from registry.execution.cluster import cluster_client

    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        with cluster_client("local:2") as client:
            yield client


# ------------------------------------------ a cluster of separate dask processes

#: Seconds a ``dask worker`` keeps trying to reach its scheduler before it ends.
DEATH_TIMEOUT = 60

#: Seconds the scheduler and the workers may take to start on a busy machine.
STARTUP = 2 * HANG

#: The directory that holds the package under test: the workers must import the same code.
SOURCE = str(Path(__file__).resolve().parents[2])


def dask_command(*args: str) -> list[str]:
    """The ``dask`` command line of this environment (``dask scheduler``, ``dask worker``)."""
    script = Path(sys.executable).parent / "dask"
    return [str(script), *args] if script.exists() else [sys.executable, "-m", "dask", *args]


def source_environment() -> dict[str, str]:
    """This environment, with the package under test first on the workers' path."""
    path = os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (SOURCE, path) if p)}


#: What a verdict is, apart from when and how fast it was found.
VERDICT_COLUMNS = ["case", "claim", "check", "verdict", "method", "reason", "witness", "residual"]


def registry_run(db: Path, *args: str, env: dict[str, str] | None = None, **kw):
    """``registry --db DB ARGS`` in a process of its own; its completed process. Its
    environment is this one (the package under test first on the path) without the
    machine's scheduler and Dask TLS settings, with ``env`` added."""
    environment = {
        k: v
        for k, v in source_environment().items()
        if not k.startswith("DASK_DISTRIBUTED__COMM") and k != "REGISTRY_SCHEDULER"
    }
    environment.update(env or {})
    return subprocess.run(
        [sys.executable, "-m", "registry", "--db", str(db), *args],
        capture_output=True,
        text=True,
        env=environment,
        timeout=900,
        **kw,
    )


def verdicts(db: Path):
    """The verdicts stored in ``db``, in a fixed order, without timings."""
    import registry

    frame = registry.open(db).verdicts()
    columns = frame[VERDICT_COLUMNS]
    return columns.sort_values(["case", "check", "claim"]).reset_index(drop=True)


@dataclass
class DaskProcesses:
    """A ``dask scheduler`` and ``dask worker`` processes started for a test."""

    address: str
    file: Path  # the scheduler file, holding the address
    scheduler: subprocess.Popen
    workers: list[subprocess.Popen]
    logs: Path

    def log(self) -> str:
        """What the processes wrote (for a failing test's message)."""
        return "\n".join(p.read_text(errors="replace") for p in sorted(self.logs.glob("*.log")))


def _stop(procs: list[subprocess.Popen]) -> None:
    for proc in procs:
        if proc.poll() is None:
            proc.terminate()
    for proc in procs:
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _address(file: Path, scheduler: subprocess.Popen, deadline: float) -> str:
    """The scheduler's address, once it has written its scheduler file."""
    while True:
        try:
            return json.loads(file.read_text())["address"]
        except (OSError, ValueError, KeyError):
            assert scheduler.poll() is None, (file.parent / "scheduler.log").read_text()
            assert time.monotonic() < deadline, "the scheduler did not start"
            time.sleep(0.1)


@dataclass(frozen=True)
class Certificate:
    """A self-signed certificate and its key, as PEM files: a cluster's CA and the
    certificate every member presents (``Security.temporary``'s pair, written out)."""

    cert: Path
    key: Path

    @classmethod
    def make(cls, where: Path, name: str) -> Certificate:
        from distributed.security import Security

        made = Security.temporary()
        where.mkdir(parents=True, exist_ok=True)
        cert, key = where / f"{name}-cert.pem", where / f"{name}-key.pem"
        cert.write_text(made.tls_client_cert, encoding="utf-8")
        key.write_text(made.tls_client_key, encoding="utf-8")
        return cls(cert, key)

    def arguments(self) -> list[str]:
        """The options of ``dask scheduler`` and ``dask worker`` that require TLS."""
        return ["--tls-ca-file", str(self.cert), "--tls-cert", str(self.cert),
                "--tls-key", str(self.key)]  # fmt: skip

    def client_environment(self, ca: Certificate | None = None) -> dict[str, str]:
        """Dask's environment variables that make a client present this certificate and
        trust ``ca`` (default: this one), as the recipe of docs/operations.md sets them."""
        return {
            "DASK_DISTRIBUTED__COMM__TLS__CA_FILE": str((ca or self).cert),
            "DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT": str(self.cert),
            "DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY": str(self.key),
            "DASK_DISTRIBUTED__COMM__REQUIRE_ENCRYPTION": "True",
        }


@contextmanager
def dask_processes(
    where: Path, n_workers: int = 2, tls: Certificate | None = None
) -> Iterator[DaskProcesses]:
    """A scheduler and ``n_workers`` workers (one thread each, no nanny: a worker killed
    stays dead), each a ``dask`` process of its own on 127.0.0.1, for the block only;
    with ``tls``, every connection to them requires TLS with that certificate."""
    from distributed import Client
    from distributed.security import Security

    where.mkdir(parents=True, exist_ok=True)
    file = where / "scheduler.json"
    env = source_environment()
    secure = tls.arguments() if tls else []
    started: list[subprocess.Popen] = []

    def start(name: str, *args: str) -> subprocess.Popen:
        with open(where / f"{name}.log", "wb") as log:
            proc = subprocess.Popen(
                dying_with_this_process(dask_command(*args)),  # nothing outlives the run
                stdout=log,
                stderr=subprocess.STDOUT,
                env=env,
            )
        started.append(proc)
        return proc

    try:
        here = "--host 127.0.0.1".split()
        scheduler = start(
            "scheduler",
            "scheduler",
            *here,
            *"--port 0 --dashboard-address 127.0.0.1:0 --scheduler-file".split(),
            str(file),
            *(["--protocol", "tls", *secure] if tls else []),
        )
        address = _address(file, scheduler, time.monotonic() + STARTUP)
        one = "--nthreads 1 --nworkers 1 --no-nanny --no-dashboard".split()
        one += ["--death-timeout", str(DEATH_TIMEOUT)]  # no scheduler: the worker ends
        workers = [
            start(
                f"worker-{i}",
                "worker",
                "--scheduler-file",
                str(file),
                *here,
                *one,
                "--name",
                f"worker-{i}",
                *secure,
            )
            for i in range(n_workers)
        ]
        security = None
        if tls:
            security = Security(
                tls_ca_file=str(tls.cert),
                tls_client_cert=str(tls.cert),
                tls_client_key=str(tls.key),
                require_encryption=True,
            )
        with Client(address, timeout=30, security=security) as client:
            client.wait_for_workers(n_workers, timeout=STARTUP)
        yield DaskProcesses(address, file, scheduler, workers, where)
    finally:
        _stop(started[1:])
        _stop(started[:1])


@pytest.fixture
def separate_processes(tmp_path) -> Iterator[DaskProcesses]:
    """A ``dask scheduler`` and two ``dask worker`` processes (see ``dask_processes``)."""
    with dask_processes(tmp_path / "dask") as cluster:
        yield cluster
