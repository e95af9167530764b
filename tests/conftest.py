"""Shared fixtures: stores (in memory, on disk and on a PostgreSQL server), database
targets for the API and CLI tests, sample cases built in code, and a registry with rows
in every table (built once a session).

The PostgreSQL variants run against a real server that the session starts itself
(``postgres_server``, see ``tests/helpers/postgres_server.py``) the first time a test needs
it, and stops at the end. Where no server can be started they are skipped with the
reason, except in CI (``REGISTRY_CI`` set), where that is a failure.

Under pytest-xdist (``-n auto``, the README's test command) every worker is a test
session of its own: it sets the environment below, starts its own PostgreSQL server
(a socket in a folder of its own, no TCP port), its own Dask clusters (on free ports)
with a Dask scratch folder of its own, its own temporary folders and its own watchdog.
Nothing a test writes is shared between workers; tests that share an expensive fixture
run in one worker (``pytest_collection_modifyitems`` below), and the tests that need the
machine to themselves are marked ``serial`` and run apart, without -n.
"""

from __future__ import annotations

import faulthandler
import hashlib
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import settings

from registry.language import forms
from registry.model import (
    Assumption,
    Case,
    Claim,
    ClaimKind,
    Equation,
    Expression,
    Source,
    System,
)
from registry.store.database import Store
from tests.helpers import watchdog
from tests.helpers.clocks import HANG, PATIENT
from tests.helpers.databases import BACKENDS, POSTGRES, Databases
from tests.helpers.postgres_server import PostgresServer, ServerUnavailable
from tests.helpers.registries import full_registry

# The tests assert verdicts, not speed: every audit given no budget of its own (in this
# process, in the workers, in the ``registry`` processes the tests start, which inherit
# the environment) gets budgets that only a hang exceeds, instead of the wall-clock
# defaults a busy machine runs out of. Tests of the budgets themselves pass theirs.
os.environ.setdefault("REGISTRY_BUDGET", f"{PATIENT.check:g}")
os.environ.setdefault("REGISTRY_CORRECTIONS_BUDGET", f"{PATIENT.corrections:g}")
# Likewise a command waits for another's database lock longer than the 10 s default (a
# whole catalog added on a loaded machine held it for over 30 s); tests of the wait set it.
os.environ.setdefault("REGISTRY_LOCK_TIMEOUT", f"{HANG / 2:g}")
# The catalog's normal forms for identification are kept between runs in a folder of the
# system's temporary folder, never in the user's ~/.cache (entries are named by content
# hash and written aside then renamed, so workers and runs may share it).
os.environ.setdefault("REGISTRY_CACHE", str(Path(tempfile.gettempdir()) / "registry-test-cache"))
# What the command line prints is wrapped to the terminal's width: the tests read it at
# 80 columns (what a pipe gets) wherever they run, a terminal of another width included;
# tests of the width set their own.
os.environ["COLUMNS"] = "80"

# Property tests draw the same examples on every run (a failure is reproducible, and CI
# does not fail at random); HYPOTHESIS_PROFILE=explore draws new ones each run. No
# wall-clock deadline per example (a busy machine would miss it): a test that bounds
# the time of its work bounds the CPU time (tests/helpers/clocks.py).
settings.register_profile("repeatable", derandomize=True, deadline=None)
settings.register_profile("explore", derandomize=False, max_examples=1000, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))


#: This process's Dask scratch folder and its registration with the watchdog.
_dask_scratch: list[tuple[str, Path | None]] = []


def pytest_configure(config):
    """Mark the processes this run starts, and watch it: what a killed run leaves
    behind (servers, Dask processes, commands and their workers) is stopped. Each
    process of the run (each xdist worker) has its own watchdog and Dask scratch folder."""
    watchdog.start()
    _own_dask_scratch(worker_name(config))
    if worker_name(config) == "main":  # the controller, or a run without -n
        os.environ[RUNNING] = tempfile.mkdtemp(prefix="registry-tests-running-")


def worker_name(config) -> str:
    """The xdist worker this process is (``gw0``, ``gw1``, ...), or ``main`` without -n."""
    return getattr(config, "workerinput", {}).get("workerid", "main")


def _own_dask_scratch(worker: str) -> None:
    """Give Dask a scratch folder of this process's own (its workers' spill and lock
    files), instead of the ``dask-scratch-space`` in the system's temporary folder that
    every run and every xdist worker would share. Set in the environment, so that the
    ``dask scheduler`` and ``dask worker`` processes the tests start use it too (an xdist
    worker inherits its controller's: it replaces it). Removed at the end of the run, or
    by the watchdog after a killed run."""
    folder = tempfile.mkdtemp(prefix=f"registry-dask-{worker}-")
    _dask_scratch.append((folder, watchdog.register("dask", root=folder)))
    os.environ["DASK_TEMPORARY_DIRECTORY"] = folder
    if "dask" in sys.modules:  # read its environment at import: read it again
        import dask.config

        dask.config.refresh()


