"""Benchmark of the Kovalevskaya exponents, against a straightforward sympy baseline in
the same run.

Ours: ``exponents`` (balances by Groebner bases and shape position, exponents per
component in k[u]/(g)), without and with the Painlevé test. The baseline: ``sympy.solve``
on the balance equations -w c = v(c), the zero solution dropped, and
``Matrix.eigenvals`` of K = Dv(c) + diag(w) at each solution. For each case: the
times, their ratio, the balances each found, and whether the exponents agree on the
balances both found (families compared at a generic point). Times are CPU seconds of
this process (the machine's cores are shared); the baseline's time limit is wall clock.

With ``--catalog``: every case of data/cases (recursively) analysed as the survey's main
job analyses it beside its search on the whole phase space (``runs.exponents_run``:
``_options`` of the first of ``stated_options``), each in a fresh process under a
generous budget (``--budget``, default 120 s; of CPU time with ``--cpu``, for a loaded
machine, else wall clock as in the survey), printed sorted by CPU time with the
result's summary (decided, balances, exponents, Painlevé test), and how many were
decided within ``--within`` seconds (default ``BESIDE_SEARCH_EXPONENT_SECONDS``).

With ``--conditions``: the failing compatibility conditions of Bobylev's top (over
Q(B, C, a), at balances written in square roots), each written at its balance in the
normal form of its square roots (``algebraic.value_at_root``) against sympy's ``radsimp``
of the substituted expression (what was done before), in the same run, with the two
compared at random rational values.

With ``--radicals``: the varying exponents of the heavy top with moments (1, 1, c) and
its centre anywhere, at balances whose coordinates bring I and square roots of the
parameters, by the quadratic formula (what the analysis does) against sympy's ``roots``
(what it did), in the same run, compared at a random point.

With ``--translations``: Kirchhoff's equations with the potential sum a_i gamma_i**2/2,
whose field involves only the differences of the a_i: the analysis over Q(a1, a2, a3)
(under ``--timeout``) against the one with a3 = 0 (``parameter_translations``), in the
same run.

With ``--witness``: heavy tops with symbolic parameters, the analysis over Q(parameters)
(under ``--timeout``) against the witness at rational values that the ARS test fails for
generic values (``exponent_witness``), in the same run, with both verdicts.

Usage: python scripts/bench_exponents.py [--timeout 120] [--repeat 3]
       python scripts/bench_exponents.py --witness [--timeout 120]
       python scripts/bench_exponents.py --translations [--timeout 120]
       python scripts/bench_exponents.py --conditions
       python scripts/bench_exponents.py --radicals [--timeout 120]
       python scripts/bench_exponents.py --catalog [--budget 120] [--cpu] [--jobs 1] [--only TEXT]
                                         [--save FILE.json]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import functools
import json
import multiprocessing
import statistics
import time
from collections import Counter
from pathlib import Path

import sympy as sp
from sympy.core.cache import clear_cache

from registry.execution.time_budget import BudgetExceeded, time_limit
from registry.mathematics import mechanics as mech
from registry.mathematics.exponent_analysis import exponents

ROOT = Path(__file__).resolve().parents[1]
WEIGHTS = (1, 1, 1, 2, 2, 2)
HALF, THIRD = sp.Rational(1, 2), sp.Rational(1, 3)
CASES = {
    "Euler (1, 2, 3)": ((1, 2, 3), (0, 0, 0)),
    "Lagrange (1, 1, 1/3), r = (0, 0, 1)": ((1, 1, THIRD), (0, 0, 1)),
    "Kovalevskaya (2, 2, 1), r = (1, 0, 0)": ((2, 2, 1), (1, 0, 0)),
    "Goryachev-Chaplygin (4, 4, 1), r = (1, 0, 0)": ((4, 4, 1), (1, 0, 0)),
    "asymmetric (3, 4, 5), r = (1, 0, 0)": ((3, 4, 5), (1, 0, 0)),
    "asymmetric (1, 2, 3), r = (1, 1, 1)": ((1, 2, 3), (1, 1, 1)),
}


def heavy_top(inertia, r):
    potential = sum(ri * g for ri, g in zip(r, mech.AXIS, strict=True))
    return [sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0))]


def limited(seconds: float, fn):
    """fn(), or BudgetExceeded after ``seconds`` of wall clock."""
    with time_limit(seconds):
        return fn()


def baseline(field):
    """sympy.solve on the balance equations, then eigenvals at every nonzero solution."""
    # plain symbols: solve drops complex solutions of the state's real=True symbols
    variables = sp.symbols("M1 M2 M3 gamma1 gamma2 gamma3")
    field = [v.xreplace(dict(zip(mech.STATE, variables, strict=True))) for v in field]
    equations = [sp.expand(v + w * x) for v, w, x in zip(field, WEIGHTS, variables, strict=True)]
    matrix = sp.Matrix(field).jacobian(variables) + sp.diag(*WEIGHTS)
    found = []
    for solution in sp.solve(equations, variables, dict=True):
        point = {x: solution.get(x, x) for x in variables}
        if all(sp.simplify(v) == 0 for v in point.values()):
            continue
        eigen = matrix.subs(point).eigenvals()
        found.append(Counter({sp.simplify(e): m for e, m in eigen.items()}))
    return found


def ours(field, painleve: bool):
    return exponents(mech.STATE, field, WEIGHTS, painleve=painleve)


def best(repeat: int, fn):
    times, value = [], None
    for _ in range(repeat):
        clear_cache()
        start = time.process_time()  # CPU time: the cores are shared, the wall clock noisy
        value = fn()
        times.append(time.process_time() - start)
    return min(times), value


def spectra(result) -> list[Counter]:
    return [Counter(sp.simplify(v) for v in b.exponents.values) for b in result.balances]


def same(spectrum: Counter, others: list[Counter]) -> bool:
    """Whether a spectrum is one of ``others`` (numerically at 30 digits, values with
    their multiplicities: the two sides write the same numbers differently)."""

    def key(c: Counter):
        return sorted(
            (round(complex(sp.N(v, 30)).real, 12), round(complex(sp.N(v, 30)).imag, 12), m)
            for v, m in c.items()
        )

    return any(key(spectrum) == key(o) for o in others)


CATALOG = Path(__file__).resolve().parent.parent / "data" / "cases"


def catalog_case(work: tuple[str, float, bool]) -> tuple[str, float, float, str, dict | None]:
    """One catalog case analysed as beside the survey's search: (file, CPU seconds, wall
    seconds, summary, the result's document without its seconds)."""
    from registry.discovery.exponents import analyse_case
    from registry.discovery.survey import stated_options
    from registry.errors import ExponentError
    from registry.language.casefile import load_case
    from registry.runs.exponents_run import _options

    path, budget, cpu_budget = work
    if cpu_budget:  # the budget in CPU seconds: the machine's load does not eat it
        import registry.discovery.exponents as module

        module.time_limit = functools.partial(time_limit, cpu=True)
    cpu, wall = time.process_time(), time.perf_counter()
    document = None
    try:
        case = load_case(path)
        options = _options(case, stated_options(case)[0])
        if options is None:
            summary = "no options (weights name a vector the case lacks)"
        else:
            document = dict(analyse_case(case, options, budget=budget).document)
            document.pop("seconds", None)
            summary = summarise(document)
    except ExponentError as err:
        summary = "refused: " + " ".join(str(err).split())[:150]
    return path, time.process_time() - cpu, time.perf_counter() - wall, summary, document


