"""Processes the tests start and watch: the ``registry`` command line, process groups
and children read from /proc, and killing a group."""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path


def registry_command(db: Path, *args: str) -> list[str]:
    return [sys.executable, "-m", "registry", "--db", str(db), *args]


def group_members(pgid: int) -> list[int]:
    """Live (not zombie) processes of a process group, from /proc."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        state, _ppid, pgrp = text[text.rindex(")") + 2 :].split()[:3]
        if int(pgrp) == pgid and state not in ("Z", "X"):
            found.append(int(stat.parent.name))
    return found


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
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        state, ppid = text[text.rindex(")") + 2 :].split()[:2]
        if int(ppid) == pid and state not in ("Z", "X"):
            found.append(int(stat.parent.name))
    return found


def busy(pid: int) -> bool:
    """Whether a process is running on a CPU or runnable (state R), i.e. computing."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return text[text.rindex(")") + 2 :].split()[0] == "R"
