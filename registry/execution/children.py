"""A batch of calls in child processes of a Dask worker: the worker's side of ``tasks``.

Why a child process. Dask runs a task in a thread of its worker, where an alarm
signal cannot interrupt it (only a process's main thread receives signals), and a
thread stuck in C code cannot be stopped at all. So each task starts a child, a new
Python interpreter, whose main thread runs the calls (there the audit's SIGALRM time
budget works). ``multiprocessing`` cannot start it: Dask's worker processes are
daemonic, and daemonic processes may not have children.

Why a new interpreter and not ``os.fork``. The worker has other threads, and a fork
copies the locks they hold at that moment without the threads that would release
them. A thread in the middle of importing a module (unpickling a result imports what
it needs) holds that module's import lock; a child forked then hangs for ever the
first time it needs the module, as sympy's functions import their helpers on first
use. A new interpreter starts with no lock held: it gets the worker's ``sys.path``,
``fn`` and the items pickled through its standard input, imports what they need, and
says it is ready; each call's deadline starts after that.

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
import pickle
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from multiprocessing import Pipe
from multiprocessing.connection import Connection
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


#: Seconds a new child may take to load its batch (a new interpreter importing sympy,
#: the registry and whatever the items need: about a second on a quiet machine).
STARTUP = 120.0

#: What the new interpreter runs: the worker's ``sys.path`` first (so that ``fn``'s
#: module is found as the worker found it), then the batch.
_BOOT = (
    "import pickle, sys; sys.path[:] = pickle.load(sys.stdin.buffer); "
    f"from {__name__} import child_main; child_main(int(sys.argv[1]))"
)


class _Child:
    """A child interpreter working through a batch; the task's thread reads its results."""

    def __init__(self, fn: Callable[[Any], Any], items: Sequence[Any]):
        reader, writer = Pipe(duplex=False)
        # only the pipe's end is passed on: not the worker's sockets or other tasks' pipes
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _BOOT, str(writer.fileno())],
            stdin=subprocess.PIPE,
            pass_fds=(writer.fileno(),),
        )
        writer.close()
        self.conn = reader
        self.exitcode: int | None = None
        assert self.proc.stdin is not None
        try:
            with self.proc.stdin as stdin:
                pickle.dump(list(sys.path), stdin)
                pickle.dump((fn, os.getpid(), list(items)), stdin)
        except (BrokenPipeError, OSError):
            pass  # it died at once: its pipe says so

    def next(self, seconds: float | None, cancelled: Callable[[], bool]) -> tuple[str, Any]:
        """The child's next message: ``("ready", None)`` once it has loaded the batch (or
        ``("failed", text)`` if it could not), then ``("ok", value)`` or ``("error", text)``
        per item; or ``("killed", None)`` past ``seconds``, ``("died", exitcode)`` if the
        child died, ``("cancelled", None)`` if Dask no longer wants the task."""
        deadline = None if seconds is None else time.monotonic() + seconds
        while True:
            left = POLL if deadline is None else max(0.0, min(POLL, deadline - time.monotonic()))
            if self.conn.poll(left):
                try:
                    return self.conn.recv()
                except (EOFError, OSError):
                    return "died", self.reap(block=True)
            if self.reap() is not None:  # died without a word
                if self.conn.poll(0):
                    continue  # it answered before it died
                return "died", self.exitcode
            if deadline is not None and time.monotonic() >= deadline:
                return "killed", None
            if cancelled():
                return "cancelled", None

    def reap(self, block: bool = False) -> int | None:
        """The child's exit code once it has ended (None while it runs; negative: the
        signal that ended it)."""
        if self.exitcode is None:
            self.exitcode = self.proc.wait() if block else self.proc.poll()
        return self.exitcode

    def stop(self) -> None:
        """Kill the child if it still runs, reap it, close the pipe."""
        if self.reap() is None:
            self.proc.kill()
            self.reap(block=True)
        self.conn.close()


def child_main(fd: int) -> None:
    """The child's side: load the batch from standard input, say so on the pipe ``fd``,
    and serve it (``serving.serve``: in this interpreter's main thread)."""
    conn = Connection(fd, readable=False)
    try:
        fn, parent, items = pickle.load(sys.stdin.buffer)
    except BaseException as exc:  # e.g. fn's module cannot be imported here
        conn.send(("failed", f"{type(exc).__name__}: {exc}"))
        return
    conn.send(("ready", None))
    serve(conn, fn, parent, items)


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
    processes of this worker (one for the batch, and a new one after each kill or crash);
    each deadline starts when the call starts, after the child has loaded the batch.
    """
    worker, cancelled = _task_context()
    outcomes: list[tuple[int, Any]] = []
    rest = list(work)
    children = 0
    while rest:
        child = _Child(fn, [item for _, item, _ in rest])
        children += 1
        try:
            status, value = child.next(STARTUP, cancelled)
            if status == "cancelled":
                return BatchResult(worker, outcomes, children)
            if status == "failed":  # no new child would do better
                why = f"the child process could not load the batch: {value}"
                outcomes += [(index, Failure("error", why, worker=worker)) for index, _, _ in rest]
                return BatchResult(worker, outcomes, children)
            if status != "ready":
                index, _, _ = rest.pop(0)
                why = (
                    f"child process did not start within {STARTUP:g} s; killed"
                    if status == "killed"
                    else f"child process died ({value}) before it started"
                )
                code = value if status == "died" else None
                outcomes.append((index, Failure("crashed", why, exitcode=code, worker=worker)))
                continue
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
