"""Picklable calls run on a Dask cluster, each in a child process of a worker.

The machinery under ``registry audit --scheduler``, and, through the same function,
under an integral search's candidates::

    for index, outcome in run_calls(client, fn, items, deadline=60.0):
        ...  # outcome is fn(items[index]), or a Failure saying why there is none

Each task is a batch of items run by one child process of a Dask worker, each call
under its deadline (``execution.children``: killed past it, even where SIGALRM cannot reach).

A worker that dies, or leaves, while it holds batches takes no results with it: the
scheduler runs those batches again on other workers, and the client, which hears of
it from the scheduler's event log, reports an ``Event`` (``worker tcp://... lost
while holding them; rescheduled``, then ``done on worker tcp://... after losing
tcp://...``). A batch whose workers died more often than
``distributed.scheduler.allowed-failures`` allows (``KilledWorker``) is tried again
item by item, and an item is given up, as ``Failure("lost")``, only after one more
try on its own (Dask blames every task a dying worker held, even one queued behind
the culprit). A run always ends: should the cluster have no worker left for
``no_worker`` seconds (every worker dead, none restarted), each item not done yet is
given up as ``Failure("lost")`` saying so, instead of waiting for a worker that never
comes. Only the client sees the results: it does all the writing.
"""

from __future__ import annotations

import math
import queue
import time
import uuid
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..errors import SchedulerError
from .children import BatchResult, run_batch
from .serving import Failure

if TYPE_CHECKING:
    from distributed import Client, Future

#: How often Dask runs a task again when the task itself raises (a child that could not
#: be started for lack of memory, say; an exception of ``fn`` is a Failure, not a raise).
RETRIES = 2
#: How often an item whose task Dask gave up (KilledWorker: its workers kept dying) is
#: submitted again on its own before it is given up.
LOST_RETRIES = 1
#: Seconds a run waits, by default, for a worker when the cluster has none left (every
#: worker dead: nannies restart theirs within seconds, a batch system within minutes).
NO_WORKER = 120.0
#: Seconds between two looks, while no result comes, at the events and the workers.
POLL = 0.1
#: Seconds between two questions to the scheduler about its workers, while no result comes.
WATCH = 1.0


@dataclass(frozen=True)
class Event:
    """Something that happened to a run on the cluster: a worker lost or gone while it
    held items (``worker-lost``, ``worker-left``, ``result-lost``), items done after such
    a loss (``retried``), a failed batch tried again item by item (``split``), an item
    tried once more on its own (``retrying``), then given up (``given-up``). ``items``
    are the labels of the items concerned; ``str(event)`` is one line for a person."""

    kind: str
    worker: str | None
    items: tuple[str, ...]
    text: str

    def __str__(self) -> str:
        return self.text


def pack(groups: Iterable[Sequence[int]], size: int) -> list[list[int]]:
    """Groups of item indices packed into batches of at most ``size`` items, in order:
    a group larger than ``size`` is cut, smaller ones share a batch where they fit whole.

    >>> pack([[0, 1, 2], [3], [4, 5], [6]], 2)
    [[0, 1], [2, 3], [4, 5], [6]]
    """
    size = max(1, size)
    out: list[list[int]] = []
    current: list[int] = []
    for group in groups:
        group = list(group)
        if current and len(current) + len(group) > size:
            out.append(current)
            current = []
        while len(group) > size:
            out.append(group[:size])
            group = group[size:]
        current.extend(group)
        if len(current) == size:
            out.append(current)
            current = []
    if current:
        out.append(current)
    return out


def guided(groups: Iterable[Sequence[int]], parts: int, largest: int) -> list[list[int]]:
    """Groups of item indices packed into batches that shrink with the work left: each
    takes about 1/``parts`` of the items not yet packed (at least 1, at most ``largest``),
    a group kept whole where it fits, cut where it does not. The first batches are
    the largest and the last ones single items, so that the last to finish keep the
    other workers idle only briefly ("guided self-scheduling").

    >>> [len(b) for b in guided([[i] for i in range(20)], 4, 3)]
    [3, 3, 3, 3, 2, 2, 1, 1, 1, 1]
    >>> guided([[0, 1, 2], [3], [4, 5]], 2, 10)
    [[0, 1, 2], [3], [4], [5]]
    """
    groups = [list(g) for g in groups]
    left = sum(len(g) for g in groups)
    out: list[list[int]] = []
    current: list[int] = []
    target = 0

    def close(batch: Sequence[int]) -> None:
        nonlocal left
        out.append(list(batch))
        left -= len(batch)

    for group in groups:
        while group:
            if not current:
                target = max(1, min(largest, math.ceil(left / max(1, parts))))
                if len(group) > target:  # cut
                    close(group[:target])
                    group = group[target:]
                    continue
            elif len(current) + len(group) > target:
                close(current)
                current = []
                continue
            current.extend(group)
            group = []
            if len(current) >= target:
                close(current)
                current = []
    if current:
        close(current)
    return out


