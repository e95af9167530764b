"""Nothing a test run starts outlives it, however the run ends (SIGKILL included).

``start(pid)`` marks the test process's environment with ``REGISTRY_TEST_RUN=<pid>``
(every process started after that inherits it: Dask schedulers and workers, the
PostgreSQL server, ``registry`` commands and their workers) and starts this module as
a watchdog process in a session of its own. The watchdog waits until the test process
has ended, then stops what it left behind: each PostgreSQL server registered with
``register`` (an immediate shutdown, SIGQUIT to the postmaster, as ``pg_ctl stop -m
immediate`` does), then every process that still carries the mark (SIGKILL), then the
registered directories; then it ends. After a normal run there is nothing left to do.

The watchdog is plain standard-library Python, run as a script: it must start fast and
never import the code under test.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: The environment variable that marks the processes of a test run (its value: the
#: test process's id).
MARK = "REGISTRY_TEST_RUN"

#: The environment variable naming the folder where services are registered.
FOLDER = "REGISTRY_TEST_WATCH"

#: Seconds between two looks at the test process.
INTERVAL = 0.1

#: Seconds a PostgreSQL server gets to shut down before its processes are killed.
SHUTDOWN = 10.0

#: Seconds the watchdog keeps killing marked processes (new ones may be forked meanwhile).
SWEEP = 30.0


# ---------------------------------------------------------------- in the test process


def start(pid: int | None = None) -> bool:
    """Mark this process's environment and start the watchdog on process ``pid`` (this
    one by default); False where /proc cannot be read (not Linux)."""
    if not Path("/proc/self/environ").exists():
        return False
    pid = os.getpid() if pid is None else pid
    folder = tempfile.mkdtemp(prefix=f"registry-test-run-{pid}-")
    os.environ[MARK] = str(pid)
    os.environ[FOLDER] = folder
    # the process started here forks the watchdog and ends at once (awaited): the
    # watchdog, which must outlive this process, is not its child
    subprocess.run(
        [sys.executable, "-I", "-S", __file__, str(pid), folder],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        start_new_session=True,  # a kill of the test's process group spares it
        check=True,
    )
    return True


def register(kind: str, **info: str) -> Path | None:
    """Tell the watchdog of a service to stop when the run ends: ``postgres`` with
    ``data`` (its data directory) and ``root`` (a directory to remove), or any other kind
    with a ``root`` alone (a folder to remove: a Dask scratch folder); the returned
    file is removed by ``unregister`` once the service is stopped (None without a
    watchdog). Written aside, then renamed: the watchdog never reads half a file."""
    folder = os.environ.get(FOLDER)
    if not folder or not Path(folder).is_dir():
        return None
    fd, aside = tempfile.mkstemp(dir=folder, prefix=f".{kind}-", suffix=".part")
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        json.dump({"kind": kind, **info}, out)
    file = Path(aside).with_name(Path(aside).name[1:].removesuffix(".part") + ".json")
    os.replace(aside, file)
    return file


def unregister(file: Path | None) -> None:
    if file is not None:
        file.unlink(missing_ok=True)


# ---------------------------------------------------------------- reading /proc


def started(pid: int) -> str | None:
    """The start time of a process (with its id, a name no later process takes), or None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()
    return None if fields[0] in ("Z", "X") else fields[19]


def marked(value: str, exclude: set[int] = frozenset()) -> list[int]:
    """Live processes whose environment carries ``REGISTRY_TEST_RUN=value``."""
    needle = f"{MARK}={value}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) in exclude:
            continue
        try:
            environ = (entry / "environ").read_bytes()
        except OSError:
            continue
        if needle in environ.split(b"\0") and started(int(entry.name)):
            found.append(int(entry.name))
    return found


# ---------------------------------------------------------------- the watchdog


def _stop_postgres(data: str) -> None:
    """Immediate shutdown of the server of ``data`` (SIGQUIT to its postmaster), then
    SIGKILL if it is still there after SHUTDOWN seconds."""
    try:
        pid = int((Path(data) / "postmaster.pid").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return
    when = started(pid)
    if when is None:
        return
    try:
        os.kill(pid, signal.SIGQUIT)
    except OSError:
        return
    deadline = time.monotonic() + SHUTDOWN
    while started(pid) == when and time.monotonic() < deadline:
        time.sleep(INTERVAL)
    if started(pid) == when:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def clean_up(pid: int, folder: Path) -> None:
    """Stop what the test run ``pid`` left: registered servers, marked processes,
    registered directories, then the folder of registrations."""
    services = []
    for file in sorted(folder.glob("*.json")):
        try:
            services.append(json.loads(file.read_text(encoding="utf-8")))
        except (OSError, ValueError):
            continue
    for service in services:
        if service.get("kind") == "postgres":
            _stop_postgres(service["data"])
    deadline = time.monotonic() + SWEEP
    me = {os.getpid()}
    while (left := marked(str(pid), me)) and time.monotonic() < deadline:
        for other in left:
            try:
                os.kill(other, signal.SIGKILL)
            except OSError:
                pass
        time.sleep(INTERVAL)
    for service in services:
        if service.get("root"):
            shutil.rmtree(service["root"], ignore_errors=True)
    shutil.rmtree(folder, ignore_errors=True)


def watch(pid: int, folder: Path) -> None:
    """Wait for process ``pid`` to end, then clean up after it."""
    for sig in (signal.SIGINT, signal.SIGHUP, signal.SIGTERM):
        signal.signal(sig, signal.SIG_IGN)  # the terminal's Ctrl-C is the test run's
    when = started(pid)
    while when is not None and started(pid) == when:
        time.sleep(INTERVAL)
    clean_up(pid, folder)


if __name__ == "__main__":
    if os.fork() == 0:  # the watchdog; its parent ends at once
        watch(int(sys.argv[1]), Path(sys.argv[2]))
