"""Processes the tests start and watch: the ``registry`` command line, process groups
and children read from /proc, killing a group, and a thread caught in the middle of an
import (the state in which a fork is unsafe)."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from tests.helpers.clocks import HANG


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


#: ``python -c _TIED PID COMMAND...``: asks the kernel (prctl PR_SET_PDEATHSIG = 1) to
#: SIGKILL this process when the thread that started it ends, checks that PID is still
#: its parent, then becomes COMMAND (the request survives exec).
_TIED = (
    "import ctypes, os, signal, sys; "
    "ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0); "
    "os.getppid() == int(sys.argv[1]) or os._exit(1); "
    "os.execvp(sys.argv[2], sys.argv[2:])"
)


def dying_with_this_process(command: list[str]) -> list[str]:
    """``command`` started so that the kernel SIGKILLs it when this process ends, however
    it ends (Linux; ``command`` as it is elsewhere).

    No Python runs in the forked child before exec (a ``preexec_fn`` would, which is
    unsafe where other threads run): a small interpreter makes the request, then
    becomes ``command``. The signal follows the thread that starts the child: start it
    from the main thread.
    """
    if not sys.platform.startswith("linux"):
        return command
    return [sys.executable, "-I", "-S", "-c", _TIED, str(os.getpid()), *command]


def descendants(pid: int) -> list[int]:
    """Live processes below ``pid``: its children, theirs, and so on."""
    found, below = [], children(pid)
    while below:
        found += below
        below = [grandchild for child in below for grandchild in children(child)]
    return found


def import_named(name: str) -> object:
    """Imports the module ``name`` and returns the ``VALUE`` it defines."""
    import importlib

    return importlib.import_module(name).VALUE  # type: ignore[attr-defined]


@contextmanager
def another_thread_importing(directory: Path) -> Iterator[str]:
    """While inside, another thread of this process is in the middle of importing a new
    module (it takes 3 s); yields the module's name (``import_named`` gives 42).

    That thread holds the module's import lock: a process forked now inherits the lock
    without the thread, and waits for ever the first time it needs the module.
    """
    name = f"slow_import_{os.getpid()}_{time.monotonic_ns()}"
    (directory / f"{name}.py").write_text("import time\ntime.sleep(3)\nVALUE = 42\n")
    sys.path.insert(0, str(directory))
    importing = threading.Thread(target=import_named, args=(name,))
    importing.start()
    try:
        # a module is in sys.modules from the start of its import: the thread is inside
        deadline = time.monotonic() + HANG
        while name not in sys.modules and time.monotonic() < deadline:
            time.sleep(0.01)
        yield name
    finally:
        importing.join()
        sys.modules.pop(name, None)
        sys.path.remove(str(directory))
