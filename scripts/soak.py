"""Soak test: a group at work on one registry for minutes, with processes killed at random.

N client processes (``scripts/soak_client.py``, default 8) work on one registry for T
minutes (default 10): a database of a PostgreSQL server started here in a temporary
folder as the tests start theirs (``tests/helpers/postgres_server.py``), or the one
``--db`` names; or, with ``--backend sqlite``, one SQLite file (WAL). Each client adds
new versions of catalog cases, audits (locally, and on a Dask cluster started here: a
``dask scheduler`` and ``--workers`` ``dask worker`` processes with nannies), records
searches of the small test families, surveys, builds the static site and reads
DataFrames, and journals every write it saw acknowledged and the latency of every read.

Every ``--kill-every`` seconds (at random around it) the soak kills, in turn, a client
(SIGKILL, at whatever it is doing; a new client takes its place) or a Dask worker
(SIGKILL; its nanny starts a new one, or the soak restarts the worker). At the end the
clients finish what they are doing, the services are stopped, and the soak checks and
prints (``soak_checks.py``):

1. every write a client saw acknowledged is present exactly once;
2. nothing is half written: ``verify_db`` is clean, no run is left running, and a run
   that is not complete was interrupted by a kill;
3. the verdicts and searches equal those of a quiet serial run of the same work, done
   afterwards in a fresh registry;
4. no process is left: clients, their workers, the Dask processes and the server (every
   process the soak started carries a mark in its environment, searched in /proc);
5. throughput (operations per minute by kind) and the median and 95th percentile of the
   read latency under that load, with the load average during the run.

It exits with status 1 when a check fails (0 otherwise). Whatever ends it (SIGKILL
included), nothing it started outlives it: the processes die with it (the registry's
parent-death rule) and a watchdog (``tests/helpers/watchdog.py``) stops the server.

Usage: python scripts/soak.py [--clients 8] [--minutes 10] [--backend postgres|sqlite]
           [--db URL|PATH] [--seed 0] [--kill-every 30] [--workers 2] [--json FILE] [--keep]
  e.g. python scripts/soak.py --backend sqlite --minutes 2 --clients 4 --kill-every 15
Nothing here is a test (tests/test_soak.py runs a short one): run it by hand, on a
release, or after touching the store, the runs or the execution layer.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(Path(__file__).resolve().parent)]

import soak_checks  # noqa: E402  (beside this script)
import soak_client  # noqa: E402

#: The environment variable that marks every process of one soak (value: its token).
MARK = "REGISTRY_SOAK_RUN"
#: Seconds between two looks at the clients, the workers and the load.
TICK = 0.5
#: Seconds between two samples of the load average.
LOAD_EVERY = 15.0
#: Seconds a nanny may take to bring a killed worker back before the soak restarts it.
RESTART_WITHIN = 90.0
#: Seconds the clients get, after the deadline, to finish what they are doing.
FINISH_WITHIN = 600.0

#: ``python -c _TIED PID COMMAND...``: ends when PID (the soak) ends, however it ends (the
#: registry's parent-death rule, which survives the exec), then becomes COMMAND.
_TIED = (
    "import os, sys\n"
    "from registry.execution.serving import die_with_parent\n"
    "die_with_parent(int(sys.argv[1]))\n"
    "os.execvp(sys.argv[2], sys.argv[2:])\n"
)


def tied(command: list[str]) -> list[str]:
    return [sys.executable, "-c", _TIED, str(os.getpid()), *command]


def environment() -> dict[str, str]:
    """The children's environment: this one, the package under test first on the path,
    without a scheduler, a database or Dask TLS settings of the machine."""
    path = os.environ.get("PYTHONPATH", "")
    env = {
        k: v
        for k, v in os.environ.items()
        if not k.startswith("DASK_DISTRIBUTED__COMM")
        and k not in ("REGISTRY_SCHEDULER", "REGISTRY_DB")
    }
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), path) if p)
    return env


def log(message: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {message}", flush=True)


# ---------------------------------------------------------------------- processes


def marked(token: str) -> list[int]:
    """Live processes (not zombies) whose environment carries this soak's mark."""
    from tests.helpers.watchdog import started

    needle = f"{MARK}={token}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            environ = (entry / "environ").read_bytes()
        except OSError:
            continue
        if needle in environ.split(b"\0") and started(int(entry.name)):
            found.append(int(entry.name))
    return found


