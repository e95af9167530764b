"""Benchmark of the exponents' and the Painlevé test's arithmetic in a field of balances
over several parameters, k[u]/(g) with k = Q(p), against the ways it replaced, in the
same run:

* the characteristic polynomial of the Kovalevskaya matrix (Berkowitz): over Z[p] in
  FLINT (``mathematics/integral_algebra.py``) against sympy's ring k[u] reduced mod g;
* the discriminant of g: FLINT's over Z[p] (``flint_polys.discriminant``) against
  sympy's subresultants over Q(p);
* the Laurent series to the last resonance: each resonance step by the projection onto
  the kernel (``painleve._Recursion._project``, no pivot inverted) against Gauss-Jordan
  elimination, whose pivots over several parameters are general elements of the field.

On Clebsch's stratum of the diagonal Kirchhoff family (moments (1, B, C), potential
(b2 gamma2^2 + gamma3^2)/2, b2 = (B - 1)/(C - 1): a curve of balances, eight points over
Q(B, C, gamma3)) and on a small designed system of degree 2 over Q(a, b).

Processor time, one run each (the baseline under a limit of ``--timeout`` s; FLINT's
calls are not interrupted, so a baseline can overrun it), the ratio, and whether both
gave the same result. Usage: python scripts/bench_series.py [--timeout 120]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse

import sympy as sp
from bench_groebner import best  # the script beside this one: the same timing

from registry.mathematics import mechanics as mech
from registry.mathematics import painleve
from registry.mathematics.balances import balance_equations
from registry.mathematics.flint_gcd import flint_gcd
from registry.mathematics.flint_polys import discriminant
from registry.mathematics.kovalevskaya import (
    berkowitz,
    characteristic_polynomial,
    kovalevskaya_matrix,
)
from registry.mathematics.prime_components import components
from registry.mathematics.weighted import split_field

B, C, A, P = sp.symbols("B C a b")
X, Y, Z = sp.symbols("x y z")
g1, g2, g3 = mech.AXIS


def clebsch():
    """The split field and its component of balances on Clebsch's stratum."""
    b2 = (B - 1) / (C - 1)
    field = [
        sp.expand(v) for v in mech.vector_field((1, B, C), (b2 * g2**2 + g3**2) / 2, (0, 0, 0))
    ]
    split = split_field(mech.STATE, field, (1,) * 6, parameters=(B, C))
    return split, mech.STATE


def designed():
    """x' = x^2 + a y^2, y' = 2 x y, z' = -2 x z + b y^2: y^2 = 1/(4a)."""
    field = [X**2 + A * Y**2, 2 * X * Y, -2 * X * Z + P * Y**2]
    return split_field([X, Y, Z], field, (1, 1, 1), parameters=(A, P)), (X, Y, Z)


def sympy_charpoly(component, matrix) -> list:
    """Berkowitz in sympy's ring k[u], reduced mod g (the way replaced)."""
    k, u, n = component.domain, component.symbol, matrix.rows
    ring = k[u].ring
    g = ring.from_dict(dict(component.minimal.as_dict(native=True)))
    rows = [
        [
            ring.from_dict(dict(component.evaluate(matrix[i, j]).as_dict(native=True)))
            for j in range(n)
        ]
        for i in range(n)
    ]
    found = berkowitz(rows, ring, lambda a: a.rem(g))
    return [sp.Poly.from_dict(dict(c.items()) or {(0,): k.zero}, u, domain=k) for c in found]


def series(split, component, matrix, resonances, project: bool):
    """The series to the last resonance, with the kernel projection (in a field of any
    degree > 1) or without it."""
    original, degree = painleve._Recursion._project, painleve.PROJECT_ABOVE_DEGREE
    if project:
        painleve.PROJECT_ABOVE_DEGREE = 1
    else:
        painleve._Recursion._project = lambda self, r, rhs: None
    try:
        return painleve.laurent_series(split, component, matrix, resonances)
    finally:
        painleve._Recursion._project, painleve.PROJECT_ABOVE_DEGREE = original, degree


def row(name: str, ours, theirs, same) -> None:
    """One line: both times, their ratio, and whether the results agree."""
    (ours_time, _), (their_time, _) = ours, theirs
    if ours_time is None or their_time is None:
        shown = [">limit" if t is None else format(t, "8.2f") for t in (ours_time, their_time)]
        print(f"{name:58} {shown[0]:>8} {shown[1]:>8} {'-':>7}  -")
        return
    ratio = their_time / max(ours_time, 1e-9)
    print(f"{name:58} {ours_time:8.2f} {their_time:8.2f} {ratio:7.1f}  {same}")


def measure(label: str, split, variables, timeout: float) -> None:
    """The three rows of one system."""
    found = components(balance_equations(split), variables, split.parameters)
    component = max(found, key=lambda c: c.degree)
    matrix = kovalevskaya_matrix(split)
    ours = best(1, timeout, lambda: characteristic_polynomial(component, matrix))
    theirs = best(1, timeout, lambda: sympy_charpoly(component, matrix))
    row(f"{label}: characteristic polynomial", ours, theirs, theirs[1] is not None)
    g = component.minimal
    ours_d = best(1, timeout, lambda: discriminant(g))
    theirs_d = best(1, timeout, lambda: sp.discriminant(g.as_expr(), g.gen))
    agree = None not in (ours_d[1], theirs_d[1]) and sp.cancel(ours_d[1] - theirs_d[1]) == 0
    row(f"{label}: discriminant of g (degree {g.degree()})", ours_d, theirs_d, agree)
    resonances: dict[int, int] = {}
    for factor, multiplicity in ours[1].common:
        root = sp.solve(factor, sp.Symbol("lambda"))[0]
        if root.is_integer and root >= 1:
            resonances[int(root)] = resonances.get(int(root), 0) + multiplicity
    projected = best(1, timeout, lambda: series(split, component, matrix, resonances, True))
    eliminated = best(1, timeout, lambda: series(split, component, matrix, resonances, False))
    agree = None not in (projected[1], eliminated[1]) and (
        projected[1].compatible == eliminated[1].compatible
    )
    row(f"{label}: series to resonance {max(resonances)}", projected, eliminated, agree)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=120.0)
    args = parser.parse_args()
    print(f"{'system, step':58} {'ours':>8} {'before':>8} {'ratio':>7}  same")
    with flint_gcd():
        measure("designed", *designed(), args.timeout)
        measure("Clebsch", *clebsch(), args.timeout)


if __name__ == "__main__":
    main()
