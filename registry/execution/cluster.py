"""Where the computing runs: a Dask distributed scheduler, for one command.

``--scheduler ADDRESS`` (else the ``REGISTRY_SCHEDULER`` environment variable) names
a running scheduler, ``tcp://HOST:PORT`` (or ``tls://``, ``ws://``, ``wss://``,
``ucx://``), or the JSON scheduler file it wrote (``dask scheduler --scheduler-file
FILE.json``: what the jobs of a batch system share); ``local:N`` starts a
``LocalCluster`` of N worker processes (one thread each, bound to 127.0.0.1, no
dashboard) for the duration of the command and closes it after; ``local`` alone
starts one worker per core. Without either, the local worker pool
(``execution/local.py``) does the work.

>>> parse_scheduler("local:2")
SchedulerAddress(text='local:2', workers=2)
>>> parse_scheduler("127.0.0.1:8786").text
'tcp://127.0.0.1:8786'
>>> parse_scheduler("local:0")
Traceback (most recent call last):
...
registry.errors.SchedulerAddressError: bad Dask scheduler address 'local:0': ...
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Callable, Iterator, Mapping
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any
from urllib.parse import urlsplit

from ..errors import (
    DaskMissingError,
    SchedulerAddressError,
    SchedulerError,
    SchedulerSecurityError,
    SchedulerUnreachableError,
)
from .local import default_jobs

if TYPE_CHECKING:
    from distributed import Client

#: The environment variable read when --scheduler is not given.
SCHEDULER_ENV = "REGISTRY_SCHEDULER"
#: Seconds to wait for a scheduler to answer before the command gives up.
CONNECT_TIMEOUT = 10.0
#: How long a ``local:N`` cluster waits before it closes the nanny of a worker that
#: died and is not back yet (Dask's ``lost-worker-timeout``, 15 s by default, closes
#: it for good): longer than any command runs, since the nanny restarts the worker.
LOST_WORKER_KEPT = "365 days"
#: Protocols of Dask's communication layer that take HOST:PORT.
PROTOCOLS = ("tcp", "tls", "ws", "wss", "ucx")


@dataclass(frozen=True)
class SchedulerAddress:
    """A parsed ``--scheduler``: a scheduler's address, or ``local:N`` (``workers`` = N)."""

    text: str
    workers: int | None = None

    @property
    def local(self) -> bool:
        """Whether the command starts its own LocalCluster."""
        return self.workers is not None


def scheduler_option(option: str | None, environ: Mapping[str, str] | None = None) -> str | None:
    """The scheduler a command should use: ``option`` if given, else $REGISTRY_SCHEDULER,
    else None (the local worker pool). An empty value counts as not given."""
    if option:
        return option
    env = os.environ if environ is None else environ
    return env.get(SCHEDULER_ENV) or None


def parse_scheduler(text: str) -> SchedulerAddress:
    """Check a scheduler address without contacting it; SchedulerAddressError if it is
    neither ``PROTOCOL://HOST:PORT`` (a bare ``HOST:PORT`` means tcp), a scheduler file
    ``*.json`` (the address in it), nor ``local[:N]``."""
    given = text
    text = text.strip()
    if text.endswith(".json"):
        return SchedulerAddress(_address_in(Path(text).expanduser(), given))
    if text == "local":
        return SchedulerAddress("local", default_jobs())
    if text.startswith("local:"):
        count = text.removeprefix("local:")
        if not count.isdigit() or int(count) < 1:
            raise SchedulerAddressError(given, "local:N needs a whole number N >= 1")
        return SchedulerAddress(f"local:{int(count)}", int(count))
    if "://" not in text:
        text = f"tcp://{text}"
    protocol = text.split("://", 1)[0]
    if protocol not in PROTOCOLS:
        raise SchedulerAddressError(given, f"unknown protocol {protocol!r}")
    parts = urlsplit(text)
    try:
        port = parts.port
    except ValueError:
        port = None
    if not parts.hostname or port is None or parts.path or parts.query:
        raise SchedulerAddressError(given, "it needs a host and a port")
    return SchedulerAddress(text)


