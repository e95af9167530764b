"""The live view of an SQLite registry (``registry serve``): the database opened in
Datasette, with metadata describing its tables and a few canned queries.

Datasette is an optional extra (``pip install -e '.[serve]'``). The static site
(``registry site``) is what to publish, cite and archive; the live view is for a group
working on one SQLite file: any table and any read-only SQL, filtered and faceted in
the browser, always the current state. This module only describes the tables and writes
the queries; it runs no SQL itself.
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path
from typing import Any

from ..errors import RegistryError

#: What each table holds, for Datasette's table pages.
TABLES: dict[str, str] = {
    "sources": "One row per source in the literature: citation, DOI and structured fields.",
    "cases": "One row per stored case version: id, version, title, the case file's text "
    "and content hash, the system's expressions, when it was added.",
    "case_aliases": "Earlier ids of a case version (a renamed case is found under either).",
    "claims": "One row per claim of a case version: label, kind (integral, casimir, measure "
    "or relation), "
    "expression and level set in the case-file language; provenance literature or "
    "discovered (attached by a recorded search).",
    "audit_runs": "One row per audit run: start and end (UTC), status, code and sympy "
    "versions, options, the process that ran it.",
    "check_results": "Every verdict of every run: check, verdict (verified, refuted, "
    "inconclusive, error), the method that decided, the reason, the residual and the "
    "witness point of a refutation. Never overwritten.",
    "corrections": "Families, re-checked corrections (Casimirs, torques) and parameter "
    "conditions found by each run.",
    "evidence": "Numerical evidence of each run: drift of a claim next to that of H.",
    "drift_curves": "The trajectory each run integrated for a refuted claim, to draw its drift.",
    "searches": "Recorded searches for polynomial integrals, with their completeness statement.",
    "discoveries": "Sets of parameter values where a search found integrals, and the integrals.",
    "exponents": "Kovalevskaya analyses of case versions: balances, exponents, Yoshida's "
    "degrees, the Painlevé test and the statement (the JSON document of registry exponents).",
    "identifications": "Which catalog cases each case version is the same system as (registry "
    "identify): their parameter values and the transformation, the cases compared, skipped "
    "and failed, and the catalog compared with.",
    "latest_verdicts": "The newest verdict of every check and claim of the newest case "
    "versions (a view).",
}

#: Canned queries: name -> (title, description, SQL). Read-only; ``:case`` is a parameter.
QUERIES: dict[str, tuple[str, str, str]] = {
    "refuted_claims": (
        "Refuted claims",
        "Claims whose newest verdict for their own kind (integral or casimir) is refuted, "
        "with the residual and the witness point.",
        """select v."case", v.claim, c.kind, v.method, v.residual, v.witness, v.run
from latest_verdicts v
join cases k on k.case_id = v."case" and k.version = v.version
join claims c on c.case_pk = k.id and c.label = v.claim
where v.verdict = 'refuted' and v."check" = c.kind
order by v."case", v.claim""",
    ),
    "cases_by_source": (
        "Cases by source",
        "Each source with its year, DOI and the ids of the cases taken from it.",
        """select s.citation, s.year, s.doi, count(distinct k.case_id) as cases,
  group_concat(distinct k.case_id) as ids
from sources s join cases k on k.source_id = s.id
group by s.id
order by s.year, s.citation""",
    ),
    "verdicts_of_a_case": (
        "Verdicts of a case",
        "The newest verdict of every check of one case (give its id).",
        'select claim, "check", verdict, method, reason, run\n'
        'from latest_verdicts where "case" = :case\n'
        'order by claim is not null, claim, "check"',
    ),
    "search_statements": (
        "What the searches establish",
        "Every recorded search with its completeness statement.",
        """select s.id as search, k.case_id as "case", k.version, s.complete, s.statement
from searches s join cases k on k.id = s.case_pk
order by s.id""",
    ),
}


def metadata(database: Path) -> dict[str, Any]:
    """Datasette's metadata for the registry in the SQLite file ``database``."""
    name = Path(database).stem
    return {
        "title": "Registry of rigid-body integrability claims",
        "description": "Cases from the literature, their claimed integrals and every "
        "verdict of their audits. A verdict is a mathematical statement: verified is "
        "proven symbolically, refuted comes with a checked witness point.",
        "license": "MIT",
        "databases": {
            name: {
                "tables": {table: {"description": text} for table, text in TABLES.items()},
                "queries": {
                    key: {"title": title, "description": description, "sql": sql}
                    for key, (title, description, sql) in QUERIES.items()
                },
            }
        },
    }


def serve(database: str | None, host: str = "127.0.0.1", port: int = 8001) -> None:
    """Serve the SQLite file ``database`` with Datasette until interrupted (Ctrl-C).

    RegistryError when the registry is not an SQLite file or Datasette is missing."""
    if not database or database == ":memory:":
        raise RegistryError(
            "registry serve opens an SQLite file; a PostgreSQL registry is browsed with "
            "the static site (registry site) or any PostgreSQL client"
        )
    try:
        from datasette.cli import cli
    except ImportError:
        raise RegistryError(
            "registry serve needs Datasette: pip install 'rigid-body-registry[serve]'"
        ) from None
    with tempfile.TemporaryDirectory() as scratch:
        meta = Path(scratch) / "metadata.json"
        meta.write_text(json.dumps(metadata(Path(database)), indent=2), encoding="utf-8")
        args = ["serve", database, "--metadata", str(meta), "--host", host, "--port", str(port)]
        cli.main(args=args, prog_name="registry serve", standalone_mode=False)
