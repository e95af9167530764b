"""Where calls run: in this process, in local worker processes, or on a Dask cluster,
behind one interface.

An ``Executor`` runs ``fn(item)`` for every item and yields ``(index, outcome)`` as the
calls finish, ``outcome`` being the result or a ``serving.Failure`` saying why there is
none. The facade builds one executor per command from ``--jobs`` and ``--scheduler``
(``open_executor``) and hands it down; the audit, the searches and the survey never
choose where their work runs.

* ``--jobs N`` means N worker processes, in every command: N = 1 runs the calls in this
  process, one after the other (each bounded only by its own time budget: nothing can
  kill a call stuck in compiled code); N > 1 starts N long-lived local workers that die
  with this process and are killed and replaced when a call overruns its deadline. The
  default is one per core.
* ``--scheduler ADDRESS`` (else ``$REGISTRY_SCHEDULER``) runs the calls on a Dask cluster
  (``cluster``, ``cluster_calls``), each in a child process of a worker, retried on
  another worker when one dies; the cluster's events (a worker lost) are reported.
  Giving both is a usage error; ``--jobs`` alone runs locally even where the variable
  is set.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Generator, Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from .. import settings
from ..errors import UsageError
from .local import default_jobs, run_in_workers
from .serving import Failure

if TYPE_CHECKING:
    from distributed import Client

    from .cluster_calls import Event

#: A call's deadline: seconds (None: none), or a function of its item.
Deadline = float | Callable[[Any], float | None] | None


def seconds_for(deadline: Deadline, item: Any) -> float | None:
    """The deadline of one item's call."""
    return deadline(item) if callable(deadline) else deadline


class Executor(ABC):
    """Runs calls somewhere (module docstring): ``map`` them, ``describe`` where. What
    happened on a cluster (workers lost, calls done elsewhere) is kept in ``events``, one
    line each, for the command to report."""

    #: How many calls run at once.
    workers: int = 1

    def __init__(self) -> None:
        self.events: list[str] = []

    @abstractmethod
    def map(
        self,
        fn: Callable[[Any], Any],
        items: Sequence[Any],
        *,
        deadline: Deadline = None,
        groups: Sequence[Sequence[int]] | None = None,
        label: Callable[[Any], str] = str,
        on_event: Callable[[Event], None] | None = None,
        name: str = "registry-call",
    ) -> Generator[tuple[int, Any], None, None]:
        """``fn(item)`` for every item; yield ``(index, outcome)`` as each call finishes
        (in any order, each index once). ``groups`` are indices best run in a row by one
        worker (items that share work: a torque, a warm cache), largest first; ``label``
        names an item in events; ``on_event`` hears what happened on a cluster; ``name``
        prefixes the calls' task keys there (what Dask's dashboard shows). Closing the
        generator stops what still runs."""

    def describe(self) -> dict[str, Any]:
        """What a run records of where it ran."""
        return {"jobs": self.workers}

    @property
    def local(self) -> bool:
        """Whether the calls run on this machine (no cluster)."""
        return True


class InProcess(Executor):
    """The calls in this process, in order (``--jobs 1``)."""

    def map(self, fn, items, *, deadline=None, groups=None, label=str, on_event=None, name=""):
        order = [i for g in groups for i in g] if groups is not None else range(len(items))
        for index in order:
            try:
                outcome = fn(items[index])
            except Exception as exc:  # a call that raises has no result, like elsewhere
                outcome = Failure("error", f"{type(exc).__name__}: {exc}")
            yield index, outcome


class LocalPool(Executor):
    """``workers`` long-lived local worker processes (``local.run_in_workers``)."""

    def __init__(self, workers: int):
        super().__init__()
        self.workers = workers

    def map(self, fn, items, *, deadline=None, groups=None, label=str, on_event=None, name=""):
        calls = run_in_workers(
            fn,
            items,
            self.workers,
            seconds=lambda item: seconds_for(deadline, item),
            batches=groups,
        )
        try:
            yield from calls
        finally:
            calls.close()  # type: ignore[attr-defined]


#: A task on a cluster takes at most 1/(SHARES_PER_THREAD x worker threads) of the items
#: still to plan: large tasks first (each task's cost is small beside its work), single
#: items at the end (the last to finish leave little idle time).
SHARES_PER_THREAD = 2
#: Items per cluster task at most: what a worker lost takes with it, and must do again.
MAX_BATCH = 25