def summarise(document: dict) -> str:
    """decided, balances (with their exponents), the Painlevé verdict, in one line."""
    if not document.get("decided"):
        return "undecided: " + document.get("reason", "")
    parts = [f"decided; {len(document['balances'])} balances"]
    for b in document["balances"]:
        along = f" dim {b['dimension']}" if b.get("dimension") else ""
        parts.append(f"[{', '.join(b['exponents'])}]{along}")
    pain = document["painleve"]
    parts.append(
        f"degrees {document['degrees']}; painleve passes={pain['passes']} "
        f"compatible={pain['compatible']} conditions={len(pain['conditions'])}"
    )
    return "; ".join(parts)


def catalog(args) -> None:
    from registry.settings import BESIDE_SEARCH_EXPONENT_SECONDS

    files = sorted(str(p) for p in CATALOG.rglob("*.toml"))
    if args.only:
        files = [f for f in files if args.only in f]
    within = args.within or BESIDE_SEARCH_EXPONENT_SECONDS
    with multiprocessing.get_context("fork").Pool(args.jobs, maxtasksperchild=1) as pool:
        rows = []
        for row in pool.imap_unordered(catalog_case, [(f, args.budget, args.cpu) for f in files]):
            rows.append(row)
            print(f"  {row[1]:8.2f} {Path(row[0]).stem}", flush=True)
    rows.sort(key=lambda r: r[1])
    if args.save:
        documents = {str(Path(r[0]).relative_to(CATALOG)): r[4] for r in rows}
        Path(args.save).write_text(json.dumps(documents, indent=1, sort_keys=True))
    print(f"\n{'cpu s':>8} {'wall s':>8}  case: result")
    for path, cpu, wall, summary, _ in rows:
        print(f"{cpu:8.2f} {wall:8.2f}  {Path(path).relative_to(CATALOG)}: {summary}")
    decided = [r for r in rows if r[3].startswith("decided")]
    quick = [r for r in decided if r[1] <= within]
    times = [r[1] for r in rows]
    print(
        f"\n{len(rows)} cases; decided within {args.budget:g} s: {len(decided)}; decided "
        f"within {within:g} s (CPU): {len(quick)}; refused: "
        f"{sum(r[3].startswith(('refused', 'no options')) for r in rows)}; CPU seconds: "
        f"median {statistics.median(times):.2f}, max {max(times):.2f}, "
        f"total {sum(times):.1f}; under 2 s: {sum(t < 2 for t in times)}"
    )


