"""The registry's own classification of the reference paper's torque class (issue 33,
part 4): mu = grad phi + lam gamma + k, with phi a polynomial of degree <= 3 in gamma (lam
gamma and k are grad phi for phi of degree 2 and 1), on the Kovalevskaya, Goryachev-
Chaplygin and Lagrange bodies with a linear potential (the families of data/families/).

Each family is searched with all 19 coefficients of phi free, at weighted degree 4
(weights M 1, gamma 2: Kovalevskaya's integral and Goryachev-Chaplygin's are of degree 4
and 3 there), and recorded in the registry (``Registry.discover(record=True)``; the catalog of
data/cases is added first, to identify the sets with): its
special sets become derived cases whose integrals the next audit decides. Printed: one
Markdown table per family (each special set, the catalog cases it is the same system as,
whether its integrals are new, the integrals), the completeness and the time; what
docs/classifications.md shows.

    python scripts/classify.py [--db URL] [--jobs N] [--scheduler ADDRESS] [--fresh]
                               [--family kovalevskaya ...]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import registry  # noqa: E402
from registry.api import Registry  # noqa: E402
from registry.language.casefile import load_case  # noqa: E402

FAMILIES = ROOT / "data" / "families"
BODIES = ("kovalevskaya", "goryachev-chaplygin", "lagrange")
WEIGHTS = {"M": 1, "gamma": 2}
DEGREE = 4


def classify(reg: Registry, body: str, *, jobs, scheduler, fresh: bool):
    """The recorded search of one body's family, every parameter free."""
    path = FAMILIES / f"{body}-gradient-torque.toml"
    free = list(load_case(path).parameters)
    return reg.discover(
        path,
        degree=DEGREE,
        weights=WEIGHTS,
        free=free,
        record=True,
        fresh=fresh,
        budget=3600,
        jobs=jobs,
        scheduler=scheduler,
    )


def table(body: str, document: dict) -> str:
    """The family's special sets as a Markdown table, with its completeness and time."""
    lines = [
        f"### {body} body: {len(document['free'])} free parameters, degree {DEGREE}",
        "",
        f"complete: {'yes' if document['complete'] else 'no'}; "
        f"{document['seconds']:.0f} s; generic values: "
        f"{len(document['generic']['integrals'])} extra integral(s)",
        "",
        "| special set (the other coefficients free) | same system as | new | integrals |",
        "|---|---|---|---|",
    ]
    for found in document["special"]:
        same = ", ".join(f"`{s['case']}`" for s in found.get("same_as", [])[:3])
        more = len(found.get("same_as", [])) - 3
        same += f" and {more} more" if more > 0 else ""
        integrals = "; ".join(f"`{i}`" for i in found["integrals"])
        lines.append(
            f"| {', '.join(found['when'])} | {same or 'none'} | {found['new']} | {integrals} |"
        )
    if not document["special"]:
        lines.append("| none | | | |")
    if not document["complete"]:
        lines += ["", "not covered: " + "; ".join(document["coverage"])]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", default=str(ROOT / "data" / "registry.sqlite"))
    parser.add_argument("--jobs", type=int, help="worker processes (default: one per core)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address, or local:N")
    parser.add_argument("--fresh", action="store_true", help="search again, not reuse")
    parser.add_argument("--family", action="append", choices=BODIES, help="only these bodies")
    args = parser.parse_args(argv)
    with registry.open(args.db) as reg:
        reg.add(ROOT / "data" / "cases")  # the catalog its sets are identified with
        for body in args.family or BODIES:
            found = classify(reg, body, jobs=args.jobs, scheduler=args.scheduler, fresh=args.fresh)
            print(table(body, found.document()), end="\n\n", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
