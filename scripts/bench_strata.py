"""Benchmark of the Painlevé strata (``discovery.painleve_strata``): where a family with
several free parameters can pass the ARS test, in one process and with the strata of
each depth examined by a pool of worker processes, in the same run, with their ratio.

The default family is the heavy top with moments (1, b, c) and centre of mass
(x0, y0, z0) (tests/data/families/heavy-top-five.toml), whose passing sets are Euler's,
the spherical top, and Lagrange's and Kovalevskaya's for each pair of equal moments;
tests/data/families/heavy-top-distinct-moments.toml with --free p,q,x0,y0,z0 is every
top with distinct moments, where only Euler's passes and the list is complete.
Times are wall clock (the pool's work is in other processes); the outcomes of the two
runs are compared, set by set.

Usage: python scripts/bench_strata.py [--family FILE --free P,Q,...] [--jobs 2]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import multiprocessing
import time
from pathlib import Path

from registry.discovery.exponents import case_field, exponent_options
from registry.discovery.painleve_strata import Strata, painleve_strata
from registry.language.casefile import load_case

ROOT = Path(__file__).resolve().parents[1]
FAMILY = ROOT / "tests" / "data" / "families" / "heavy-top-five.toml"
FREE = "b,c,x0,y0,z0"


def run(path: Path, free: list[str], jobs: int) -> tuple[Strata, float]:
    case = load_case(path)
    found = case_field(case, exponent_options(case, free=free))
    start = time.perf_counter()
    if jobs == 1:
        strata = painleve_strata(found.variables, found.field, found.weights, found.free)
    else:
        with multiprocessing.get_context("fork").Pool(jobs) as pool:
            strata = painleve_strata(
                found.variables, found.field, found.weights, found.free, mapper=pool.map
            )
    return strata, time.perf_counter() - start


def shown(strata: Strata) -> list[str]:
    return [f"{s.text()} ({', '.join(map(str, s.free)) or 'a point'})" for s in strata.passing]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--family", type=Path, default=FAMILY)
    parser.add_argument("--free", default=FREE)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    free = args.free.split(",")
    one, t1 = run(args.family, free, 1)
    pooled, tn = run(args.family, free, args.jobs)
    print(f"{args.family.name}, free {', '.join(free)}: {one.visited} strata")
    print(f"  one process      {t1:8.1f} s")
    print(f"  {args.jobs} processes      {tn:8.1f} s   ratio {t1 / tn:.2f}")
    print(f"  same outcome: {shown(one) == shown(pooled) and one.undecided == pooled.undecided}")
    print(f"  complete: {one.complete}; passing sets:")
    for text in shown(one):
        print(f"    {text}")
    for text in one.undecided:
        print(f"  not decided: {text}")


if __name__ == "__main__":
    main()
