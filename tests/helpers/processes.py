"""Processes the tests start and watch: the ``registry`` command line, process groups
and children read from /proc, and killing a group."""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path


def registry_command(db: Path, *args: str) -> list[str]:
    return [sys.executable, "-m", "registry", "--db", str(db), *args]


def _stat(pid: int | str) -> tuple[str, int, int] | None:
    """(state, parent, process group) of a process, from /proc/PID/stat; None if gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    state, ppid, pgrp = text[text.rindex(")") + 2 :].split()[:3]  # the name may hold ")"
    return state, int(ppid), int(pgrp)


def _live() -> Iterator[tuple[int, int, int]]:
    """(pid, parent, process group) of every live (not zombie) process, from /proc."""
    for entry in Path("/proc").glob("[0-9]*"):
        found = _stat(entry.name)
        if found is not None and found[0] not in ("Z", "X"):
            yield int(entry.name), found[1], found[2]


def group_members(pgid: int) -> list[int]:
    """Live (not zombie) processes of a process group."""
    return [pid for pid, _, pgrp in _live() if pgrp == pgid]


def wait_until_gone(pgid: int, timeout: float = 15.0) -> list[int]:
    """Wait for every process of a group to end; return those still alive after ``timeout``."""
    deadline = time.monotonic() + timeout
    while (alive := group_members(pgid)) and time.monotonic() < deadline:
        time.sleep(0.05)
    return alive


def kill_group(pgid: int) -> None:
    try:
        os.killpg(pgid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def children(pid: int) -> list[int]:
    """Live child processes of ``pid``."""
    return [child for child, ppid, _ in _live() if ppid == pid]


def busy(pid: int) -> bool:
    """Whether a process is running on a CPU or runnable (state R), i.e. computing."""
    found = _stat(pid)
    return found is not None and found[0] == "R"


def alive(pid: int) -> bool:
    """Whether a process exists and is not a zombie (one that ended, not yet reaped)."""
    found = _stat(pid)
    return found is not None and found[0] not in ("Z", "X")


#: prctl(2) option: the signal a process gets when the thread that started it ends.
_PR_SET_PDEATHSIG = 1


def dying_with_this_process() -> Callable[[], None] | None:
    """A ``preexec_fn`` for ``subprocess.Popen`` that has the kernel SIGKILL the child
    when this process ends, however it ends (Linux); None elsewhere.

    ``prctl`` is looked up here, before the fork: the child only calls it. The signal
    follows the thread that starts the child: start it from the main thread.
    """
    if not sys.platform.startswith("linux"):
        return None
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    parent = os.getpid()

    def preexec() -> None:
        prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:  # the parent died before the request took effect
            os._exit(1)

    return preexec
