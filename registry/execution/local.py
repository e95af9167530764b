"""Running calls in worker processes of this machine that can be killed.

``run_in_workers`` keeps long-lived workers (forked where the platform allows, so sympy
is not imported again, and its caches stay warm from item to item; new interpreters
where this process runs other Python threads), gives each a batch
of items, and waits on their pipes with a deadline per item: a worker that overruns it
(stuck in C code, where the in-process timer cannot interrupt it) is killed, the item
becomes ``Failure("killed")``, and a new worker takes the rest of the batch. Every
worker dies with this process. ``local_mapper`` offers them as a ``mapping.Mapper``,
the interface the Dask cluster's mapper has too.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import wait
from typing import Any

from .serving import Failure, serve


def default_jobs() -> int:
    """Worker processes by default: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _context() -> Any:
    """How workers start: forked from this process where it runs one Python thread (they
    inherit its imports and sympy's caches), else as new interpreters.

    A fork copies the locks that other threads hold, without those threads: a worker
    forked while another Python thread imports a module (a Jupyter kernel's threads, a
    Dask client's) would wait for ever on that module's lock. Threads of C libraries
    that never run Python (OpenBLAS's, started with numpy) hold no such lock, and they
    are prepared for a fork. A new interpreter imports sympy and the registry again
    (about a second of processor time per worker), and is this process's own child, so
    it dies with it as a forked one does. (A fork server would start warm, but its
    workers keep it alive, and it keeps them.)
    """
    if "fork" in mp.get_all_start_methods() and threading.active_count() == 1:
        return mp.get_context("fork")
    return mp.get_context("spawn")


class _Worker:
    """A long-lived worker process serving batches (``serving.serve``)."""

    def __init__(self, ctx: Any, fn: Callable[[Any], Any]):
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=serve, args=(child, fn, os.getpid()), daemon=True)
        self.proc.start()
        child.close()
        self.batch: list[int] = []  # the indices it has still to do, in order
        self.deadline = 0.0  # for the item it is doing now
        self.seconds = 0.0

    def give(
        self, batch: list[int], items: Sequence[Any], seconds: Callable[[Any], float | None]
    ) -> None:
        try:
            self.conn.send([items[i] for i in batch])
        except ConnectionError:  # BrokenPipeError or ConnectionResetError
            pass  # it died already: its pipe reads as closed, the item comes back crashed
        self.batch = list(batch)
        self.start_clock(items, seconds)

    def start_clock(self, items: Sequence[Any], seconds: Callable[[Any], float | None]) -> None:
        """Start the deadline of the next item of its batch (none: no deadline)."""
        limit = seconds(items[self.batch[0]])
        self.seconds = float("inf") if limit is None else limit
        self.deadline = time.monotonic() + self.seconds

    def stop(self, kill: bool = False) -> None:
        if not kill:
            try:
                self.conn.send(None)
            except (BrokenPipeError, OSError):
                kill = True
        if kill:
            self.proc.kill()
        self.proc.join(timeout=5)
        if self.proc.is_alive():
            self.proc.kill()
            self.proc.join()
        self.conn.close()


def run_in_workers(
    fn: Callable[[Any], Any],
    items: Sequence[Any],
    jobs: int,
    seconds: Callable[[Any], float | None],
    batches: Sequence[Sequence[int]] | None = None,
    started: Callable[[int], None] | None = None,
) -> Iterator[tuple[int, Any]]:
    """``fn`` on every item in up to ``jobs`` worker processes; yield ``(index,
    outcome)`` as each finishes, ``outcome`` being ``fn(item)`` or a ``Failure``.

    ``batches`` (default: each item alone) are the indices a worker does in a row;
    ``seconds(item)`` is an item's deadline; ``started(index)`` is called as a worker
    begins an item. A worker that overruns a deadline is killed and replaced, the rest
    of its batch going back to the front of the queue; one that dies is replaced too.
    """
    ctx = _context()
    groups = batches if batches is not None else [[i] for i in range(len(items))]
    pending = [list(b) for b in groups if b]
    workers: list[_Worker] = []

    def begin(w: _Worker) -> None:
        if started is not None:
            started(w.batch[0])

    def renew(k: int) -> None:
        """Kill worker k and start a new one; the rest of its batch goes back in front."""
        old = workers[k]
        rest, old.batch = old.batch[1:], []
        old.stop(kill=True)
        workers[k] = _Worker(ctx, fn)
        if rest:
            pending.insert(0, rest)

    try:
        for _ in range(min(max(1, jobs), len(pending))):
            workers.append(_Worker(ctx, fn))
        while True:
            for w in workers:
                if not w.batch and pending:
                    w.give(pending.pop(0), items, seconds)
                    begin(w)
            busy = [w for w in workers if w.batch]
            if not busy:
                return
            soonest = min(w.deadline for w in busy)
            left = None if soonest == float("inf") else max(0.0, soonest - time.monotonic())
            ready = wait([w.conn for w in busy], timeout=left)
            for k, w in enumerate(workers):
                if not w.batch:
                    continue
                index = w.batch[0]
                if w.conn in ready:
                    try:
                        status, value = w.conn.recv()
                    except (EOFError, ConnectionError):  # it died: report and replace it
                        code = w.proc.exitcode
                        why = f"worker died ({code})"
                        yield index, Failure("crashed", why, exitcode=code)
                        renew(k)
                        continue
                    w.batch.pop(0)
                    yield index, value if status == "ok" else Failure("error", value)
                    if w.batch:
                        w.start_clock(items, seconds)
                        begin(w)
                elif time.monotonic() >= w.deadline:  # stuck where the timer cannot reach
                    renew(k)
                    yield index, Failure("killed", "deadline exceeded", w.seconds)
    finally:
        for w in workers:
            w.stop(kill=bool(w.batch))
