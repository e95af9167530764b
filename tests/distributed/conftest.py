"""The Dask clusters of the distributed tests (defined in ``tests/helpers/dask_clusters.py``)."""

from tests.helpers.dask_clusters import (  # noqa: F401 - fixtures
    process_cluster,
    separate_processes,
    thread_cluster,
)