def run_calls(
    client: Client,
    fn: Callable[[Any], Any],
    items: Sequence[Any],
    *,
    deadline: float | Callable[[Any], float] | None = None,
    batches: Sequence[Sequence[int]] | None = None,
    label: Callable[[Any], str] = str,
    on_event: Callable[[Event], None] | None = None,
    name: str = "registry-call",
    no_worker: float = NO_WORKER,
) -> Generator[tuple[int, Any], None, None]:
    """Run ``fn(item)`` for every item on the cluster of ``client``, each call in a child
    process of a Dask worker; yield ``(index, outcome)`` as the calls complete.

    Parameters
    ----------
    client
        A connected ``distributed.Client`` (``scheduler.cluster_client``). One run at a
        time per client: a run listens to the scheduler's events under the client.
    fn, items
        ``fn`` and the items must pickle (a module-level function, or a
        ``functools.partial`` of one), and the workers must be able to import them.
    deadline
        Seconds allowed to one call (a number, or a function of the item; None: no
        limit). The clock starts when the call starts; a call past it is killed.
    batches
        Lists of item indices, each run by one task in one child, in that order
        (default: one task per item). Batch items that share work (a torque, a warm
        cache), and keep tasks long enough that Dask's cost per task does not show.
    label
        A short name of an item, for the events.
    on_event
        Called with each ``Event`` (a worker lost, a batch retried), in the caller's
        thread, between two yields.
    name
        The prefix of the tasks' keys (what Dask's dashboard shows).
    no_worker
        Seconds the run waits while the cluster has no worker at all; past them, every
        item not done yet is ``Failure("lost")`` (and a ``given-up`` event) and the run
        ends. Dask itself would wait for ever for a worker to come.

    Yields
    ------
    ``(index, outcome)``: ``outcome`` is ``fn(items[index])``, or a ``serving.Failure``.
    Every index comes exactly once. SchedulerError if the cluster drops the tasks (its
    scheduler is gone) or its workers cannot unpickle them (the package is missing
    there). Leaving the loop early cancels what has not run, and stops what runs.
    """
    items = list(items)
    plan = [list(b) for b in batches] if batches is not None else [[i] for i in range(len(items))]
    if sorted(i for b in plan for i in b) != list(range(len(items))):
        raise ValueError("batches must hold every item index exactly once")
    seconds = [deadline(item) if callable(deadline) else deadline for item in items]
    labels = [label(item) for item in items]
    run = _Run(client, fn, items, seconds, labels, on_event, name, no_worker)
    return run.results([b for b in plan if b])