def command_line(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()[:160]
    except OSError:
        return "(gone)"


def stop(procs: list[subprocess.Popen], timeout: float = 20) -> None:
    """SIGTERM, then SIGKILL for those still there after ``timeout`` seconds."""
    for proc in procs:
        if proc.poll() is None:
            proc.terminate()
    for proc in procs:
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def running_task(worker: int) -> bool:
    """Whether a Dask worker runs a registry task (in a child interpreter of its own)."""
    import psutil

    try:
        children = psutil.Process(worker).children()
        return any("resource_tracker" not in " ".join(c.cmdline()) for c in children)
    except psutil.Error:
        return False


class DaskProcesses:
    """A ``dask scheduler`` and ``n`` ``dask worker`` processes, each with a nanny that
    starts a new worker when its worker dies (one thread each, on 127.0.0.1)."""

    def __init__(self, where: Path, n: int):
        self.where, self.n = where, n
        self.file = where / "scheduler.json"
        self.scheduler: subprocess.Popen | None = None
        self.nannies: list[subprocess.Popen] = []
        self.address = ""
        self.restarted = 0  # workers restarted by the soak (their nanny was gone)

    def _start(self, name: str, *args: str) -> subprocess.Popen:
        script = Path(sys.executable).parent / "dask"
        command = [str(script)] if script.exists() else [sys.executable, "-m", "dask"]
        with open(self.where / f"{name}.log", "ab") as out:
            return subprocess.Popen(
                tied([*command, *args]),
                stdout=out,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                env=environment(),
            )

    def _worker(self, i: int) -> subprocess.Popen:
        return self._start(
            f"worker-{i}",
            "worker",
            "--scheduler-file",
            str(self.file),
            "--host",
            "127.0.0.1",
            "--nworkers",
            "1",
            "--nthreads",
            "1",
            "--no-dashboard",
            "--death-timeout",
            "60",
            "--name",
            f"soak-worker-{i}",
        )

    def start(self) -> None:
        from distributed import Client

        self.where.mkdir(parents=True, exist_ok=True)
        self.scheduler = self._start(
            "scheduler",
            "scheduler",
            "--host",
            "127.0.0.1",
            "--port",
            "0",
            "--dashboard-address",
            "127.0.0.1:0",
            "--scheduler-file",
            str(self.file),
        )
        deadline = time.monotonic() + 120
        while True:
            try:
                self.address = json.loads(self.file.read_text())["address"]
                break
            except (OSError, ValueError, KeyError):
                if self.scheduler.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError((self.where / "scheduler.log").read_text()) from None
                time.sleep(0.2)
        self.nannies = [self._worker(i) for i in range(self.n)]
        with Client(self.address, timeout=60) as client:
            client.wait_for_workers(self.n, timeout=300)

    def worker_of(self, nanny: subprocess.Popen) -> int | None:
        """The pid of the worker process a nanny runs (None: none at the moment)."""
        import psutil

        try:
            for child in psutil.Process(nanny.pid).children():
                if "spawn_main" in " ".join(child.cmdline()):
                    return child.pid
        except psutil.Error:
            return None
        return None

    def busy(self) -> bool:
        """Whether some worker is running a task."""
        return any((w := self.worker_of(n)) and running_task(w) for n in self.nannies)

    def kill_worker(self, rng: random.Random) -> dict[str, Any] | None:
        """SIGKILL the worker process of a nanny drawn at random, one running a task if
        there is one (its task runs in a child process); what was killed."""
        live = [(i, w) for i, n in enumerate(self.nannies) if (w := self.worker_of(n))]
        if not live:
            return None
        busy = [(i, w) for i, w in live if running_task(w)]
        i, pid = rng.choice(busy or live)
        os.kill(pid, signal.SIGKILL)
        return {
            "kind": "worker",
            "worker": f"soak-worker-{i}",
            "pid": pid,
            "slot": i,
            "doing": "a task" if busy else "idle",
        }

    def back(self, slot: int, killed: int) -> bool:
        """Whether slot's nanny runs a new worker (not the killed one)."""
        now = self.worker_of(self.nannies[slot])
        return now is not None and now != killed

    def restart(self, slot: int) -> None:
        """Start the worker of a slot again, nanny and all (its nanny did not)."""
        stop([self.nannies[slot]])
        self.nannies[slot] = self._worker(slot)
        self.restarted += 1

    def stop(self) -> None:
        stop(self.nannies)
        if self.scheduler is not None:
            stop([self.scheduler])


@dataclass
class Slot:
    """One client's place: the process that holds it now and how many held it before."""

    index: int
    proc: subprocess.Popen | None = None
    incarnation: int = 0

    @property
    def name(self) -> str:
        return f"c{self.index}.{self.incarnation}"


@dataclass
class Soak:
    """The running soak: its clients, the cluster, the kills and the loads seen."""

    args: argparse.Namespace
    work: Path
    db: str
    dask: DaskProcesses | None
    deadline: float = 0.0
    slots: list[Slot] = field(default_factory=list)
    kills: list[dict[str, Any]] = field(default_factory=list)
    loads: list[float] = field(default_factory=list)
    exits: list[str] = field(default_factory=list)  # clients that ended on their own too soon
    killed_pids: set[int] = field(default_factory=set)
    pending: list[tuple[float, dict[str, Any]]] = field(default_factory=list)  # worker restarts

    def spawn(self, slot: Slot) -> None:
        slot.incarnation += 1
        journal = self.work / "journal" / f"{slot.name}.jsonl"
        journal.parent.mkdir(parents=True, exist_ok=True)
        logs = self.work / "logs"
        logs.mkdir(exist_ok=True)
        command = [
            sys.executable,
            str(ROOT / "scripts" / "soak_client.py"),
            "--db",
            self.db,
            "--journal",
            str(journal),
            "--work",
            str(self.work / "clients" / slot.name),
            "--deadline",
            repr(self.deadline),
            "--parent",
            str(os.getpid()),
            "--name",
            slot.name,
            "--seed",
            str(self.args.seed),
        ]
        if self.dask is not None:
            command += ["--scheduler", self.dask.address]
        if self.args.cases is not None:
            command += ["--cases", str(self.args.cases)]
        with open(logs / f"{slot.name}.log", "wb") as out:
            slot.proc = subprocess.Popen(
                command,
                stdout=out,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                env=environment(),
                cwd=ROOT,
            )

    def kill_client(self, rng: random.Random) -> dict[str, Any] | None:
        live = [s for s in self.slots if s.proc is not None and s.proc.poll() is None]
        if not live:
            return None
        slot = rng.choice(live)
        assert slot.proc is not None
        journals = soak_checks.Journals.read(self.work / "journal")
        doing = journals.last_begun(slot.name)
        slot.proc.kill()
        slot.proc.wait()
        self.killed_pids.add(slot.proc.pid)
        killed = {"kind": "client", "client": slot.name, "pid": slot.proc.pid, "doing": doing}
        if time.time() < self.deadline:
            self.spawn(slot)
        return killed

    def run(self) -> None:
        rng = random.Random(f"{self.args.seed}/kills")
        self.deadline = time.time() + 60 * self.args.minutes
        self.slots = [Slot(i) for i in range(self.args.clients)]
        for slot in self.slots:
            self.spawn(slot)
        kinds = ["client", "worker"] if self.dask is not None else ["client"]
        turn = rng.randrange(len(kinds))
        limit = float("inf") if self.args.kills is None else self.args.kills
        every = self.args.kill_every
        next_kill = time.time() + (every * rng.uniform(0.5, 1.5) if every > 0 else float("inf"))
        next_load = time.time() + LOAD_EVERY
        while time.time() < self.deadline:
            time.sleep(TICK)
            now = time.time()
            for slot in self.slots:
                if slot.proc is not None and slot.proc.poll() is not None and now < self.deadline:
                    self.exits.append(f"{slot.name} ended with status {slot.proc.returncode}")
                    log(f"client {slot.name} ended on its own ({slot.proc.returncode}); respawned")
                    self.spawn(slot)
            self.watch_restarts()
            if now >= next_load:
                self.loads.append(os.getloadavg()[0])
                next_load += LOAD_EVERY
            if now >= next_kill and len(self.kills) < limit:
                kind = kinds[turn % len(kinds)]
                assert self.dask is not None or kind == "client"
                if kind == "worker" and not self.dask.busy() and now < next_kill + every / 2:
                    continue  # a worker running a task is worth waiting for, a little
                done = self.kill_client(rng) if kind == "client" else self.dask.kill_worker(rng)
                if done is not None:
                    turn += 1
                    done["t"] = now
                    self.kills.append(done)
                    what = done.get("doing") or done.get("worker") or ""
                    who = done.get("client", "")
                    log(f"killed {done['kind']} {who} (pid {done['pid']}): {what}")
                    if kind == "worker":
                        self.pending.append((now, done))
                next_kill = now + every * rng.uniform(0.5, 1.5)
        log("deadline: the clients finish what they are doing")
        self.finish()

    def state(self, load_before: tuple[float, float, float]) -> dict[str, Any]:
        """What the checks need of the run, beside the journals and the database."""
        return {
            "command": " ".join([Path(sys.executable).name, *sys.argv]),
            "backend": self.args.backend if self.args.db is None else self.args.db,
            "clients": self.args.clients,
            "minutes": self.args.minutes,
            "kills": self.kills,
            "killed_pids": sorted(self.killed_pids),
            "exits": self.exits,
            "loads": self.loads,
            "load_before": load_before[0],
        }

    def watch_restarts(self) -> None:
        """Note when a killed worker is back; restart it if its nanny has not in time."""
        assert self.dask is not None or not self.pending
        for item in list(self.pending):
            when, done = item
            if self.dask.back(done["slot"], done["pid"]):
                done["back_after"] = round(time.time() - when, 1)
                done["restarted_by"] = "nanny"
                self.pending.remove(item)
            elif time.time() - when > RESTART_WITHIN:
                self.dask.restart(done["slot"])
                done["restarted_by"] = "soak"
                self.pending.remove(item)

    def finish(self) -> None:
        """Wait for the clients to end after the deadline; kill those that do not."""
        until = time.time() + FINISH_WITHIN
        for slot in self.slots:
            assert slot.proc is not None
            try:
                slot.proc.wait(timeout=max(1.0, until - time.time()))
            except subprocess.TimeoutExpired:
                slot.proc.kill()
                slot.proc.wait()
                self.killed_pids.add(slot.proc.pid)
                self.kills.append(
                    {
                        "kind": "client",
                        "client": slot.name,
                        "pid": slot.proc.pid,
                        "doing": "(still working at the end)",
                        "t": time.time(),
                    }
                )
            if slot.proc.returncode not in (0, -signal.SIGKILL):
                self.exits.append(f"{slot.name} ended with status {slot.proc.returncode}")
        while self.pending:  # a worker killed near the end: back, or restarted by the soak
            self.watch_restarts()
            time.sleep(TICK)


# ---------------------------------------------------------------------- the run


def family_ids() -> set[str]:
    """The ids of the test families (searched by ``discover``; the catalog's cases by
    ``survey``)."""
    return {soak_client.case_id(p) for p in soak_client.FAMILIES.glob("*.toml")}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=8, help="client processes (default 8)")
    parser.add_argument("--minutes", type=float, default=10.0, help="how long (default 10)")
    parser.add_argument("--backend", choices=["postgres", "sqlite"], default="postgres")
    parser.add_argument(
        "--db", default=None, help="an empty database (URL or SQLite path) instead of a new one"
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--kill-every", type=float, default=30.0, help="seconds between kills, on average (0: none)"
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=2,
        help="Dask workers (default 2; 0: no cluster, no Dask audits)",
    )
    parser.add_argument(
        "--cases",
        type=int,
        default=None,
        help="start with this many of the catalog's cases (default: all)",
    )
    parser.add_argument(
        "--kills",
        type=int,
        default=None,
        help="kill this many processes at most (default: no limit)",
    )
    parser.add_argument("--json", default=None, help="write the figures and checks here")
    parser.add_argument("--keep", action="store_true", help="keep the working folder")
    parser.add_argument(
        "--recheck",
        metavar="FOLDER",
        default=None,
        help="only check again the soak kept in FOLDER (its journals, state and database)",
    )
    args = parser.parse_args(argv)
    if not sys.platform.startswith("linux"):
        parser.error("the soak reads /proc: Linux only")
    if args.recheck:
        return recheck(args, Path(args.recheck))

    from tests.helpers import watchdog

    watchdog.start()  # the server and every process stopped however the soak ends
    token = f"{os.getpid()}-{time.time_ns()}"
    os.environ[MARK] = token  # after the watchdog: it must not carry the mark
    work = Path(tempfile.mkdtemp(prefix="registry-soak-"))
    started_at, loads_before = time.time(), os.getloadavg()
    log(
        f"soak: {args.clients} clients, {args.minutes:g} min, {args.backend}, "
        f"kill every ~{args.kill_every:g} s, seed {args.seed}; folder {work}"
    )

    server = None
    dask: DaskProcesses | None = None
    soak: Soak | None = None
    outcomes: list[soak_checks.Outcome] = []
    state: dict[str, Any] = {}
    try:
        import registry

        if args.db is not None:
            db = args.db
        elif args.backend == "postgres":
            from tests.helpers.postgres_server import PostgresServer

            server = PostgresServer.start()
            db = server.create_database("soak")
        else:
            db = str(work / "registry.sqlite")
        with registry.open(db) as reg:
            if len(reg.runs()) or len(reg.cases()):
                parser.error(f"{db}: the soak needs an empty database (its checks read every row)")
            added = reg.add(*soak_client.catalog_files(args.cases))
            engine = reg.verify_db().engine
        log(f"database {db}: the catalog's {len(added)} cases added; {engine}")

        if args.workers > 0:
            dask = DaskProcesses(work / "dask", args.workers)
            dask.start()
            log(f"Dask scheduler {dask.address} with {args.workers} workers (nannies)")

        soak = Soak(args, work, db, dask)
        soak.run()
        state = soak.state(loads_before)
        if dask is not None:
            dask.stop()
        log("clients and cluster stopped; checking")
        if server is not None:  # for --recheck, once the server is gone
            with registry.open(db, create=False) as reg:
                reg.copy_to(work / "soak.sqlite")
        (work / "state.json").write_text(json.dumps(state, indent=1), encoding="utf-8")
        outcomes = run_checks(work, db, state)
    finally:
        if soak is not None:
            for slot in soak.slots:
                if slot.proc is not None and slot.proc.poll() is None:
                    slot.proc.kill()
                    slot.proc.wait()
        if dask is not None:
            dask.stop()
        if server is not None:
            server.stop()
    outcomes.append(no_process_left(token))
    return conclude(args, work, state, outcomes, time.time() - started_at)