class DaskCluster(Executor):
    """The calls on the Dask cluster of a connected client, each in a child process of a
    worker (``cluster_calls.run_calls``); ``address`` is how the command named it."""

    def __init__(self, client: Client, address: str):
        from .cluster import threads

        super().__init__()
        self.client = client
        self.address = address
        self.workers = threads(client)

    @property
    def local(self) -> bool:
        return False

    def describe(self) -> dict[str, Any]:
        from .cluster import describe

        return {"jobs": None, "scheduler": self.address, "cluster": describe(self.client)}

    def plan(self, groups: Sequence[Sequence[int]], count: int) -> list[list[int]]:
        """The items cut into tasks: groups kept together where they fit (largest first),
        tasks shrinking as the items left do (``cluster_calls.guided``), none larger than
        ``MAX_BATCH``."""
        from .cluster import threads
        from .cluster_calls import guided

        parts = SHARES_PER_THREAD * max(1, threads(self.client))
        return guided(groups, parts, MAX_BATCH)

    def map(self, fn, items, *, deadline=None, groups=None, label=str, on_event=None, name=""):
        from .cluster_calls import run_calls

        def heard(event: Event) -> None:
            self.events.append(str(event))
            if on_event is not None:
                on_event(event)

        calls = run_calls(
            self.client,
            fn,
            items,
            deadline=deadline,
            batches=None if groups is None else self.plan(groups, len(items)),
            label=label,
            on_event=heard,
            name=name or "registry-call",
        )
        try:
            yield from calls
        finally:
            calls.close()


def jobs_or_default(jobs: int | None) -> int:
    """``--jobs``: a number of worker processes (at least 1), default one per core."""
    if jobs is None:
        return default_jobs()
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise UsageError(f"--jobs must be a whole number of worker processes, 1 or more: {jobs!r}")
    return jobs


def check_options(jobs: int | None, scheduler: object) -> None:
    """UsageError for ``--jobs`` and ``--scheduler`` given together, or a ``--jobs`` that
    is no number of worker processes (checked before a command does anything else)."""
    if jobs is not None and scheduler is not None:
        raise UsageError("give --jobs (local worker processes) or --scheduler (Dask), not both")
    if jobs is not None:
        jobs_or_default(jobs)


@contextmanager
def open_executor(
    jobs: int | None = None, scheduler: str | Client | None = None
) -> Iterator[Executor]:
    """The executor of one command (module docstring): ``scheduler`` (a Dask address,
    ``local:N``, a scheduler file, or a connected ``distributed.Client``; else
    ``$REGISTRY_SCHEDULER`` unless ``jobs`` is given) or ``jobs`` local workers. A Dask
    cluster must run this process's code version (its results are recorded under it)."""
    check_options(jobs, scheduler)
    if jobs is None and scheduler is None:
        scheduler = settings.scheduler()
    if scheduler is None:
        count = jobs_or_default(jobs)
        yield InProcess() if count == 1 else LocalPool(count)
        return
    from ..version import code_version
    from .cluster import check_same_code, cluster_client, scheduler_address

    with cluster_client(scheduler) as client:
        check_same_code(client, code_version)
        given = scheduler if isinstance(scheduler, str) else scheduler_address(client)
        yield DaskCluster(client, given)


def in_order(
    calls: Iterator[tuple[int, Any]], count: int
) -> Generator[tuple[int, Any], None, None]:
    """An executor's (index, outcome) pairs, which come in any order, in the order of the
    indices 0..count-1, each as soon as those before it are in; an index that never came
    back comes as ``Failure("lost")``. The calls are closed at the end (at once, also when
    the consumer stops in the middle)."""
    arrived: dict[int, Any] = {}
    following = 0
    try:
        for index, value in calls:
            arrived[index] = value
            while following in arrived:
                yield following, arrived.pop(following)
                following += 1
        for index in range(following, count):
            yield index, arrived.pop(index, Failure("lost", "no result came back"))
    finally:
        close = getattr(calls, "close", None)
        if close is not None:
            close()


def timed(seconds: float | None) -> float | None:
    """A deadline for a call that bounds itself by ``seconds`` (a search's budget): a few
    seconds more, so that its own alarm stops it first."""
    return None if seconds is None else seconds + GRACE


#: Seconds a call may run past its own budget before its worker is killed.
GRACE = 5.0
