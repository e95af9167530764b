"""The end checks of the soak test (``scripts/soak.py``), on what the clients' journals
say they saw acknowledged and on what the database holds.

1. ``acknowledged``: every write a client saw acknowledged is there, once: each added
   case version (id, version, content hash), each audit run (complete, with a result for
   every case version it reported), each search (its case version and options); no case
   version stored twice (two versions in a row with the same content), no result of a
   run stored twice.
2. ``sound``: nothing half written: ``verify_db`` finds no problem, the versions of each
   case are numbered 1..n, no run is left ``running``, and a run that is not
   ``complete`` is ``interrupted`` and belonged to a client the soak killed.
3. ``serial``: the verdicts and searches equal those of a quiet serial run of the same
   work: every case version audited and every search recorded is done again, one after
   the other in one process, in a fresh registry (``replay``), and compared verdict by
   verdict (case version, claim, check) and search by search (case version, options);
   a claim a search attached is known by its expression, its label holding the search's
   number (``compared`` says what of its verdict is compared). Each audit of a case
   version holds every check of every claim of that version (the claims a search
   attached later excepted): none is half recorded.

``figures`` gives throughput and read latency from the journals.
"""

from __future__ import annotations

import json
import statistics
from collections import Counter, defaultdict
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: Lines of detail printed for a failed check, at most.
SHOWN = 12


@dataclass
class Outcome:
    """A check's result: passed or not, with what it counted and what it found wrong."""

    name: str
    title: str
    passed: bool = True
    counts: dict[str, int] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def fail(self, problem: str) -> None:
        self.passed = False
        self.problems.append(problem)

    def lines(self) -> list[str]:
        head = f"[{'PASS' if self.passed else 'FAIL'}] ({self.name}) {self.title}"
        out = [head]
        if self.counts:
            out.append("    " + ", ".join(f"{n} {what}" for what, n in self.counts.items()))
        out += [f"    note: {n}" for n in self.notes]
        out += [f"    problem: {p}" for p in self.problems[:SHOWN]]
        if len(self.problems) > SHOWN:
            out.append(f"    ... and {len(self.problems) - SHOWN} more problems")
        return out


# ------------------------------------------------------------------------ journals


@dataclass
class Journals:
    """Every entry of the clients' journals, and how many lines were torn by a kill."""

    entries: list[dict[str, Any]]
    torn: int

    @classmethod
    def read(cls, folder: Path) -> Journals:
        entries, torn = [], 0
        for path in sorted(folder.glob("*.jsonl")):
            data = path.read_bytes()
            for line in data.split(b"\n"):
                if not line:
                    continue
                try:
                    entries.append(json.loads(line))
                except ValueError:
                    torn += 1  # the last line of a client killed while writing it
        entries.sort(key=lambda e: e["t"])
        return cls(entries, torn)

    def done(self, *ops: str) -> list[dict[str, Any]]:
        """Entries of operations that returned (no error), of these kinds."""
        return [e for e in self.entries if e.get("op") in ops and "error" not in e]

    def errors(self) -> list[dict[str, Any]]:
        return [e for e in self.entries if "error" in e]

    def last_begun(self, client: str) -> str | None:
        """What a client had begun and not finished when its journal ends (None: idle)."""
        begun = None
        for e in self.entries:
            if e.get("client") != client:
                continue
            if "begin" in e:
                begun = e["begin"]
            elif e.get("op") == begun:
                begun = None
        return begun


# ------------------------------------------------------------------------ the database