def recheck(args: argparse.Namespace, work: Path) -> int:
    """The checks again on a soak's kept folder: its database (the copy of a server's),
    journals and state; the processes are not looked at again."""
    started = time.time()
    state = json.loads((work / "state.json").read_text(encoding="utf-8"))
    copy = work / "soak.sqlite"
    db = str(copy if copy.exists() else work / "registry.sqlite")
    log(f"checking again the soak of {work} on {db}")
    return conclude(args, work, state, run_checks(work, db, state), time.time() - started)


def run_checks(work: Path, db: str, state: dict[str, Any]) -> list[soak_checks.Outcome]:
    """Checks 1, 2, 3 and the clients' errors, on the database ``db`` and the journals and
    state kept in ``work``; a check that breaks is a failed check, with its traceback."""
    import traceback

    import registry

    journals = soak_checks.Journals.read(work / "journal")
    outcomes = []
    try:
        with registry.open(db, create=False) as reg:  # marks the runs of killed clients
            snap = soak_checks.Snapshot.read(reg.store)
            outcomes.append(soak_checks.acknowledged(snap, journals))
            outcomes.append(soak_checks.sound(reg, snap, set(state["killed_pids"]), journals))
        log("the serial run of the same work, in a fresh registry")
        serial = work / "serial.sqlite"
        serial.unlink(missing_ok=True)
        quiet, seconds = soak_checks.replay(snap, serial, family_ids(), *_budgets())
        outcomes.append(soak_checks.serial(snap, quiet, seconds))
    except Exception:
        broken = soak_checks.Outcome("x", "the checks ran to their end")
        broken.fail(traceback.format_exc())
        outcomes.append(broken)
    errors = journals.errors()
    clients = soak_checks.Outcome("e", "no operation of a client failed, none ended early")
    for e in errors:
        clients.fail(f"{e['client']} {e['op']}: {e['error'][:300]}")
    for ended in state["exits"]:
        clients.fail(ended)
    clients.counts = {"failed operations": len(errors), "clients ended early": len(state["exits"])}
    outcomes.append(clients)
    return outcomes


