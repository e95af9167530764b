"""Benchmark of the audit, with ratios measured side by side in the same run.

1. The literature catalog (data/cases, sub-folders included, and the Hamiltonian-form
   cases of tests/data/hamiltonian; the systems on the paper's state M, gamma, which the
   lean verifier writes out), audited fresh in worker
   processes (all checks and corrections) and decided by a lean independent verifier (exact
   values at random points, expanded numerators, Groebner reduction on level sets; no
   corrections) in as many processes, both forked from this process before anything warms
   its caches: the wall times side by side, and disagreements.
2. The seed catalog (data/cases), audited fresh: all checks and corrections, in
   worker processes; then the same checks (no corrections) against a naive
   baseline that applies plain ``sympy.simplify`` to every residual.
3. A generated stress catalog (seeded): random polynomial and rational torques
   mu = psi gamma + grad phi with a true claim (C = s + phi) and a false one.
   Ours against the baseline on a sample, and the time per case as the catalog
   grows, with peak memory.

Usage: python scripts/bench_audit.py [--sizes 10 100 1000] [--baseline-sample 20]

With ``--profile`` (nothing else runs): the catalog (data/cases, sub-folders included;
``--seed``: the seed catalog, data/cases/*.toml)
audited fresh in this process, one case after another as a worker audits its batches,
and where the time went, sorted, largest first: per check kind, per correction search
(the torque's family, the corrected Casimir, the corrected torque), per condition
search, per numeric evidence (the drift curves of refuted claims; with ``--numeric``,
every claim's evidence) and per case. The timing wraps the audit's functions from here
(monkeypatched for this process only); the package has no timing code of its own.
``--functions N`` adds cProfile's N most expensive functions (cumulative time; the
profiler slows the audit down about twofold).

Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import contextlib
import random
import resource
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from dataclasses import replace
from pathlib import Path

import sympy as sp

import registry
from registry.audit import case_audit, checks, corrections, numeric_evidence
from registry.audit.case_audit import audit_case
from registry.audit.parallel import audit_cases, batches
from registry.execution.executor import LocalPool
from registry.execution.local import default_jobs
from registry.execution.time_budget import TimeBudget
from registry.language.printer import to_text
from registry.mathematics import flow
from registry.mathematics import mechanics as mech
from registry.mathematics.case_mechanics import CaseMechanics
from registry.model import Verdict

ROOT = Path(__file__).resolve().parents[1]
CHECKS = ["jacobi", "energy", "c1", "hamiltonian", "integral", "casimir"]


# --- the naive baseline: the same residuals, plain simplify --------------------


def naive_residuals(case) -> dict[tuple[str, str | None], list[sp.Expr]]:
    """The residuals of the checks the audit runs on ``case`` (those that apply to its
    system, claims on a level set left out), with every shorthand (``s``) written out."""
    m = CaseMechanics(case)
    d = m.dynamics
    out: dict[tuple[str, str | None], list[sp.Expr]] = {}
    if d.bracket is not None:
        out[("jacobi", None)] = list(m.jacobiator.values())
    if d.hamiltonian is not None:
        out[("energy", None)] = [m.time_derivative(d.hamiltonian)]
    if d.c1 is not None:
        out[("c1", None)] = list(m.casimir_residual(d.c1).values())
    if d.bracket is not None and d.hamiltonian is not None and not d.from_bracket:
        # a case that gives H has Pi grad H as its field: nothing to compare
        generated = flow.hamiltonian_field(d.bracket, d.hamiltonian, d.variables, d.shorthands)
        out[("hamiltonian", None)] = [x - y for x, y in zip(m.field, generated, strict=True)]
    for claim in case.claims:
        if claim.on:
            continue
        i = claim.expression.expr
        out[("integral", claim.label)] = list(m.integral_residual(i).values())
        if d.bracket is not None:
            out[("casimir", claim.label)] = list(m.casimir_residual(i).values())
    return {key: [d.expanded(r) for r in residuals] for key, residuals in out.items()}


def naive_verdict(residuals: list[sp.Expr], rng: random.Random) -> str:
    """verified if simplify gives 0 for every component; refuted if one is visibly
    nonzero at a random floating-point point; otherwise undecided."""
    simplified = [sp.simplify(r.subs(mech.s, mech.S_VALUE)) for r in residuals]
    if all(r == 0 for r in simplified):
        return "verified"
    for r in simplified:
        point = {x: rng.uniform(0.3, 1.3) for x in r.free_symbols}
        try:
            value = complex(r.evalf(subs=point))
        except (TypeError, ValueError):
            continue
        if abs(value) > 1e-8:
            return "refuted"
    return "undecided"


def naive_audit(cases) -> tuple[float, dict]:
    rng = random.Random(0)
    started = time.perf_counter()
    verdicts = {}
    for case in cases:
        for key, residuals in naive_residuals(case).items():
            verdicts[(case.id, *key)] = naive_verdict(residuals, rng)
    return time.perf_counter() - started, verdicts


def our_audit(cases, jobs: int = 0) -> tuple[float, dict]:
    started = time.perf_counter()
    if jobs:
        audits = [a for _, a in audit_cases(cases, LocalPool(jobs), TimeBudget())]
    else:
        audits = [audit_case(c, checks=CHECKS, corrections=False) for c in cases]
    elapsed = time.perf_counter() - started
    verdicts = {(a.case, r.check, r.claim): str(r.verdict) for a in audits for r in a.results}
    return elapsed, verdicts


def disagreements(ours: dict, naive: dict) -> list:
    """Keys where the baseline decides (verified/refuted) and we say the opposite."""
    out = []
    for key, theirs in naive.items():
        mine = ours.get(key)
        if theirs in ("verified", "refuted") and mine in ("verified", "refuted") and mine != theirs:
            out.append((key, mine, theirs))
    return out


# --- the lean verifier: an independent decision procedure, same claims ----------


def lean_decide(exprs, on=(), rng: random.Random | None = None) -> str:
    """verified / refuted / undecided for residuals that must all vanish: exact values
    at two random rational points, then the expanded numerator (reduced by the level
    set's Groebner basis), with none of the audit's machinery."""
    rng = rng or random.Random(0)
    live = [e for e in (sp.sympify(e).subs(mech.s, mech.S_VALUE) for e in exprs) if e != 0]
    if not live:
        return "verified"
    symbols = sorted(set().union(*(e.free_symbols for e in live)), key=str)
    if not on:
        for _ in range(2):
            point = {x: sp.Rational(rng.randint(1, 19), rng.randint(1, 7)) for x in symbols}
            for e in live:
                try:
                    v = e.xreplace(point)
                    if v.is_number and abs(complex(v.evalf(30))) > 1e-20:
                        return "refuted"
                except (TypeError, ValueError, ZeroDivisionError):
                    pass
    basis = None
    if on:
        polys = [sp.numer(sp.together(sp.expand(g.subs(mech.s, mech.S_VALUE)))) for g in on]
        names = set().union(*(p.free_symbols for p in [*polys, *live]))
        params = sorted(names - set(mech.STATE), key=str)
        domain = sp.QQ.frac_field(*params) if params else sp.QQ
        basis = sp.groebner(polys, *mech.STATE, order="grevlex", domain=domain)
    for e in live:
        numer = sp.expand(sp.numer(sp.together(e)))
        if basis is not None and numer != 0:
            numer = sp.numer(sp.together(basis.reduce(numer)[1]))
        if numer != 0:
            return "refuted" if not on else "undecided"
    return "verified"


def lean_pi(mu, kappa) -> sp.Matrix:
    """Pi = [[hat(M + mu), hat(gamma)], [hat(gamma), kappa hat(M)]], written out here
    (not the audit's ``poisson_tensor``), so that the verifier stays independent."""

    def hat(v):
        return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    m = sp.Matrix(mech.MOMENTUM)
    g = sp.Matrix(mech.AXIS)
    top = hat(m + sp.Matrix(mu)).row_join(hat(g))
    return top.col_join(hat(g).row_join(kappa * hat(m)))


def lean_case(case) -> dict:
    """The lean verifier's verdict on every check and claim of one case (either form:
    H given, or H = M.I^-1 M/2 + U with the paper's equations (2.2) written out)."""
    system = case.system
    mu, kappa = system.torque_exprs, system.kappa_expr
    pi = lean_pi(mu, kappa)
    if system.hamiltonian is not None:
        h = system.hamiltonian.expr
        field = list(pi * sp.Matrix(mech.gradient(h)))
    else:
        inertia, potential = system.inertia_exprs, system.potential.expr
        h = sum(m**2 / (2 * a) for m, a in zip(mech.MOMENTUM, inertia, strict=True)) + potential
        field = mech.vector_field(inertia, potential, mu, kappa)
    c1 = (kappa * sum(m**2 for m in mech.MOMENTUM) + sum(g**2 for g in mech.AXIS)) / 2
    out = {
        (case.id, "jacobi", None): lean_decide(list(mech.jacobiator(pi).values())),
        (case.id, "energy", None): lean_decide([mech.time_derivative(h, field)]),
        (case.id, "c1", None): lean_decide(list(pi * sp.Matrix(mech.gradient(c1)))),
    }
    if system.hamiltonian is None:
        generated = pi * sp.Matrix(mech.gradient(h))
        out[(case.id, "hamiltonian", None)] = lean_decide(
            [a - b for a, b in zip(field, generated, strict=True)]
        )
    for c in case.claims:
        on = [eq.expr for eq in c.on]
        i = c.expression.expr
        out[(case.id, "integral", c.label)] = lean_decide([mech.time_derivative(i, field)], on)
        grad = sp.Matrix(mech.gradient(i))
        out[(case.id, "casimir", c.label)] = lean_decide(list(pi * grad), on)
        if on:
            rates = [mech.time_derivative(g, field) for g in on]
            out[(case.id, "invariant", c.label)] = lean_decide(rates, on)
    return out


def lean_audit(cases, jobs: int) -> tuple[float, dict]:
    """The lean verifier over ``cases`` in ``jobs`` processes, as the audit runs."""
    import multiprocessing as mp

    started = time.perf_counter()
    with mp.get_context("fork").Pool(jobs) as pool:
        verdicts = {
            k: v for part in pool.map(lean_case, cases, chunksize=1) for k, v in part.items()
        }
    return time.perf_counter() - started, verdicts


# --- the profile: where one fresh audit of the catalog spends its time --------------


class Timings:
    """Wall time per (section, kind) and per instance (case, item), collected by wrapping
    functions of the audit (``patched``); nested calls count in each section they reach
    (a check that a correction re-runs counts under the correction, not the check)."""

    def __init__(self) -> None:
        self.case = ""
        self.by_kind: dict[tuple[str, str], list[float]] = defaultdict(list)
        self.instances: dict[str, list[tuple[float, str, str]]] = defaultdict(list)

    def timed(self, section: str, fn: Callable, label: Callable[..., tuple[str, str]]):
        """``fn`` recording its time under ``section``, its kind and item from ``label``."""

        def wrapper(*args, **kwargs):
            started = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                seconds = time.perf_counter() - started
                kind, item = label(*args, **kwargs)
                self.by_kind[(section, kind)].append(seconds)
                self.instances[section].append((seconds, self.case, item))

        return wrapper

    @contextlib.contextmanager
    def patched(self) -> Iterator[None]:
        """The audit's timing points wrapped, for the duration of the block."""
        saved: list[tuple[object, str, object]] = []

        def wrap(owner, name: str, section: str, label) -> None:
            original = getattr(owner, name)
            saved.append((owner, name, original))
            setattr(owner, name, self.timed(section, original, label))

        def claim_label(m, claim=None, *_, **__):
            return "", "" if claim is None else claim.label

        specs = dict(checks.CHECKS)
        for name, spec in specs.items():
            run = self.timed(
                "check", spec.run, lambda m, claim=None, _n=name: (_n, claim_label(m, claim)[1])
            )
            checks.CHECKS[name] = replace(spec, run=run)
        wrap(checks, "readable", "check", lambda *a, **k: ("(of which: residual shown)", ""))
        wrap(corrections, "recognise", "correction", lambda mu, d: ("torque family", ""))
        wrap(
            corrections,
            "corrected_casimir",
            "correction",
            lambda m, family, claim=None: ("corrected Casimir", family.name),
        )
        wrap(
            corrections,
            "corrected_torque",
            "correction",
            lambda m, claim: ("corrected torque", claim.label),
        )
        wrap(
            corrections,
            "holds_when",
            "condition",
            lambda residuals, m, target, domain=None: (
                "jacobi" if target == "jacobi" else "claim",
                target,
            ),
        )
        wrap(case_audit, "drift_curve", "numeric", lambda m, label, *a, **k: ("drift curve", label))
        wrap(
            numeric_evidence,
            "claim_drift",
            "numeric",
            lambda m, claim, *a, **k: ("evidence", claim.label),
        )
        try:
            yield
        finally:
            checks.CHECKS.update(specs)
            for owner, name, original in reversed(saved):
                setattr(owner, name, original)


SECTIONS = {
    "check": "per check kind",
    "correction": "per correction search",
    "condition": "per condition search (parameter conditions of a failed identity)",
    "numeric": "per numeric evidence (trajectories integrated)",
}


def profile(numeric: bool, top: int, functions: int, seed: bool = False) -> None:
    """Audit the catalog (``seed``: the seed catalog, data/cases/*.toml) fresh in this
    process and print where the time went."""
    files = (
        (ROOT / "data" / "cases").glob("*.toml")
        if seed
        else (ROOT / "data" / "cases").rglob("*.toml")
    )
    cases = [registry.load_case(p) for p in sorted(files)]
    order = [case for group in batches(cases) for _, case in group]
    timings = Timings()
    per_case: list[tuple[float, str]] = []
    profiler = None
    if functions:
        import cProfile

        profiler = cProfile.Profile()
    started, cpu = time.perf_counter(), time.process_time()
    with timings.patched():
        for case in order:
            timings.case = case.id
            at = time.perf_counter()
            if profiler is not None:
                profiler.enable()
            audit_case(case, numeric=numeric)
            if profiler is not None:
                profiler.disable()
            per_case.append((time.perf_counter() - at, case.id))
    wall, cpu = time.perf_counter() - started, time.process_time() - cpu
    print(
        f"== profile: fresh audit of {len(cases)} cases in this process "
        f"(all checks and corrections{', numeric evidence' if numeric else ''}): {wall:.2f} s "
        f"wall, {cpu:.2f} s processor time"
    )
    for section, title in SECTIONS.items():
        kinds = sorted(
            (
                (sum(t), len(t), max(t), kind)
                for (sec, kind), t in timings.by_kind.items()
                if sec == section
            ),
            reverse=True,
        )
        if not kinds:
            continue
        # a kind in parentheses runs inside the others (a refuted check showing its residual)
        total = sum(k[0] for k in kinds if not k[3].startswith("("))
        print(f"-- {title}: {total:.2f} s")
        print(f"   {'kind':34s} {'total s':>8s} {'calls':>6s} {'mean ms':>8s} {'max ms':>8s}")
        for total, calls, largest, kind in kinds:
            print(
                f"   {kind:34s} {total:8.2f} {calls:6d} {1000 * total / calls:8.1f} "
                f"{1000 * largest:8.1f}"
            )
        print(f"   largest {top}:")
        for seconds, case_id, item in sorted(timings.instances[section], reverse=True)[:top]:
            print(f"   {1000 * seconds:9.1f} ms  {case_id}  {item}")
    print(f"-- per case: {sum(t for t, _ in per_case):.2f} s; largest {top}:")
    for seconds, case_id in sorted(per_case, reverse=True)[:top]:
        print(f"   {1000 * seconds:9.1f} ms  {case_id}")
    if profiler is not None:
        import pstats

        print(f"-- cProfile, {functions} functions by cumulative time (profiled run):")
        pstats.Stats(profiler).sort_stats("cumulative").print_stats(functions)


# --- the stress catalog ----------------------------------------------------------


def _poly(rng: random.Random, degree: int, params: list[sp.Symbol]) -> sp.Expr:
    g = mech.AXIS
    terms = []
    for _ in range(rng.randint(2, 5)):
        mono = sp.Mul(*(rng.choice(g) for _ in range(rng.randint(1, degree))))
        coeff = sp.Rational(rng.randint(-5, 5) or 1, rng.randint(1, 3))
        terms.append(coeff * mono * (rng.choice(params) if rng.random() < 0.4 else 1))
    return sp.Add(*terms)


def stress_case_text(index: int, rng: random.Random) -> str:
    p, q = sp.symbols("p q", real=True)
    g1, g2, g3 = mech.AXIS
    phi = _poly(rng, 3, [p, q])
    psi = _poly(rng, 1, [p, q])
    if index % 2:  # a rational torque
        phi += p / (1 + g3**2)
        psi += q / (1 + g1**2)
    mu = [sp.expand(psi * g + sp.diff(phi, g)) for g in mech.AXIS]
    potential = _poly(rng, 2, [p, q])
    wrong = phi + sp.Rational(rng.randint(1, 4), rng.randint(1, 3)) * rng.choice(
        [g1 * g2, g2 * g3**2, g1**3]
    )
    torque = ", ".join(f'"{to_text(m)}"' for m in mu)
    return f'''id = "stress-{index:04d}"
title = "Generated stress case {index}"
[source]
citation = "generated by scripts/bench_audit.py"
[parameters]
A = "positive"
B = "positive"
C = "positive"
p = "real"
q = "real"
[system]
inertia = ["A", "B", "C"]
potential = "{to_text(potential)}"
torque = [{torque}]
[[claims]]
label = "true"
kind = "casimir"
expression = "s + {to_text(phi)}"
[[claims]]
label = "false"
kind = "{rng.choice(["casimir", "integral"])}"
expression = "s + {to_text(wrong)}"
'''


def stress_catalog(n: int, seed: int = 2026) -> list:
    rng = random.Random(seed)
    return [registry.parse_case_text(stress_case_text(i, rng), f"stress-{i}") for i in range(n)]


def peak_memory_mb() -> tuple[float, float]:
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return own, children


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[10, 100, 1000])
    parser.add_argument("--baseline-sample", type=int, default=20)
    parser.add_argument("--jobs", type=int, default=default_jobs())
    parser.add_argument(
        "--only-catalog", action="store_true", help="only the literature catalog (1.)"
    )
    parser.add_argument(
        "--profile",
        action="store_true",
        help="only where a fresh audit of the catalog spends its time, in this process",
    )
    parser.add_argument("--numeric", action="store_true", help="profile: numeric evidence too")
    parser.add_argument("--seed", action="store_true", help="profile: the seed catalog only")
    parser.add_argument("--top", type=int, default=15, help="profile: instances listed")
    parser.add_argument(
        "--functions", type=int, default=0, help="profile: cProfile's N costliest functions"
    )
    args = parser.parse_args()
    if args.profile:
        profile(args.numeric, args.top, args.functions, args.seed)
        return

    # first, while this process is cold: each side forks its processes from it; the
    # catalog with the Hamiltonian-form test cases (so(4), so(3,1), Kirchhoff as printed)
    catalog = [registry.load_case(p) for p in sorted((ROOT / "data" / "cases").rglob("*.toml"))]
    catalog += [
        registry.load_case(p) for p in sorted((ROOT / "tests" / "data" / "hamiltonian").glob("*"))
    ]
    # the lean verifier writes out the paper's state (M, gamma) only: a system on a state
    # of its own (its equations, or H with its own bracket) is left out on both sides
    others = [c for c in catalog if c.system.form not in ("inertia", "hamiltonian")]
    catalog = [c for c in catalog if c.system.form in ("inertia", "hamiltonian")]
    new_form = sum(c.system.hamiltonian is not None or c.system.kappa_expr != 0 for c in catalog)
    claims = sum(len(c.claims) for c in catalog)
    print(
        f"== literature catalog: {len(catalog)} cases ({new_form} in the Hamiltonian form or "
        f"on so(4), so(3,1)), {claims} claims, {args.jobs} workers; {len(others)} cases on a "
        "state of their own left out (the lean verifier writes out M, gamma only)"
    )
    started = time.perf_counter()
    full = dict(audit_cases(catalog, LocalPool(args.jobs), TimeBudget()))
    wall = time.perf_counter() - started
    lean_t, lean = lean_audit(catalog, args.jobs)
    ours = {(a.case, r.check, r.claim): str(r.verdict) for a in full.values() for r in a.results}
    inconclusive = sum(v == "inconclusive" for v in ours.values())
    print(
        f"fresh audit, all checks and corrections: {wall:.2f} s wall (target <= 15 s), "
        f"{inconclusive} inconclusive; lean verifier, same claims, no corrections: {lean_t:.2f} s; "
        f"ratio ours/lean {wall / lean_t:.2f} (target <= 1.0)"
    )
    undecided = sum(v == "undecided" for v in lean.values())
    bad = disagreements(ours, lean)
    print(
        f"  disagreements where the lean verifier decides: {len(bad)} (target 0); "
        f"it leaves {undecided} of {len(lean)} undecided"
    )
    for key, mine, theirs in bad:
        print(f"    {key}: ours {mine}, lean {theirs}")
    if args.only_catalog:
        return

    seed = [registry.load_case(p) for p in sorted((ROOT / "data" / "cases").glob("*.toml"))]
    print(f"== seed catalog: {len(seed)} cases, {args.jobs} workers")
    started = time.perf_counter()
    full = dict(audit_cases(seed, LocalPool(args.jobs), TimeBudget()))
    wall = time.perf_counter() - started
    print(f"fresh audit, all checks and corrections: {wall:.2f} s wall (target < 3 s)")
    refuted = sum(r.verdict is Verdict.REFUTED for a in full.values() for r in a.results)
    print(f"  {sum(len(a.results) for a in full.values())} results, {refuted} refuted")

    ours_t, ours = our_audit(seed)
    naive_t, naive = naive_audit(seed)
    bad = disagreements(ours, naive)
    print(
        f"identical checks, one process: ours {ours_t:.2f} s, naive simplify {naive_t:.2f} s, "
        f"ratio {naive_t / ours_t:.1f}x (target >= 5x)"
    )
    undecided = sum(v == "undecided" for v in naive.values())
    print(
        f"  disagreements where the baseline decides: {len(bad)} (target 0); "
        f"baseline undecided on {undecided} of {len(naive)}"
    )
    for key, mine, theirs in bad:
        print(f"    {key}: ours {mine}, baseline {theirs}")

    print("== stress catalog (seeded)")
    sample = stress_catalog(args.baseline_sample)
    ours_t, ours = our_audit(sample)
    naive_t, naive = naive_audit(sample)
    bad = disagreements(ours, naive)
    expected_ok = all(
        ours[(c.id, "casimir", "true")] == "verified"
        and ours[(c.id, str(c.claim("false").kind), "false")] == "refuted"
        for c in sample
    )
    print(
        f"{len(sample)} cases, identical checks: ours {ours_t:.2f} s, naive {naive_t:.2f} s, "
        f"ratio {naive_t / ours_t:.1f}x; disagreements {len(bad)}; "
        f"true claims verified and false ones refuted: {expected_ok}"
    )
    for n in args.sizes:
        cases = stress_catalog(n)
        started = time.perf_counter()
        audits = dict(audit_cases(cases, LocalPool(args.jobs), TimeBudget()))
        wall = time.perf_counter() - started
        inconclusive = sum(
            r.verdict is Verdict.INCONCLUSIVE for a in audits.values() for r in a.results
        )
        own, children = peak_memory_mb()
        print(
            f"  {n:5d} cases: {wall:7.2f} s wall, {1000 * wall / n:6.1f} ms per case, "
            f"{inconclusive} inconclusive, peak memory {own:.0f} MB (parent), "
            f"{children:.0f} MB (largest worker)"
        )


if __name__ == "__main__":
    main()