class _Run:
    """One ``run_calls``: the tasks submitted, what the scheduler said of lost workers."""

    def __init__(self, client, fn, items, seconds, labels, on_event, name, no_worker):
        self.client, self.fn, self.items, self.seconds = client, fn, items, seconds
        self.labels, self.on_event, self.no_worker = labels, on_event, no_worker
        self.prefix = f"{name}-{uuid.uuid4().hex[:8]}"
        self.tasks: dict[str, list[int]] = {}  # key -> the indices it runs
        self.futures: dict[str, Future] = {}
        self.done: set[str] = set()
        self.losses: dict[str, list[str]] = {}  # key -> workers lost while they held it
        self.tries = [0] * len(items)  # submissions on its own after a failed task
        self.heard: queue.SimpleQueue[dict] = queue.SimpleQueue()
        self.looked = -math.inf  # when the workers were last counted
        self.workerless: float | None = None  # since when the cluster has had none

    # -- events

    def listen(self, event) -> None:
        """The scheduler's event log, in the client's event loop: hand over, no more."""
        _, message = event
        if isinstance(message, dict) and message.get("action") == "remove-worker":
            self.heard.put(message)

    def report(self, kind: str, worker: str | None, indices: Sequence[int], what: str) -> None:
        if self.on_event is not None:
            names = tuple(self.labels[i] for i in indices)
            self.on_event(Event(kind, worker, names, f"{', '.join(names)}: {what}"))

    def hear(self) -> None:
        """Report the workers lost, or gone, while they held tasks of this run."""
        while not self.heard.empty():
            message = self.heard.get()
            worker = str(message.get("worker"))
            held = set(message.get("processing-tasks", ())) & self.tasks.keys()
            for key in sorted(held - self.done):
                indices = self.tasks[key]
                self.losses.setdefault(key, []).append(worker)
                kind, what = (
                    ("worker-left", "left")
                    if message.get("expected")
                    else (
                        "worker-lost",
                        "lost",
                    )
                )
                them = "it" if len(indices) == 1 else "them"
                self.report(
                    kind,
                    worker,
                    indices,
                    f"worker {worker} {what} while holding {them}; rescheduled",
                )
            computed = set(message.get("lost-computed-tasks", ())) & self.tasks.keys()
            for key in sorted(computed - self.done):
                self.losses.setdefault(key, []).append(worker)
                what = f"result lost with worker {worker} before it was fetched; recomputed"
                self.report("result-lost", worker, self.tasks[key], what)

    # -- tasks

    def submit(self, key: str, indices: list[int], ac) -> None:
        self.tasks[key] = indices
        work = [(i, self.items[i], self.seconds[i]) for i in indices]
        future = self.client.submit(run_batch, self.fn, work, key=key, pure=False, retries=RETRIES)
        self.futures[key] = future
        ac.add(future)

    def results(self, plan: list[list[int]]) -> Generator[tuple[int, Any], None, None]:
        from distributed import as_completed

        self.client.subscribe_topic("all", self.listen)  # first: no loss goes unheard
        try:
            ac = as_completed()
            for b, indices in enumerate(plan):
                self.submit(f"{self.prefix}-{b}", indices, ac)
            while not ac.is_empty():
                if not ac.has_ready():
                    self.hear()
                    if self.deserted():
                        yield from self.give_up()
                        return
                    time.sleep(POLL)
                    continue
                future = next(ac)
                self.hear()
                self.workerless = None  # something came back: a worker was there
                if future.status == "finished":
                    yield from self.finished(future)
                else:
                    yield from self.failed(future, ac)
        finally:
            try:
                self.client.unsubscribe_topic("all")
            except Exception:  # a client already closed has no subscriptions left
                pass
            outstanding = [f for f in self.futures.values() if not f.done()]
            if outstanding:
                self.client.cancel(outstanding)

    def deserted(self) -> bool:
        """Whether the cluster has had no worker for ``no_worker`` seconds: nothing left
        to run this run's tasks (Dask keeps them waiting for a worker, for ever). The
        scheduler is asked at most every ``WATCH`` seconds; a scheduler that does not
        answer is the futures' business (they are dropped: ``failed``)."""
        now = time.monotonic()
        if now - self.looked < WATCH:
            return False
        self.looked = now
        try:
            workers = len(self.client.nthreads(callback_timeout=10 * WATCH))
        except Exception:  # a scheduler gone or reconnecting: no count, no verdict
            return False
        if workers:
            self.workerless = None
            return False
        if self.workerless is None:
            self.workerless = now
        return now - self.workerless >= self.no_worker

    def give_up(self) -> Iterator[tuple[int, Any]]:
        """Every item not done yet, as ``Failure("lost")``: the cluster has no worker."""
        address = self.client.scheduler.address
        why = f"no Dask worker left on the cluster at {address} for {self.no_worker:g} s"
        for key, indices in list(self.tasks.items()):
            if key in self.done:  # its items came, or went on in other tasks
                continue
            self.done.add(key)
            self.report("given-up", None, indices, f"given up ({why})")
            for index in indices:
                yield index, Failure("lost", why)

    def finished(self, future: Future) -> Iterator[tuple[int, Any]]:
        key = str(future.key)  # this run's keys are strings (see ``submit``)
        indices = self.tasks[key]
        result: BatchResult = future.result()
        future.release()
        self.done.add(key)
        if key in self.losses:
            lost = ", ".join(self.losses[key])
            self.report(
                "retried",
                result.worker,
                indices,
                f"done on worker {result.worker} after losing {lost}",
            )
        seen = set()
        for index, outcome in result.outcomes:
            seen.add(index)
            yield index, outcome
        for index in indices:
            if index not in seen:  # the task stopped early: Dask had cancelled it
                yield index, Failure("lost", "the task ended without it")

    def failed(self, future: Future, ac) -> Iterator[tuple[int, Any]]:
        key = str(future.key)  # this run's keys are strings (see ``submit``)
        indices = self.tasks[key]
        address = self.client.scheduler.address
        if future.status in ("lost", "pending"):
            # its result went with a worker that died before it was fetched: the
            # scheduler computes it again (``hear`` says so), and it comes back then
            ac.add(future)
            return
        if future.status == "cancelled":
            raise SchedulerError(
                address,
                f"the Dask scheduler at {address} dropped the run's tasks ({future.status}); "
                "is it still running?",
            )
        error = future.exception()
        future.release()
        self.done.add(key)
        if isinstance(error, ImportError):  # every task would fail alike
            raise SchedulerError(
                address,
                f"the Dask workers cannot load the tasks ({type(error).__name__}: {error}); "
                "install the registry package where the workers run",
            ) from error
        why = f"{type(error).__name__}: {error}"
        if len(indices) > 1:
            self.report("split", None, indices, f"batch failed ({why}); retrying each alone")
            for index in indices:
                self.submit(f"{key}-{index}", [index], ac)
            return
        (index,) = indices
        if self.tries[index] < LOST_RETRIES:
            self.tries[index] += 1
            self.report("retrying", None, indices, f"failed ({why}); retrying")
            self.submit(f"{key}-again{self.tries[index]}", indices, ac)
            return
        self.report("given-up", None, indices, f"given up ({why})")
        yield index, Failure("lost", why)
