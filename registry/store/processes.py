"""The process that runs an audit: identified by host, pid and the pid's start time,
so that a run left ``running`` by a process that has died can be told from a live one
(``Store`` marks such runs ``interrupted`` when it opens the database).
"""

from __future__ import annotations

import os
import socket
from pathlib import Path


def this_process() -> tuple[str, int, str | None]:
    """(host, pid, start time) of the running process, recorded with each audit run."""
    return socket.gethostname(), os.getpid(), process_started(os.getpid())


def process_started(pid: int) -> str | None:
    """When process ``pid`` started, in the kernel's clock ticks since boot (Linux), else None.

    With the pid it identifies a process: a pid reused by a later process differs here.
    """
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = stat[stat.rindex(")") + 2 :].split()  # after "pid (command) "
    return None if fields[0] in ("Z", "X") else fields[19]  # a zombie has died


def process_gone(host: str | None, pid: int | None, started: str | None) -> bool:
    """Whether the process that ran an audit has certainly ended: it ran on this host
    and no live process has its pid and start time. Runs from before the schema
    recorded processes (no pid) count as ended."""
    if pid is None:
        return True
    if host != socket.gethostname():
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # alive, another user's
        pass
    now = process_started(pid)
    if started is not None and Path("/proc").is_dir():
        return now != started
    return False