@dataclass
class Snapshot:
    """What a registry holds, as plain values: case versions, claims, runs, results,
    searches and what they found (by primary key)."""

    #: case_id, version, content hash, text, path
    cases: dict[int, tuple[str, int, str, str, str | None]]
    #: case_pk, label, expression, level set, the search that attached it (None: the text's)
    claims: dict[int, tuple[int, str, str, tuple[str, ...], int | None]]
    runs: dict[int, tuple[str, int | None]]  # status, pid
    #: run, case_pk, claim_id, check, verdict, method, reason, witness, residual
    results: list[tuple]
    searches: dict[int, tuple[int, dict, str, tuple]]  # case_pk, options, options_key, fields
    discoveries: dict[int, list[tuple]]  # search -> rows (position, when, ..., derived case_pk)

    @classmethod
    def read(cls, store) -> Snapshot:
        from sqlalchemy import select

        from registry.store.tables import (
            CaseRow,
            ClaimRow,
            DiscoveryRow,
            ResultRow,
            RunRow,
            SearchRow,
        )

        with store.read() as s:
            cases = {
                r.id: (r.case_id, r.version, r.content_hash, r.text, r.path)
                for r in s.execute(
                    select(
                        CaseRow.id,
                        CaseRow.case_id,
                        CaseRow.version,
                        CaseRow.content_hash,
                        CaseRow.text,
                        CaseRow.path,
                    )
                )
            }
            claims = {
                r.id: (r.case_pk, r.label, r.expression, tuple(r.on or ()), r.search_id)
                for r in s.execute(
                    select(
                        ClaimRow.id,
                        ClaimRow.case_pk,
                        ClaimRow.label,
                        ClaimRow.expression,
                        ClaimRow.on,
                        ClaimRow.search_id,
                    )
                )
            }
            runs = {
                r.id: (r.status, r.pid)
                for r in s.execute(select(RunRow.id, RunRow.status, RunRow.pid))
            }
            results = [
                (
                    r.run_id,
                    r.case_pk,
                    r.claim_id,
                    r.check,
                    r.verdict,
                    r.method,
                    r.reason,
                    json.dumps(r.witness, sort_keys=True),
                    r.residual,
                )
                for r in s.execute(
                    select(
                        ResultRow.run_id,
                        ResultRow.case_pk,
                        ResultRow.claim_id,
                        ResultRow.check,
                        ResultRow.verdict,
                        ResultRow.method,
                        ResultRow.reason,
                        ResultRow.witness,
                        ResultRow.residual,
                    ).order_by(ResultRow.id)
                )
            ]
            searches = {
                r.id: (
                    r.case_pk,
                    r.options,
                    r.options_key,
                    (
                        r.complete,
                        tuple(r.coverage),
                        tuple(r.known),
                        tuple(map(tuple, r.dimensions)),
                        r.method,
                        r.statement,
                        tuple(r.claims or ()),
                        r.claims_complete,
                    ),
                )
                for r in s.scalars(select(SearchRow).order_by(SearchRow.id))
            }
            discoveries: dict[int, list[tuple]] = defaultdict(list)
            for r in s.scalars(select(DiscoveryRow).order_by(DiscoveryRow.id)):
                discoveries[r.search_id].append(
                    (
                        r.position,
                        tuple(r.when),
                        r.extra,
                        tuple(r.integrals),
                        tuple(r.casimir),
                        json.dumps(r.status, sort_keys=True),
                        r.derived_case_pk,
                    )
                )
        return cls(cases, claims, runs, results, searches, dict(discoveries))

    # --- keys that mean the same in two registries (primary keys do not) -----------

    def claim_key(self, claim_id: int | None) -> tuple | None:
        """A claim as it is known in any registry: its label, or for a claim a search
        attached (labelled by the search's number), its expression and level set."""
        if claim_id is None:
            return None
        _, label, expression, on, search = self.claims[claim_id]
        return ("claim", label) if search is None else ("discovered", expression, on)

    def version_hash(self, case_pk: int) -> tuple[str, str]:
        case_id, _, content_hash, _, _ = self.cases[case_pk]
        return case_id, content_hash

    def verdict_key(self, case_pk: int, claim_id: int | None, check: str) -> tuple:
        """(case id, content hash, claim key, check): a verdict's place in any registry."""
        return (*self.version_hash(case_pk), self.claim_key(claim_id), check)

    def verdicts(self) -> dict[tuple, set[tuple]]:
        """``verdict_key`` -> the verdicts stored for it (``compared``)."""
        found: dict[tuple, set[tuple]] = defaultdict(set)
        for _run, pk, claim, check, *verdict in self.results:
            key = self.verdict_key(pk, claim, check)
            found[key].add(compared(key, tuple(verdict)))
        return found

    def search_result(self, search: int) -> tuple:
        """What a search established, with its derived cases named by content; not what
        it was identified with (each integral new, a claim again, the same system as a
        case: its statement and its findings' status), which depends on the cases the
        registry held when it ran, and so on the order of the work."""
        rows = tuple(
            (*row[:5], None if row[-1] is None else self.version_hash(row[-1]))
            for row in self.discoveries.get(search, [])
        )
        found = self.searches[search][3]
        return (found[:5] + found[6:], rows)


