"""One client of the soak test (``scripts/soak.py``): a member of a group at work.

Until its deadline, the client does what a group does with a registry, picked at random
(seeded) by the weights of ``MIX``: adds new versions of catalog cases (copies of
``data/cases`` files with a changed title or notes, so that each add is a new version),
audits a few cases (in this process, in two local workers, or on the Dask cluster),
audits everything now and then, records searches of the small test families
(``tests/data/families``, as given or as a changed copy: a new version searched anew),
surveys a catalog case or two, builds the static site, reads DataFrames (cases,
verdicts, searches) and verifies the database. Each operation opens the registry as a
command does, and closes it after.

Its journal (one JSON object a line, appended with one ``write`` each) records each
operation as it begins (``begin``) and, once the API call has returned, what it saw
acknowledged: an add's case id, content hash, version and status; an audit's run and
the case versions it audited; a search's number, case version and options; the latency
of each read; an operation that raised, with the error. A client killed in the middle
leaves its last ``begin`` without an end (and perhaps half a line, which the soak
ignores). The client dies with the soak (the parent-death rule of the registry's
workers) and never writes to the journal of another.

Usage (by scripts/soak.py only): python scripts/soak_client.py --db DB --journal FILE
    --work DIR --deadline EPOCH --parent PID --name NAME --seed SEED [--scheduler ADDRESS]
    [--cases N]
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
CATALOG = ROOT / "data" / "cases"
FAMILIES = ROOT / "tests" / "data" / "families"

#: Seconds each check and each case's corrections may take: far more than they need on a
#: quiet machine (about a second), so that a loaded one decides as a quiet one does (the
#: soak compares the verdicts with those of a quiet serial run).
CHECK_SECONDS, CORRECTIONS_SECONDS = 300.0, 900.0
#: Seconds a search may take (the same reason).
SEARCH_SECONDS = 900.0

#: The operations and their weights: what a group does, most often first.
MIX: dict[str, int] = {
    "read": 30,
    "add": 24,
    "audit": 14,
    "audit-dask": 8,
    "discover": 12,
    "survey": 5,
    "site": 4,
    "audit-all": 2,
    "verify-db": 1,
}

#: The searches of the test families the group records: (family, options), each quick.
SEARCHES: list[tuple[str, dict[str, Any]]] = [
    ("euler-top", {"degree": 2}),
    ("euler-top", {"degree": 4}),
    ("asymmetric-heavy-top", {"degree": 2}),
    ("heavy-top-lam", {"degree": 2, "free": ["lam"]}),
    ("heavy-top-lam", {"degree": 4, "free": ["lam"]}),
    ("lagrange-lam", {"degree": 2, "free": ["lam"]}),
    ("heavy-top-axis1", {"degree": 2, "free": ["a"]}),
    ("clebsch-b3", {"degree": 2, "free": ["b3"]}),
    ("kirchhoff-diagonal", {"degree": 2}),
    ("heavy-top-lam-z0", {"degree": 2, "free": ["lam", "z0"]}),
    ("goryachev-1916-lam", {"degree": 3, "free": ["lam"], "on": ["s = 0"]}),
    ("lagrange-a-real", {"degree": 2}),
    ("kovalevskaya-gyrostat", {"degree": 2}),
    ("heavy-top-b-c-z0", {"degree": 2, "free": ["b", "c"]}),
]

#: Reads whose latency is measured: the DataFrames a group reads in notebooks.
READS = ("cases", "verdicts", "searches")


def catalog_files(count: int | None = None) -> list[Path]:
    """The catalog's case files, or ``count`` of them spread over it (every k-th file, so
    that each topic has some): what the soak's registry starts with and copies."""
    files = sorted(CATALOG.rglob("*.toml"))
    if count is None or count >= len(files):
        return files
    return files[:: max(1, len(files) // max(1, count))][:count]


def case_id(path: Path) -> str:
    """The id a case file gives its case (its ``id`` line)."""
    found = _ID.search(path.read_text(encoding="utf-8"))
    if found is None:
        raise ValueError(f"{path}: no id line")
    return found.group(1)


_ID = re.compile(r'(?m)^id = "([^"\n]+)"$')
_TITLE = re.compile(r'(?m)^title = "([^"\n]*)"$')
_NOTES = re.compile(r'(?m)^notes = "([^"\n]*)"$')


class Journal:
    """An append-only journal: one JSON object a line, each written whole by one
    ``write`` to a file opened for appending (a kill leaves at most the last one torn)."""

    def __init__(self, path: Path, name: str):
        self.fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        self.name = name

    def write(self, **entry: Any) -> None:
        entry = {"t": time.time(), "client": self.name, "pid": os.getpid(), **entry}
        os.write(self.fd, (json.dumps(entry, default=str) + "\n").encode())


@dataclass
class Client:
    """What an operation needs: where the registry and the cluster are, the client's
    folder, its random draws, and how many copies it has written."""

    db: str
    scheduler: str | None
    work: Path
    name: str
    rng: random.Random
    catalog: list[Path]
    copies: int = 0

    def altered(self, source: Path) -> Path:
        """A copy of a case file with a changed title, or notes, in this client's folder:
        a new content, so a new version of the same case id."""
        text = source.read_text(encoding="utf-8")
        self.copies += 1
        tag = f"[soak {self.name} #{self.copies}]"
        pattern = _NOTES if _NOTES.search(text) and self.rng.random() < 0.5 else _TITLE
        text, n = pattern.subn(lambda m: f'{m.group(0)[:-1]} {tag}"', text, count=1)
        assert n == 1, source
        path = self.work / "copies" / f"{source.stem}-{self.copies}.toml"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return path

    def budget(self):
        from registry.api import time_budget

        return time_budget(CHECK_SECONDS, CORRECTIONS_SECONDS)

    def where(self, on_cluster: bool) -> dict[str, Any]:
        """The executor options of an operation: the cluster, or 1 or 2 local workers."""
        if on_cluster:
            return {"scheduler": self.scheduler}
        return {"jobs": self.rng.choice([1, 1, 2])}


# ---------------------------------------------------------------------- operations


def op_add(reg, c: Client) -> dict[str, Any]:
    from registry.language.toml_input import content_hash

    path = c.altered(c.rng.choice(c.catalog))
    expected = content_hash(path.read_text(encoding="utf-8"))
    (result,) = reg.add(path)
    if result.status == "refused":
        raise RuntimeError(f"refused: {result.error}")
    return {
        "case": result.case,
        "version": result.version,
        "status": result.status,
        "hash": expected,
    }


def _audit(reg, c: Client, case_ids: list[str] | None, on_cluster: bool) -> dict[str, Any]:
    where = c.where(on_cluster)
    report = reg.audit(case_ids, budget=c.budget(), **where)
    return {
        "run": report.run,
        "cases": [[a.case, a.content_hash] for a in report.audits],
        "where": "dask" if on_cluster else f"jobs={where['jobs']}",
        "events": list(report.events),
    }


def _some_cases(reg, c: Client) -> list[str]:
    ids = sorted(reg.cases()["case"])
    return c.rng.sample(ids, k=min(len(ids), c.rng.randint(1, 4)))


def op_audit(reg, c: Client) -> dict[str, Any]:
    return _audit(reg, c, _some_cases(reg, c), on_cluster=False)


def op_audit_dask(reg, c: Client) -> dict[str, Any]:
    return _audit(reg, c, _some_cases(reg, c), on_cluster=c.scheduler is not None)


def op_audit_all(reg, c: Client) -> dict[str, Any]:
    return _audit(reg, c, None, on_cluster=c.scheduler is not None and c.rng.random() < 0.5)


def _search_entry(report) -> dict[str, Any]:
    from registry.store.conversions import options_key

    return {
        "search": report.number,
        "reused": report.reused,
        "case": report.search.case,
        "hash": report.search.content_hash,
        "options": options_key(report.search.options),
        "derived": list(report.derived),
    }


def op_discover(reg, c: Client) -> dict[str, Any]:
    family, options = c.rng.choice(SEARCHES)
    path = FAMILIES / f"{family}.toml"
    if c.rng.random() < 0.5:  # a changed copy: a new version, searched anew
        path = c.altered(path)
    on_cluster = c.scheduler is not None and c.rng.random() < 0.3
    where = {"scheduler": c.scheduler} if on_cluster else {"jobs": 1}
    report = reg.discover(path, record=True, budget=SEARCH_SECONDS, **options, **where)
    return {
        **_search_entry(report),
        "where": "dask" if on_cluster else "jobs=1",
        "events": list(report.events),
    }


def op_survey(reg, c: Client) -> dict[str, Any]:
    ids = [case_id(p) for p in c.rng.sample(c.catalog, k=c.rng.randint(1, 2))]
    reports = reg.survey(ids, budget=SEARCH_SECONDS, jobs=1)
    return {"cases": ids, "searches": [_search_entry(r) for r in reports]}


def op_site(reg, c: Client) -> dict[str, Any]:
    started = time.perf_counter()
    written = reg.site(c.work / "site")
    return {"kind": "site", "seconds": time.perf_counter() - started, "rows": len(written)}


def op_read(reg, c: Client) -> dict[str, Any]:
    kind = c.rng.choice(READS)
    started = time.perf_counter()
    frame = getattr(reg, kind)()
    return {"kind": kind, "seconds": time.perf_counter() - started, "rows": len(frame)}


def op_verify_db(reg, c: Client) -> dict[str, Any]:
    started = time.perf_counter()
    found = reg.verify_db()
    return {
        "kind": "verify-db",
        "seconds": time.perf_counter() - started,
        "problems": list(found.problems),
    }


OPERATIONS: dict[str, Callable[[Any, Client], dict[str, Any]]] = {
    "read": op_read,
    "add": op_add,
    "audit": op_audit,
    "audit-dask": op_audit_dask,
    "discover": op_discover,
    "survey": op_survey,
    "site": op_site,
    "audit-all": op_audit_all,
    "verify-db": op_verify_db,
}


def warm_up() -> None:
    """Import what the operations use, as a notebook has by the time it reads: the
    latency of a read is that of the query, not of importing pandas."""
    import pandas  # noqa: F401

    import registry.presentation.site  # noqa: F401
    import registry.runs.audit_run  # noqa: F401
    import registry.runs.search_run  # noqa: F401
    import registry.store.frames  # noqa: F401


def run(args: argparse.Namespace) -> None:
    import registry

    journal = Journal(Path(args.journal), args.name)
    rng = random.Random(f"{args.seed}/{args.name}")
    catalog = catalog_files(args.cases)
    client = Client(args.db, args.scheduler, Path(args.work), args.name, rng, catalog)
    client.work.mkdir(parents=True, exist_ok=True)
    kinds, weights = list(MIX), list(MIX.values())
    warm_up()
    journal.write(op="start")
    while time.time() < args.deadline:
        kind = rng.choices(kinds, weights)[0]
        if kind in ("audit-dask",) and args.scheduler is None:
            kind = "audit"
        journal.write(begin=kind)
        started = time.perf_counter()
        try:
            with registry.open(args.db, create=False) as reg:
                opened = time.perf_counter() - started
                done = OPERATIONS[kind](reg, client)
        except Exception as exc:  # an operation that failed is recorded; the work goes on
            journal.write(
                op=kind,
                error=f"{type(exc).__name__}: {exc}",
                trace=traceback.format_exc(),
                elapsed=time.perf_counter() - started,
            )
            time.sleep(1.0)
            continue
        journal.write(op=kind, elapsed=time.perf_counter() - started, opened=opened, **done)
    journal.write(op="stop")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", required=True)
    parser.add_argument("--journal", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--deadline", type=float, required=True)
    parser.add_argument("--parent", type=int, required=True)
    parser.add_argument("--name", required=True)
    parser.add_argument("--seed", default="0")
    parser.add_argument("--scheduler", default=None)
    parser.add_argument("--cases", type=int, default=None)
    args = parser.parse_args(argv)
    from registry.execution.serving import die_with_parent

    die_with_parent(args.parent)  # nothing of the soak outlives it
    run(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
