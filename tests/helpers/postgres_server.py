"""A throwaway PostgreSQL server for the tests, started from the installed binaries.

``PostgresServer.start()`` finds ``initdb`` and ``pg_ctl`` (on PATH, in ``pg_config
--bindir``, or in the Debian package's ``/usr/lib/postgresql/*/bin``), creates a cluster
in a temporary directory with the superuser ``registry`` and trust authentication, and
starts it listening on a Unix socket in that directory only (no TCP port), with fsync
off: its data is thrown away. PostgreSQL refuses to run as root, so under root (as in
CI) the directory belongs to an unprivileged user, ``postgres`` (which the Debian package
creates) or, when that user is missing, one created for the purpose, and the binaries
run as that user through ``runuser``. ``stop()`` stops the server and removes the
directory; it is also called at exit, whatever happened before. A run that ends
without exit handlers (SIGKILL, a CI time limit) leaves both to the test run's
watchdog (``watchdog.py``), with which the server is registered from its start.

Each test gets a database of its own (``create_database``), named by a URL of the form
docs/operations.md gives: ``postgresql+psycopg://registry@/NAME?host=/socket/dir``.

Servers started side by side (one per xdist worker, or another checkout's test run on
the same machine) share nothing: each has its own folder, data directory and socket
(``.s.PGSQL.5432`` in that folder); with no TCP port there is no port to collide on, and
PostgreSQL picks a free System V shared-memory key for each.
"""

from __future__ import annotations

import atexit
import glob
import itertools
import os
import pwd
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from tests.helpers import watchdog

#: The cluster's superuser, which the tests connect as.
SUPERUSER = "registry"

#: The user that owns the cluster when the tests run as root and ``postgres`` is missing.
FALLBACK_OWNER = "registry-postgres"

#: Settings of the throwaway cluster: a socket in its own directory and no TCP port; no
#: fsync (its data is thrown away); enough connections for concurrent test processes.
SETTINGS = {
    "listen_addresses": "''",
    "fsync": "off",
    "synchronous_commit": "off",
    "full_page_writes": "off",
    "max_connections": "200",
    "shared_buffers": "32MB",
}


class ServerUnavailable(RuntimeError):
    """No PostgreSQL server could be started here; the message says why."""


def find_bindir() -> Path | None:
    """The folder holding ``initdb``, ``pg_ctl`` and ``postgres``, or None."""
    candidates = []
    initdb = shutil.which("initdb")
    if initdb:
        candidates.append(Path(initdb).parent)
    pg_config = shutil.which("pg_config")
    if pg_config:
        try:
            out = subprocess.run(
                [pg_config, "--bindir"], capture_output=True, text=True, timeout=30
            ).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            out = ""
        if out:
            candidates.append(Path(out))

    def version(path: str) -> tuple[int, ...]:
        return tuple(int(n) for n in re.findall(r"\d+", path))

    debian = sorted(glob.glob("/usr/lib/postgresql/*/bin"), key=version, reverse=True)
    candidates += [Path(p) for p in debian]
    for folder in candidates:
        if all((folder / name).is_file() for name in ("initdb", "pg_ctl", "postgres")):
            return folder
    return None