#: What is compared of a verdict: verdict, method, reason, witness, residual.
VERDICT_FIELDS = ("verdict", "method", "reason", "witness", "residual")


def compared(key: tuple, verdict: tuple) -> tuple:
    """What two registries must agree on for a verdict: all of it, except for a claim a
    search attached: its witness and residual come from points sampled with a seed drawn
    from the claim's label, which holds the number of the search (another number in
    another registry), so only its verdict, method and reason are compared."""
    claim = key[2]
    if claim is not None and claim[0] == "discovered":
        return verdict[:3]
    return verdict


# ------------------------------------------------------------------------ 1. acknowledged


def acknowledged(snap: Snapshot, journals: Journals) -> Outcome:
    out = Outcome("1", "every acknowledged write is present, exactly once")
    by_version = {(c[0], c[1]): pk for pk, c in snap.cases.items()}
    hashes = Counter((c[0], c[2]) for c in snap.cases.values())

    adds = journals.done("add")
    for e in adds:
        pk = by_version.get((e["case"], e["version"]))
        if pk is None:
            out.fail(f"add by {e['client']}: {e['case']} version {e['version']} is missing")
        elif snap.cases[pk][2] != e["hash"]:
            out.fail(
                f"add by {e['client']}: {e['case']} version {e['version']} holds another "
                f"content ({snap.cases[pk][2][:12]}, not {e['hash'][:12]})"
            )
        elif hashes[(e["case"], e["hash"])] != 1:
            out.fail(
                f"add by {e['client']}: {e['case']} content {e['hash'][:12]} is stored "
                f"{hashes[(e['case'], e['hash'])]} times"
            )

    # a content stored twice in a row is an add stored twice (an add of the newest
    # content changes nothing)
    versions: dict[str, list[tuple[int, str]]] = defaultdict(list)
    for case_id, version, content_hash, _, _ in snap.cases.values():
        versions[case_id].append((version, content_hash))
    for case_id, found in versions.items():
        found.sort()
        for (v1, h1), (v2, h2) in zip(found, found[1:], strict=False):
            if h1 == h2:
                out.fail(f"{case_id}: versions {v1} and {v2} hold the same content")

    results_by_run: dict[int, set[int]] = defaultdict(set)
    for run, pk, *_ in snap.results:
        results_by_run[run].add(pk)
    audits = journals.done("audit", "audit-dask", "audit-all")
    for e in audits:
        run = e["run"]
        if run not in snap.runs:
            out.fail(f"audit by {e['client']}: run {run} is missing")
            continue
        if snap.runs[run][0] != "complete":
            out.fail(f"audit by {e['client']}: run {run} is {snap.runs[run][0]}")
        stored = {snap.version_hash(pk) for pk in results_by_run[run]}
        for case_id, content_hash in e["cases"]:
            if (case_id, content_hash) not in stored:
                out.fail(
                    f"audit by {e['client']}: run {run} has no result for {case_id} "
                    f"({content_hash[:12]})"
                )

    twice = Counter((run, pk, claim, check) for run, pk, claim, check, *_ in snap.results)
    for (run, pk, claim, check), n in twice.items():
        if n > 1:
            case_id, version = snap.cases[pk][:2]
            out.fail(f"run {run}: {check} of {case_id} v{version} claim {claim} stored {n} times")

    searches = [s for e in journals.done("discover") for s in [e]] + [
        s for e in journals.done("survey") for s in e["searches"]
    ]
    for s in searches:
        number = s["search"]
        if number not in snap.searches:
            out.fail(f"search {number} of {s['case']} is missing")
            continue
        pk, _, key, _ = snap.searches[number]
        if snap.version_hash(pk) != (s["case"], s["hash"]) or key != s["options"]:
            out.fail(
                f"search {number} is not the search of {s['case']} ({s['hash'][:12]}) "
                f"with {s['options']} that was acknowledged"
            )
        if not s["reused"] and not snap.discoveries.get(number):
            out.fail(f"search {number} has no findings stored (not even the generic values)")
        for derived in s.get("derived", []):
            if not any(c[0] == derived for c in snap.cases.values()):
                out.fail(f"search {number}: its derived case {derived} is missing")

    out.counts = {
        "adds": len(adds),
        "audit runs": len(audits),
        "searches": sum(not s["reused"] for s in searches),
        "searches reused": sum(s["reused"] for s in searches),
        "torn journal lines": journals.torn,
    }
    return out


