"""Auditing cases in parallel worker processes that can be killed.

Each case is audited in a child process (forked where the platform allows, so
sympy is not imported again). The parent waits on the children's pipes with a
deadline per case: a child that overruns it (stuck in C code, where the
in-process timer cannot interrupt it) is killed, the case is recorded as
inconclusive, and the next case takes its place.
"""

from __future__ import annotations

import ctypes
import multiprocessing as mp
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import wait
from typing import Any

import sympy as sp

from ..model import Case, CaseAudit, CheckResult, Verdict
from .case_audit import audit_case, count_checks
from .time_budget import TimeBudget


def default_jobs() -> int:
    """Worker processes by default: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _context():
    methods = mp.get_all_start_methods()
    return mp.get_context("fork" if "fork" in methods else "spawn")


def estimated_cost(case: Case) -> int:
    """A rough size of the work a case needs: its expressions' operation counts, with
    families of arbitrary functions weighted up. Used to start the largest cases first."""
    exprs = [*case.system.torque, case.system.potential, *(c.expression for c in case.claims)]
    return sum(sp.count_ops(e.expr) for e in exprs) + 100 * len(case.functions)


#: prctl(2) option: the signal this process gets when its parent dies (Linux).
_PR_SET_PDEATHSIG = 1
#: Seconds between two looks at the parent, where the kernel cannot be asked to tell.
WATCHDOG_INTERVAL = 0.2


def die_with_parent(parent: int) -> None:
    """Make this process end when ``parent`` dies, however it dies (SIGKILL included),
    even in the middle of a long check.

    On Linux the kernel sends SIGKILL on the parent's death (``PR_SET_PDEATHSIG``);
    elsewhere a daemon thread watches the parent and kills this process when it is gone.
    """
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0:
                if os.getppid() != parent:  # it died before the request took effect
                    os._exit(1)
                return
        except (OSError, AttributeError):
            pass  # no prctl: fall back to the watchdog

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCHDOG_INTERVAL)
        os.kill(os.getpid(), signal.SIGKILL)

    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()


def _serve(conn, budget: TimeBudget, numeric: bool, parent: int) -> None:
    """A worker: audit each batch of cases received, sending each audit (or the
    exception) as it finishes, until told to stop (None).

    SIGTERM ends a worker at once; Ctrl-C is the parent's to handle (it stops the
    workers and records the run as interrupted); the worker never outlives the
    parent (``die_with_parent``)."""
    die_with_parent(parent)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    while True:
        try:
            batch = conn.recv()
        except EOFError:
            return
        if batch is None:
            return
        for case in batch:
            try:
                conn.send(audit_case(case, budget=budget, numeric=numeric))
            except BaseException as exc:  # report, never hang the parent
                conn.send(exc)


def in_processes(fn: Callable[[Any], Any], items: Sequence[Any], jobs: int) -> Iterator[Any]:
    """``fn(item)`` for each item in up to ``jobs`` worker processes, results in the
    items' order; the processes die with this one, and are ended at once when the
    consumer stops (a budget ran out in the middle)."""
    pool = _context().Pool(
        min(jobs, len(items)), initializer=die_with_parent, initargs=(os.getpid(),)
    )
    try:
        yield from pool.imap(fn, items)
    finally:
        pool.terminate()
        pool.join()


class _Worker:
    """A long-lived audit process (its sympy caches stay warm from case to case)."""

    def __init__(self, ctx, budget: TimeBudget, numeric: bool):
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(
            target=_serve, args=(child, budget, numeric, os.getpid()), daemon=True
        )
        self.proc.start()
        child.close()
        self.batch: list[tuple[int, Case]] = []  # what it has still to audit, in order
        self.deadline = 0.0  # for the case it is auditing now
        self.seconds = 0.0

    def give(self, batch: list[tuple[int, Case]], budget: TimeBudget) -> None:
        self.conn.send([case for _, case in batch])
        self.batch = list(batch)
        self.start_clock(budget)

    def start_clock(self, budget: TimeBudget) -> None:
        """Start the deadline of the next case of its batch."""
        self.seconds = budget.case_deadline(count_checks(self.batch[0][1]))
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


def _torque(case: Case) -> tuple:
    """What cases sharing a torque share: its components and the parameters' assumptions."""
    return tuple(e.text for e in case.system.torque), tuple(sorted(case.assumptions.items()))