def _owner() -> str | None:
    """The unprivileged user that runs the server when we are root (None otherwise)."""
    if os.geteuid() != 0:
        return None
    for name in ("postgres", FALLBACK_OWNER):
        try:
            pwd.getpwnam(name)
            return name
        except KeyError:
            continue
    useradd = shutil.which("useradd") or "/usr/sbin/useradd"
    done = subprocess.run(
        [useradd, "--system", "--no-create-home", "--shell", "/usr/sbin/nologin", FALLBACK_OWNER],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise ServerUnavailable(
            f"running as root, no user 'postgres', and 'useradd {FALLBACK_OWNER}' failed: "
            f"{done.stderr.strip()}"
        )
    return FALLBACK_OWNER


class PostgresServer:
    """A running throwaway cluster (see the module docstring)."""

    def __init__(self, bindir: Path, root: Path, owner: str | None):
        self.bindir, self.root, self.owner = bindir, root, owner
        self.data = root / "data"
        self.socket_dir = root
        self._names = itertools.count(1)
        self._running = False
        self._watched: Path | None = None  # the registration with the run's watchdog

    # ------------------------------------------------------------------ lifecycle

    @classmethod
    def start(cls, label: str = "") -> PostgresServer:
        """Create and start a cluster (in a new folder, named with ``label``: the xdist
        worker that started it); ServerUnavailable says why when that fails."""
        try:
            import psycopg  # noqa: F401  (the driver the registry uses)
        except ImportError as err:
            raise ServerUnavailable(
                "psycopg is not installed (pip install -e '.[postgres]')"
            ) from err
        bindir = find_bindir()
        if bindir is None:
            raise ServerUnavailable(
                "initdb and pg_ctl were not found (on PATH, in pg_config --bindir, or in "
                "/usr/lib/postgresql/*/bin); install the Debian package 'postgresql'"
            )
        owner = _owner()
        root = Path(tempfile.mkdtemp(prefix=f"registry-pg-{label}-" if label else "registry-pg-"))
        server = cls(bindir, root, owner)
        atexit.register(server.stop)
        server._watched = watchdog.register("postgres", data=str(server.data), root=str(root))
        try:
            if owner is not None:
                shutil.chown(root, user=owner)
            server._initdb()
            server._pg_ctl_start()
        except BaseException:
            server.stop()
            raise
        return server

    def _run(self, *command: str | Path, timeout: float = 120) -> subprocess.CompletedProcess:
        args = [str(c) for c in command]
        if self.owner is not None:
            runuser = shutil.which("runuser") or "/usr/sbin/runuser"
            args = [runuser, "-u", self.owner, "--", *args]
        return subprocess.run(
            args, capture_output=True, text=True, timeout=timeout, cwd=self.root,
            stdin=subprocess.DEVNULL,
        )  # fmt: skip

    def _initdb(self) -> None:
        done = self._run(
            self.bindir / "initdb", "-D", self.data, "--auth=trust", "-U", SUPERUSER,
            "--encoding=UTF8", "--locale=C", "--no-sync",
        )  # fmt: skip
        if done.returncode != 0:
            raise ServerUnavailable(f"initdb failed: {(done.stderr or done.stdout).strip()}")
        settings = {**SETTINGS, "unix_socket_directories": f"'{self.socket_dir}'"}
        with (self.data / "postgresql.conf").open("a", encoding="utf-8") as conf:
            conf.write("\n# the registry's tests\n")
            conf.writelines(f"{key} = {value}\n" for key, value in settings.items())

    def _pg_ctl_start(self) -> None:
        log = self.root / "server.log"
        done = self._run(
            self.bindir / "pg_ctl", "-D", self.data, "-l", log, "-w", "-t", "60", "start"
        )
        if done.returncode != 0:
            try:
                detail = log.read_text(encoding="utf-8", errors="replace").strip()
            except OSError:
                detail = ""
            raise ServerUnavailable(
                f"pg_ctl start failed: {(done.stderr or done.stdout).strip()} {detail}".strip()
            )
        self._running = True

    def stop(self) -> None:
        """Stop the server (at once: its data is thrown away) and remove its directory."""
        if self._running:
            self._running = False
            try:
                self._run(self.bindir / "pg_ctl", "-D", self.data, "-m", "immediate", "stop")
            except (OSError, subprocess.SubprocessError):
                pass
        shutil.rmtree(self.root, ignore_errors=True)
        watchdog.unregister(self._watched)
        self._watched = None

    # ------------------------------------------------------------------ databases

    def url(self, database: str, user: str = SUPERUSER) -> str:
        """The SQLAlchemy URL of a database of this server, through its socket."""
        return f"postgresql+psycopg://{user}@/{database}?host={self.socket_dir}"

    def connect(self, database: str = "postgres", user: str = SUPERUSER):
        """A psycopg connection in autocommit mode (for CREATE DATABASE and the like)."""
        import psycopg

        return psycopg.connect(
            host=str(self.socket_dir), dbname=database, user=user, autocommit=True
        )

    def execute(self, *statements: str, database: str = "postgres") -> None:
        """Run SQL statements, each in its own transaction, as the superuser."""
        with self.connect(database) as conn:
            for sql in statements:
                conn.execute(sql)

    def new_name(self, hint: str = "test") -> str:
        """A database name not used before in this cluster (at most 63 characters)."""
        slug = re.sub(r"[^a-z0-9]+", "_", hint.lower()).strip("_")[:40] or "db"
        return f"{slug}_{next(self._names)}"

    def create_database(self, hint: str = "test", template: str | None = None) -> str:
        """A new, empty database (or a copy of ``template``); returns its URL."""
        name = self.new_name(hint)
        source = f' TEMPLATE "{template}"' if template else " TEMPLATE template0"
        self.execute(f'CREATE DATABASE "{name}"{source} STRATEGY FILE_COPY')
        return self.url(name)

    def missing_database(self, hint: str = "missing") -> str:
        """The URL of a database that does not exist (and was never created)."""
        return self.url(self.new_name(hint))
