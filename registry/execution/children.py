"""A batch of calls in child processes of a Dask worker: the worker's side of ``tasks``.

Why a child process. Dask runs a task in a thread of its worker, where an alarm
signal cannot interrupt it (only a process's main thread receives signals), and a
thread stuck in C code cannot be stopped at all. So each task forks a child
(``os.fork``: the worker's imported modules and the items come along for free, and
the forking thread becomes the child's main thread, where the audit's SIGALRM time
budget works). ``multiprocessing`` cannot start it: Dask's worker processes are
daemonic, and daemonic processes may not have children.

A task is a batch of items. Its child calls ``fn`` on each item in turn and sends
each result back through a pipe as soon as it is done; the task's thread waits for
each with that item's deadline. A child that overruns it is killed (SIGKILL) and the
item becomes ``Failure("killed")``; a child that dies without answering makes
``Failure("crashed")``; an exception raised by ``fn`` is ``Failure("error")``. After a
kill or a crash a new child takes the rest of the batch. The child never outlives
its worker, however the worker dies (``die_with_parent``: the kernel's parent-death
signal, tied to the task's thread, which waits for the child), holds none of the
worker's sockets or other tasks' pipes, and is stopped when Dask cancels the task
(its client went away).
"""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from multiprocessing import Pipe
from typing import Any

from .serving import Failure, serve

#: Seconds between two looks, while a child works, at whether Dask still wants the task.
POLL = 0.5


@dataclass(frozen=True)
class BatchResult:
    """What a task returns: the worker that ran it, ``(index, outcome)`` for each of its
    items, and how many child processes it started."""

    worker: str
    outcomes: list[tuple[int, Any]]
    children: int


class _Child:
    """A forked child working through a batch; the task's thread reads its results."""

    def __init__(self, fn: Callable[[Any], Any], items: Sequence[Any]):
        reader, writer = Pipe(duplex=False)
        parent = os.getpid()
        pid = os.fork()
        if pid == 0:  # the child: it only ever leaves through os._exit
            code = 1
            try:
                keep = writer.fileno()
                # other tasks' pipes and the worker's sockets are not the child's to hold
                os.closerange(3, keep)
                os.closerange(keep + 1, _max_fd())
                serve(writer, fn, parent, items)
                code = 0
            finally:
                os._exit(code)
        writer.close()
        self.pid = pid
        self.conn = reader
        self.exitcode: int | None = None

    def next(self, seconds: float | None, cancelled: Callable[[], bool]) -> tuple[str, Any]:
        """The child's next message, ``("ok", value)`` or ``("error", text)``; or
        ``("killed", None)`` past ``seconds``, ``("died", exitcode)`` if the child died,
        ``("cancelled", None)`` if Dask no longer wants the task."""
        deadline = None if seconds is None else time.monotonic() + seconds
        while True:
            left = POLL if deadline is None else max(0.0, min(POLL, deadline - time.monotonic()))
            if self.conn.poll(left):
                try:
                    return self.conn.recv()
                except (EOFError, OSError):
                    return "died", self.reap(block=True)
            if self.reap() is not None:  # died without a word (its pipe may be shared)
                if self.conn.poll(0):
                    continue  # it answered before it died
                return "died", self.exitcode
            if deadline is not None and time.monotonic() >= deadline:
                return "killed", None
            if cancelled():
                return "cancelled", None

    def reap(self, block: bool = False) -> int | None:
        """The child's exit code once it has ended (None while it runs)."""
        if self.exitcode is None:
            pid, status = os.waitpid(self.pid, 0 if block else os.WNOHANG)
            if pid:
                self.exitcode = os.waitstatus_to_exitcode(status)
        return self.exitcode

    def stop(self) -> None:
        """Kill the child if it still runs, reap it, close the pipe."""
        if self.exitcode is None:
            try:
                os.kill(self.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.reap(block=True)
        self.conn.close()


def _max_fd() -> int:
    try:
        return os.sysconf("SC_OPEN_MAX")
    except (ValueError, OSError):
        return 65536


def _task_context() -> tuple[str, Callable[[], bool]]:
    """(this worker's address, whether Dask has cancelled the running task); outside a
    Dask worker (a test calling ``run_batch`` directly), ("", never)."""
    try:
        from distributed import get_worker
        from distributed.worker import thread_state

        worker = get_worker()
        key = thread_state.key
    except (ImportError, ValueError, AttributeError):
        return "", lambda: False

    def cancelled() -> bool:
        task = worker.state.tasks.get(key)
        return task is None or task.state not in ("executing", "long-running", "resumed")

    return worker.address, cancelled


def run_batch(
    fn: Callable[[Any], Any], work: Sequence[tuple[int, Any, float | None]]
) -> BatchResult:
    """One task: ``fn`` on each ``(index, item, deadline)`` of ``work``, in child
    processes of this worker (one for the batch, and a new one after each kill or crash).
    """
    worker, cancelled = _task_context()
    outcomes: list[tuple[int, Any]] = []
    rest = list(work)
    children = 0
    while rest:
        child = _Child(fn, [item for _, item, _ in rest])
        children += 1
        try:
            while rest:
                index, _, seconds = rest[0]
                status, value = child.next(seconds, cancelled)
                if status == "cancelled":
                    return BatchResult(worker, outcomes, children)
                rest.pop(0)
                if status == "ok":
                    outcomes.append((index, value))
                elif status == "error":
                    outcomes.append((index, Failure("error", value, worker=worker)))
                elif status == "killed":
                    why = f"deadline of {seconds:g} s exceeded; child process killed"
                    outcomes.append((index, Failure("killed", why, seconds, worker=worker)))
                    break
                else:
                    why = f"child process died ({value})"
                    outcomes.append((index, Failure("crashed", why, exitcode=value, worker=worker)))
                    break
        finally:
            child.stop()
    return BatchResult(worker, outcomes, children)
