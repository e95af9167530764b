"""Time budgets: no check may run unbounded.

Inside a process, a check runs under ``time_limit``, an interval timer whose
signal interrupts sympy's Python code; the check then becomes
``inconclusive: time budget exceeded``. Code stuck in C (a huge integer
product in gmpy, say) cannot be interrupted that way: the audit's worker
processes (``local``, ``children``) are killed from outside when their case overruns.
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, replace

from .. import settings

#: Seconds between further signals once a block's time is up, until it ends: Python drops
#: an exception raised where it cannot propagate (a garbage collector's weakref callback,
#: a ``__del__``), and a signal that lands there would otherwise be lost.
AGAIN = 0.5


class BudgetExceeded(BaseException):
    """Raised inside a check whose time is up.

    A BaseException, so that sympy's own ``except Exception`` clauses cannot swallow it.
    """


@dataclass(frozen=True)
class TimeBudget:
    """Seconds allowed to one check, to the corrections of one case, and the margin a
    worker gets before it is killed."""

    check: float = settings.DEFAULT_CHECK_SECONDS
    corrections: float = settings.DEFAULT_CORRECTIONS_SECONDS
    margin: float = 10.0

    def case_deadline(self, n_checks: int) -> float:
        """Seconds after which a worker auditing a case with ``n_checks`` checks is killed."""
        return self.check * n_checks + self.corrections + self.margin


#: Budgets used when none is given: a few seconds per check.
DEFAULT_BUDGET = TimeBudget()


def default_budget(
    environ: Mapping[str, str] | None = None,
    *,
    check: float | None = None,
    corrections: float | None = None,
) -> TimeBudget:
    """The budget of a run: ``check`` and ``corrections`` where given (a command's
    options), else ``$REGISTRY_BUDGET`` and ``$REGISTRY_CORRECTIONS_BUDGET`` where set
    (``settings``: for a slow or busy machine, or a test suite that asserts verdicts, not
    speed), else the built-in defaults (SettingError for a variable that holds no
    positive number of seconds).

    >>> default_budget({"REGISTRY_BUDGET": "60"})
    TimeBudget(check=60.0, corrections=20.0, margin=10.0)
    >>> default_budget({}, check=2)
    TimeBudget(check=2, corrections=20.0, margin=10.0)
    """
    return replace(
        DEFAULT_BUDGET,
        check=check or settings.check_seconds(environ),
        corrections=corrections or settings.corrections_seconds(environ),
    )


@contextmanager
def time_limit(seconds: float | None, *, cpu: bool = False) -> Iterator[None]:
    """Raise BudgetExceeded in this thread after ``seconds`` (no limit if None or 0) of
    wall clock, or with ``cpu`` of this process's processor time (what a benchmark on a
    shared machine counts: the load does not eat it).

    A block that the signal interrupted always ends in BudgetExceeded, also when code
    inside it caught the exception and went on (sympy's ``except Exception`` around a C
    extension's callback, where the exception arrives as a SystemError): what it then
    computed came after its time. Once the time is up the signal comes again every
    ``AGAIN`` seconds until the block ends, so that one Python dropped (raised in a
    garbage collector's callback) does not let the block run on; not while a
    BudgetExceeded is being handled (a ``finally`` stopping worker processes on the way
    out), which it would cut short.

    Blocks nest: an inner block ends no later than the enclosing one's time, and the
    enclosing block's timer goes on after it (a stage with its own budget inside an
    analysis with a budget of its own).

    Timers are per process and only the main thread receives the signal; elsewhere
    (a notebook's worker thread) the block runs without a limit.
    """
    if not seconds or threading.current_thread() is not threading.main_thread():
        yield
        return
    sig, timer = (
        (signal.SIGPROF, signal.ITIMER_PROF) if cpu else (signal.SIGALRM, signal.ITIMER_REAL)
    )
    fired: list[bool] = []
    over: list[bool] = []

    def interrupt(signum, frame):
        if over:  # a signal that outlived its block (its cleanup was cut short): stop it
            signal.setitimer(timer, 0)
            return
        if fired and isinstance(sys.exc_info()[1], BudgetExceeded):
            return  # a cleanup on the way out (a pool stopping its workers): let it end
        fired.append(True)
        raise BudgetExceeded

    previous = signal.signal(sig, interrupt)
    outer, interval = signal.getitimer(timer)  # what an enclosing block has left (0: none)
    clock = time.process_time if cpu else time.monotonic
    begun = clock()
    try:
        # armed inside the try: a signal at once (a budget of 1e-9 s) still meets the
        # cleanup below, and no timer is left running after the block
        signal.setitimer(timer, min(seconds, outer) if outer else seconds, AGAIN)
        yield
        if fired:  # the BudgetExceeded was caught inside the block, and it went on
            raise BudgetExceeded
    except SystemError as err:
        # the signal arrived in Python code a C extension called back (symengine asking a
        # sympy object for its parts): Python reports it as that call's SystemError,
        # caused by the BudgetExceeded; the time is up all the same
        if _budget_cause(err):
            raise BudgetExceeded from err
        raise
    finally:
        over.append(True)
        signal.setitimer(timer, 0)
        signal.signal(sig, previous)
        if outer:  # the enclosing block's timer goes on: what it has left, or at once
            signal.setitimer(timer, max(outer - (clock() - begun), 1e-6), interval)


def _budget_cause(err: BaseException) -> bool:
    """Whether ``err`` was caused, directly or down its chain, by a BudgetExceeded."""
    seen: set[int] = set()
    cause: BaseException | None = err
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, BudgetExceeded):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False
