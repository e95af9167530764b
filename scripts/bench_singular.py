"""The rank-drop locus of a classification search, computed by the registry and by
Singular on the same matrices, side by side in one run (issue 33, part 6;
../shared/CLASSIFICATION_ANCHOR.md).

A family search (``registry discover --free ...``) finds where the ansatz's matrix
A(p) loses rank. The search hands ``locus.drop_locus`` one matrix per block of the
ansatz and per weight cut-off, over Q[p] (p the free parameters; the symbolic ones stay
in the ground field). Each such matrix, with the rank it has for generic p, is given
here to both:

* the registry: ``drop_locus`` (case splitting on pivots, ``discovery.splitting``);
* Singular: the ideal of the minors of that size, saturated by the product of the
  parameters the assumptions keep nonzero, decomposed by ``minAssGTZ`` (what the anchor
  measured), each matrix its own Singular process with a time limit.

Printed: per family, the number of matrices, the registry's total time, Singular's total
time over the matrices it finished, and how many it did not finish within the limit.
Singular must be on the PATH (``apt-get install singular``); without it the script says
so and stops. Nothing here is asserted by the tests: machines are shared and noisy.

    python scripts/bench_singular.py [--limit SECONDS] [--family NAME ...]
"""

from __future__ import annotations

import argparse
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sympy as sp  # noqa: E402

from registry.discovery import search  # noqa: E402
from registry.discovery.locus import drop_locus  # noqa: E402
from registry.discovery.search import discover, search_options  # noqa: E402
from registry.language.casefile import load_case  # noqa: E402

FAMILIES = ROOT / "tests" / "data" / "families"

#: (family file, degree, weights, free parameters): the anchor's heavy top with three
#: free parameters, and the same top with five.
RUNS = {
    "heavy-top-b-c-z0": ("heavy-top-b-c-z0", 4, {"M": 1, "gamma": 2}, ["b", "c", "z0"]),
    "heavy-top-five": ("heavy-top-five", 4, {"M": 1, "gamma": 2}, ["b", "c", "x0", "y0", "z0"]),
}


def captured(name: str) -> list[tuple]:
    """Every matrix the family's search hands ``drop_locus``: (rows, rank, free, positive,
    nonzero)."""
    file, degree, weights, free = RUNS[name]
    case = load_case(FAMILIES / f"{file}.toml")
    seen: list[tuple] = []

    def keep(rows, rho, nfree, rnd, *, positive=frozenset(), nonzero=frozenset(), spread=None):
        seen.append(([dict(r) for r in rows], rho, nfree, positive, nonzero))
        return drop_locus(rows, rho, nfree, rnd, positive=positive, nonzero=nonzero)

    search.drop_locus = keep  # this process only: the search's call, recorded
    try:
        discover(case, search_options(case, degree=degree, weights=weights, free=free))
    finally:
        search.drop_locus = drop_locus
    return [m for m in seen if m[0] and m[1] > 0]


def ours(matrices: list[tuple]) -> float:
    """The registry's time for every matrix, one after another."""
    started = time.perf_counter()
    for rows, rho, nfree, positive, nonzero in matrices:
        drop_locus(rows, rho, nfree, random.Random(0), positive=positive, nonzero=nonzero)
    return time.perf_counter() - started


def singular_script(rows, rho: int, nfree: int, positive, nonzero) -> str:
    """The matrix's rank-drop locus in Singular: minors, saturation, minimal primes."""
    ring = next(iter(rows[0].values())).ring
    names = [str(s) for s in ring.symbols]
    columns = sorted({k for r in rows for k in r})
    index = {k: j for j, k in enumerate(columns)}

    def text(value) -> str:
        return sp.sstr(sp.expand(value.as_expr())).replace("**", "^")

    entries = []
    for r in rows:
        line = ["0"] * len(columns)
        for k, v in r.items():
            line[index[k]] = text(v)
        entries.extend(line)
    free, symbolic = names[:nfree], names[nfree:]
    field = f"(0, {', '.join(symbolic)})" if symbolic else "0"
    units = [names[i] for i in sorted(set(positive) | set(nonzero)) if i < nfree]
    unit = "*".join(units) if units else "1"
    return "\n".join(
        [
            'LIB "primdec.lib";',
            f"ring r = {field}, ({', '.join(free)}), dp;",
            f"matrix M[{len(rows)}][{len(columns)}] = {', '.join(entries)};",
            f"ideal I = minor(M, {rho});",
            f"ideal S = sat(I, ideal({unit}))[1];",
            "list L = minAssGTZ(S);",
            'print("components " + string(size(L)));',
            "quit;",
        ]
    )


def singular(matrices: list[tuple], limit: float) -> tuple[float, int]:
    """Singular's total time over the matrices it finished within ``limit`` seconds each,
    and how many it did not finish."""
    total, unfinished = 0.0, 0
    with tempfile.TemporaryDirectory() as folder:
        for i, matrix in enumerate(matrices):
            path = Path(folder) / f"m{i}.sing"
            path.write_text(singular_script(*matrix))
            started = time.perf_counter()
            try:
                done = subprocess.run(
                    ["Singular", "-q", str(path)], capture_output=True, text=True, timeout=limit
                )
            except subprocess.TimeoutExpired:
                unfinished += 1
                continue
            if "components" not in done.stdout:
                raise RuntimeError(f"Singular failed on matrix {i}: {done.stdout[-500:]}")
            total += time.perf_counter() - started
    return total, unfinished


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=60.0, help="seconds per matrix")
    parser.add_argument("--family", action="append", choices=RUNS, help="only these")
    args = parser.parse_args()
    if shutil.which("Singular") is None:
        print("Singular is not on the PATH (apt-get install singular): nothing to compare")
        return 1
    for name in args.family or list(RUNS):
        matrices = captured(name)
        mine = ours(matrices)
        theirs, unfinished = singular(matrices, args.limit)
        largest = max(len(m[0]) * len({k for r in m[0] for k in r}) for m in matrices)
        print(
            f"{name}: {len(matrices)} matrices (largest {largest} entries); "
            f"registry {mine:.2f} s; Singular {theirs:.2f} s over the "
            f"{len(matrices) - unfinished} it finished, {unfinished} not finished within "
            f"{args.limit:g} s each"
            + (f"; ratio Singular/registry {theirs / mine:.1f}" if not unfinished else "")
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
