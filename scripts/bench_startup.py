"""Benchmark of start-up: what ``import registry``, ``registry --help`` and a fresh audit
of the seed catalog cost, beside baselines measured in the same run.

Each command runs in a fresh process, ``--repeat`` times (the best time counts: a shared
machine only ever adds time), alternating with the baselines ``python -c pass`` and
``python -c "import sympy"`` so that the ratios compare like with like. Then
``python -X importtime`` says which imports ``registry --help`` and ``import registry``
pay for (the heaviest few, cumulative microseconds).

The fresh audit: the 16 seed files (``data/cases/*.toml``, the top level) added to a new
SQLite file, then ``registry audit`` on it, as a user types them; both whole processes.

Usage: python scripts/bench_startup.py [--repeat 5] [--top 8]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SEEDS = sorted((ROOT / "data" / "cases").glob("*.toml"))
PY = sys.executable
REGISTRY = [PY, "-m", "registry"]


def wall(command: list[str], env: dict[str, str] | None = None) -> float:
    """Seconds the whole process takes (it must succeed)."""
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, cwd=ROOT, env=env)
    return time.perf_counter() - started


def best(commands: dict[str, list[str]], repeat: int) -> dict[str, float]:
    """The best wall time of each command, the commands interleaved round by round."""
    found = {name: float("inf") for name in commands}
    for _ in range(repeat):
        for name, command in commands.items():
            found[name] = min(found[name], wall(command))
    return found


def importtime(command: list[str], top: int) -> list[tuple[int, str]]:
    """The ``top`` heaviest imports of a command: (cumulative microseconds, module)."""
    done = subprocess.run(
        [PY, "-X", "importtime", *command], capture_output=True, text=True, cwd=ROOT
    )
    rows = []
    for line in done.stderr.splitlines():
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _, cumulative, name = line[len("import time:") :].split("|")
        rows.append((int(cumulative), name.strip()))
    return sorted(rows, reverse=True)[:top]


def fresh_audit(repeat: int) -> tuple[float, float, int]:
    """(best add seconds, best audit seconds, cases): the seed files into a new database
    and audited, each a whole ``registry`` process."""
    adds, audits = [], []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as folder:
            db = str(Path(folder) / "seed.sqlite")
            env = {**os.environ, "REGISTRY_DB": db}
            env.pop("REGISTRY_SCHEDULER", None)
            adds.append(wall([*REGISTRY, "add", *map(str, SEEDS)], env))
            audits.append(wall([*REGISTRY, "audit"], env))
    return min(adds), min(audits), len(SEEDS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--top", type=int, default=8)
    parser.add_argument("--audit-repeat", type=int, default=2)
    args = parser.parse_args()

    load = os.getloadavg()[0]
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores, load {load:.1f}")
    times = best(
        {
            "python -c pass": [PY, "-c", "pass"],
            "python -c 'import sympy'": [PY, "-c", "import sympy"],
            "python -c 'import registry'": [PY, "-c", "import registry"],
            "registry --help": [*REGISTRY, "--help"],
            "registry audit --help": [*REGISTRY, "audit", "--help"],
            "python -c 'import registry.api'": [PY, "-c", "import registry.api"],
        },
        args.repeat,
    )
    base, sympy_time = times["python -c pass"], times["python -c 'import sympy'"]
    print(f"\nwhole processes, best of {args.repeat} (interleaved):")
    for name, seconds in times.items():
        print(
            f"  {name:34} {seconds:6.3f} s   {seconds - base:+6.3f} s over python, "
            f"{seconds / sympy_time:5.2f} x 'import sympy'"
        )

    for label, command in (
        ("registry --help", ["-m", "registry", "--help"]),
        ("import registry", ["-c", "import registry"]),
        ("import registry.api", ["-c", "import registry.api"]),
    ):
        print(f"\nheaviest imports of {label} (python -X importtime, cumulative):")
        for micros, name in importtime(command, args.top):
            print(f"  {micros / 1e6:6.3f} s  {name}")

    add, audit, n = fresh_audit(args.audit_repeat)
    print(f"\nfresh audit of the {n} seed files, best of {args.audit_repeat}:")
    print(f"  registry add     {add:6.2f} s")
    print(f"  registry audit   {audit:6.2f} s   ({audit / sympy_time:.1f} x 'import sympy')")


if __name__ == "__main__":
    main()