def witnesses(args) -> None:
    """The generic analysis against the witness, each heavy top once, CPU seconds."""
    from registry.mathematics.exponent_witness import witness
    from registry.mathematics.weighted import split_field

    a, b, c, x0, y0, z0 = sp.symbols("a b c x0 y0 z0")
    tops = {
        "moments (2, 2, a), r = (1, 0, 0)": ((2, 2, a), (1, 0, 0)),
        "moments (2, 3, 4), r = (1, 2, a)": ((2, 3, 4), (1, 2, a)),
        "moments (1, b, c), r = (x0, 0, z0)": ((1, b, c), (x0, 0, z0)),
        "moments (a, b, c), r = (x0, y0, z0)": ((a, b, c), (x0, y0, z0)),
    }
    print(
        f"{'heavy top':38} {'generic':>9} {'verdict':>8} {'witness':>8} {'found':>6} {'ratio':>8}"
    )
    for name, (inertia, r) in tops.items():
        field = heavy_top(inertia, r)
        clear_cache()
        start = time.process_time()
        try:
            verdict = limited(args.timeout, lambda f=field: ours(f, False)).painleve_verdict
            generic, shown = time.process_time() - start, f"{time.process_time() - start:.2f}"
        except BudgetExceeded:
            verdict, generic, shown = None, None, f"> {args.timeout:g}"
        clear_cache()
        start = time.process_time()
        found = witness(split_field(mech.STATE, field, WEIGHTS))
        mine = time.process_time() - start
        ratio = f"{generic / mine:.0f}x" if generic else f"> {args.timeout / mine:.0f}x"
        word = {True: "passes", False: "fails", None: "-"}[verdict]
        print(
            f"{name:38} {shown:>9} {word:>8} {mine:8.2f} {'yes' if found else 'no':>6} {ratio:>8}",
            flush=True,
        )
    print(
        "generic: CPU s of the analysis over Q(parameters) without the series; witness: CPU s "
        "to a simple balance at rational values with an exponent off the integers; ratio: "
        "generic / witness"
    )