def pytest_unconfigure(config):
    """Remove this process's Dask scratch folder (its clusters are closed by now), and
    the controller its tests' marks."""
    if worker_name(config) == "main":
        shutil.rmtree(os.environ.pop(RUNNING), ignore_errors=True)
    while _dask_scratch:
        folder, registration = _dask_scratch.pop()
        shutil.rmtree(folder, ignore_errors=True)
        watchdog.unregister(registration)


#: Wall-clock seconds after which a test (its fixtures included) is taken to hang; the
#: slowest test of CI takes a few minutes. ``REGISTRY_TEST_HANG`` sets another.
TEST_HANG = float(os.environ.get("REGISTRY_TEST_HANG", "900"))

#: The environment variable naming the folder where each test running leaves a mark (a
#: file named by its node id and process), into which the stacks of a hung test are written.
RUNNING = "REGISTRY_TESTS_RUNNING"

_hung_before = pytest.StashKey[str]()


def _marks(nodeid: str) -> Path:
    """Where a test's marks are (one per process, ``<this>-<pid>``)."""
    return Path(os.environ[RUNNING]) / hashlib.sha256(nodeid.encode()).hexdigest()


def _stacks_of(nodeid: str) -> str:
    """The stacks a test left in a mark of its own when it hung in this run, or ''."""
    marks = _marks(nodeid)
    return "".join(m.read_text() for m in marks.parent.glob(f"{marks.name}-*"))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """A test that hangs ends its process once its stacks are written, instead of holding
    CI until CI's own time runs out with nothing said: under xdist the controller reports
    the test that crashed its worker with those stacks (``pytest_handlecrashitem``), and
    fails it at once if it gives it to another worker."""
    item.stash[_hung_before] = _stacks_of(item.nodeid)
    marks = _marks(item.nodeid)
    mark = marks.with_name(f"{marks.name}-{os.getpid()}")
    with mark.open("w") as stacks:
        faulthandler.dump_traceback_later(TEST_HANG, exit=True, file=stacks)
        try:
            yield
        finally:
            faulthandler.cancel_dump_traceback_later()
    mark.unlink(missing_ok=True)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    if item.stash.get(_hung_before, ""):
        pytest.fail(f"hung for over {TEST_HANG:g} s in another worker of this run; not run "
                    "again", pytrace=False)  # fmt: skip


@pytest.hookimpl(optionalhook=True)
def pytest_handlecrashitem(crashitem, report, sched):
    """xdist's report of a test whose worker died: with its stacks, if it hung."""
    stacks = _stacks_of(crashitem)
    if stacks:
        report.longrepr = f"{report.longrepr}: it hung for over {TEST_HANG:g} s\n\n{stacks}"


#: Module-scoped fixtures too cheap to keep a module's tests in one xdist worker.
CHEAP_MODULE_FIXTURES = {"backend"}

#: Session fixtures that take long to build (``full_registry_file``: about 15 s): the
#: tests that use one run in one worker, which builds it once.
BUILT_ONCE = ("full_registry_file",)


@pytest.hookimpl(tryfirst=True)  # before xdist reads the groups (--dist loadgroup)
def pytest_collection_modifyitems(config, items):
    """Under ``-n`` with ``--dist loadgroup`` (pyproject.toml), the tests of a module that
    share a module-scoped fixture (a registry audited once, a site built once, a Dask
    cluster) run in one worker, which builds it once; so do the tests that share one of
    ``BUILT_ONCE``. The others are spread test by test. Without -n this changes nothing."""
    for item in items:
        if item.get_closest_marker("xdist_group") is None:
            group = _shared_fixture_group(item)
            if group:
                item.add_marker(pytest.mark.xdist_group(group))


def _shared_fixture_group(item) -> str | None:
    info = getattr(item, "_fixtureinfo", None)  # doctests have none
    if info is None:
        return None
    names = set(item.fixturenames)
    for name in BUILT_ONCE:
        if name in names:
            return name
    for name in sorted(names - CHEAP_MODULE_FIXTURES):
        definitions = info.name2fixturedefs.get(name)
        if definitions and definitions[-1].scope == "module":
            return item.nodeid.split("::", 1)[0]  # the module's file
    return None


