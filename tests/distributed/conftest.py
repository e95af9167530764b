"""Dask clusters for the tests: in this process (workers as threads, so that a
monkeypatched check reaches the child processes they fork), or in processes."""

from __future__ import annotations

from collections.abc import Iterator

import dask
import distributed  # noqa: F401 - its config defaults, before any dask.config.set
import pytest


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
    from registry.distributed.scheduler import cluster_client

    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        with cluster_client("local:2") as client:
            yield client