def translations(args) -> None:
    """Kirchhoff's equations with a potential sum a_i gamma_i**2/2 (weights 1): the analysis
    over Q(a1, a2, a3) (under ``--timeout``) against the one with a3 = 0 that a translation
    of the a_i allows (``parameter_translations``), written back, CPU seconds."""
    from registry.mathematics.parameter_translations import reduction

    a1, a2, a3 = sp.symbols("a1 a2 a3", real=True)
    m, g = sp.Matrix(mech.STATE[:3]), sp.Matrix(mech.STATE[3:])
    grad = sp.Matrix([a1 * g[0], a2 * g[1], a3 * g[2]])
    print(f"{'moments':14} {'Q(a1, a2, a3)':>14} {'a3 = 0':>8} {'ratio':>8} {'same':>6}")
    for inertia in ((1, 1, 1), (1, 2, 3)):
        omega = sp.Matrix([m[i] / inertia[i] for i in range(3)])
        field = [sp.expand(e) for e in (*m.cross(omega) + g.cross(grad), *g.cross(omega))]
        clear_cache()
        start = time.process_time()
        try:
            whole = limited(args.timeout, lambda f=field: exponents(mech.STATE, f, (1,) * 6))
            direct, shown = time.process_time() - start, f"{time.process_time() - start:.2f}"
        except BudgetExceeded:
            whole, direct, shown = None, None, f"> {args.timeout:g}"
        clear_cache()
        start = time.process_time()
        reduced = reduction(field, (a1, a2, a3))
        assert reduced is not None
        analysis = exponents(mech.STATE, reduced.field, (1,) * 6, parameters=reduced.parameters)
        mine = time.process_time() - start
        ratio = f"{direct / mine:.0f}x" if direct else f"> {args.timeout / mine:.0f}x"
        same = (
            "-"
            if whole is None
            else str(
                sorted(map(str, whole.degrees)) == sorted(map(str, analysis.degrees))
                and whole.painleve_verdict == analysis.painleve_verdict
                and len(whole.balances) == len(analysis.balances)
            )
        )
        print(f"{str(inertia):14} {shown:>14} {mine:8.2f} {ratio:>8} {same:>6}", flush=True)
    print(
        "CPU s of the analysis with the Painlevé test; same: the balances' count, Yoshida's "
        "degrees and the test's verdict agree (where the direct analysis ended)"
    )


def conditions(args) -> None:
    """Each condition at its balance: square roots' normal form against radsimp."""
    import random

    from registry.discovery.exponents import case_field, exponent_options
    from registry.language.casefile import load_case
    from registry.mathematics.algebraic import value_at_root
    from registry.mathematics.balances import balances
    from registry.mathematics.kovalevskaya import (
        balance_exponents,
        characteristic_polynomial,
        kovalevskaya_matrix,
    )
    from registry.mathematics.painleve import laurent_series
    from registry.mathematics.weighted import split_field

    case = load_case(ROOT / "data" / "cases" / "heavy-top" / "bobylev-1896-heavy-top.toml")
    found = case_field(case, exponent_options(case))
    split = split_field(found.variables, found.field, found.weights, parameters=found.parameters)
    matrix = kovalevskaya_matrix(split)
    work = []
    for balance in balances(split):
        if balance.root is None:
            continue
        polynomial = characteristic_polynomial(balance.component, matrix)
        resonances = balance_exponents(balance, polynomial).resonances
        series = laurent_series(split, balance.component, matrix, resonances)
        u = balance.component.symbol
        work += [(c, u, balance.root) for s in series.resonances for c in s.conditions]
    ours = theirs = 0.0
    rng = random.Random(1)
    agree = True
    for c, u, root in work:
        clear_cache()
        start = time.process_time()
        mine = value_at_root(c, u, root)
        ours += time.process_time() - start
        clear_cache()
        start = time.process_time()
        other = sp.radsimp(sp.expand(c.subs(u, root)))
        theirs += time.process_time() - start
        values = {x: sp.Rational(rng.randint(2, 30), rng.randint(1, 7)) for x in other.free_symbols}
        a, b = sp.N(mine.xreplace(values), 30), sp.N(other.xreplace(values), 30)
        agree = agree and abs(a - b) <= 1e-20 * (1 + abs(a))
    print(f"Bobylev's top: {len(work)} conditions at balances in square roots")
    print(
        f"  square roots' normal form: {ours:.3f} s   radsimp: {theirs:.3f} s   "
        f"ratio {theirs / max(ours, 1e-9):.1f}x   agree at random values: {agree}"
    )


