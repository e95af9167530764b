"""The child's side of running work elsewhere: the one loop that serves calls, the
parent-death rule every child obeys, and ``Failure``, the record of a call that has no
result.

A child calls ``fn`` on each item it is given, in turn, and sends each result back
through a pipe as soon as it is done (``("ok", value)``, or ``("error", text)`` when
``fn`` raised). The local worker pool (``local``: long-lived workers, batch after
batch) and the child interpreters of Dask tasks (``children``: one batch) both run it.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

#: Failure kinds, and what each means.
FAILURES = {
    "killed": "the call overran its deadline; its child process was killed",
    "crashed": "the child process died without answering (a signal, or an exit)",
    "error": "the call raised an exception",
    "lost": "the cluster could not run the call (its workers kept dying, or it failed)",
}


@dataclass(frozen=True)
class Failure:
    """Why a call has no result (``kind`` is a key of ``FAILURES``).

    ``seconds`` is the deadline a killed call overran; ``exitcode`` that of a crashed
    child (negative: the signal that ended it, as in ``multiprocessing``); ``worker``
    the address of the Dask worker where it happened, when known.
    """

    kind: str
    reason: str
    seconds: float | None = None
    exitcode: int | None = None
    worker: str | None = None


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


def serve_items(fn: Callable[[Any], Any], items: Sequence[Any], conn: Any) -> bool:
    """``fn`` on each item in turn, each result sent as soon as it is done; False when
    the other end has stopped listening."""
    for item in items:
        try:
            message = ("ok", fn(item))
        except BaseException as exc:  # report, never hang the parent
            message = ("error", f"{type(exc).__name__}: {exc}")
        try:
            conn.send(message)
        except (BrokenPipeError, ConnectionError):
            return False  # the parent has stopped waiting
        except Exception as exc:  # a result that cannot be pickled
            conn.send(("error", f"result cannot be sent back: {type(exc).__name__}: {exc}"))
    return True


def serve(
    conn: Any, fn: Callable[[Any], Any], parent: int, items: Sequence[Any] | None = None
) -> None:
    """The one child loop: serve ``items`` (a Dask task's child's batch), or else each batch
    received on ``conn`` until told to stop (None) or the pipe closes.

    SIGALRM works here (this is the child's main thread); SIGTERM ends the child at
    once; Ctrl-C is the parent's to handle; the child never outlives ``parent``."""
    die_with_parent(parent)
    signal.pthread_sigmask(signal.SIG_SETMASK, [])
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if items is not None:
        serve_items(fn, items, conn)
        return
    while True:
        try:
            batch = conn.recv()
        except EOFError:
            return
        if batch is None or not serve_items(fn, batch, conn):
            return
