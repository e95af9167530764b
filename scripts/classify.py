"""The registry's own classification of the reference paper's torque class (issue 33,
part 4): mu = grad phi + lam gamma + k, with phi a polynomial of degree <= 3 in gamma (lam
gamma and k are grad phi for phi of degree 2 and 1), on the Kovalevskaya, Goryachev-
Chaplygin and Lagrange bodies with a linear potential (the families of data/families/).

Each family is searched with all 19 coefficients of phi free, at weighted degree 4
(weights M 1, gamma 2: Kovalevskaya's integral and Goryachev-Chaplygin's are of degree 4
and 3 there); so is a part of Wolf and Efimovskaya's e(3) setting (issue 33, part 3:
quadratic Hamiltonians at the Kovalevskaya ratio, eight coefficients free, degree 4 at
weights M 1, gamma 1, also on s = 0; and at Goryachev-Chaplygin's ratio on s = 0, degree
3). Each search is recorded in the registry
(``Registry.discover(record=True)``; the catalog of data/cases is added first, to
identify the sets with): its special sets become derived cases whose integrals the next
audit decides. Printed: one Markdown table per family (each special set, the catalog
cases it is the same system as, whether its integrals are new, the integrals), the
completeness and the time; what docs/classifications.md shows.

    python scripts/classify.py [--db URL] [--jobs N] [--scheduler ADDRESS] [--fresh]
                               [--family kovalevskaya|goryachev-chaplygin|lagrange|
                                         wolf-kovalevskaya-ratio|wolf-kovalevskaya-ratio-s0|
                                         wolf-goryachev-chaplygin-ratio ...]
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import registry  # noqa: E402
from registry.api import Registry  # noqa: E402
from registry.language.casefile import load_case  # noqa: E402

FAMILIES = ROOT / "data" / "families"


@dataclass(frozen=True)
class Family:
    """A family file of data/families/ and the ansatz it is classified with."""

    name: str
    degree: int
    weights: dict[str, int]
    #: the level set searched on (Goryachev-Chaplygin's integrals hold on s = 0)
    on: tuple[str, ...] = ()


#: The torque class on three bodies (weights M 1, gamma 2: Kovalevskaya's integral has
#: degree 4, Goryachev-Chaplygin's 3), and a part of Wolf and Efimovskaya's e(3) setting
#: at the Kovalevskaya ratio (weights M 1, gamma 1: its quartic integrals have degree 4),
#: on the whole phase space and on s = 0 (Chaplygin's entry), and at Goryachev-Chaplygin's
#: ratio on s = 0 (its cubic integrals).
CLASSIFIED = {
    "kovalevskaya": Family("kovalevskaya-gradient-torque", 4, {"M": 1, "gamma": 2}),
    "goryachev-chaplygin": Family("goryachev-chaplygin-gradient-torque", 4, {"M": 1, "gamma": 2}),
    "lagrange": Family("lagrange-gradient-torque", 4, {"M": 1, "gamma": 2}),
    "wolf-kovalevskaya-ratio": Family("wolf-e3-kovalevskaya-ratio", 4, {"M": 1, "gamma": 1}),
    "wolf-kovalevskaya-ratio-s0": Family(
        "wolf-e3-kovalevskaya-ratio", 4, {"M": 1, "gamma": 1}, ("s = 0",)
    ),
    "wolf-goryachev-chaplygin-ratio": Family(
        "wolf-e3-goryachev-chaplygin-ratio", 3, {"M": 1, "gamma": 1}, ("s = 0",)
    ),
}


def classify(reg: Registry, family: Family, *, jobs, scheduler, fresh: bool):
    """The recorded search of one family, every parameter free."""
    path = FAMILIES / f"{family.name}.toml"
    free = list(load_case(path).parameters)
    return reg.discover(
        path,
        degree=family.degree,
        weights=family.weights,
        free=free,
        on=list(family.on),
        record=True,
        fresh=fresh,
        budget=3600,
        jobs=jobs,
        scheduler=scheduler,
    )


def table(name: str, document: dict) -> str:
    """The family's special sets as a Markdown table, with its completeness and time."""
    lines = [
        f"### {name}: {len(document['free'])} free parameters, degree {document['degree']}"
        + (f", on {', '.join(document['on'])}" if document.get("on") else ""),
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
    parser.add_argument("--family", action="append", choices=CLASSIFIED, help="only these")
    args = parser.parse_args(argv)
    with registry.open(args.db) as reg:
        reg.add(ROOT / "data" / "cases")  # the catalog its sets are identified with
        for name in args.family or CLASSIFIED:
            found = classify(
                reg, CLASSIFIED[name], jobs=args.jobs, scheduler=args.scheduler, fresh=args.fresh
            )
            print(table(name, found.document()), end="\n\n", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