def radicals(args) -> None:
    """The varying exponents at balances whose coordinates bring radicals of the
    parameters (moments (1, 1, c), centre (x0, y0, z0)): the quadratic formula, as
    ``kovalevskaya._balance_roots`` writes them, against sympy's ``roots``, which factors
    over the extension first (time limit ``--timeout``), compared at a random point."""
    from sympy.polys.polyroots import roots_quadratic

    from registry.mathematics.balances import balances
    from registry.mathematics.kovalevskaya import (
        LAMBDA,
        characteristic_polynomial,
        kovalevskaya_matrix,
    )
    from registry.mathematics.weighted import split_field

    c = sp.Symbol("c", positive=True)
    centre = sp.symbols("x0 y0 z0", real=True)
    field = heavy_top((1, 1, c), centre)
    split = split_field(mech.STATE, field, WEIGHTS, parameters=(c, *centre))
    matrix = kovalevskaya_matrix(split)
    work = []
    for balance in balances(split):
        if balance.root is None:
            continue
        rest = characteristic_polynomial(balance.component, matrix).rest
        at = sp.Poly(sp.expand(rest.subs(balance.component.symbol, balance.root)), LAMBDA)
        if at.domain == sp.EX and at.degree() == 2:
            work.append(at)
    point = {c: sp.Rational(3, 7), centre[0]: sp.Rational(2, 3), centre[1]: -1, centre[2]: 3}
    for at in work:
        clear_cache()
        start = time.process_time()
        mine = roots_quadratic(at)
        ours_s = time.process_time() - start
        clear_cache()
        start = time.process_time()
        try:
            theirs = limited(args.timeout, lambda a=at: list(sp.roots(a)))
            theirs_s = f"{time.process_time() - start:.2f} s"
            key = lambda r: (sp.re(r), sp.im(r))  # noqa: E731
            values = [sorted((sp.N(r.xreplace(point), 30) for r in rs), key=key)
                      for rs in (mine, theirs)]  # fmt: skip
            agree = all(abs(a - b) < 1e-20 for a, b in zip(*values, strict=True))
            ratio = f"{(time.process_time() - start) / max(ours_s, 1e-9):.0f}x"
        except BudgetExceeded:
            theirs_s, agree, ratio = f"over {args.timeout:.0f} s", "-", "-"
        print(f"  formula: {ours_s:.3f} s   sympy roots: {theirs_s}   ratio {ratio}   "
              f"agree at a random point: {agree}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--catalog", action="store_true", help="every case of data/cases")
    parser.add_argument("--budget", type=float, default=120.0, help="--catalog: seconds each")
    parser.add_argument("--within", type=float, default=None, help="--catalog: the survey's")
    parser.add_argument("--jobs", type=int, default=1, help="--catalog: processes")
    parser.add_argument("--only", default="", help="--catalog: files whose path has this")
    parser.add_argument(
        "--cpu", action="store_true", help="--catalog: the budget in CPU seconds, not wall clock"
    )
    parser.add_argument("--save", default="", help="--catalog: the documents to this JSON file")
    parser.add_argument(
        "--conditions", action="store_true", help="conditions at balances: ours against radsimp"
    )
    parser.add_argument(
        "--radicals", action="store_true", help="exponents among radicals: formula vs roots"
    )
    parser.add_argument(
        "--witness", action="store_true", help="generic analysis against a witness at values"
    )
    parser.add_argument(
        "--translations", action="store_true", help="a potential of differences: a3 = 0 or not"
    )
    args = parser.parse_args()
    if args.witness:
        witnesses(args)
        return
    if args.translations:
        translations(args)
        return
    if args.radicals:
        radicals(args)
        return
    if args.conditions:
        conditions(args)
        return
    if args.catalog:
        catalog(args)
        return
    header = (
        f"{'case':46} {'ours':>7} {'+ARS':>7} {'sympy':>8} {'ratio':>7} "
        f"{'balances':>10} {'agree':>6}"
    )
    print(header)
    print("-" * len(header))
    for name, (inertia, r) in CASES.items():
        field = heavy_top(inertia, r)
        t_ours, result = best(args.repeat, lambda f=field: ours(f, False))
        t_ars, _ = best(args.repeat, lambda f=field: ours(f, True))
        try:
            t_base, found = best(
                args.repeat, lambda f=field: limited(args.timeout, lambda: baseline(f))
            )
        except BudgetExceeded:
            t_base, found = None, None
        mine = spectra(result)
        if found is None:
            shown, ratio, counts, agree = f"> {args.timeout:g}", "-", f"{len(mine)}/-", "-"
        else:
            shown, ratio = f"{t_base:.2f}", f"{t_base / t_ours:.1f}x"
            counts = f"{len(mine)}/{len(found)}"
            agree = "yes" if all(same(s, mine) for s in found) else "NO"
        print(f"{name:46} {t_ours:7.2f} {t_ars:7.2f} {shown:>8} {ratio:>7} {counts:>10} {agree:>6}")
    print(
        "\nours: exponents(painleve=False), +ARS: with the Painlevé test; sympy: solve + "
        "eigenvals; ratio: sympy / ours; balances: ours / the baseline's solutions (a "
        "family may come back from solve as a family, as points on it, or not at all); "
        "agree: every spectrum the baseline found is one of ours. CPU seconds, best of "
        "--repeat runs of each, sympy's cache cleared before each run."
    )


if __name__ == "__main__":
    main()