def conclude(
    args: argparse.Namespace,
    work: Path,
    state: dict[str, Any],
    outcomes: list[soak_checks.Outcome],
    seconds: float,
) -> int:
    """Print the report (and write it as JSON with --json); the exit status."""
    found = soak_checks.figures(soak_checks.Journals.read(work / "journal"), state["minutes"])
    loads = state["loads"]
    report = {
        "command": state["command"],
        "backend": state["backend"],
        "clients": state["clients"],
        "minutes": state["minutes"],
        "cores": os.cpu_count(),
        "load": {
            "mean": statistics.fmean(loads) if loads else None,
            "min": min(loads, default=None),
            "max": max(loads, default=None),
            "before": state["load_before"],
            "samples": len(loads),
        },
        "kills": state["kills"],
        "figures": found,
        "checks": {
            o.name: {
                "title": o.title,
                "passed": o.passed,
                "counts": o.counts,
                "problems": o.problems,
            }
            for o in outcomes
        },
        "seconds": seconds,
    }
    print_report(report, outcomes, found)
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2, default=str), encoding="utf-8")
    passed = all(o.passed for o in outcomes)
    if passed and not args.keep and not args.recheck:
        shutil.rmtree(work, ignore_errors=True)
    else:
        print(f"working folder kept: {work} (python scripts/soak.py --recheck {work})")
    return 0 if passed else 1


