"""Benchmark of identification with the catalog (issue 33, part 6: one special set against
the whole catalog in under 1 s).

1. the catalog index of ``data/cases`` built cold (an empty ``$REGISTRY_CACHE``: every
   case's normal form, reachable support and prepared matching data computed), then
   read again from the cache folder in a fresh process state;
2. the Kovalevskaya point (t1 = t2 = t3 = 0) of the diagonal-torque family
   (tests/data/families/kovalevskaya-diagonal-torque.toml) identified against every
   case of the index: the cases it is (with the claims' carrying not counted);
3. the same for the Lagrange body with a linear potential and no torque, and for a
   heavy top with moments 1, 2, 3 (asymmetric-heavy-top), a member of the catalog's
   general heavy-top cases only: the special cases must be ruled out or fail to match.

4. with --catalog, every case of the catalog against all the others in this process
   (what ``registry identify`` does, one case per worker): the total, the slowest
   cases, and how many are the same system as another.

CPU seconds (process time) are printed beside wall seconds: the machine is shared.
Usage: python scripts/bench_identify.py [--repeat 3] [--catalog]
Nothing here is asserted by the tests.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import sympy as sp

ROOT = Path(__file__).resolve().parents[1]


def timed(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--catalog", action="store_true", help="every case against the others")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-identify-") as cache:
        os.environ["REGISTRY_CACHE"] = cache  # cold: an empty cache folder, removed after
        run(args.repeat, args.catalog)


def run(repeat: int, catalog: bool) -> None:

    from registry.discovery.identification import catalog_index  # noqa: PLC0415
    from registry.discovery.identification.identify import identify  # noqa: PLC0415
    from registry.language.casefile import load_case  # noqa: PLC0415
    from registry.language.forms import with_values  # noqa: PLC0415

    cases = [load_case(p) for p in sorted((ROOT / "data" / "cases").rglob("*.toml"))]
    index, wall, cpu = timed(lambda: catalog_index.CatalogIndex.of(cases))
    print(f"index of {len(cases)} cases, cold: {wall:.2f} s wall, {cpu:.2f} s CPU")
    unindexed = index.unindexed()
    print(f"  {len(unindexed)} cases not compared (no normal form):")
    for case_id, reason in sorted(unindexed.items()):
        print(f"    {case_id}: {reason}")
    catalog_index._CACHE.clear()
    index, wall, cpu = timed(lambda: catalog_index.CatalogIndex.of(cases))
    print(f"index read from the cache folder: {wall:.2f} s wall, {cpu:.2f} s CPU")

    families = ROOT / "tests" / "data" / "families"
    diagonal = load_case(families / "kovalevskaya-diagonal-torque.toml")
    point = with_values(
        diagonal, {diagonal.parameters[t]: sp.Integer(0) for t in ("t1", "t2", "t3")}
    )
    lagrange = next(c for c in cases if c.id == "lagrange-1788-heavy-top")
    asymmetric = load_case(families / "asymmetric-heavy-top.toml")
    for name, dynamics, exclude in (
        ("Kovalevskaya point of the diagonal torque", point.dynamics, ()),
        ("lagrange-1788-heavy-top", lagrange.dynamics, (lagrange.id,)),
        ("asymmetric heavy top (general cases only)", asymmetric.dynamics, ()),
    ):
        best = None
        for _ in range(repeat):
            found, wall, cpu = timed(lambda d=dynamics, e=exclude: identify(d, index, exclude=e))
            best = (wall, cpu) if best is None or cpu < best[1] else best
        assert best is not None
        print(
            f"{name}: {len(found.same)} cases ({', '.join(s.case for s in found.same[:4])}"
            f"{', ...' if len(found.same) > 4 else ''}), {len(found.compared)} compared, "
            f"best of {repeat}: {best[0]:.2f} s wall, {best[1]:.2f} s CPU"
        )
    if catalog:
        times = []
        for case in cases:
            found, wall, cpu = timed(lambda c=case: identify(c.dynamics, index, exclude=(c.id,)))
            times.append((cpu, case.id, len(found.same)))
        same = sum(1 for _, _, n in times if n)
        print(
            f"the catalog against itself: {sum(t for t, _, _ in times):.1f} s CPU for "
            f"{len(cases)} cases, {same} the same system as another; slowest:"
        )
        for cpu, case_id, n in sorted(times, reverse=True)[:5]:
            print(f"    {case_id}: {cpu:.2f} s CPU, {n} cases")


if __name__ == "__main__":
    main()
