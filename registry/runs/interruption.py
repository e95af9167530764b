"""A run's interruption: SIGTERM and SIGINT end a run as Ctrl-C does, never in the
middle of a database session.

The audit records its run as interrupted when a KeyboardInterrupt reaches it; a signal
that arrives while the store is in a session (``Store.busy``) is held until the session
has ended (``Store.on_idle``), so that no transaction or connection is left half done.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager

from ..store.database import Store


@contextmanager
def interruptible(store: Store) -> Iterator[None]:
    """SIGTERM ends an audit like Ctrl-C (its run is recorded as interrupted), but never
    in the middle of a database session: a signal arriving there takes effect when the
    session has ended, so that no transaction or connection is left half done."""
    pending: list[int] = []

    def stop(signum, frame):
        if store.busy:
            pending.append(signum)
        else:
            raise KeyboardInterrupt(f"signal {signum}")

    def idle():
        if pending:
            signum = pending.pop()
            pending.clear()
            raise KeyboardInterrupt(f"signal {signum}")

    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGTERM, signal.SIGINT)}
    store.on_idle = idle
    try:
        yield
    finally:
        store.on_idle = None
        for sig, handler in previous.items():
            signal.signal(sig, handler)
