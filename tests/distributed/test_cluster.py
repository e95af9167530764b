"""--scheduler: addresses checked before any connection, the environment variable as the
default, one-line errors for a bad address, a scheduler that does not answer and Dask
not installed; local:N starts a LocalCluster of N worker processes for the block only."""

from __future__ import annotations

import json
import os
import signal
import socket
import sys
import time

import pytest

from registry.errors import (
    DaskMissingError,
    RegistryError,
    SchedulerAddressError,
    SchedulerError,
    SchedulerUnreachableError,
)
from registry.execution.cluster import (
    SCHEDULER_ENV,
    SchedulerAddress,
    check_same_code,
    cluster_client,
    describe,
    parse_scheduler,
    scheduler_option,
    threads,
)
from tests.helpers.clocks import HANG


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("tcp://127.0.0.1:8786", SchedulerAddress("tcp://127.0.0.1:8786")),
        ("127.0.0.1:8786", SchedulerAddress("tcp://127.0.0.1:8786")),
        (
            "tls://scheduler.cluster.example:8786",
            SchedulerAddress("tls://scheduler.cluster.example:8786"),
        ),
        ("tcp://[::1]:8786", SchedulerAddress("tcp://[::1]:8786")),
        (" local:3 ", SchedulerAddress("local:3", 3)),
        ("local:02", SchedulerAddress("local:2", 2)),
    ],
)
def test_addresses_are_parsed_without_contacting_anything(text, expected):
    assert parse_scheduler(text) == expected
    assert parse_scheduler(text).local == (expected.workers is not None)


def test_a_scheduler_file_gives_the_address_written_in_it(tmp_path):
    file = tmp_path / "scheduler.json"
    file.write_text(json.dumps({"type": "Scheduler", "address": "tcp://10.1.2.3:8786"}))
    assert parse_scheduler(str(file)) == SchedulerAddress("tcp://10.1.2.3:8786")
    assert parse_scheduler(f" {file} ").text == "tcp://10.1.2.3:8786"


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (None, "no such scheduler file"),
        ("{", "not a scheduler file (Expecting property name enclosed in double quotes: "
         "line 1 column 2 (char 1))"),
        ('{"type": "Scheduler"}', "not a scheduler file (no address in it)"),
        ('{"address": "local:2"}', "not a scheduler file (no address in it)"),
        ('{"address": "tcp://10.1.2.3"}',
         "its address 'tcp://10.1.2.3': it needs a host and a port"),
    ],
)  # fmt: skip
def test_a_bad_scheduler_file_is_one_line(tmp_path, monkeypatch, content, reason):
    # a name short enough to be quoted whole (a longer one is cut: an xdist worker's
    # temporary folder is longer than a plain run's)
    monkeypatch.chdir(tmp_path)
    file = "scheduler.json"
    if content is not None:
        (tmp_path / file).write_text(content)
    with pytest.raises(SchedulerAddressError) as caught:
        parse_scheduler(file)
    assert caught.value.reason == reason
    assert str(caught.value).startswith(f"bad Dask scheduler address {file!r}: {reason} ")


def test_local_alone_means_one_worker_per_core():
    found = parse_scheduler("local")
    assert found.local and found.workers >= 1


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("local:0", "local:N needs a whole number N >= 1"),
        ("local:two", "local:N needs a whole number N >= 1"),
        ("local:-1", "local:N needs a whole number N >= 1"),
        ("http://127.0.0.1:8786", "unknown protocol 'http'"),
        ("tcp://127.0.0.1", "it needs a host and a port"),
        ("tcp://:8786", "it needs a host and a port"),
        ("tcp://127.0.0.1:99999", "it needs a host and a port"),
        ("tcp://127.0.0.1:8786/path", "it needs a host and a port"),
        ("", "it needs a host and a port"),
    ],
)
def test_a_bad_address_is_one_line_naming_it_and_what_is_expected(text, reason):
    with pytest.raises(SchedulerAddressError) as caught:
        parse_scheduler(text)
    err = caught.value
    assert str(err) == (
        f"bad Dask scheduler address {text!r}: {reason} "
        "(expected tcp://HOST:PORT, a scheduler file FILE.json, or local:N for N local "
        "worker processes)"
    )
    assert (err.address, err.reason) == (text, reason)
    assert isinstance(err, ValueError) and isinstance(err, SchedulerError)
    assert isinstance(err, RegistryError)


def test_the_option_beats_the_environment_variable_and_empty_means_unset():
    env = {SCHEDULER_ENV: "tcp://10.0.0.1:8786"}
    assert scheduler_option("local:2", env) == "local:2"
    assert scheduler_option(None, env) == "tcp://10.0.0.1:8786"
    assert scheduler_option("", env) == "tcp://10.0.0.1:8786"
    assert scheduler_option(None, {SCHEDULER_ENV: ""}) is None
    assert scheduler_option(None, {}) is None


def test_the_environment_variable_is_read_from_the_process_environment(monkeypatch):
    monkeypatch.setenv(SCHEDULER_ENV, "local:1")
    assert scheduler_option(None) == "local:1"
    monkeypatch.delenv(SCHEDULER_ENV)
    assert scheduler_option(None) is None


