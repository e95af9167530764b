"""The main job: load the catalog into the default database, audit it, print the verdicts.

Before the audit every case gets its recorded search (``Registry.survey``: which
polynomial integrals it has up to the degree its claims reach) and its Kovalevskaya
analysis under the same weights; what a search finds that is not one of the case's claims
again is a claim that this audit decides. Stored audits, searches and analyses are reused.
The main job is a first look: each search has SURVEY_SECONDS and each analysis
EXPONENT_SECONDS, and what runs out says so in its record (``registry survey`` and
``registry exponents ID`` take longer, and make again what ran out of a smaller budget).

Usage: python scripts/audit.py [--db PATH|URL] [--json] [--no-survey]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import registry
from registry.presentation.text_table import wrapped

ROOT = Path(__file__).resolve().parents[1]
#: Seconds for each search and each Kovalevskaya analysis of the main job.
SURVEY_SECONDS = 20.0
EXPONENT_SECONDS = 3.0


def survey_line(searches: list) -> str:
    """The survey in one line: what the literature already claimed (rediscovered), what
    the registry found (new), where the claims span every integral searched for."""
    undecided = sum(not s.decided for s in searches)
    new = sum(len(s.generic.new) + sum(x.extra for x in s.special) for s in searches)
    again = sum(len(s.generic.rediscovered) for s in searches)
    complete = sorted({s.case for s in searches if s.claims_complete})
    return (
        f"{len(searches)} recorded searches: {new} new integral(s), {again} rediscovered "
        f"claim(s), {len(complete)} case(s) whose claims span every integral up to the "
        f"searched degree; {undecided} not decided (refused systems, with the reason); "
        "list them with: registry searches"
    )


def exponents_line(reports: list) -> str:
    """The Kovalevskaya analyses made beside the survey's searches in one line: how many
    were decided, passed the Painlevé (ARS) test, and had every degree Yoshida's theorem
    allows within their case's complete search (``discovery.every_degree``)."""
    analyses = {
        (r.search.case, repr(r.exponents.options.as_dict())): r.exponents
        for r in reports
        if r.exponents is not None
    }
    decided = [a for a in analyses.values() if a.decided]
    passing = sum(a.passes is True for a in decided)  # None: the test was not made
    witnessed = sum(a.passes is False for a in analyses.values() if not a.decided)
    within = len({r.search.case for r in reports if r.bounded})
    return (
        f"{len(analyses)} Kovalevskaya analyses: {len(decided)} decided, {passing} passing "
        f"the ARS test; of the others, {witnessed} failing it for generic values (a "
        f"witness at rational values); {within} case(s) with every degree Yoshida allows "
        "searched; see reg.exponents()"
    )


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
        surveyed = (
            []
            if args.no_survey
            else reg.survey(budget=SURVEY_SECONDS, exponent_budget=EXPONENT_SECONDS)
        )
        report = reg.audit()
        if args.json:
            print(json.dumps(report.document(), indent=2))
        else:
            print(report.table())  # wrapped to the terminal, as registry audit prints it
            if surveyed:
                width = registry.api.terminal_width()
                print(wrapped(survey_line([r.search for r in surveyed]), width))
                print(wrapped(exponents_line(surveyed), width))
            print(wrapped(identification_line(reg.cases()), width))
    return 1 if refused else 0


def identification_line(cases) -> str:
    """Which cases are recorded as the same system as another (``registry identify``,
    not run by the main job: the catalog against itself takes minutes)."""
    identified = cases[cases["same_as"].notna()]
    if not len(identified):
        return (
            "Same systems: not identified yet; registry identify compares every case with "
            "the others (a few minutes), then registry cases and the site show them"
        )
    same = sum(bool(s) for s in identified["same_as"])
    return (
        f"Same systems: {same} of {len(identified)} identified cases are the same system as "
        "another case; see reg.identifications()"
    )


if __name__ == "__main__":
    sys.exit(main())
