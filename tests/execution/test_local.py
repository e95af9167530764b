"""Local worker processes (``registry/execution/local.py``): killable workers whose every
item comes back as a result or a ``Failure`` saying why, behind the executor's interface."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import threading
import time

from registry.execution.executor import LocalPool, in_order
from registry.execution.local import default_jobs, run_in_workers
from registry.execution.serving import Failure
from tests.helpers.clocks import HANG
from tests.helpers.processes import (
    alive,
    another_thread_importing,
    descendants,
    import_named,
)


def _pid_after(seconds: float) -> tuple[float, int]:
    import os

    time.sleep(seconds)
    return seconds, os.getpid()


def test_the_local_pool_keeps_the_order_and_ends_its_processes_when_stopped():
    import os

    results = in_order(LocalPool(2).map(_pid_after, [0.3, 0.0, 0.1, 0.0]), 4)
    (_, first), (_, second) = next(results), next(results)
    assert [first[0], second[0]] == [0.3, 0.0]  # the slow first item still comes first
    pids = [first[1], second[1]]
    assert os.getpid() not in pids
    results.close()  # the consumer stops in the middle: the workers are ended at once
    # (an idle worker left running would keep its processes: waiting for them to end, with
    # a zombie waiting to be reaped counted as gone, tells the two apart on a busy machine)
    deadline = time.monotonic() + HANG
    while (left := [p for p in set(pids) if alive(p)]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert left == [], "the workers outlived the stopped map"


def _behave(item: str) -> object:
    """A call that answers, raises, dies or hangs, as ``item`` says."""
    if item == "raise":
        raise ValueError("no")
    if item == "die":
        os._exit(3)
    if item == "hang":
        time.sleep(60)
    return (item, os.getpid())


def test_each_item_comes_back_as_its_result_or_the_failure_that_stopped_it():
    items = ["a", "raise", "b", "die", "c", "hang", "d"]
    started: list[int] = []
    found = dict(
        run_in_workers(
            _behave,
            items,
            jobs=2,
            seconds=lambda item: 2.0,
            batches=[[0, 1, 2, 3, 4], [5, 6]],
            started=started.append,
        )
    )
    assert sorted(found) == list(range(len(items)))
    for i in (0, 2, 4, 6):
        assert found[i][0] == items[i] and found[i][1] != os.getpid()
    assert found[1] == Failure("error", "ValueError: no")
    assert found[3].kind == "crashed" and found[3].reason.startswith("worker died (")
    assert found[5] == Failure("killed", "deadline exceeded", 2.0)
    # the worker that died is replaced: what came after the crash ran elsewhere
    assert found[4][1] != found[0][1] and found[6][1] != found[0][1]
    assert sorted(started) == list(range(len(items)))


def test_default_jobs_is_at_least_one():
    assert default_jobs() >= 1


def test_the_local_pool_names_a_call_without_a_result():
    found = dict(LocalPool(2).map(_behave, ["a", "die", "hang"], deadline=1.0))
    assert found[0][0] == "a"
    assert isinstance(found[1], Failure) and found[1].kind == "crashed"
    assert (found[2].kind, found[2].reason) == ("killed", "deadline exceeded")


def test_workers_started_while_another_thread_imports_a_module_do_not_hang(tmp_path):
    # The caller runs other threads (a Jupyter kernel does): a worker forked from it while
    # one of them imports a module would wait for ever on that module's lock, and be
    # killed at its deadline. Workers are then new interpreters.
    with another_thread_importing(tmp_path) as name:
        found = dict(run_in_workers(import_named, [name], jobs=1, seconds=lambda _: HANG))
    assert found == {0: 42}


def test_a_function_a_new_worker_cannot_import_is_a_crash_for_each_item(tmp_path):
    # with another thread running, workers are new interpreters, which import fn's
    # module again: where it is gone, each worker dies before it reads its batch
    name = f"gone_{os.getpid()}"
    (tmp_path / f"{name}.py").write_text("def twice(x):\n    return 2 * x\n")
    sys.path.insert(0, str(tmp_path))
    other = threading.Event()
    threading.Thread(target=other.wait, daemon=True).start()
    try:
        twice = importlib.import_module(name).twice
        (tmp_path / f"{name}.py").unlink()
        found = dict(run_in_workers(twice, [1, 2], jobs=1, seconds=lambda _: HANG))
    finally:
        other.set()
        sys.modules.pop(name, None)
        sys.path.remove(str(tmp_path))
    assert sorted(found) == [0, 1]
    for failure in found.values():
        assert isinstance(failure, Failure) and failure.kind == "crashed"


#: A caller with another thread, whose two workers sleep; it prints "started" when both run.
CALLER = """
import threading, time
from registry.execution.local import run_in_workers
threading.Thread(target=threading.Event().wait, daemon=True).start()
for _ in run_in_workers(time.sleep, [600, 600], 2, seconds=lambda _: None,
                        started=lambda i: print("started", i, flush=True)):
    pass
"""


def test_workers_started_beside_other_threads_die_with_their_caller():
    caller = subprocess.Popen([sys.executable, "-c", CALLER], stdout=subprocess.PIPE, text=True)
    try:
        assert caller.stdout is not None
        assert [caller.stdout.readline().split()[0] for _ in range(2)] == ["started"] * 2
        below = descendants(caller.pid)
        assert len(below) >= 2  # the two workers, and multiprocessing's resource tracker
    finally:
        caller.kill()
        caller.wait()
    deadline = time.monotonic() + HANG
    while (left := [p for p in below if alive(p)]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert left == [], "processes outlived the killed caller"
