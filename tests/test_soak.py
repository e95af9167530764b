"""A short soak (``scripts/soak.py``) on each backend: three clients for half a minute on a
dozen catalog cases and the test families, with a Dask cluster of two workers; one
client is killed with SIGKILL and one Dask worker is killed, and every end check of the
soak passes: each acknowledged write present once, nothing half written (``verify-db``
clean, no run left running, an interrupted run only where a client was killed), the
verdicts and searches those of a quiet serial run, and no process left behind.

The soak runs as the script it is, in a process of its own that dies with the test; on
PostgreSQL it works on a database of the session's server (``--db``), on SQLite on the
file it makes. The long runs, and their figures, are in docs/operations.md.
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from tests.helpers.clocks import HANG
from tests.helpers.databases import POSTGRES
from tests.helpers.processes import dying_with_this_process

ROOT = Path(__file__).resolve().parents[1]

#: Three clients for 30 s on 12 catalog cases; a kill every 8 s or so, two in all: the
#: kills alternate, so one client and one Dask worker.
SHORT = ["--clients", "3", "--minutes", "0.5", "--cases", "12", "--workers", "2",
         "--kill-every", "8", "--kills", "2", "--seed", "34"]  # fmt: skip

#: The soak's end checks, by the number it prints them with ("e": no client's operation
#: failed and none ended on its own).
CHECKS = {"1", "2", "3", "4", "e"}


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the soak reads /proc")
@pytest.mark.parametrize("kind", ["sqlite", pytest.param("postgres", marks=POSTGRES)])
def test_a_short_soak_with_a_client_and_a_worker_killed_passes_every_check(kind, tmp_path, request):
    summary = tmp_path / "soak.json"
    where = ["--backend", "sqlite"]
    if kind == "postgres":
        where = ["--db", request.getfixturevalue("postgres_server").create_database("soak")]
    command = [sys.executable, str(ROOT / "scripts" / "soak.py"), *SHORT, *where]
    done = subprocess.run(
        dying_with_this_process([*command, "--json", str(summary)]),
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=20 * HANG,  # half a minute of work, then the checks: on a busy machine
    )
    assert done.returncode == 0, done.stdout[-6000:] + done.stderr[-4000:]
    found = json.loads(summary.read_text(encoding="utf-8"))

    checks = found["checks"]
    assert set(checks) == CHECKS
    assert all(c["passed"] and not c["problems"] for c in checks.values()), checks
    assert Counter(k["kind"] for k in found["kills"]) == {"client": 1, "worker": 1}
    (worker,) = [k for k in found["kills"] if k["kind"] == "worker"]
    assert worker.get("restarted_by") == "nanny"  # back within the soak's patience

    acknowledged = checks["1"]["counts"]
    assert acknowledged["adds"] + acknowledged["audit runs"] > 0  # the clients wrote
    assert checks["3"]["counts"]["verdicts compared"] > 0
    assert checks["4"]["counts"]["processes left"] == 0
    assert "throughput" in done.stdout and "read latency" in done.stdout
