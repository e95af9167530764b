"""Benchmark against the closest peer, the PyPI package ``poissongeometry``.

Same inputs, same run: for each case of the seed catalog without arbitrary
functions, Pi_mu is handed to ``PoissonGeometry(6).is_poisson_bivector`` and
each claim to ``is_casimir``; ours are the ``jacobi`` and ``casimir`` checks.
Prints both times, their ratio, and any disagreement of the verdicts. Then, in the same
run, the seed audit end to end (``bench_startup.fresh_audit``: the 16 seed files added
to a new database and ``registry audit`` on it, whole processes, start-up, every check
and correction included), best of ``--audit-repeat``, and the peer's total time for its
checks as a ratio to it.

Install the peer first: python -m pip install -e '.[peer]'
Usage: python scripts/bench_peer.py [--cap SECONDS] [--audit-repeat N]

The peer simplifies every Jacobiator component; where one call exceeds the cap
(default 120 s) it is stopped and counted at the cap, so the ratio printed is
then a lower bound.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import sympy as sp

import registry
from registry.audit.case_audit import audit_case
from registry.execution.time_budget import BudgetExceeded, time_limit
from registry.mathematics import mechanics as mech

try:
    from poisson.poisson import PoissonGeometry
except ImportError:  # the peer is an optional extra
    raise SystemExit(
        "poissongeometry is not installed: python -m pip install -e '.[peer]'"
    ) from None

ROOT = Path(__file__).resolve().parents[1]


def peer_inputs(case):
    """Pi_mu as poissongeometry's bivector dict, and the claims, in its variables x1..x6."""
    names = {v: sp.Symbol(f"x{i + 1}") for i, v in enumerate(mech.STATE)}
    # parameters renamed: the peer sympifies strings, where names such as N or E are taken
    names.update({p: sp.Symbol(f"c{i}") for i, p in enumerate(case.parameters.values())})

    def text(expr):
        return str(sp.sympify(expr).subs(mech.s, mech.S_VALUE).xreplace(names))

    pi = mech.poisson_tensor(case.system.torque_exprs)
    bivector = {(i + 1, j + 1): text(pi[i, j]) for i in range(6) for j in range(i + 1, 6)}
    claims = {c.label: text(c.expression.expr) for c in case.claims if not c.on}
    return bivector, claims


def capped(call, cap: float):
    """The peer's answer, or 'timeout' when it takes longer than ``cap`` seconds."""
    try:
        with time_limit(cap):
            return call()
    except BudgetExceeded:
        return "timeout"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cap", type=float, default=120.0)
    parser.add_argument("--audit-repeat", type=int, default=2)
    args = parser.parse_args()
    cap = args.cap
    cases = [
        c
        for c in (registry.load_case(p) for p in sorted((ROOT / "data" / "cases").glob("*.toml")))
        if not c.functions
    ]
    peer = PoissonGeometry(6)
    ours_total = theirs_total = 0.0
    disagreements = []
    print(f"{'case':36} {'ours':>8} {'peer':>8}  verdicts (ours / peer)", flush=True)
    for case in cases:
        bivector, claims = peer_inputs(case)
        started = time.perf_counter()
        audit = audit_case(case, checks=["jacobi", "casimir"], corrections=False)
        ours = time.perf_counter() - started
        started = time.perf_counter()
        theirs = {"jacobi": capped(lambda b=bivector: peer.is_poisson_bivector(b), cap)}
        for label, function in claims.items():
            theirs[label] = capped(lambda b=bivector, f=function: peer.is_casimir(b, f), cap)
        peer_time = time.perf_counter() - started
        ours_total += ours
        theirs_total += peer_time
        mine = {"jacobi": audit.result("jacobi").verdict.value}
        mine.update({lbl: audit.result("casimir", lbl).verdict.value for lbl in claims})
        for key, value in theirs.items():
            if value != "timeout" and (value is True) != (mine[key] == "verified"):
                disagreements.append((case.id, key, mine[key], value))
        shown = ", ".join(f"{k}: {mine[k]} / {theirs[k]}" for k in theirs)
        print(f"{case.id:36} {ours:8.3f} {peer_time:8.3f}  {shown}", flush=True)
    print(
        f"total: ours {ours_total:.2f} s, poissongeometry {theirs_total:.2f} s, "
        f"ratio {theirs_total / ours_total:.1f}x (target >= 20x)"
    )
    print(f"disagreements: {len(disagreements)}")
    for d in disagreements:
        print("  ", d)
    from bench_startup import fresh_audit  # scripts/ is on the path of a script it runs

    add, audit, n = fresh_audit(args.audit_repeat)
    end_to_end = add + audit
    print(
        f"seed audit end to end ({n} files, registry add + registry audit, fresh database, "
        f"best of {args.audit_repeat}): {end_to_end:.2f} s (add {add:.2f} s, audit "
        f"{audit:.2f} s); poissongeometry's checks / it: {theirs_total / end_to_end:.1f}x "
        "(target >= 20x)"
    )


if __name__ == "__main__":
    main()
