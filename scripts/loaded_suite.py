"""The test suite on a busy machine: the README's test command, run while busy processes
(pure-Python loops, three per core by default) compete with it for the cores.

A test that holds only on a quiet machine (a tight wall-clock bound, a file read before
it is complete) fails here. The busy processes are started and stopped by this script,
and die with it however it ends (a parent-death signal on Linux).

Usage: python scripts/loaded_suite.py [--load N] [-- PYTEST ARGUMENTS]
  e.g. python scripts/loaded_suite.py
       python scripts/loaded_suite.py --load 4 -- tests/distributed -x
Prints the load, pass/fail and counts, and the duration; exits with pytest's status.
Nothing here is a test: run it by hand, before a release or after touching timings.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: prctl(2) option: the signal a process gets when its parent ends (Linux).
_PR_SET_PDEATHSIG = 1

#: A busy process: computes forever, one core's worth.
BUSY = "while True: sum(i * i for i in range(1000))"


def dying_with_this_process():
    """A ``preexec_fn`` that has the kernel kill the child when this script ends (Linux)."""
    if not sys.platform.startswith("linux"):
        return None
    prctl = ctypes.CDLL(None, use_errno=True).prctl
    parent = os.getpid()

    def preexec() -> None:
        prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:
            os._exit(1)

    return preexec


def start_load(n: int) -> list[subprocess.Popen]:
    return [
        subprocess.Popen(
            [sys.executable, "-c", BUSY],
            stdin=subprocess.DEVNULL,
            preexec_fn=dying_with_this_process(),
        )
        for _ in range(n)
    ]


def stop_load(busy: list[subprocess.Popen]) -> float:
    """Stop the busy processes; the CPU seconds they used."""
    for proc in busy:
        proc.kill()
    used = 0.0
    for proc in busy:
        _, _, usage = os.wait4(proc.pid, 0)
        proc.returncode = -signal.SIGKILL
        used += usage.ru_utime + usage.ru_stime
    return used


def counts(junit: Path) -> dict[str, int]:
    """Tests, failures, errors and skips from pytest's JUnit XML report."""
    found = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    try:
        root = ET.parse(junit).getroot()
    except (OSError, ET.ParseError):
        return found
    for suite in root.iter("testsuite"):
        for key in found:
            found[key] += int(suite.get(key, 0))
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    cores = os.cpu_count() or 1
    parser.add_argument(
        "--load", type=int, default=3 * cores, help=f"busy processes (default 3 x {cores} cores)"
    )
    parser.add_argument("pytest_args", nargs="*", help="arguments for pytest (after --)")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="loaded-suite-") as tmp:
        junit = Path(tmp) / "junit.xml"
        command = [sys.executable, "-m", "pytest", f"--junitxml={junit}", *args.pytest_args]
        print(f"{cores} cores, {args.load} busy processes; load average before: "
              f"{os.getloadavg()[0]:.1f}")  # fmt: skip
        print("running:", " ".join(command[2:]), flush=True)
        busy = start_load(args.load)
        started = time.monotonic()
        try:
            status = subprocess.call(command, cwd=ROOT)
        except KeyboardInterrupt:
            status = 130
        finally:
            seconds = time.monotonic() - started
            load = os.getloadavg()[0]
            busy_cpu = stop_load(busy)
        found = counts(junit)

    passed = found["tests"] - found["failures"] - found["errors"] - found["skipped"]
    print()
    print(f"loaded suite: {'PASS' if status == 0 else 'FAIL'} (pytest exit status {status})")
    print(f"  {passed} passed, {found['failures']} failed, {found['errors']} errors, "
          f"{found['skipped']} skipped")  # fmt: skip
    print(f"  duration {seconds:.0f} s; load average at the end {load:.1f}; "
          f"the busy processes used {busy_cpu:.0f} CPU seconds")  # fmt: skip
    return status


if __name__ == "__main__":
    sys.exit(main())
