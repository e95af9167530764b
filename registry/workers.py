"""Auditing cases in parallel worker processes that can be killed.

Each case is audited in a child process (forked where the platform allows, so
sympy is not imported again). The parent waits on the children's pipes with a
deadline per case: a child that overruns it (stuck in C code, where the
in-process timer cannot interrupt it) is killed, the case is recorded as
inconclusive, and the next case takes its place.
"""

from __future__ import annotations

import importlib
import multiprocessing as mp
import os
import time
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import wait

import sympy as sp

from .audit import audit_case, count_checks
from .budget import Budget
from .model import Case, CaseAudit, CheckResult, Verdict


def default_jobs() -> int:
    """Worker processes by default: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


#: sympy modules imported on first use deep inside integration and solving: imported
#: once in the parent, so that forked workers do not each pay for them.
_LAZY_SYMPY = (
    "sympy.integrals.heurisch",
    "sympy.integrals.manualintegrate",
    "sympy.integrals.risch",
    "sympy.polys.polymatrix",
    "sympy.sets.setexpr",
    "sympy.physics.units",
)


def _preload() -> None:
    for name in _LAZY_SYMPY:
        importlib.import_module(name)


def _context():
    methods = mp.get_all_start_methods()
    return mp.get_context("fork" if "fork" in methods else "spawn")


def estimated_cost(case: Case) -> int:
    """A rough size of the work a case needs: its expressions' operation counts, with
    families of arbitrary functions weighted up. Used to start the largest cases first."""
    exprs = [*case.system.torque, case.system.potential, *(c.expression for c in case.claims)]
    return sum(sp.count_ops(e.expr) for e in exprs) + 100 * len(case.functions)


def _serve(conn, budget: Budget, numeric: bool) -> None:
    """A worker: audit each case received until told to stop (None)."""
    while True:
        try:
            case = conn.recv()
        except EOFError:
            return
        if case is None:
            return
        try:
            conn.send(audit_case(case, budget=budget, numeric=numeric))
        except BaseException as exc:  # report, never hang the parent
            conn.send(exc)


class _Worker:
    """A long-lived audit process (its sympy caches stay warm from case to case)."""

    def __init__(self, ctx, budget: Budget, numeric: bool):
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_serve, args=(child, budget, numeric), daemon=True)
        self.proc.start()
        child.close()
        self.task: tuple[int, float, float] | None = None  # (index, deadline, seconds)
        self.torque: tuple | None = None  # of the last case, whose work it has cached

    def give(self, index: int, case: Case, seconds: float) -> None:
        self.conn.send(case)
        self.task = (index, time.monotonic() + seconds, seconds)
        self.torque = _torque(case)

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


def _next(pending: list[tuple[int, Case]], torque: tuple | None) -> int:
    """Which pending case a worker takes: the largest with the torque of its last case
    (its family and sympy caches are warm for it), else the largest."""
    for i in range(len(pending) - 1, -1, -1):
        if _torque(pending[i][1]) == torque:
            return i
    return -1


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
    budget: Budget,
    started: Callable[[Case], None] | None = None,
    numeric: bool = False,
) -> Iterator[tuple[int, CaseAudit]]:
    """Audit ``cases`` in up to ``jobs`` processes; yield (index, audit) as each finishes.

    A worker that overruns its case's deadline is killed and replaced by a new one.
    """
    ctx = _context()
    _preload()
    # largest first, so that no long case starts last while the other workers idle
    pending = sorted(enumerate(cases), key=lambda item: estimated_cost(item[1]))
    workers = [_Worker(ctx, budget, numeric) for _ in range(min(max(1, jobs), len(cases)))]
    try:
        while True:
            for w in workers:
                if w.task is None and pending:
                    index, case = pending.pop(_next(pending, w.torque))
                    if started is not None:
                        started(case)
                    w.give(index, case, budget.case_deadline(count_checks(case)))
            busy = [w for w in workers if w.task is not None]
            if not busy:
                return
            soonest = min(w.task[1] for w in busy)
            ready = wait([w.conn for w in busy], timeout=max(0.0, soonest - time.monotonic()))
            for i, w in enumerate(workers):
                if w.task is None:
                    continue
                index, deadline, seconds = w.task
                if w.conn in ready:
                    w.task = None
                    try:
                        outcome = w.conn.recv()
                    except EOFError:  # the worker died: report it and replace it
                        yield index, crashed(cases[index], f"worker died ({w.proc.exitcode})")
                        w.stop(kill=True)
                        workers[i] = _Worker(ctx, budget, numeric)
                        continue
                    if isinstance(outcome, CaseAudit):
                        yield index, outcome
                    else:
                        yield index, crashed(cases[index], f"{type(outcome).__name__}: {outcome}")
                elif time.monotonic() >= deadline:  # stuck where the timer cannot reach
                    w.stop(kill=True)
                    workers[i] = _Worker(ctx, budget, numeric)
                    yield index, killed(cases[index], seconds)
    finally:
        for w in workers:
            w.stop(kill=w.task is not None)