# ------------------------------------------------------------------------ 2. sound


def sound(reg, snap: Snapshot, killed: set[int], journals: Journals) -> Outcome:
    """``killed``: the pids of the clients the soak killed (their runs may be interrupted);
    the clients' own ``verify-db`` during the run must have been clean too."""
    out = Outcome("2", "nothing half written: verify-db clean, no run left running")
    found = reg.verify_db()
    for problem in found.problems:
        out.fail(f"verify-db: {problem}")
    out.notes += [f"verify-db: {n}" for n in found.notes]
    during = journals.done("verify-db")
    for e in during:
        for problem in e["problems"]:
            out.fail(f"verify-db by {e['client']} during the run: {problem}")

    versions: dict[str, list[int]] = defaultdict(list)
    for case_id, version, *_ in snap.cases.values():
        versions[case_id].append(version)
    for case_id, numbers in versions.items():
        if sorted(numbers) != list(range(1, len(numbers) + 1)):
            out.fail(f"{case_id}: versions {sorted(numbers)} are not 1..{len(numbers)}")

    statuses = Counter(status for status, _ in snap.runs.values())
    for run, (status, pid) in sorted(snap.runs.items()):
        if status == "complete":
            continue
        if status == "interrupted" and pid in killed:
            continue
        why = "its process was killed" if pid in killed else "its process was not killed"
        out.fail(f"run {run} is {status!r} ({why}; pid {pid})")
    out.counts = {
        "case versions": len(snap.cases),
        **{f"runs {s}": n for s, n in statuses.items()},
        "verify-db during the run": len(during),
    }
    return out


# ------------------------------------------------------------------------ 3. serial


