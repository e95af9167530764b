"""Bounds on the time a test's work takes that hold on a busy machine.

A bound against a runaway computation is a bound on the CPU time the work used
(``cpu_bound``): other processes competing for the cores slow the wall clock, not the
work's own CPU time. The block is also interrupted when it overruns (a profiling timer,
which counts this process's CPU time), so that a guard that no longer works fails the
test instead of hanging it. Waiting (a sleep, a blocked read, another process) uses no
CPU time: such a bound stays on the wall clock, an order of magnitude above the
expected time (``HANG``), so that only a real hang exceeds it, and where the wait might
never end, the test stops waiting (``within``).
"""

from __future__ import annotations

import signal
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

import pytest

from registry.execution.time_budget import TimeBudget

T = TypeVar("T")

#: Seconds of wall clock after which waiting for something counts as a hang.
HANG = 60.0

#: An audit's time budgets that only a hang exceeds: for a test that asserts a verdict
#: (the default budgets, 5 s per check, are wall clock, which a busy machine slows).
PATIENT = TimeBudget(check=HANG, corrections=5 * HANG, margin=HANG)
#: The same budgets as options of ``registry audit``.
PATIENT_OPTIONS = ("--budget", f"{PATIENT.check:g}", "--corrections-budget",
                   f"{PATIENT.corrections:g}")  # fmt: skip


class CpuTime:
    """The CPU time a ``cpu_bound`` block used, known when the block ends."""

    seconds: float = 0.0


@contextmanager
def cpu_bound(seconds: float) -> Iterator[CpuTime]:
    """Fail the test if the block uses more than ``seconds`` of this process's CPU time
    (all its threads, user and system); interrupt it when it does.

    The interruption is a profiling timer's signal, handled between two Python
    instructions: code stuck in one long C call is caught when it returns.
    """
    used = CpuTime()
    started = time.process_time()

    def overrun(signum, frame):
        pytest.fail(f"the work used more than {seconds:g} s of CPU time: a runaway")

    main = threading.current_thread() is threading.main_thread()
    if main:
        previous = signal.signal(signal.SIGPROF, overrun)
        signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield used
    finally:
        if main:
            signal.setitimer(signal.ITIMER_PROF, 0)
            signal.signal(signal.SIGPROF, previous)
        used.seconds = time.process_time() - started
    assert used.seconds < seconds, f"the work used {used.seconds:.2f} s of CPU time"


def within(seconds: float, fn: Callable[[], T]) -> T:
    """``fn()``, or the test fails once ``seconds`` of wall clock have passed (a hang).

    For work that waits on other processes (a cluster, a pool), where this process's CPU
    time says nothing: ``fn`` runs in a daemon thread, left behind if it never returns.
    """
    outcome: list[tuple[bool, Any]] = []

    def run() -> None:
        try:
            outcome.append((True, fn()))
        except BaseException as exc:  # handed to the test's thread
            outcome.append((False, exc))

    thread = threading.Thread(target=run, name="bounded-wait", daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        pytest.fail(f"still waiting after {seconds:g} s of wall clock: a hang")
    done, value = outcome[0]
    if not done:
        raise value
    return value
