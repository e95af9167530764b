"""Worker processes never outlive the audit that started them, however it dies.

A real ``registry audit`` runs in its own process group with two workers busy in
long checks; SIGKILL of the audit process alone (not its group) must take every
worker with it within about a second.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import sympy as sp
from test_crashes import group_members, kill_group, registry_command

#: A claim that is identically zero, so no probe refutes it, but whose proof must expand
#: powers of a six-variable linear form (minutes of work): a worker busy in a long check.
SLOW_CASE = """\
id = "slow-{n}"
title = "A claim whose proof takes minutes"

[source]
citation = "Test, Nowhere (2026)"

[parameters]
k = "real"

[system]
inertia = ["1", "2", "3"]
potential = "gamma3"
torque = ["0", "0", "{n}"]  # cases of different torques go to different workers

[[claims]]
label = "I"
kind = "casimir"
expression = "s + ({linear})**40 - ({square})**20"
"""


def slow_case(n: int) -> str:
    """The text of a case whose claim's proof takes minutes (see SLOW_CASE)."""
    linear = sp.sympify(f"gamma1 + gamma2 + gamma3 + M1 + k + {n}")
    return SLOW_CASE.format(n=n, linear=linear, square=sp.expand(linear**2))


#: How long the workers may survive the audit process (the issue's bound: one second).
SURVIVAL = 1.0


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


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_sigkill_of_the_audit_takes_its_workers_with_it_mid_check(tmp_path):
    cases = tmp_path / "cases"
    cases.mkdir()
    for n in (1, 2):
        (cases / f"slow-{n}.toml").write_text(slow_case(n), encoding="utf-8")
    db = tmp_path / "r.sqlite"
    added = subprocess.run(registry_command(db, "add", str(cases)), capture_output=True)
    assert added.returncode == 0, added.stderr
    proc = subprocess.Popen(
        registry_command(db, "audit", "--jobs", "2", "--budget", "600"),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        deadline = time.monotonic() + 60
        workers: list[int] = []
        while time.monotonic() < deadline:
            workers = children(proc.pid)
            if len(workers) == 2 and all(busy(w) for w in workers):
                break
            time.sleep(0.05)
        assert len(workers) == 2, "the audit did not start two workers"
        time.sleep(1.0)  # well inside the long proof
        assert proc.poll() is None, "the audit ended before it could be killed"
        assert set(workers) <= set(group_members(proc.pid))
        os.kill(proc.pid, signal.SIGKILL)  # the audit process only, not its group
        proc.wait(timeout=10)
        killed = time.monotonic()
        while group_members(proc.pid) and time.monotonic() - killed < SURVIVAL:
            time.sleep(0.02)
        assert group_members(proc.pid) == [], "workers outlived the killed audit"
    finally:
        kill_group(proc.pid)
        proc.wait(timeout=10)
