"""The live view (``registry serve``): Datasette's metadata describes every table of the
schema, the canned queries run on a real audited registry and return what the API
returns, and ``registry serve`` answers them over HTTP in a separate process."""

from __future__ import annotations

import importlib.util
import json
import os
import socket
import sqlite3
import subprocess
import sys
import time
import urllib.request

import pytest

import registry
from registry.errors import RegistryError
from registry.presentation.live_view import QUERIES, TABLES, metadata, serve
from tests.helpers.samples import CASES, SEED


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    path = tmp_path_factory.mktemp("live") / "registry.sqlite"
    with registry.open(path) as reg:
        reg.add(*(CASES / f"{c}.toml" for c in SEED))
        reg.audit(jobs=1)
    return path


def _refuted(db) -> list[tuple[str, str]]:
    """(case, claim) of every claim whose own kind's newest verdict is refuted (API)."""
    with registry.open(db) as reg:
        kinds = {(c.case, c.label): c.kind for c in reg.claims().itertuples()}
        return sorted(
            (v.case, v.claim)
            for v in reg.verdicts().itertuples()
            if v.claim is not None and kinds.get((v.case, v.claim)) == v.check
            and v.verdict == "refuted"
        )  # fmt: skip


def test_every_table_and_view_is_described(db):
    with sqlite3.connect(db) as conn:
        names = {
            name
            for (name,) in conn.execute(
                "select name from sqlite_master where type in ('table', 'view')"
                " and name not like 'sqlite_%'"
            )
        }
    assert set(TABLES) == names - {"meta", "alembic_version"}
    described = metadata(db)["databases"][db.stem]
    assert set(described["queries"]) == set(QUERIES)


def test_the_canned_queries_run_and_agree_with_the_api(db):
    with sqlite3.connect(db) as conn:
        rows = conn.execute(QUERIES["refuted_claims"][2]).fetchall()
        assert sorted((r[0], r[1]) for r in rows) == _refuted(db) != []
        sources = conn.execute(QUERIES["cases_by_source"][2]).fetchall()
        assert sum(r[3] for r in sources) == len(SEED)
        verdicts = conn.execute(QUERIES["verdicts_of_a_case"][2], {"case": SEED[0]}).fetchall()
        assert {r[1] for r in verdicts} >= {"jacobi", "energy", "integral", "casimir"}
        conn.execute(QUERIES["search_statements"][2]).fetchall()


def test_serve_refuses_what_is_not_an_sqlite_file():
    for database in (None, ":memory:"):
        with pytest.raises(RegistryError, match="SQLite file"):
            serve(database)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_registry_serve_answers_the_canned_queries_over_http(db):
    if importlib.util.find_spec("datasette") is None:
        if os.environ.get("REGISTRY_CI"):
            pytest.fail("Datasette (the 'serve' extra, in 'test') is required in CI")
        pytest.skip("no Datasette (pip install -e '.[serve]')")
    port = _free_port()
    command = [sys.executable, "-m", "registry", "--db", str(db), "serve", "--port", str(port)]
    server = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    base = f"http://127.0.0.1:{port}/{db.stem}"
    try:
        deadline = time.monotonic() + 90
        while True:
            try:
                with urllib.request.urlopen(f"{base}/refuted_claims.json?_shape=array") as r:
                    rows = json.loads(r.read())
                break
            except OSError:
                assert server.poll() is None, server.stderr.read().decode()
                assert time.monotonic() < deadline, "registry serve did not answer"
                time.sleep(0.5)
        assert sorted((r["case"], r["claim"]) for r in rows) == _refuted(db)
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/-/metadata.json") as r:
            assert json.loads(r.read())["title"].startswith("Registry of rigid-body")
    finally:
        server.terminate()
        server.wait(timeout=30)
