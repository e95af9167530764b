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

import pytest

from tests.helpers.processes import busy, children, group_members, kill_group, registry_command
from tests.helpers.samples import slow_case

#: How long the workers may survive the audit process (the issue's bound: one second).
SURVIVAL = 1.0


# a bound of one second on the wall clock, and two workers that must both be seen running:
# alone on the machine, not beside another xdist worker's computations
@pytest.mark.serial
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
