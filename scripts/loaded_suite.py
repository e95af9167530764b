"""The test suite on a busy machine: the README's test command (``python -m pytest``: the
default selection, in one worker per core, pyproject.toml's addopts), run while busy
processes (pure-Python loops) keep the machine's load at three times its cores by default.

A test that holds only on a quiet machine (a tight wall-clock bound, a file read before
it is complete) fails here. The load is held, not guessed: every two seconds the script
counts the runnable processes and starts or stops busy ones, so that the suite's own
processes plus the busy ones make the load asked for. The busy processes and pytest die
with this script however it ends (the registry's parent-death rule; pytest's own
watchdog then stops what the tests started).

Usage: python scripts/loaded_suite.py [--load L] [-- PYTEST ARGUMENTS]
  e.g. python scripts/loaded_suite.py
       python scripts/loaded_suite.py --load 4 -- tests/distributed -x
       python scripts/loaded_suite.py -- -m "slow and not serial"  # CI's slow step
       python scripts/loaded_suite.py -- -n 0 -m serial  # and its serial one
Prints the load held (the 1-minute load average, sampled each minute), pass/fail and
counts, and the duration; exits with pytest's status.
Nothing here is a test: run it by hand, before a release or after touching timings.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: ``python -c _TIED PID COMMAND...``: ends when PID (this script) ends, however it ends
#: (the registry's parent-death rule), then becomes COMMAND.
_TIED = (
    "import os, sys\n"
    "from registry.execution.serving import die_with_parent\n"
    "die_with_parent(int(sys.argv[1]))\n"
    "os.execvp(sys.argv[2], sys.argv[2:])\n"
)

#: A busy process: computes forever, one core's worth.
BUSY = [sys.executable, "-c", "while True: sum(i * i for i in range(1000))"]


def tied(command: list[str]) -> list[str]:
    """``command``, started so that it dies with this script (the kernel's parent-death
    signal survives the exec)."""
    return [sys.executable, "-c", _TIED, str(os.getpid()), *command]


#: Seconds between two looks at the load; looks averaged to decide (half a minute).
LOOK_EVERY = 2.0
LOOKS = 15


def runnable() -> int:
    """Processes running or waiting for a core now, this script not counted (Linux)."""
    with open("/proc/loadavg") as f:
        return int(f.read().split()[3].split("/")[0]) - 1


class Load:
    """Busy processes, as many as the load asked for needs beside everything else."""

    def __init__(self, target: float, most: int) -> None:
        self.target, self.most = target, most
        self.busy: list[subprocess.Popen] = []
        self.looks: list[int] = []  # the other runnable processes, at each look
        self.cpu = 0.0

    def adjust(self) -> None:
        # each look counts the others at that moment: a window of totals would lag
        # behind a change of busy processes, and the count would swing
        self.looks = (self.looks + [runnable() - len(self.busy)])[-LOOKS:]
        others = statistics.fmean(self.looks)
        want = max(0, min(self.most, round(self.target - others)))
        while len(self.busy) < want:
            self.busy.append(subprocess.Popen(tied(BUSY), cwd=ROOT, stdin=subprocess.DEVNULL))
        while len(self.busy) > want:
            self.cpu += _kill(self.busy.pop())

    def stop(self) -> float:
        """Stop every busy process; the CPU seconds they used, all told."""
        while self.busy:
            self.cpu += _kill(self.busy.pop())
        return self.cpu


def _kill(proc: subprocess.Popen) -> float:
    """Kill a busy process; the CPU seconds it used."""
    proc.kill()
    _, _, usage = os.wait4(proc.pid, 0)
    proc.returncode = -signal.SIGKILL
    return usage.ru_utime + usage.ru_stime


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


def run(command: list[str], load: Load) -> tuple[int, list[float]]:
    """pytest's exit status, and the 1-minute load average seen each minute meanwhile."""
    proc = subprocess.Popen(tied(command), cwd=ROOT)
    seen: list[float] = []
    next_sample = time.monotonic() + 60
    while True:
        load.adjust()
        try:
            return proc.wait(timeout=LOOK_EVERY), seen
        except subprocess.TimeoutExpired:
            pass
        if time.monotonic() >= next_sample:
            seen.append(os.getloadavg()[0])
            next_sample += 60


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    cores = os.cpu_count() or 1
    parser.add_argument(
        "--load",
        type=float,
        default=3.0 * cores,
        help=f"the load to hold, in runnable processes (default 3 x {cores} cores)",
    )
    parser.add_argument("pytest_args", nargs="*", help="arguments for pytest (after --)")
    args = parser.parse_args()
    if not sys.platform.startswith("linux"):
        parser.error("the load is read from /proc/loadavg: Linux only")

    with tempfile.TemporaryDirectory(prefix="loaded-suite-") as tmp:
        junit = Path(tmp) / "junit.xml"
        command = [sys.executable, "-m", "pytest", f"--junitxml={junit}", *args.pytest_args]
        print(f"{cores} cores, holding a load of {args.load:g}; load average before: "
              f"{os.getloadavg()[0]:.1f}")  # fmt: skip
        print("running:", " ".join(command[2:]), flush=True)
        load = Load(args.load, most=4 * max(1, round(args.load)))
        started = time.monotonic()
        seen: list[float] = []
        try:
            status, seen = run(command, load)
        except KeyboardInterrupt:
            status = 130
        finally:
            seconds = time.monotonic() - started
            seen.append(os.getloadavg()[0])
            busy_cpu = load.stop()
        found = counts(junit)

    passed = found["tests"] - found["failures"] - found["errors"] - found["skipped"]
    print()
    print(f"loaded suite: {'PASS' if status == 0 else 'FAIL'} (pytest exit status {status})")
    print(f"  {passed} passed, {found['failures']} failed, {found['errors']} errors, "
          f"{found['skipped']} skipped")  # fmt: skip
    print(f"  duration {seconds:.0f} s; load average {min(seen):.1f}-{max(seen):.1f} "
          f"(mean {statistics.fmean(seen):.1f}, {len(seen)} looks: each minute and at the end); "
          f"the busy processes used {busy_cpu:.0f} CPU seconds")  # fmt: skip
    return status


if __name__ == "__main__":
    sys.exit(main())