def batches(cases: Sequence[Case]) -> list[list[tuple[int, Case]]]:
    """The cases as (index, case), grouped by torque, largest group first, largest case
    first within a group: one worker audits a group, recognising its torque's family
    once and with sympy's caches warm (a correction after the case it corrects costs a
    fraction of the first); largest first, so no long group starts last."""
    cost = [estimated_cost(c) for c in cases]
    groups: dict[tuple, list[tuple[int, Case]]] = {}
    for i in sorted(range(len(cases)), key=lambda i: -cost[i]):
        groups.setdefault(_torque(cases[i]), []).append((i, cases[i]))
    return sorted(groups.values(), key=lambda g: -sum(cost[i] for i, _ in g))


def killed(case: Case, seconds: float) -> CaseAudit:
    """The audit of a case whose worker overran its deadline and was killed."""
    reason = f"worker killed after {seconds:.0f} s (case time budget exceeded)"
    return CaseAudit(
        case.id,
        case.content_hash,
        (CheckResult("audit", Verdict.INCONCLUSIVE, "time budget", reason=reason),),
    )


def crashed(case: Case, why: str) -> CaseAudit:
    """The audit of a case whose worker died or failed."""
    return CaseAudit(
        case.id, case.content_hash, (CheckResult("audit", Verdict.ERROR, "exception", reason=why),)
    )


def audit_in_workers(
    cases: Sequence[Case],
    jobs: int,
    budget: TimeBudget,
    started: Callable[[Case], None] | None = None,
    numeric: bool = False,
) -> Iterator[tuple[int, CaseAudit]]:
    """Audit ``cases`` in up to ``jobs`` processes; yield (index, audit) as each finishes.

    A worker that overruns its case's deadline is killed and replaced by a new one;
    the rest of its batch goes back to the queue.
    """
    ctx = _context()
    pending = batches(cases)
    workers: list[_Worker] = []

    def begin(w: _Worker) -> None:
        if started is not None:
            started(w.batch[0][1])

    def renew(i: int) -> None:
        """Kill worker i and start a new one; the rest of its batch goes back in front."""
        old = workers[i]
        rest, old.batch = old.batch[1:], []
        old.stop(kill=True)
        workers[i] = _Worker(ctx, budget, numeric)
        if rest:
            pending.insert(0, rest)

    try:
        for _ in range(min(max(1, jobs), len(pending))):
            workers.append(_Worker(ctx, budget, numeric))
        while True:
            for w in workers:
                if not w.batch and pending:
                    w.give(pending.pop(0), budget)
                    begin(w)
            busy = [w for w in workers if w.batch]
            if not busy:
                return
            soonest = min(w.deadline for w in busy)
            ready = wait([w.conn for w in busy], timeout=max(0.0, soonest - time.monotonic()))
            for i, w in enumerate(workers):
                if not w.batch:
                    continue
                index, case = w.batch[0]
                if w.conn in ready:
                    try:
                        outcome = w.conn.recv()
                    except EOFError:  # the worker died: report it and replace it
                        yield index, crashed(case, f"worker died ({w.proc.exitcode})")
                        renew(i)
                        continue
                    w.batch.pop(0)
                    if isinstance(outcome, CaseAudit):
                        yield index, outcome
                    else:
                        yield index, crashed(case, f"{type(outcome).__name__}: {outcome}")
                    if w.batch:
                        w.start_clock(budget)
                        begin(w)
                elif time.monotonic() >= w.deadline:  # stuck where the timer cannot reach
                    renew(i)
                    yield index, killed(case, w.seconds)
    finally:
        for w in workers:
            w.stop(kill=bool(w.batch))