C = sp.Symbol("C", positive=True)
N = sp.Symbol("N", real=True)
g1, g2, g3 = sp.symbols("gamma1 gamma2 gamma3", real=True)
ZERO = Expression("0", sp.Integer(0))


def _hash(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def make_case(
    case_id: str = "demo-2003-lagrange",
    text: str = 'id = "demo-2003-lagrange"\n',
    *,
    citation: str = "A. Author, Journal 1 (2003) 1-10",
    doi: str = "",
    claims: tuple[Claim, ...] | None = None,
) -> Case:
    """A small case (Lagrange-like top with a torque parameter N) whose hash is that of ``text``."""
    if claims is None:
        claims = (
            Claim("I1", ClaimKind.INTEGRAL, Expression("gamma3", g3), locator="p. 2"),
            Claim(
                "I2",
                ClaimKind.CASIMIR,
                Expression("N*gamma1", N * g1),
                on=(Equation("gamma1**2 + gamma2**2 + gamma3**2 = 1", g1**2 + g2**2 + g3**2, 1),),
            ),
        )
    system = System(
        inertia=(Expression("C", C), Expression("C", C), Expression("2*C", 2 * C)),
        potential=Expression("C*gamma3", C * g3),
        torque=(ZERO, ZERO, Expression("N*gamma3", N * g3)),
    )
    return Case(
        id=case_id,
        title=f"Title of {case_id}",
        source=Source(citation, locator="p. 1", doi=doi),
        system=system,
        dynamics=forms.dynamics(system, {"C": C, "N": N}, {}),
        claims=claims,
        parameters={"C": C, "N": N},
        assumptions={"C": Assumption.POSITIVE, "N": Assumption.REAL},
        notes="made in conftest",
        text=text,
        content_hash=_hash(text),
        path=f"data/cases/{case_id}.toml",
    )


@pytest.fixture
def case_factory() -> Callable[..., Case]:
    """``make_case`` as a fixture, for cases with other ids, texts or claims."""
    return make_case


@pytest.fixture
def sample_case() -> Case:
    return make_case()


@pytest.fixture
def other_case() -> Case:
    """A second case from the same source, without claims."""
    return make_case("demo-1999-euler", 'id = "demo-1999-euler"\n', claims=())


@pytest.fixture
def memory_store() -> Iterator[Store]:
    with Store(":memory:") as store:
        yield store


@pytest.fixture
def file_store(tmp_path) -> Iterator[Store]:
    with Store(tmp_path / "db" / "registry.sqlite") as store:
        yield store


@pytest.fixture(scope="session")
def full_registry_file(tmp_path_factory) -> Path:
    """An SQLite registry with rows in every table (``helpers.registries.full_registry``),
    built once per session; tests copy it (``shutil.copyfile``) before they change it."""
    return full_registry(tmp_path_factory.mktemp("full") / "full.sqlite")


@pytest.fixture(scope="session")
def postgres_server(request) -> Iterator[PostgresServer]:
    """A PostgreSQL server of this test session (started on first use, stopped at the end):
    under xdist each worker is a session, and starts a server of its own."""
    try:
        server = PostgresServer.start(label=worker_name(request.config))
    except ServerUnavailable as why:
        if os.environ.get("REGISTRY_CI"):
            pytest.fail(f"REGISTRY_CI is set, but no PostgreSQL server could be started: {why}")
        pytest.skip(f"no PostgreSQL server could be started: {why}")
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture(scope="module", params=BACKENDS)
def backend(request) -> str:
    """The backend of a test module's databases: each module runs once per backend."""
    return request.param


@pytest.fixture(scope="module")
def module_databases(backend, tmp_path_factory, request) -> Databases:
    """Fresh databases of the module's backend, for module-scoped fixtures."""
    folder = tmp_path_factory.mktemp(backend)
    return Databases(backend, lambda: folder, request)


@pytest.fixture
def databases(backend, tmp_path, request) -> Databases:
    """Fresh databases of the module's backend, for one test."""
    return Databases(backend, lambda: tmp_path, request)


@pytest.fixture
def db_target(databases) -> str:
    """A fresh database for one test: an SQLite path, or a PostgreSQL URL."""
    return databases.new()


@pytest.fixture(params=["memory", "file", pytest.param("postgres", marks=POSTGRES)])
def store(request, tmp_path) -> Iterator[Store]:
    """Each test using it runs on an in-memory and on a file database, and on a database
    of a PostgreSQL server."""
    if request.param == "postgres":
        target = request.getfixturevalue("postgres_server").create_database(request.node.name)
    else:
        target = ":memory:" if request.param == "memory" else tmp_path / "registry.sqlite"
    with Store(target) as s:
        yield s
