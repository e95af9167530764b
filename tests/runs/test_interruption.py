"""A run's interruption (``registry/runs/interruption.py``): SIGTERM ends a run as Ctrl-C
does, but a signal that arrives inside a database session waits for its end."""

from __future__ import annotations

import os
import signal

import pytest

from registry.runs.interruption import interruptible
from registry.store.database import Store


def test_sigterm_outside_a_session_interrupts_at_once(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    with pytest.raises(KeyboardInterrupt, match="signal 15"):
        with interruptible(store):
            os.kill(os.getpid(), signal.SIGTERM)
    assert store.on_idle is None
    store.close()


def test_a_signal_inside_a_session_waits_for_the_session_to_end(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    reached: list[str] = []
    with pytest.raises(KeyboardInterrupt, match="signal 15"):
        with interruptible(store):
            with store.read():
                os.kill(os.getpid(), signal.SIGTERM)
                reached.append("still in the session")
            reached.append("not reached: the session's end interrupts")
    assert reached == ["still in the session"]
    store.close()


def test_the_handlers_before_are_restored(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    with interruptible(store):
        pass
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before
    store.close()
