"""run_calls: each index exactly once; a worker that dies takes no results with it (its
batch is done elsewhere, and the events say so); a batch whose workers keep dying is
tried item by item, and only the item that kills them is lost; leaving the loop
early stops what runs."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest

from registry.execution.cluster_calls import Failure, guided, pack, run_calls
from tests.helpers.clocks import HANG, within
from tests.helpers.dask_clusters import dask_processes
from tests.helpers.processes import alive

# ------------------------------------------------------- calls the workers run


def square(n: int) -> int:
    return n * n


def sleep_then_mark(item: tuple[str, float]):
    """Writes this process's id to ``item[0]`` (at once: written aside, then renamed),
    then sleeps ``item[1]`` seconds."""
    aside = Path(f"{item[0]}.{os.getpid()}.part")
    aside.write_text(str(os.getpid()))
    os.replace(aside, item[0])
    time.sleep(item[1])
    return item


def kill_my_worker(item: tuple[str, str]):
    """``("always", _)`` kills its Dask worker every time; ``("once", marker)`` only when
    ``marker`` does not exist yet (it creates it); anything else is returned."""
    how, marker = item
    if how == "always" or (how == "once" and not os.path.exists(marker)):
        if how == "once":
            Path(marker).touch()
        os.kill(os.getppid(), signal.SIGKILL)  # the parent of this child: the worker
        time.sleep(60)
    return item


# ------------------------------------------------------------------ helpers


# -------------------------------------------------------------------- tests


def test_pack_keeps_groups_whole_where_they_fit():
    assert pack([[0, 1, 2], [3], [4, 5], [6]], 2) == [[0, 1], [2, 3], [4, 5], [6]]
    assert pack([[0], [1], [2]], 5) == [[0, 1, 2]]
    assert pack([[3, 1, 2]], 1) == [[3], [1], [2]]
    assert pack([], 3) == []


def test_guided_batches_shrink_with_the_work_left_and_keep_groups_whole_where_they_fit():
    sizes = [len(b) for b in guided([[i] for i in range(1000)], 4, 25)]
    assert sum(sizes) == 1000 and max(sizes) == 25
    assert sizes == sorted(sizes, reverse=True)  # the largest first
    assert sizes[-4:] == [1, 1, 1, 1]  # single items at the end, one per part
    assert len(sizes) == 50  # 37 full batches while a quarter of the rest exceeds 25
    grouped = guided([[0, 1, 2, 3], [4, 5], [6], [7, 8, 9]], 2, 10)
    assert grouped == [[0, 1, 2, 3], [4, 5, 6], [7, 8], [9]]  # [4, 5] not cut: it fits
    assert [i for b in grouped for i in b] == list(range(10))  # in order, each once
    assert guided([], 4, 25) == []


def test_every_index_comes_once_with_its_result(process_cluster):
    items = list(range(20))
    batches = pack([[i] for i in items], 3)
    found = list(run_calls(process_cluster, square, items, batches=batches))
    assert sorted(i for i, _ in found) == items
    assert all(value == i * i for i, value in found)


def test_batches_must_partition_the_items(thread_cluster):
    with pytest.raises(ValueError, match="every item index exactly once"):
        list(run_calls(thread_cluster, square, [1, 2], batches=[[0], [0]]))


def test_leaving_the_loop_early_stops_the_running_child(thread_cluster, tmp_path):
    marker = tmp_path / "pid"
    items = [(str(tmp_path / "first"), 0.0), (str(marker), 120.0)]  # one worker thread
    calls = run_calls(thread_cluster, sleep_then_mark, items)
    assert next(calls) == (0, items[0])
    deadline = time.monotonic() + HANG
    while not marker.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    child = int(marker.read_text())  # complete: the child renames it into place
    assert alive(child)
    calls.close()  # what a Ctrl-C does to the loop
    deadline = time.monotonic() + HANG  # far below the 120 s the child would sleep
    while alive(child) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not alive(child), "the child of a cancelled task kept running"


def test_a_worker_that_dies_takes_no_results_with_it(process_cluster, tmp_path):
    items = [("once", str(tmp_path / "killed-once")), ("fine", "a"), ("fine", "b")]
    events = []
    found = dict(
        run_calls(
            process_cluster,
            kill_my_worker,
            items,
            deadline=60,
            batches=[[0, 1, 2]],
            label=lambda item: item[0],
            on_event=events.append,
        )
    )
    assert found == dict(enumerate(items))
    kinds = [e.kind for e in events]
    assert kinds == ["worker-lost", "retried"], [str(e) for e in events]
    lost, retried = events
    assert lost.items == ("once", "fine", "fine")
    assert (
        str(lost) == f"once, fine, fine: worker {lost.worker} lost while holding them; rescheduled"
    )
    assert str(retried) == (
        f"once, fine, fine: done on worker {retried.worker} after losing {lost.worker}"
    )


@pytest.mark.slow  # every worker killed and restarted, twice: over a minute when loaded
def test_an_item_that_kills_every_worker_is_given_up_alone(process_cluster, tmp_path):
    items = [("always", ""), ("fine", "a"), ("fine", "b")]
    events = []
    found = dict(
        run_calls(
            process_cluster,
            kill_my_worker,
            items,
            deadline=60,
            batches=[[0, 1, 2]],
            label=lambda item: f"{item[0]}-{item[1]}",
            on_event=events.append,
        )
    )
    assert (found[1], found[2]) == (items[1], items[2])
    assert isinstance(found[0], Failure) and found[0].kind == "lost"
    assert "KilledWorker" in found[0].reason
    said = [str(e) for e in events]
    culprit = [e for e in events if "always-" in e.items]
    assert [e.kind for e in culprit if e.kind != "worker-lost"] == [
        "split",
        "retrying",
        "given-up",
    ], said
    # 2 deaths per try (allowed-failures is 1 here): the batch, alone, alone again
    assert [e.kind for e in culprit].count("worker-lost") == 6, said
    # a fine item queued on a worker the culprit kills is run again elsewhere: said so
    others = [e for e in events if "always-" not in e.items]
    assert {e.kind for e in others} <= {"worker-lost", "result-lost", "retried"}, said
    given_up = next(e for e in events if e.kind == "given-up")
    assert given_up.items == ("always-",)
    assert str(given_up).startswith("always-: given up (KilledWorker: ")


@pytest.mark.slow  # waits out the run's no-worker timeout: a minute when loaded
def test_a_run_ends_when_the_cluster_has_no_worker_left(tmp_path):
    """Workers without a nanny stay dead: once the batch has killed both, Dask keeps it
    waiting for a worker for ever; the run gives its items up after ``no_worker``."""
    from distributed import Client

    items = [("always", ""), ("fine", "a")]
    events = []
    with dask_processes(tmp_path / "dask") as cluster, Client(cluster.address) as client:
        found = within(
            HANG,
            lambda: dict(
                run_calls(
                    client,
                    kill_my_worker,
                    items,
                    deadline=60,
                    batches=[[0, 1]],
                    label=lambda item: f"{item[0]}-{item[1]}",
                    on_event=events.append,
                    no_worker=2.0,
                )
            ),
        )
        assert all(w.poll() is not None for w in cluster.workers), cluster.log()
    why = f"no Dask worker left on the cluster at {cluster.address} for 2 s"
    assert found == {0: Failure("lost", why), 1: Failure("lost", why)}
    assert [e.kind for e in events] == ["worker-lost", "worker-lost", "given-up"]
    assert str(events[-1]) == f"always-, fine-a: given up ({why})"
