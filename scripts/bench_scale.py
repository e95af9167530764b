"""Benchmark of audits at scale: the local worker pool against a Dask cluster.

A generated catalog (seeded) of random members of the paper's torque families, each
case with a true claim and a false one:

* affine, mu = T gamma + e: C = 1/2 gamma.T gamma + (M + e).gamma, true when T is
  symmetric (a quarter of these cases have a non-symmetric T, and the claim is false);
* psi gamma + grad phi: C = s + phi;
* a(s) grad phi + b gamma with a = 1/D'(s): C = D(s) + phi;
* along one axis, mu = (0, 0, G'(gamma3)/F'(s)): C = F(s) + G(gamma3);

the false claim of each case is its true one with a term added (or the plain ``s``
where the true one needs D or F). The catalog is audited fresh, each time into a
database of its own, by

1. the local pool with 1 worker, then with 2 (``registry audit --jobs N``);
2. a Dask cluster of separate processes on this machine, started here: one
   ``dask scheduler`` and two ``dask worker`` (one thread each), the audit sent
   with ``--scheduler ADDRESS`` (client, connection and check of the workers' code
   included in the time), twice: the first audit on new workers pays for their
   imports of the package, the second is what later audits on a running cluster cost;
3. with ``--local-cluster``, also ``--scheduler local:2`` (the cluster started and
   stopped by the audit itself, included in the time).

The 2-worker timings are taken in ``--repeat`` rounds, one after the other in each,
and the best of each counts: on a shared machine the load of other programs comes
and goes, and would otherwise weigh on one of them only.

It prints the wall time and the time per case of each, the overhead of Dask against
the local pool of as many workers (target: at most 10% at 1,000 cases), and checks
that every verdict is the same whichever ran it.

Usage: python scripts/bench_scale.py [--cases 1000] [--seed 2026] [--budget 30]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import sympy as sp

import registry
from registry.execution.time_budget import TimeBudget
from registry.language.printer import to_text
from registry.mathematics import mechanics as mech

ROOT = Path(__file__).resolve().parents[1]
FAMILIES = ("affine", "psi-gamma-grad-phi", "a(s)-grad-phi", "axis")
#: What a verdict is, apart from when and how fast it was found.
COLUMNS = ["case", "claim", "check", "verdict", "method", "reason", "witness", "residual"]

# --- the catalog -------------------------------------------------------------------


def _coefficient(rng: random.Random) -> sp.Rational:
    return sp.Rational(rng.choice([-1, 1]) * rng.randint(1, 5), rng.randint(1, 3))


def _poly(rng: random.Random, variables, degree: int, terms: tuple[int, int]) -> sp.Expr:
    """A random polynomial: a few monomials of degree 1..``degree`` in ``variables``."""
    out = sp.Integer(0)
    for _ in range(rng.randint(*terms)):
        monomial = sp.Mul(*(rng.choice(variables) for _ in range(rng.randint(1, degree))))
        out += _coefficient(rng) * monomial
    return sp.expand(out)


def _wrong(rng: random.Random) -> sp.Expr:
    """A term that breaks a true Casimir."""
    g1, g2, g3 = mech.AXIS
    return _coefficient(rng) * rng.choice([g1 * g2, g2 * g3**2, g1**3, g1 * g3])


def family_member(index: int, rng: random.Random) -> tuple[str, list[sp.Expr], sp.Expr, sp.Expr]:
    """(family, torque, true Casimir, false Casimir) of the ``index``-th case."""
    g = mech.AXIS
    s = mech.s
    family = FAMILIES[index % len(FAMILIES)]
    if family == "affine":
        t = [[rng.randint(-4, 4) for _ in range(3)] for _ in range(3)]
        for i in range(3):
            for j in range(i):
                t[i][j] = t[j][i]
        if index % 16 == 0:  # a quarter of the affine cases: T not symmetric
            t[1][0] += rng.choice([-2, -1, 1, 2])
        e = [rng.randint(-3, 3) for _ in range(3)]
        torque = [sum(t[i][j] * g[j] for j in range(3)) + e[i] for i in range(3)]
        true = sp.expand(
            sp.Rational(1, 2) * sum(g[i] * torque[i] - g[i] * e[i] for i in range(3))
            + sum((mech.MOMENTUM[i] + e[i]) * g[i] for i in range(3))
        )
        return family, torque, true, true + _wrong(rng)
    phi = _poly(rng, g, 3, (2, 4))
    if family == "psi-gamma-grad-phi":
        psi = _poly(rng, g, 1, (1, 3))
        torque = [psi * g[i] + sp.diff(phi, g[i]) for i in range(3)]
        return family, torque, s + phi, s + phi + _wrong(rng)
    c = rng.choice([-3, -2, -1, 1, 2, 3])
    d = s + c * s**2 if rng.random() < 0.5 else s + c * s**3
    a = 1 / sp.diff(d, s)
    if family == "a(s)-grad-phi":
        b = _poly(rng, g, 1, (1, 2))
        torque = [a * sp.diff(phi, g[i]) + b * g[i] for i in range(3)]
        return family, torque, d + phi, s + phi
    big_g = _poly(rng, [g[2]], 3, (1, 3))
    torque = [sp.Integer(0), sp.Integer(0), a * sp.diff(big_g, g[2])]
    return family, torque, d + big_g, d + big_g + _wrong(rng)


def case_text(index: int, rng: random.Random) -> str:
    family, torque, true, false = family_member(index, rng)
    potential = _poly(rng, mech.AXIS, 2, (1, 3))
    inertia = [rng.randint(1, 9) for _ in range(3)]
    torque_text = ", ".join(f'"{to_text(m)}"' for m in torque)
    false_kind = rng.choice(["casimir", "integral"])
    return f'''id = "scale-{index:05d}"
title = "Generated member {index} of the family {family}"
topic = "generated"

[source]
citation = "generated by scripts/bench_scale.py"

[system]
inertia = ["{inertia[0]}", "{inertia[1]}", "{inertia[2]}"]
potential = "{to_text(potential)}"
torque = [{torque_text}]

[[claims]]
label = "true"
kind = "casimir"
expression = "{to_text(true)}"

[[claims]]
label = "false"
kind = "{false_kind}"
expression = "{to_text(false)}"
'''


def write_catalog(folder: Path, n: int, seed: int) -> None:
    rng = random.Random(seed)
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        (folder / f"scale-{i:05d}.toml").write_text(case_text(i, rng), encoding="utf-8")


# --- a cluster of separate dask processes ------------------------------------------


def _environment() -> dict[str, str]:
    path = os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(ROOT), path) if p)}


def _dask(*args: str) -> list[str]:
    script = Path(sys.executable).parent / "dask"
    return [str(script), *args] if script.exists() else [sys.executable, "-m", "dask", *args]


@contextmanager
def dask_processes(where: Path, n_workers: int):
    """``dask scheduler`` and ``n_workers`` ``dask worker`` processes (one thread each)
    on 127.0.0.1; yields the scheduler's address."""
    from distributed import Client

    file = where / "scheduler.json"
    procs: list[subprocess.Popen] = []
    logs = []

    def start(name: str, *args: str) -> None:
        log = open(where / f"{name}.log", "wb")  # closed below
        logs.append(log)
        procs.append(
            subprocess.Popen(_dask(*args), stdout=log, stderr=subprocess.STDOUT, env=_environment())
        )

    try:
        start("scheduler", "scheduler", "--host", "127.0.0.1", "--port", "0",
              "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(file))  # fmt: skip
        deadline = time.monotonic() + 60
        while True:
            try:
                address = json.loads(file.read_text())["address"]
                break
            except (OSError, ValueError, KeyError):
                if procs[0].poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError((where / "scheduler.log").read_text()) from None
                time.sleep(0.1)
        for i in range(n_workers):
            start(f"worker-{i}", "worker", "--scheduler-file", str(file), "--host", "127.0.0.1",
                  "--nthreads", "1", "--nworkers", "1", "--no-dashboard")  # fmt: skip
        with Client(address, timeout=30) as client:
            client.wait_for_workers(n_workers, timeout=120)
        yield address
    finally:
        for proc in reversed(procs):
            proc.terminate()
        for proc in reversed(procs):
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        for log in logs:
            log.close()


# --- the measurements --------------------------------------------------------------


def audit_once(folder: Path, work: Path, name: str, budget: TimeBudget, **how):
    """A fresh database with the catalog, audited once; (seconds, verdicts, run)."""
    db = work / f"{name}.sqlite"
    if db.exists():
        db.unlink()
    reg = registry.open(db)
    reg.add(folder)
    started = time.perf_counter()
    report = reg.audit(fresh=True, budget=budget, **how)
    wall = time.perf_counter() - started
    frame = reg.verdicts()[COLUMNS].sort_values(["case", "check", "claim"])
    run = reg.runs().to_dict("records")[-1]
    reg.close()
    assert run["run"] == report.run
    return wall, frame.reset_index(drop=True), run


LOCAL1, LOCAL2 = "local pool, 1 worker", "local pool, 2 workers"
DASK_NEW, DASK_AGAIN = "dask processes, new workers", "dask processes, running"
LOCAL_CLUSTER = "--scheduler local:2"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=1000, help="catalog size (default 1000)")
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--budget", type=float, default=30.0, help="seconds per check")
    parser.add_argument(
        "--repeat", type=int, default=1, help="rounds of the 2-worker timings; the best counts"
    )
    parser.add_argument(
        "--local-cluster", action="store_true", help="also time --scheduler local:2"
    )
    parser.add_argument("--keep", type=Path, default=None, help="keep the work here")
    args = parser.parse_args()
    budget = TimeBudget(check=args.budget)

    with tempfile.TemporaryDirectory(prefix="bench-scale-") as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        folder = work / "cases"
        write_catalog(folder, args.cases, args.seed)
        print(
            f"== {args.cases} generated cases (seed {args.seed}), 2 claims each, families "
            f"{', '.join(FAMILIES)}; {os.cpu_count()} cores; budget {args.budget:g} s per check"
        )
        times: dict[str, list[float]] = {}
        tables = {}

        def record(name: str, wall: float, frame, run) -> None:
            times.setdefault(name, []).append(wall)
            tables.setdefault(name, frame)
            if not frame.equals(tables[name]):
                print(f"  !! {name}: verdicts differ from its first round")
            counts = frame.verdict.value_counts().to_dict()
            print(
                f"  {name:30s} {wall:8.2f} s  {1000 * wall / args.cases:7.1f} ms/case  "
                f"run {run['status']}, {run['n_results']} results {counts}",
                flush=True,
            )
            events = run["options"].get("events") or []
            if events:
                print(f"    {len(events)} event(s) on the cluster, first: {events[0]}")

        record(LOCAL1, *audit_once(folder, work, "local-1", budget, jobs=1))
        # the 2-worker timings in rounds, each round one after the other, so that the
        # load of a shared machine weighs on all of them alike; no Dask process runs
        # while the local pool is timed
        for round_ in range(args.repeat):
            record(LOCAL2, *audit_once(folder, work, "local-2", budget, jobs=2))
            dask_dir = work / f"dask-{round_}"
            dask_dir.mkdir(exist_ok=True)
            started = time.perf_counter()
            with dask_processes(dask_dir, 2) as address:
                print(f"  (dask scheduler + 2 dask workers started in "
                      f"{time.perf_counter() - started:.1f} s at {address})")  # fmt: skip
                # the first audit on new workers pays for their imports of the package;
                # the second is what every later audit on a running cluster costs
                for name in (DASK_NEW, DASK_AGAIN):
                    record(name, *audit_once(folder, work, "dask", budget, scheduler=address))
            if args.local_cluster:
                record(LOCAL_CLUSTER, *audit_once(folder, work, "local-cluster", budget,
                                                  scheduler="local:2"))  # fmt: skip

        reference = tables[LOCAL1]
        same = {name: frame.equals(reference) for name, frame in tables.items()}
        print(f"identical verdicts, case by case: {all(same.values())}"
              + ("" if all(same.values()) else f" {same}"))  # fmt: skip
        best = {name: min(walls) for name, walls in times.items()}
        print(f"best of {args.repeat} round(s):")
        for name, wall in best.items():
            print(f"  {name:30s} {wall:8.2f} s  {1000 * wall / args.cases:7.1f} ms/case")
        print(f"local pool speed-up, 2 workers against 1: {best[LOCAL1] / best[LOCAL2]:.2f}x")
        for name in (DASK_NEW, DASK_AGAIN, LOCAL_CLUSTER):
            if name in best:
                overhead = 100 * (best[name] / best[LOCAL2] - 1)
                print(f"overhead of {name} against the local pool of 2 workers: "
                      f"{overhead:+.1f}% (target <= 10% at 1,000 cases)")  # fmt: skip


if __name__ == "__main__":
    main()
