"""Benchmark of ``registry discover`` against a naive sympy search, side by side.

The three searches of the issue, on families that do not name their answers:

1. the heavy top A = B = 1, C = 1/lam, centre of mass (1, 0, 0), degree 4, free lam
   (target <= 0.5 s; the answer is lam = 1 and lam = 2);
2. the same on s = 0, degree 3 (target <= 0.3 s; lam = 1 and lam = 4);
3. centre of mass (1, 0, z0), degree 4, free lam and z0 (target <= 10 s, complete).

Then the general bracket (issue 20), timed the same way:

4. the audit of a case with a degree-4 integral on so(4) (Komarov's Kovalevskaya
   analogue: the catalog's case where there is one, else tests/data/hamiltonian's),
   all checks and corrections (target well under 1 s);
5. a search at degree 6 with weights M = 1, gamma = 1 (924 monomials) at a point of
   the Sokolov-Wolf family, which must find its sextic integral (target < 10 s). Where
   the catalog has no case of that family yet, Kovalevskaya's top on so(4) at degree 6
   stands in (same ansatz, a quartic extra integral), and the line says so.

Then classification scale (issue 21), with several free parameters:

6. moments (1, b, c), centre of mass (1, 0, z0), free b, c, z0, degree 4 (target < 60 s,
   complete: the four classical sets);
7. diagonal Kirchhoff, moments (1, B, C) and potential (b1 g1^2 + b2 g2^2 + b3 g3^2)/2,
   five free parameters, degree 2 at weights M = 1, gamma = 1 (Clebsch's condition);
8. the same at degree 4 on s = 0 (Chaplygin's case besides); 7 and 8 target < 10 min.

Then a classification at the scale of the published lists (issue 33, part 6):

10. the reference paper's torque class on the Kovalevskaya body
    (data/families/kovalevskaya-gradient-torque.toml): mu = grad phi, phi cubic in
    gamma, all 19 coefficients free, degree 4 at weights M = 1, gamma = 2 (target < 10
    min on two cores, complete: Yehia's gyrostat and the quadratic integral of
    data/cases/discovered/).

Then the survey of the whole catalog (issue 21, item 5):

9. ``Registry.survey`` of every case of ``data/cases`` on a fresh throwaway SQLite
   database, in one process and in two (--jobs 2; target < 30 s on two cores), with the
   load average beside each time, the counts the main job prints and the slowest
   searches.

Each is timed in one process, in two local processes (--jobs 2) and on a Dask cluster
of two local worker processes started once (local:2, the cluster's start not counted),
in one process with the ansatz not split along the field's symmetries (the results
must be the same), and as a ratio to search 1 timed in the same run (the machine is
shared: ratios are what compares across runs).

Each is timed in this process after one warm-up search (imports and sympy's caches
are not what is measured), proofs of the reported integrals included. The naive
baseline builds the whole system with sympy expressions and matrices (no blocks),
takes its rank over Q(p) with DomainMatrix, the special values from the factored
determinant of a random projection computed symbolically, and the integrals there
with sympy's nullspace. It runs in a child process with a time cap: past it the
ratio printed is a lower bound.

Usage: python scripts/bench_discover.py [--repeat 5] [--baseline-cap 300]
       [--only-general | --only-scale | --only-classification | --only-survey]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import itertools
import multiprocessing as mp
import os
import queue as queue_module
import random
import statistics
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import sympy as sp
from sympy.polys.matrices import DomainMatrix

import registry
from registry.api import discover_file
from registry.audit.case_audit import audit_case
from registry.discovery.ansatz import count_monomials
from registry.discovery.search import discover, search_options
from registry.language.casefile import load_case
from registry.mathematics import mechanics as mech
from registry.model import Expression

ROOT = Path(__file__).resolve().parents[1]
FAMILIES = ROOT / "tests" / "data" / "families"

SEARCHES = [
    ("1 parameter, degree 4", "heavy-top-lam", dict(degree=4, free=["lam"]), 0.5),
    ("s = 0, degree 3", "heavy-top-lam", dict(degree=3, free=["lam"], on=["s = 0"]), 0.3),
    ("2 parameters, degree 4", "heavy-top-lam-z0", dict(degree=4, free=["lam", "z0"]), 10.0),
]


# --- the naive baseline ---------------------------------------------------------------


def naive_search(name: str, degree: int, free: list[str], on: list[str] = ()) -> list:
    """Special values of the free parameters where the kernel of A(p) grows, naively."""
    case = load_case(FAMILIES / f"{name}.toml")
    params = [case.parameters[f] for f in free]
    field = mech.vector_field(case.system.inertia_exprs, case.system.potential.expr, (0, 0, 0))
    weights = (1, 1, 1, 2, 2, 2)
    monomials = [
        sp.Mul(*(x**e for x, e in zip(mech.STATE, exps, strict=True)))
        for exps in itertools.product(range(degree + 1), repeat=6)
        if 1 <= sum(a * w for a, w in zip(exps, weights, strict=True)) <= degree
    ]
    coeffs = sp.symbols(f"c0:{len(monomials)}")
    F = sum(c * m for c, m in zip(coeffs, monomials, strict=True))
    rate = sp.numer(sp.together(sp.expand(mech.time_derivative(F, field))))
    if on:
        rate = sp.reduced(sp.expand(rate), [mech.S_VALUE], *mech.STATE)[1]
    rows = [[sp.expand(c).coeff(k) for k in coeffs] for c in sp.Poly(rate, *mech.STATE).coeffs()]
    A = sp.Matrix(rows)
    generic = DomainMatrix.from_Matrix(A).convert_to(sp.QQ.frac_field(*params)).rank()
    rnd = random.Random(0)
    R = sp.Matrix(generic, A.rows, lambda i, j: rnd.randint(-3, 3))
    S = sp.Matrix(A.cols, generic, lambda i, j: rnd.randint(-3, 3))
    projected = (R * A * S).applyfunc(sp.expand)
    ring = sp.ZZ[tuple(params)]
    det = DomainMatrix.from_Matrix(projected).convert_to(ring).det()
    special = []
    for factor, _ in sp.factor_list(ring.to_sympy(det))[1]:
        symbols = factor.free_symbols & set(params)
        if len(symbols) == 1 and sp.degree(factor, *symbols) == 1:
            (p,) = symbols
            for value in sp.solve(factor, p):  # empty where the root breaks an assumption
                at = A.subs(p, value)
                if at.rank() < generic:
                    special.append((str(p), str(value), len(at.nullspace())))
    return special


def _run_naive(queue, name, options):
    started = time.perf_counter()
    try:
        found = naive_search(name, **options)
    except Exception as err:  # reported by the parent, not waited for until the cap
        found = [("error", repr(err), 0)]
    queue.put((time.perf_counter() - started, found))


def naive_timed(name: str, options: dict, cap: float) -> tuple[float, bool, list]:
    """(seconds, finished, special values) of the naive search in a child process."""
    context = mp.get_context("fork")
    queue = context.Queue()
    child = context.Process(target=_run_naive, args=(queue, name, options), daemon=True)
    started = time.perf_counter()
    child.start()
    try:
        seconds, found = queue.get(timeout=cap)  # before join: the child flushes its result
    except queue_module.Empty:
        child.kill()
        child.join()
        return time.perf_counter() - started, False, []
    child.join()
    return seconds, True, found


# --- ours --------------------------------------------------------------------------------


def ours_timed(name: str, options: dict, repeat: int) -> tuple[float, object]:
    """Median seconds of ``repeat`` searches (after one warm-up), and the last result."""
    path = FAMILIES / f"{name}.toml"
    discover_file(path, jobs=1, **options)
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        report = discover_file(path, jobs=1, **options)
        times.append(time.perf_counter() - started)
    return statistics.median(times), report.search


# --- the general bracket (issue 20) -------------------------------------------------------

SO4_FIXTURE = ROOT / "tests" / "data" / "hamiltonian" / "kovalevskaya-so4.toml"


def catalog_case(*words: str):
    """The first catalog case whose id holds every word, or None."""
    for path in sorted((ROOT / "data" / "cases").rglob("*.toml")):
        if all(w in path.stem for w in words):
            return load_case(path)
    return None


def sextic_case():
    """The first catalog case on so(4) or so(3,1) with a claimed integral of degree 6 in
    M and gamma (Sokolov and Wolf's), its claims dropped (the search must find it), or
    None."""
    for path in sorted((ROOT / "data" / "cases").rglob("*.toml")):
        case = load_case(path)
        if case.system.kappa_expr == 0:
            continue
        for claim in case.claims:
            expr = claim.expression.expr.subs(mech.s, mech.S_VALUE)
            if not claim.on and expr.is_polynomial(*mech.STATE):
                if sp.Poly(expr, *mech.STATE).total_degree() == 6:
                    return replace(case, claims=())
    return None


def median_seconds(fn, repeat: int) -> tuple[float, object]:
    fn()
    times, result = [], None
    for _ in range(repeat):
        started = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - started)
    return statistics.median(times), result


def general_bracket(repeat: int) -> None:
    case = catalog_case("komarov", "so4", "kovalevskaya") or load_case(SO4_FIXTURE)
    seconds, audit = median_seconds(lambda: audit_case(case), repeat)
    verdicts = ", ".join(
        " ".join(x for x in (r.check, r.claim, str(r.verdict)) if x) for r in audit.results
    )
    print(f"audit of {case.id} (so(4), degree-4 integral): {seconds:.3f} s (target < 1 s)")
    print(f"  {verdicts}")
    sextic = sextic_case()
    stand_in = sextic is None
    if stand_in:
        sextic = load_case(SO4_FIXTURE)
        sextic = replace(
            sextic,
            system=replace(
                sextic.system,
                kappa=Expression("1", sp.Integer(1)),
                hamiltonian=Expression(
                    "M1**2 + M2**2 + 2*M3**2 + 2*gamma1",
                    sextic.system.hamiltonian.expr.subs(sextic.parameters["c"], 1),
                ),
            ),
            parameters={},
            claims=(),
        )
    options = search_options(sextic, degree=6, weights=(1, 1))
    seconds, search = median_seconds(lambda: discover(sextic, options), max(1, repeat // 2))
    label = (
        "Kovalevskaya on so(4) (kappa = c = 1) standing in: no case on so(4) or so(3,1) "
        "with a sextic integral in the catalog"
        if stand_in
        else sextic.id
    )
    print(
        f"search at degree 6, weights M=1, gamma=1 ({count_monomials(6, (1,) * 6)} monomials), "
        f"{label}: {seconds:.2f} s (target < 10 s), extra {search.generic.extra}, complete "
        f"{search.complete}"
    )
    for text in search.generic.integrals:
        print(f"  {text[:120]}{'...' if len(text) > 120 else ''}")


SCALE = [
    ("(b, c, z0), degree 4", "heavy-top-b-c-z0", dict(degree=4, free=["b", "c", "z0"]), 60.0),
    (
        "5 parameters, degree 2",
        "kirchhoff-diagonal",
        dict(degree=2, weights=(1, 1), free=["B", "C", "b1", "b2", "b3"]),
        600.0,
    ),
    (
        "5 parameters, degree 4 on s = 0",
        "kirchhoff-diagonal",
        dict(degree=4, weights=(1, 1), on=["s = 0"], free=["B", "C", "b1", "b2", "b3"]),
        600.0,
    ),
]


#: Search 10: the classification of the torque class mu = grad phi, phi cubic (all of
#: data/families/kovalevskaya-gradient-torque.toml's 19 coefficients free).
TORQUE_CLASS = ROOT / "data" / "families" / "kovalevskaya-gradient-torque"
CLASSIFICATION = [
    (
        "19 parameters (mu = grad phi, phi cubic), degree 4",
        TORQUE_CLASS,
        dict(
            degree=4,
            weights={"M": 1, "gamma": 2},
            free=list(load_case(f"{TORQUE_CLASS}.toml").parameters),
        ),
        600.0,
    ),
]


def family_file(name: str | Path) -> Path:
    """A test family by its name, or a family file given by its path without suffix."""
    return Path(f"{name}.toml") if isinstance(name, Path) else FAMILIES / f"{name}.toml"


def once(name: str | Path, options: dict, **how) -> tuple[float, object]:
    """Seconds of one search (``how``: jobs, scheduler) and its result."""
    started = time.perf_counter()
    report = discover_file(family_file(name), budget=1800, **options, **how)
    return time.perf_counter() - started, report.search


def with_and_without_symmetries(name: str, options: dict) -> tuple[float, float, bool, int]:
    """Processor seconds of one search in this process with the ansatz split along the
    field's symmetries (registry.discovery.symmetry) and of one without (both after the
    timed searches above, so that caches are warm alike; processor time, since the
    machine is shared), whether their results are the same, and how many searched sets
    were split."""
    case = load_case(family_file(name))
    opts = search_options(case, **options)
    seconds, searches = [], []
    for symmetries in (True, False):
        started = time.process_time()
        searches.append(discover(case, opts, budget=1800, symmetries=symmetries))
        seconds.append(time.process_time() - started)
    a, b = searches
    same = (a.generic, a.special, a.complete, a.dimensions) == (
        b.generic,
        b.special,
        b.complete,
        b.dimensions,
    )
    used = sum("split into" in p for p in a.method.split("; "))
    return seconds[0], seconds[1], same, used


def scale(repeat: int, searches: list = SCALE) -> None:
    """Searches 6-8 (or 10): one process, two processes, a local Dask cluster of two
    workers, and one process without symmetries."""
    from registry.execution.cluster import cluster_client

    reference, _ = ours_timed("heavy-top-lam", dict(degree=4, free=["lam"]), repeat)
    print(f"reference (search 1, 1 parameter, degree 4): {reference:.3f} s")
    with cluster_client("local:2") as client:
        once("heavy-top-lam", dict(degree=4, free=["lam"]), scheduler=client)  # warm workers
        for label, name, options, target in searches:
            one, search = once(name, options, jobs=1)
            two, search2 = once(name, options, jobs=2)
            dask, search3 = once(name, options, scheduler=client)
            found = "; ".join(", ".join(s.when) for s in search.special)
            same = search.special == search2.special == search3.special
            print(
                f"{label}: {one:.2f} s (target < {target:g} s; {one / reference:.0f}x search 1), "
                f"complete {search.complete}, {len(search.special)} special sets: {found}"
            )
            print(
                f"  --jobs 2: {two:.2f} s (speed-up {one / two:.2f}); local:2 Dask: "
                f"{dask:.2f} s (speed-up {one / dask:.2f}); same result: {same}"
            )
            cpu, plain, kept, used = with_and_without_symmetries(name, options)
            print(
                f"  symmetries: {cpu:.2f} s of processor time with them, {plain:.2f} s without "
                f"(ratio {cpu / plain:.2f}; {used} of the searched sets split); same result: "
                f"{kept}"
            )


def survey(repeat: int) -> None:
    """Search 9: the whole catalog's survey, in one process and in two."""
    reference, _ = ours_timed("heavy-top-lam", dict(degree=4, free=["lam"]), repeat)
    print(f"reference (search 1, 1 parameter, degree 4): {reference:.3f} s")
    for jobs in (1, 2):
        with tempfile.TemporaryDirectory() as folder:
            with registry.open(Path(folder) / "survey.sqlite") as reg:
                reg.add(ROOT / "data" / "cases")
                load = os.getloadavg()[0]
                started = time.perf_counter()
                reports = reg.survey(jobs=jobs)
                seconds = time.perf_counter() - started
        searches = [r.search for r in reports]
        new = sum(len(s.generic.new) + sum(x.extra for x in s.special) for s in searches)
        again = sum(len(s.generic.rediscovered) for s in searches)
        complete = len({s.case for s in searches if s.claims_complete})
        undecided = sum(not s.decided for s in searches)
        target = " (target < 30 s)" if jobs == 2 else ""
        print(
            f"survey of the catalog, --jobs {jobs}: {seconds:.1f} s{target}, "
            f"{seconds / reference:.0f}x search 1 (load average {load:.1f} at the start, "
            f"{os.getloadavg()[0]:.1f} at the end); {len(searches)} searches: {new} new "
            f"integral(s), {again} rediscovered, {complete} case(s) with complete claims, "
            f"{undecided} not decided"
        )
        slowest = sorted(searches, key=lambda s: -s.seconds)[:5]
        named = [
            s.case
            + (" on " + ", ".join(e.text for e in s.options.on) if s.options.on else "")
            + f" {s.seconds:.1f} s"
            for s in slowest
        ]
        print("  slowest: " + "; ".join(named))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--baseline-cap", type=float, default=300.0)
    parser.add_argument("--only-general", action="store_true", help="only searches 4 and 5")
    parser.add_argument("--only-scale", action="store_true", help="only searches 6 to 8")
    parser.add_argument("--only-survey", action="store_true", help="only the survey (9)")
    parser.add_argument(
        "--only-classification", action="store_true", help="only the torque class (10)"
    )
    args = parser.parse_args()
    if args.only_classification:
        scale(args.repeat, CLASSIFICATION)
        return
    if args.only_scale:
        scale(args.repeat)
        return
    if args.only_survey:
        survey(args.repeat)
        return
    general_bracket(args.repeat)
    if args.only_general:
        return
    for label, name, options, target in SEARCHES:
        ours, search = ours_timed(name, options, args.repeat)
        found = "; ".join(", ".join(s.when) for s in search.special)
        print(
            f"{label}: ours {ours:.3f} s (target <= {target:g} s), complete "
            f"{search.complete}, special: {found}"
        )
        naive_options = {k: v for k, v in options.items() if k != "on"}
        naive_options["on"] = options.get("on", [])
        seconds, finished, naive = naive_timed(name, naive_options, args.baseline_cap)
        if finished:
            values = "; ".join(f"{p} = {v}" for p, v, _ in naive)
            print(f"  naive sympy {seconds:.1f} s, ratio {seconds / ours:.0f}x; special: {values}")
        else:
            print(
                f"  naive sympy did not finish within {args.baseline_cap:.0f} s: "
                f"ratio > {seconds / ours:.0f}x"
            )
    scale(args.repeat)
    scale(args.repeat, CLASSIFICATION)
    survey(args.repeat)


if __name__ == "__main__":
    main()