def replay(
    snap: Snapshot,
    target: Path,
    family_ids: set[str],
    check: float,
    corrections: float,
    search_seconds: float,
) -> tuple[Snapshot, float]:
    """The same work, quiet and serial, in a fresh registry at ``target``: each case
    version that was audited or searched is added (the versions of a case in order, so
    that each is the newest when its turn comes), its searches recorded again in the
    order they were recorded (a family's by ``discover`` of its text, a catalog case's by
    ``survey``, as the clients did), then it is audited; the snapshot of that registry,
    and the seconds it took."""
    import time

    import registry
    from registry.api import time_budget
    from registry.language.casefile import parse_case_text

    started = time.perf_counter()
    budget = time_budget(check, corrections)
    audited = {pk for _, pk, *_ in snap.results}
    searched: dict[int, list[int]] = defaultdict(list)
    for number, (pk, *_rest) in sorted(snap.searches.items()):
        searched[pk].append(number)
    wanted: dict[str, list[int]] = defaultdict(list)
    for pk in audited | set(searched):
        wanted[snap.cases[pk][0]].append(pk)
    # the searched cases first: their searches add the derived cases audited after
    order = sorted(wanted, key=lambda c: (not any(pk in searched for pk in wanted[c]), c))
    with registry.open(target) as reg:
        for case_id in order:
            for pk in sorted(wanted[case_id], key=lambda pk: snap.cases[pk][1]):
                _, _, _, text, path = snap.cases[pk]
                case = parse_case_text(text, path or case_id)
                reg.add_case(case)
                done: set[str] = set()
                for number in searched.get(pk, []):
                    _, options, key, _ = snap.searches[number]
                    if key in done:
                        continue
                    if case_id in family_ids:
                        reg.discover(case, record=True, budget=search_seconds, jobs=1, **options)
                        done.add(key)
                    else:
                        for report in reg.survey([case_id], budget=search_seconds, jobs=1):
                            from registry.store.conversions import options_key

                            done.add(options_key(report.search.options))
                if pk in audited:
                    reg.audit([case_id], jobs=1, budget=budget, fresh=True)
        return Snapshot.read(reg.store), time.perf_counter() - started


def serial(snap: Snapshot, quiet: Snapshot, seconds: float) -> Outcome:
    out = Outcome("3", "verdicts and searches equal those of a quiet serial run")
    theirs = quiet.verdicts()
    n_compared = differ = 0
    for run, pk, claim, check, *verdict in snap.results:
        key = snap.verdict_key(pk, claim, check)
        mine = compared(key, tuple(verdict))
        n_compared += 1
        if mine not in theirs.get(key, set()):
            differ += 1
            case_id, version = snap.cases[pk][:2]
            out.fail(
                f"run {run}: {case_id} v{version} {claim_text(key[2])} {check}: "
                f"{verdict_difference(mine, theirs.get(key, set()))}"
            )

    # each case version's audit is whole: the checks of every claim it had
    serial_keys: dict[tuple[str, str], set[tuple]] = defaultdict(set)
    for key in theirs:
        serial_keys[key[:2]].add(key[2:])
    per_audit: dict[tuple[int, int], set[tuple]] = defaultdict(set)
    for run, pk, claim, check, *_ in snap.results:
        per_audit[(run, pk)].add((snap.claim_key(claim), check))
    partial = 0
    for (run, pk), keys in per_audit.items():
        expected = serial_keys[snap.version_hash(pk)]
        missing = {k for k in expected - keys if k[0] is None or k[0][0] != "discovered"}
        if missing:
            partial += 1
            case_id, version = snap.cases[pk][:2]
            out.fail(
                f"run {run}: the audit of {case_id} v{version} lacks "
                f"{sorted(map(str, missing))[:4]}"
            )

    by_key: dict[tuple, list[int]] = defaultdict(list)
    for number, (pk, _, key, _) in quiet.searches.items():
        by_key[(*quiet.version_hash(pk), key)].append(number)
    searches_differ = 0
    for number, (pk, _, key, _) in sorted(snap.searches.items()):
        case_id, content_hash = snap.version_hash(pk)
        mine = snap.search_result(number)
        others = [quiet.search_result(n) for n in by_key.get((case_id, content_hash, key), [])]
        if mine not in others:
            searches_differ += 1
            out.fail(
                f"search {number} of {case_id} v{snap.cases[pk][1]} with {key}: "
                f"{describe_difference(mine, others)}"
            )
    out.counts = {
        "verdicts compared": n_compared,
        "differ": differ,
        "case audits": len(per_audit),
        "partial": partial,
        "case versions": len({pk for _, pk in per_audit}),
        "searches compared": len(snap.searches),
        "searches differ": searches_differ,
    }
    out.notes.append(f"the serial run took {seconds:.0f} s")
    return out