def closed_port() -> int:
    """A port on 127.0.0.1 that nothing listens on (bound, then released)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_scheduler_that_does_not_answer_is_one_line_with_the_wait():
    address = f"tcp://127.0.0.1:{closed_port()}"
    with pytest.raises(SchedulerUnreachableError) as caught:
        with cluster_client(address, timeout=1):
            pass
    assert str(caught.value) == (
        f"no Dask scheduler answered at {address!r} within 1 s; "
        "start one (dask scheduler) or check the address"
    )
    assert caught.value.address == address
    assert isinstance(caught.value, ConnectionError)


def test_without_dask_installed_the_error_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    with pytest.raises(DaskMissingError) as caught:
        with cluster_client("local:1"):
            pass
    assert str(caught.value) == (
        "--scheduler 'local:1' needs Dask distributed, which is not installed "
        "(no module 'distributed'); install with pip install -e '.[dask]'"
    )
    assert isinstance(caught.value, ImportError)


def test_a_bad_address_is_refused_before_dask_is_even_imported(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(SchedulerAddressError):
        with cluster_client("local:x"):
            pass


def test_local_n_starts_n_worker_processes_on_127_0_0_1_for_the_block_only():
    with cluster_client("local:2") as client:
        cluster = client.cluster
        workers = client.nthreads()
        assert sorted(workers.values()) == [1, 1]
        assert all(w.startswith("tcp://127.0.0.1:") for w in workers)
        pids = client.run(os.getpid)
        assert os.getpid() not in pids.values() and len(set(pids.values())) == 2
        assert threads(client) == 2
        found = describe(client)
        assert found["workers"] == 2 and found["threads"] == 2
        assert found["address"].startswith("tcp://127.0.0.1:")
        assert listening(os.getpid(), *pids.values())  # scheduler, nannies, workers
        assert all(ip == "127.0.0.1" for ip, _ in listening(os.getpid(), *pids.values()))
        assert ("127.0.0.1", 8787) not in listening(os.getpid())  # not the dashboard's port
    assert client.status == "closed"
    assert cluster.status.name == "closed"


def test_a_local_worker_that_dies_is_restarted_and_kept_in_the_cluster():
    """Dask closes the nanny of a worker lost ``lost-worker-timeout`` ago that is not back
    yet, for good; with the timer at 0 s (the worst moment: while the nanny restarts it)
    the cluster still has both workers after a death."""
    import dask

    with dask.config.set({"distributed.deploy.lost-worker-timeout": "0s"}):
        with cluster_client("local:2") as client:
            first = client.run(os.getpid)
            victim = next(iter(first.values()))
            os.kill(victim, signal.SIGKILL)
            deadline = time.monotonic() + HANG
            while time.monotonic() < deadline:
                pids = client.run(os.getpid, on_error="ignore")  # the victim may be dying
                if len(pids) == 2 and victim not in pids.values():
                    break
                time.sleep(0.2)
            time.sleep(1.0)  # past the lost-worker timer of the restarted worker's loss
            pids = client.run(os.getpid, on_error="ignore")
            assert len(pids) == 2 and victim not in pids.values(), pids
            assert len(client.cluster.workers) == 2  # both nannies still there


def listening(*pids: int) -> set[tuple[str, int]]:
    """(address, port) of every socket on which these processes listen."""
    import psutil

    return {
        (c.laddr.ip, c.laddr.port)
        for pid in pids
        for c in psutil.Process(pid).net_connections(kind="inet")
        if c.status == psutil.CONN_LISTEN
    }


def _pid() -> str:
    return str(os.getpid())


def test_a_client_given_is_used_as_it_is_and_left_open(thread_cluster):
    with cluster_client(thread_cluster) as given:
        assert given is thread_cluster
    assert thread_cluster.status == "running"
    assert all(ip == "127.0.0.1" for ip, _ in listening(os.getpid()))


def test_workers_running_other_code_are_refused():
    with cluster_client("local:1") as client:
        check_same_code(client, lambda: "same")  # the same answer everywhere
        with pytest.raises(SchedulerError) as caught:
            check_same_code(client, _pid)  # each process its own answer
        (worker,) = client.nthreads()
        assert str(caught.value).startswith(f"Dask worker {worker} runs registry ")
        assert "start the workers from the same code" in str(caught.value)


def _same_unless_worker_1_dies(dask_worker=None) -> str:
    """The same answer everywhere, except on the worker named worker-1, which dies while
    it is asked (as a worker killed at that moment does)."""
    if dask_worker is not None and dask_worker.name == "worker-1":
        os.kill(os.getpid(), signal.SIGKILL)
    return "same"


def test_a_worker_that_dies_while_its_code_is_checked_is_not_asked(separate_processes):
    from distributed import Client

    with Client(separate_processes.address, timeout=30) as client:
        check_same_code(client, _same_unless_worker_1_dies)
    assert separate_processes.workers[1].wait(timeout=HANG) == -signal.SIGKILL