def _address_in(file: Path, given: str) -> str:
    """The scheduler's address written in a scheduler file, checked like any other."""
    try:
        found = json.loads(file.read_text(encoding="utf-8")).get("address")
    except FileNotFoundError:
        raise SchedulerAddressError(given, "no such scheduler file") from None
    except (OSError, ValueError, AttributeError) as err:
        raise SchedulerAddressError(given, f"not a scheduler file ({err})") from None
    if not isinstance(found, str) or found.endswith(".json") or found.startswith("local"):
        raise SchedulerAddressError(given, "not a scheduler file (no address in it)")
    try:
        return parse_scheduler(found).text
    except SchedulerAddressError as err:
        raise SchedulerAddressError(given, f"its address {found!r}: {err.reason}") from None


def _distributed():
    """The ``distributed`` module; DaskMissingError naming the install command if absent."""
    try:
        import distributed
    except ImportError as err:
        raise DaskMissingError("", err.name or "distributed") from err
    return distributed


@contextmanager
def cluster_client(
    scheduler: str | Client, *, timeout: float = CONNECT_TIMEOUT
) -> Iterator[Client]:
    """A Dask client connected for the duration of the block.

    ``scheduler`` is an address (checked by ``parse_scheduler``), ``local:N``, or a
    ``distributed.Client`` the caller already holds (used as it is, and left open).
    For ``local:N`` a LocalCluster of N worker processes with one thread each is
    started on 127.0.0.1 and closed when the block ends. SchedulerAddressError,
    SchedulerUnreachableError and DaskMissingError are one-line user errors.
    """
    if not isinstance(scheduler, str):
        yield scheduler
        return
    address = parse_scheduler(scheduler)
    try:
        distributed = _distributed()
        from dask.config import set as dask_config
    except (DaskMissingError, ImportError) as err:
        missing = err.missing if isinstance(err, DaskMissingError) else err.name or "dask"
        raise DaskMissingError(scheduler, missing) from err
    with ExitStack() as stack:
        if address.local:
            # a worker is sent only the tasks it can run at once: the tail of a run is
            # shared out evenly, and a worker that dies held no task queued behind
            saturation = {"distributed.scheduler.worker-saturation": 1.0}
            # a worker that died is its nanny's to restart: the cluster must not close
            # that nanny for good because the worker happened to be down (restarting)
            # when Dask's lost-worker timer fired, or the cluster ends with no worker
            kept = {"distributed.deploy.lost-worker-timeout": LOST_WORKER_KEPT}
            stack.enter_context(dask_config({**saturation, **kept}))
            cluster = stack.enter_context(
                distributed.LocalCluster(
                    n_workers=address.workers,
                    threads_per_worker=1,
                    processes=True,
                    host="127.0.0.1",
                    dashboard_address=None,
                    # the scheduler's HTTP endpoint (health, metrics) still starts: on a
                    # free port of 127.0.0.1, not on 8787 where another cluster may be
                    scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                    # Dask's own log lines (a worker's last heartbeat as the cluster closes)
                    # are not the command's output: its errors come back as exceptions
                    silence_logs=logging.CRITICAL,
                )
            )
            client = stack.enter_context(distributed.Client(cluster, timeout=timeout))
        else:
            _check_tls_files(address.text)
            try:
                client = distributed.Client(address.text, timeout=timeout)
            except (OSError, TimeoutError, TypeError, RuntimeError) as err:
                problem = _connection_error(address.text, scheduler, timeout, err)
                if problem is None:
                    raise
                raise problem from err
            stack.enter_context(client)
        yield client


#: Dask's configuration keys of the client's side of TLS, and their environment variables.
TLS_KEYS = {
    "distributed.comm.tls.ca-file": "DASK_DISTRIBUTED__COMM__TLS__CA_FILE",
    "distributed.comm.tls.client.cert": "DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT",
    "distributed.comm.tls.client.key": "DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY",
}
#: What to configure, said once for every TLS error.
TLS_REMEDY = (
    "give this command the cluster's CA certificate and a client certificate and key "
    "signed by that CA, in Dask's configuration ("
    + ", ".join(TLS_KEYS)
    + ") or its environment variables ("
    + ", ".join(TLS_KEYS.values())
    + ")"
)


def _check_tls_files(address: str) -> None:
    """SchedulerSecurityError naming the key when Dask's TLS configuration names a file
    that is not there (Dask itself would only say ``No such file or directory``)."""
    from dask.config import get

    for key, variable in TLS_KEYS.items():
        value = get(key, default=None)
        if value and "-----BEGIN" not in str(value) and not Path(value).expanduser().is_file():
            raise SchedulerSecurityError(
                address,
                f"Dask's TLS configuration {key} (${variable}) names {str(value)!r}, "
                "which is not a readable file",
                TLS_REMEDY,
            )