def verdict_difference(mine: tuple, theirs: set[tuple]) -> str:
    """How a verdict differs from the serial run's (the fields that differ)."""
    if not theirs:
        return f"{mine[0]}, absent from the serial run"
    other = sorted(theirs)[0]
    pairs = zip(VERDICT_FIELDS, mine, other, strict=False)
    return "; ".join(f"{n} {a!r:.120} (serially {b!r:.120})" for n, a, b in pairs if a != b)


def claim_text(key: tuple | None) -> str:
    if key is None:
        return "(case)"
    return key[1] if key[0] == "claim" else f"discovered {key[1]}"


def describe_difference(mine: tuple, others: list[tuple]) -> str:
    if not others:
        return "absent from the serial run"
    other = others[0]
    names = (
        "complete",
        "coverage",
        "known",
        "dimensions",
        "method",
        "claims",
        "claims_complete",
    )
    pairs = zip(names, mine[0], other[0], strict=True)
    diffs = [f"{n}: {a!r} vs {b!r}" for n, a, b in pairs if a != b]
    if mine[1] != other[1]:
        diffs.append(f"findings: {mine[1]!r} vs {other[1]!r}")
    return "; ".join(diffs)[:400]


# ------------------------------------------------------------------------ 5. figures


def percentile(values: list[float], q: float) -> float:
    """The q-quantile (0..1) of ``values``, by linear interpolation (numpy's default)."""
    ordered = sorted(values)
    if not ordered:
        return float("nan")
    pos = q * (len(ordered) - 1)
    low = int(pos)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (pos - low)


def figures(journals: Journals, minutes: float) -> dict[str, Any]:
    """Operations per minute by kind, and the latency of the reads (median, p95)."""
    done = [e for e in journals.entries if "op" in e and "elapsed" in e and "error" not in e]
    kinds = Counter(e["op"] for e in done)
    latency: dict[str, list[float]] = defaultdict(list)
    for e in done:
        if e["op"] in ("read", "site", "verify-db"):
            latency[e["kind"]].append(e["seconds"])
    latency["all reads"] = [
        s for kind in ("cases", "verdicts", "searches") for s in latency.get(kind, [])
    ]
    events = [event for e in done for event in e.get("events", [])]
    return {
        "minutes": minutes,
        "dask_events": len(events),
        "dask_lost": sum("lost" in event for event in events),
        "operations": dict(kinds),
        "per_minute": {k: n / minutes for k, n in kinds.items()},
        "errors": dict(Counter(e["op"] for e in journals.errors())),
        "latency": {
            kind: {
                "n": len(values),
                "median": statistics.median(values) if values else float("nan"),
                "p95": percentile(values, 0.95),
                "max": max(values, default=float("nan")),
            }
            for kind, values in latency.items()
        },
        "mean_elapsed": {
            k: statistics.fmean(e["elapsed"] for e in done if e["op"] == k) for k in kinds
        },
    }


def figure_lines(found: dict[str, Any]) -> Iterable[str]:
    total = sum(found["operations"].values())
    yield (
        f"throughput: {total} operations in {found['minutes']:.1f} min "
        f"({total / found['minutes']:.1f}/min)"
    )
    for kind, n in sorted(found["operations"].items(), key=lambda kv: -kv[1]):
        yield (
            f"    {kind:10} {n:6d}  {found['per_minute'][kind]:7.1f}/min  "
            f"mean {found['mean_elapsed'][kind]:6.2f} s each"
        )
    if found["dask_events"]:
        yield (
            f"    Dask events seen by the clients: {found['dask_events']} "
            f"({found['dask_lost']} of a worker lost, its tasks done elsewhere)"
        )
    if found["errors"]:
        yield f"    failed operations: {found['errors']}"
    yield "read latency under that load (seconds):"
    for kind, stats in found["latency"].items():
        yield (
            f"    {kind:10} n={stats['n']:5d}  median {stats['median']:.3f}  "
            f"p95 {stats['p95']:.3f}  max {stats['max']:.3f}"
        )
