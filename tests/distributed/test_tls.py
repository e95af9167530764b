"""Audits and searches on a Dask cluster that requires TLS (the recipe of
docs/operations.md): a ``dask scheduler`` and two ``dask worker`` processes with a
certificate made here, and ``registry`` processes configured through Dask's environment
variables.

With the cluster's certificate the verdicts and the search are the local pool's; a
command without a TLS configuration, with a CA the scheduler's certificate is not
signed by, with a client certificate the cluster does not trust, or naming a file that
is not there, is refused with one line that says what to configure.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

import registry
from registry.execution.cluster import TLS_KEYS
from tests.helpers.clocks import PATIENT_OPTIONS
from tests.helpers.dask_clusters import Certificate, dask_processes, registry_run, verdicts

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "data" / "cases"
FILES = [SEED / "zhukovsky-gyrostat.toml", SEED / "yehia-2003-kovalevskaya-b.toml"]
FAMILY = ROOT / "tests" / "data" / "families" / "heavy-top-lam.toml"

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="POSIX processes")


@pytest.fixture(scope="module")
def certificates(tmp_path_factory) -> dict[str, Certificate]:
    """The cluster's certificate, and another one that nobody in the cluster trusts."""
    where = tmp_path_factory.mktemp("tls")
    return {name: Certificate.make(where, name) for name in ("cluster", "stranger")}


@pytest.fixture(scope="module")
def tls_cluster(certificates, tmp_path_factory):
    with dask_processes(tmp_path_factory.mktemp("dask"), tls=certificates["cluster"]) as cluster:
        assert cluster.address.startswith("tls://")
        yield cluster


def added(db: Path) -> Path:
    done = registry_run(db, "add", *map(str, FILES))
    assert done.returncode == 0, done.stderr
    return db


@pytest.mark.slow  # the seed catalog audited over TLS and in the local pool: a minute loaded
def test_an_audit_over_tls_gives_the_local_pools_verdicts(tmp_path, tls_cluster, certificates):
    local, remote = added(tmp_path / "local.sqlite"), added(tmp_path / "tls.sqlite")
    expected = registry_run(local, "audit", "--jobs", "2", *PATIENT_OPTIONS)
    assert expected.returncode == 0, expected.stderr
    env = certificates["cluster"].client_environment()
    got = registry_run(
        remote, "audit", "--scheduler", tls_cluster.address, *PATIENT_OPTIONS, env=env
    )
    assert got.returncode == 0, got.stderr + tls_cluster.log()
    assert verdicts(remote).equals(verdicts(local))
    run = registry.open(remote).runs().to_dict("records")[-1]
    assert run["status"] == "complete"


def test_a_search_through_the_scheduler_file_over_tls_is_the_local_one(
    tmp_path, tls_cluster, certificates
):
    env = certificates["cluster"].client_environment()
    args = ["discover", str(FAMILY), "--degree", "4", "--free", "lam", "--json"]
    local = registry_run(tmp_path / "a.sqlite", *args)
    remote = registry_run(
        tmp_path / "b.sqlite", *args, "--scheduler", str(tls_cluster.file), env=env
    )
    assert local.returncode == 0 and remote.returncode == 0, remote.stderr
    mine, theirs = json.loads(local.stdout), json.loads(remote.stdout)
    for document in (mine, theirs):
        document.pop("seconds")
        document.pop("events", None)
        # the Kovalevskaya analysis beside the search has a short wall-clock budget of its
        # own (settings.BESIDE_SEARCH_EXPONENT_SECONDS): on a loaded machine one of the two
        # may run out; the search is what runs on the cluster
        document.pop("exponents", None)
        document.pop("every_degree", None)
    assert theirs == mine
    assert [s["when"] for s in mine["special"]] == [["lam = 1"], ["lam = 2"]]


def refused(tmp_path: Path, address: str, env: dict[str, str]) -> str:
    """The one line a refused audit prints; the database is left without a run."""
    db = added(tmp_path / "refused.sqlite")
    done = registry_run(db, "audit", "--scheduler", address, env=env)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert registry.open(db).runs().empty
    return lines[0]


def test_a_client_without_a_certificate_is_told_what_to_configure(tmp_path, tls_cluster):
    line = refused(tmp_path, tls_cluster.address, env={})
    assert line.startswith(f"Error: Dask scheduler {tls_cluster.address!r}: it requires TLS, ")
    assert "this command has no TLS configuration" in line
    for key, variable in TLS_KEYS.items():
        assert key in line and variable in line


def test_a_scheduler_signed_by_another_ca_is_refused(tmp_path, tls_cluster, certificates):
    mine = certificates["stranger"].client_environment()  # trusts only itself
    line = refused(tmp_path, tls_cluster.address, env=mine)
    assert "its certificate is not signed by the CA this command trusts" in line
    assert "DASK_DISTRIBUTED__COMM__TLS__CA_FILE" in line


def test_a_client_certificate_the_cluster_does_not_trust_is_refused(
    tmp_path, tls_cluster, certificates
):
    env = certificates["stranger"].client_environment(ca=certificates["cluster"])
    line = refused(tmp_path, tls_cluster.address, env=env)
    assert "it does not trust this command's client certificate" in line


def test_a_missing_certificate_file_is_named(tmp_path, tls_cluster, certificates):
    env = certificates["cluster"].client_environment()
    env["DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY"] = str(tmp_path / "nowhere.pem")
    line = refused(tmp_path, tls_cluster.address, env=env)
    assert "distributed.comm.tls.client.key ($DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY)" in line
    assert "nowhere.pem', which is not a readable file" in line


def test_plain_tcp_to_a_tls_scheduler_says_how_it_is_reached(tmp_path, tls_cluster):
    address = tls_cluster.address.replace("tls://", "tcp://")
    line = refused(tmp_path, address, env={})
    assert "a scheduler that requires TLS is reached at tls://HOST:PORT" in line
