"""Benchmark of the balances' prime decomposition over Q(parameters)
(``registry.mathematics.prime_components``) with its splits on coordinate hyperplanes
against the same decomposition without them, in the same run, on the balance equations
of heavy tops and Kirchhoff systems.

For each system: the processor time of each (the best of ``--repeat``; the baseline's
under a limit of ``--timeout`` s of processor time), their ratio, and whether the two
found the same components (they must: a split only changes the way to them).

Usage: python scripts/bench_components.py [--timeout 120] [--repeat 1]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse

import sympy as sp
from bench_groebner import best  # the script beside this one: the same timing

from registry.mathematics import mechanics as mech
from registry.mathematics.balances import balance_equations
from registry.mathematics.prime_components import components, same_components
from registry.mathematics.weighted import split_field

B, C, A, X, Y, Z = sp.symbols("B C a x0 y0 z0")
B1, B2, B3 = sp.symbols("b1 b2 b3")
g1, g2, g3 = mech.AXIS


def balances(inertia, potential, weights, parameters):
    """The balance equations of the top with these moments and potential."""
    field = [sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0))]
    split = split_field(mech.STATE, field, weights, parameters=parameters)
    return balance_equations(split), parameters


HEAVY, KIRCHHOFF = (1, 1, 1, 2, 2, 2), (1, 1, 1, 1, 1, 1)
SYSTEMS = {
    "heavy top (1, B, C), centre (a, 0, 0)": balances((1, B, C), A * g1, HEAVY, (B, C, A)),
    "heavy top (1, B, C), centre (1, y0, z0)": balances(
        (1, B, C), g1 + Y * g2 + Z * g3, HEAVY, (B, C, Y, Z)
    ),
    "Kirchhoff (1, 1/2, 1/3), potential b": balances(
        (1, sp.Rational(1, 2), sp.Rational(1, 3)),
        (B1 * g1**2 + B2 * g2**2 + B3 * g3**2) / 2,
        KIRCHHOFF,
        (B1, B2, B3),
    ),
    "Kirchhoff (1, B, C), potential (b2 g2^2 + g3^2)/2": balances(
        (1, B, C), (B2 * g2**2 + g3**2) / 2, KIRCHHOFF, (B, C, B2)
    ),
    "Kirchhoff (1, B, C), potential b": balances(
        (1, B, C), (B1 * g1**2 + B2 * g2**2 + B3 * g3**2) / 2, KIRCHHOFF, (B, C, B1, B2, B3)
    ),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    print(f"{'system':52} {'split':>8} {'unsplit':>8} {'ratio':>7}  same")
    for name, (equations, parameters) in SYSTEMS.items():
        split_time, split = best(
            args.repeat, args.timeout, lambda e=equations, p=parameters: components(
                e, mech.STATE, p
            ),
        )  # fmt: skip
        plain_time, plain = best(
            args.repeat,
            args.timeout,
            lambda e=equations, p=parameters: components(e, mech.STATE, p, hyperplanes=False),
        )
        if split_time is None or plain_time is None:
            over = "> " + str(int(args.timeout))
            shown = [over if t is None else format(t, "8.2f") for t in (split_time, plain_time)]
            ratio = "-" if split_time is None else "> " + format(args.timeout / split_time, ".0f")
            print(f"{name:52} {shown[0]:>8} {shown[1]:>8} {ratio:>7}  -")
            continue
        ratio = plain_time / max(split_time, 1e-9)
        agree = same_components(split, plain)
        print(f"{name:52} {split_time:8.2f} {plain_time:8.2f} {ratio:7.1f}  {agree}")


if __name__ == "__main__":
    main()
