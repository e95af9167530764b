"""The main job: load the catalog into the default database, audit it, print the verdicts.

Before the audit every case gets its recorded search (``Registry.survey``: which
polynomial integrals it has up to the degree its claims reach); what a search finds is
a claim that this audit decides. Stored audits and searches are reused.

Usage: python scripts/audit.py [--db PATH|URL] [--json] [--no-survey]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import registry
from registry.presentation.verdict_table import verdict_table

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", default=str(ROOT / "data" / "registry.sqlite"))
    parser.add_argument("--cases", default=str(ROOT / "data" / "cases"))
    parser.add_argument("--json", action="store_true", help="print the JSON document instead")
    parser.add_argument("--no-survey", action="store_true", help="skip the recorded searches")
    args = parser.parse_args(argv)
    with registry.open(args.db) as reg:
        refused = [r for r in reg.add(args.cases) if r.status == "refused"]
        for r in refused:
            for line in str(r.error).splitlines():
                print(f"Error: {line}", file=sys.stderr)
        surveyed = [] if args.no_survey else reg.survey()
        report = reg.audit()
        if args.json:
            print(json.dumps(report.document(), indent=2))
        else:
            print(verdict_table(report.outcomes(), report.run))
            if surveyed:
                undecided = sum(not r.search.decided for r in surveyed)
                print(
                    f"{len(surveyed)} recorded searches ({undecided} not decided: "
                    "non-polynomial systems or level sets); list them with: registry searches"
                )
    return 1 if refused else 0


if __name__ == "__main__":
    sys.exit(main())
