"""Benchmark of the audit on systems given by their equations or their bracket, against
a plain sympy check of the same claims in the same run (issue 31, part 5).

Ours: ``audit_case`` of a case (every check, corrections and drift curves included), in
this process, after one warm-up (imports), sympy's cache cleared before every run. The
baseline: what a careful user of plain sympy does for each claim: the residual (dI/dt,
div(rho v), or each Pi grad F) with the field's definitions written out, then
``sympy.simplify``, decided zero or not; no Jacobi check (the audit proves it besides).
Cases: the Kowalevski top in two fields (nine variables, a given bracket), and
Chaplygin's ball in (M, gamma) with its density (a square root) and its energy (omega
rational in M and gamma). Times are CPU seconds of this process (the cores are shared);
the baseline's limit is wall clock, and a baseline that does not finish in it is printed
as "> limit".

Usage: python scripts/bench_any_form.py [--repeat 3] [--timeout 120]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import sympy as sp
from sympy.core.cache import clear_cache

from registry import audit_case, load_case
from registry.execution.time_budget import BudgetExceeded, time_limit
from registry.mathematics import flow

ROOT = Path(__file__).resolve().parents[1]
CASES = {
    "two fields: Kowalevski top (9 variables, bracket)": ROOT
    / "data/cases/two-fields/ryabov-2014-two-field-kowalevski-top.toml",
    "Chaplygin's ball: density and energy": ROOT
    / "tests/data/any-form/chaplygin-ball-derived-claims.toml",
}


def limited(seconds: float, fn):
    """fn(), or BudgetExceeded after ``seconds`` of wall clock."""
    with time_limit(seconds):
        return fn()


def cpu(fn) -> float:
    clear_cache()  # no run profits from sympy's cache of an earlier one
    started = time.process_time()
    fn()
    return time.process_time() - started


def plain_sympy(path: Path) -> bool:
    """Every claim of the case by residual and ``simplify``; True when all vanish."""
    case = load_case(path)
    dyn = case.dynamics
    field = [dyn.expanded(v) for v in dyn.field]
    ok = True
    for claim in case.claims:
        f = dyn.expanded(claim.expression.expr)
        if str(claim.kind) == "measure":
            residuals = [sum(sp.diff(f * v, x) for x, v in zip(dyn.variables, field, strict=True))]
        elif str(claim.kind) == "casimir":
            residuals = list(flow.bracket_gradient(dyn, f))
        else:
            residuals = [sum(sp.diff(f, x) * v for x, v in zip(dyn.variables, field, strict=True))]
        ok = ok and all(sp.simplify(r) == 0 for r in residuals)
    return ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=120.0)
    args = parser.parse_args()
    print(f"{'case':55} {'audit s':>8} {'sympy s':>9} {'ratio':>7}")
    for name, path in CASES.items():
        case = load_case(path)
        audit_case(case)  # warm-up: imports and caches
        ours = min(cpu(lambda c=case: audit_case(c)) for _ in range(args.repeat))
        try:
            theirs = cpu(lambda p=path: limited(args.timeout, lambda: plain_sympy(p)))
            shown, ratio = f"{theirs:9.2f}", f"{theirs / ours:7.1f}"
        except BudgetExceeded:
            shown, ratio = f"> {args.timeout:.0f}", f"> {args.timeout / ours:.0f}"
        print(f"{name:55} {ours:8.2f} {shown:>9} {ratio:>7}")


if __name__ == "__main__":
    main()