def _budgets() -> tuple[float, float, float]:
    return soak_client.CHECK_SECONDS, soak_client.CORRECTIONS_SECONDS, soak_client.SEARCH_SECONDS


def no_process_left(token: str) -> soak_checks.Outcome:
    """(4): nothing the soak started is still running (a little time allowed for the
    server's processes and the workers' children to end)."""
    import psutil

    out = soak_checks.Outcome("4", "no process left (clients, workers, scheduler, server)")
    deadline = time.monotonic() + 30
    while (left := marked(token)) and time.monotonic() < deadline:
        time.sleep(0.2)
    children = psutil.Process().children(recursive=True)
    for pid in left:
        out.fail(f"left running: {pid} {command_line(pid)}")
    for child in children:
        if child.pid not in left:
            out.fail(f"a child of the soak is left: {child.pid} {command_line(child.pid)}")
    out.counts = {"processes left": len(left) + len(children)}
    return out


def print_report(report: dict[str, Any], outcomes, found) -> None:
    print()
    print(
        f"soak: {report['clients']} clients for {report['minutes']:g} min on "
        f"{report['backend']}, {report['cores']} cores"
    )
    print(f"command: {report['command']}")
    load = report["load"]
    if load["samples"]:
        print(
            f"load average (1 min) during the run: mean {load['mean']:.1f}, "
            f"{load['min']:.1f}-{load['max']:.1f} ({load['samples']} samples; "
            f"{load['before']:.1f} before the soak started)"
        )
    clients = [k for k in report["kills"] if k["kind"] == "client"]
    workers = [k for k in report["kills"] if k["kind"] == "worker"]
    doing = ", ".join(
        f"{d}: {n}"
        for d, n in sorted(_count(str(k.get("doing") or "idle") for k in clients).items())
    )
    busy = sum(k.get("doing") == "a task" for k in workers)
    restarted = _count(str(k.get("restarted_by", "nobody")) for k in workers)
    print(
        f"kills: {len(clients)} clients (SIGKILL; doing {doing or '-'}), "
        f"{len(workers)} Dask workers (SIGKILL; {busy} running a task; restarted by "
        f"{', '.join(f'{w}: {n}' for w, n in restarted.items()) or '-'})"
    )
    for line in soak_checks.figure_lines(found):
        print(line)
    print("checks:")
    for outcome in outcomes:
        for line in outcome.lines():
            print("  " + line)
    passed = all(o.passed for o in outcomes)
    print(f"soak: {'PASS' if passed else 'FAIL'} in {report['seconds']:.0f} s")


def _count(items) -> dict[str, int]:
    counts: dict[str, int] = {}
    for item in items:
        counts[item] = counts.get(item, 0) + 1
    return counts


if __name__ == "__main__":
    sys.exit(main())
