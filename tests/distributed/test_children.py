"""Calls in child processes of a Dask worker: each in a child of its worker, in the
child's main thread (the audit's SIGALRM budget works there); a call past its deadline
killed even where SIGALRM cannot reach it; a crash, an exception and an unpicklable
result recorded, and the rest of the batch still done by a new child; a child that
starts clean while another thread of its worker is importing a module, and a batch
the child cannot load reported as such."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time

from registry.execution.children import run_batch
from registry.execution.cluster_calls import run_calls
from registry.execution.serving import FAILURES, Failure
from registry.execution.time_budget import BudgetExceeded, time_limit
from tests.helpers.clocks import HANG
from tests.helpers.processes import another_thread_importing, import_named

# ------------------------------------------------------- calls the workers run


def family(_item) -> tuple[int, int, bool]:
    """(this process, its parent, whether this thread is the main one)."""
    return os.getpid(), os.getppid(), threading.current_thread() is threading.main_thread()


def alarm_in_python(seconds: float) -> str:
    """A loop that never ends by itself, under the audit's SIGALRM time limit."""
    try:
        with time_limit(seconds):
            while True:
                sum(range(1000))
    except BudgetExceeded:
        return "interrupted"


def stuck_in_c(item):
    """Simulates code the timer cannot interrupt: SIGALRM blocked, then a long sleep."""
    if item == "stuck":
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
        with time_limit(0.2):
            time.sleep(120)
    return item


def misbehave(item):
    if item == "segfault":
        os.kill(os.getpid(), signal.SIGSEGV)
    if item == "exit":
        os._exit(3)
    if item == "raise":
        raise ValueError("no good")
    if item == "unpicklable":
        return threading.Lock()
    return item


# -------------------------------------------------------------------- tests


def test_each_call_runs_in_a_child_of_its_worker_in_the_childs_main_thread(process_cluster):
    workers = set(process_cluster.run(os.getpid).values())
    found = dict(run_calls(process_cluster, family, range(4)))
    for pid, parent, main in found.values():
        assert parent in workers and pid not in workers and pid != os.getpid()
        assert main  # so SIGALRM reaches the call


def test_the_audits_alarm_interrupts_a_call_in_the_child(process_cluster):
    # without the alarm, the loops would run until their deadline kills them
    found = dict(run_calls(process_cluster, alarm_in_python, [0.3, 0.3], deadline=HANG))
    assert found == {0: "interrupted", 1: "interrupted"}


def test_a_call_where_the_alarm_cannot_reach_is_killed_at_its_deadline(thread_cluster):
    items = ["stuck", "next", "last"]
    started = time.monotonic()
    found = dict(run_calls(thread_cluster, stuck_in_c, items, deadline=1.0, batches=[[0, 1, 2]]))
    # waiting, not computing: a bound far above the seconds this takes, below the 120 s
    # that the stuck call would sleep if no one killed it
    assert time.monotonic() - started < HANG
    killed = found[0]
    assert isinstance(killed, Failure) and killed.kind == "killed"
    assert killed.seconds == 1.0
    assert killed.reason == "deadline of 1 s exceeded; child process killed"
    assert (found[1], found[2]) == ("next", "last")  # a new child took the rest


def test_a_crash_an_exception_and_an_unpicklable_result_are_recorded(thread_cluster):
    items = ["segfault", "a", "exit", "raise", "unpicklable", "b"]
    found = dict(run_calls(thread_cluster, misbehave, items, deadline=30, batches=[range(6)]))
    assert (found[1], found[5]) == ("a", "b")
    assert (found[0].kind, found[0].exitcode) == ("crashed", -signal.SIGSEGV)
    assert found[0].reason == f"child process died ({-signal.SIGSEGV})"
    assert (found[2].kind, found[2].exitcode) == ("crashed", 3)
    assert (found[3].kind, found[3].reason) == ("error", "ValueError: no good")
    assert found[4].kind == "error" and found[4].reason.startswith("result cannot be sent back")


def test_run_batch_outside_a_worker_starts_children_too():
    result = run_batch(family, [(0, None, None), (1, None, 5.0)])
    assert [i for i, _ in result.outcomes] == [0, 1]
    assert {parent for _, (_, parent, _) in result.outcomes} == {os.getpid()}
    assert result.children == 1 and result.worker == ""


def test_every_failure_kind_is_explained():
    assert set(FAILURES) == {"killed", "crashed", "error", "lost"}


def test_a_child_started_while_another_worker_thread_imports_a_module_does_not_hang(
    tmp_path,
):
    # A worker thread that is importing a module holds that module's import lock. A
    # child forked from the worker at that moment inherits the lock held by a thread it
    # does not have, and hangs for ever the first time it needs the module (as sympy's
    # functions import their helpers on first use). Children must start clean.
    with another_thread_importing(tmp_path) as name:
        result = run_batch(import_named, [(0, name, HANG)])
    assert result.outcomes == [(0, 42)]


def test_a_batch_the_child_cannot_load_is_an_error_for_each_item_and_no_new_child(
    tmp_path, monkeypatch
):
    # fn's module exists in the worker only: the new interpreter cannot import it
    name = f"gone_{os.getpid()}"
    (tmp_path / f"{name}.py").write_text("def twice(x):\n    return 2 * x\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import importlib

    try:
        twice = importlib.import_module(name).twice
        (tmp_path / f"{name}.py").unlink()
        result = run_batch(twice, [(0, 1, HANG), (1, 2, HANG)])
    finally:
        sys.modules.pop(name, None)
    assert [i for i, _ in result.outcomes] == [0, 1] and result.children == 1
    for _, failure in result.outcomes:
        assert isinstance(failure, Failure) and failure.kind == "error"
        assert failure.reason == (
            f"the child process could not load the batch: "
            f"ModuleNotFoundError: No module named '{name}'"
        )
