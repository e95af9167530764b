"""The main job: load the seed catalog into the default database, audit it, print the verdicts.

Usage: python scripts/audit.py [--db PATH|URL] [--json]
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
    args = parser.parse_args(argv)
    with registry.open(args.db) as reg:
        refused = [r for r in reg.add(args.cases) if r.status == "refused"]
        for r in refused:
            for line in str(r.error).splitlines():
                print(f"Error: {line}", file=sys.stderr)
        report = reg.audit()
        if args.json:
            print(json.dumps(report.document(), indent=2))
        else:
            print(verdict_table(report.outcomes(), report.run))
    return 1 if refused else 0


if __name__ == "__main__":
    sys.exit(main())