def _connection_error(
    address: str, given: str, timeout: float, err: BaseException
) -> SchedulerError | None:
    """The one-line error for a client that could not connect to ``address``: TLS that
    does not fit (none configured, a certificate one side does not trust), a scheduler
    that speaks TLS asked for plain TCP, or no answer at all (None: ``err`` is no
    connection problem, a bug to show as it is)."""
    said = str(err)
    lowered = said.lower()
    tls = address.startswith(("tls://", "wss://"))
    if isinstance(err, TypeError) and "ssl_context" in said:
        problem = "it requires TLS, and this command has no TLS configuration"
        return SchedulerSecurityError(address, problem, TLS_REMEDY)
    if isinstance(err, RuntimeError) and "encryption required" in lowered:
        return SchedulerSecurityError(
            address,
            "Dask's configuration requires encryption (distributed.comm.require-encryption) "
            "and the address is not tls://",
            "give the scheduler's tls:// address",
        )
    if isinstance(err, TypeError | RuntimeError):
        return None
    if tls and ("certificate does not match" in lowered or "certificate verify failed" in lowered):
        problem = (
            "its certificate is not signed by the CA this command trusts "
            "(distributed.comm.tls.ca-file)"
        )
        return SchedulerSecurityError(address, problem, TLS_REMEDY)
    if tls and ("ssl" in lowered or "eof occurred" in lowered):
        problem = (
            "it ended the TLS handshake: it does not trust this command's client certificate "
            "(distributed.comm.tls.client.cert and .key)"
        )
        return SchedulerSecurityError(address, problem, TLS_REMEDY)
    if not tls and "connection reset" in lowered:
        return SchedulerUnreachableError(
            given,
            timeout,
            f"{said}; a scheduler that requires TLS is reached at tls://HOST:PORT",
        )
    detail = "" if "Timed out" in said else said  # the timeout says it all
    return SchedulerUnreachableError(given, timeout, detail)


def scheduler_address(client: Client) -> str:
    """The address of the scheduler a connected client talks to (``tcp://HOST:PORT``).

    distributed types ``Client.scheduler`` as optional: it is None until the client
    connects, and ``cluster_client`` hands out connected clients only."""
    scheduler = client.scheduler
    address = scheduler.address if scheduler is not None else None
    if not address:
        raise RuntimeError("the Dask client is not connected to a scheduler")
    return str(address)


def describe(client: Client) -> dict[str, Any]:
    """What a run records of the cluster it used: the scheduler's address, the number of
    workers and threads when it started, and the version of Dask distributed."""
    nthreads = client.nthreads()
    return {
        "address": scheduler_address(client),
        "workers": len(nthreads),
        "threads": sum(nthreads.values()),
        "distributed": _distributed().__version__,
    }


def threads(client: Client) -> int:
    """Worker threads the cluster has now (at least 1: a cluster still starting counts
    as one, and tasks wait for its workers)."""
    return max(1, sum(client.nthreads().values()))


def check_same_code(client: Client, version_of: Callable[[], str]) -> None:
    """SchedulerError unless every worker of the cluster gives the answer this process
    gives to ``version_of()`` (a picklable function): a run records results under this
    process's code version, so its workers must run the same code. Workers that join
    later are not asked, nor one that dies while it is asked (its connection lost: the
    scheduler gives it no task, and the run goes on as when a worker dies later)."""
    from distributed.comm import CommClosedError

    mine = version_of()
    answers = client.run(version_of, on_error="return")
    gone = {w for w, v in answers.items() if isinstance(v, CommClosedError)}
    for worker, answer in answers.items():
        if isinstance(answer, BaseException) and worker not in gone:
            raise answer  # the function failed there, as before
    wrong = {w: v for w, v in answers.items() if w not in gone and v != mine}
    if wrong:
        worker, theirs = sorted(wrong.items())[0]
        others = f" (and {len(wrong) - 1} other worker(s))" if len(wrong) > 1 else ""
        raise SchedulerError(
            scheduler_address(client),
            f"Dask worker {worker}{others} runs registry {theirs}, this command {mine}: "
            "start the workers from the same code, or the run would record their "
            "results under the wrong code version",
        )
