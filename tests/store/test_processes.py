"""The process running an audit: identified by host, pid and start time, so that a pid
reused by a later process is not mistaken for the one that ran the audit."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from registry.store import processes


def test_this_process_is_identified_by_host_pid_and_start_time():
    host, pid, started = processes.this_process()
    assert (host, pid) == (socket.gethostname(), os.getpid())
    if Path("/proc").is_dir():
        assert started == processes.process_started(pid) is not None
    assert not processes.process_gone(host, pid, started)


def test_a_process_that_has_ended_is_gone():
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    assert processes.process_gone(socket.gethostname(), child.pid, "1")


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="start times come from /proc")
def test_a_reused_pid_is_not_the_process_that_ran_the_audit():
    host, pid, started = processes.this_process()
    assert processes.process_gone(host, pid, str(int(started) + 1))


def test_runs_without_a_pid_count_as_ended_and_other_hosts_are_left_alone():
    assert processes.process_gone(socket.gethostname(), None, None)
    assert not processes.process_gone("another-host.invalid", 1, "1")
