"""Benchmark of the fraction-free Gröbner bases (``registry.mathematics.groebner``)
against sympy's ``groebner`` in the same run, on the balance equations of heavy tops
and Kirchhoff systems over Q(parameters) (graded reverse lexicographic order); and of
a saturation I : x^oo (the balances off a coordinate hyperplane, as the decomposition
into components splits them) by the block-order ``elimination`` against the lex basis
it replaced, both ours; of a basis extended by gamma3 (I + (gamma3), the balances on
the hyperplane) given as the basis found (``known=``: its pairs not formed again)
against its expressions read back (the way before); and of the normal forms of a
finite algebra's monomials (the multiplication matrices of the decomposition) by
``NormalForms`` against sympy's ``rem`` over Q(p).

For each system: the processor time of each (the best of ``--repeat``; the baseline's
under a limit of ``--timeout`` s of processor time), their ratio, and whether the two
bases are the same (they must be: both are the reduced basis).

Usage: python scripts/bench_groebner.py [--timeout 60] [--repeat 3]
Nothing here is asserted by the tests: machines are shared and noisy.
"""

from __future__ import annotations

import argparse
import functools
import time

import sympy as sp
from sympy.core.cache import clear_cache

from registry.execution.time_budget import BudgetExceeded, time_limit
from registry.mathematics import mechanics as mech
from registry.mathematics.balances import balance_equations
from registry.mathematics.groebner import NormalForms, elimination, groebner
from registry.mathematics.prime_components import standard_monomials
from registry.mathematics.weighted import split_field

B, C, A, X, Y, Z = sp.symbols("B C a x0 y0 z0")
B1, B2, B3 = sp.symbols("b1 b2 b3")
g1, g2, g3 = mech.AXIS


def heavy_top(inertia, potential, parameters):
    """The balance equations of a heavy top (weights M: 1, gamma: 2)."""
    field = [sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0))]
    split = split_field(mech.STATE, field, (1, 1, 1, 2, 2, 2), parameters=parameters)
    return balance_equations(split), parameters


def kirchhoff(inertia, potential, parameters):
    """The balance equations of Kirchhoff's equations (weights M: 1, gamma: 1)."""
    field = [sp.expand(v) for v in mech.vector_field(inertia, potential, (0, 0, 0))]
    split = split_field(mech.STATE, field, (1, 1, 1, 1, 1, 1), parameters=parameters)
    return balance_equations(split), parameters


SYSTEMS = {
    "heavy top (1, B, C), centre (a, 0, 0)": heavy_top((1, B, C), A * g1, (B, C, A)),
    "heavy top (1, B, C), centre (1, y0, z0)": heavy_top(
        (1, B, C), g1 + Y * g2 + Z * g3, (B, C, Y, Z)
    ),
    "heavy top (1, B, C), centre (x0, y0, z0)": heavy_top(
        (1, B, C), X * g1 + Y * g2 + Z * g3, (B, C, X, Y, Z)
    ),
    "Kirchhoff (1, 1/2, 1/3), potential b": kirchhoff(
        (1, sp.Rational(1, 2), sp.Rational(1, 3)),
        (B1 * g1**2 + B2 * g2**2 + B3 * g3**2) / 2,
        (B1, B2, B3),
    ),
    "Kirchhoff (1, B, C), potential (g1^2 + b2 g2^2)/2": kirchhoff(
        (1, B, C), (g1**2 + B2 * g2**2) / 2, (B, C, B2)
    ),
}


def best(repeat: int, timeout: float, fn):
    """The least processor time of ``repeat`` runs of fn and its value; (None, None)
    past ``timeout`` s of processor time."""
    times, value = [], None
    for _ in range(repeat):
        clear_cache()
        start = time.process_time()
        try:
            with time_limit(timeout, cpu=True):
                value = fn()
        except BudgetExceeded:
            return None, None
        times.append(time.process_time() - start)
    return min(times), value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"{'system':52} {'ours':>8} {'sympy':>8} {'ratio':>7}  same")
    for name, (equations, parameters) in SYSTEMS.items():
        domain = sp.QQ.frac_field(*parameters)
        ours = best(
            args.repeat, args.timeout, lambda e=equations, d=domain: groebner(e, mech.STATE, d)
        )
        theirs = best(
            args.repeat,
            args.timeout,
            lambda e=equations, d=domain: sp.groebner(e, *mech.STATE, order="grevlex", domain=d),
        )
        report(name, ours, theirs, args.timeout, lambda basis: basis.exprs)
    print(f"\n{'saturation by gamma3':52} {'block':>8} {'lex':>8} {'ratio':>7}  same")
    for name in SATURATED:
        equations, parameters = SYSTEMS[name]
        domain = sp.QQ.frac_field(*parameters)
        ours = best(args.repeat, args.timeout, functools.partial(saturation, equations, domain))
        lex = functools.partial(saturation, equations, domain, lex=True)
        theirs = best(1, args.timeout, lex)
        report(name, ours, theirs, args.timeout, list)
    print(f"\n{'basis extended by gamma3':52} {'known':>8} {'exprs':>8} {'ratio':>7}  same")
    for name in EXTENDED:
        equations, parameters = SYSTEMS[name]
        domain = sp.QQ.frac_field(*parameters)
        basis = groebner(equations, mech.STATE, domain)
        known = functools.partial(groebner, [mech.STATE[-1]], mech.STATE, domain, known=basis)
        again = functools.partial(groebner, [*basis.exprs, mech.STATE[-1]], mech.STATE, domain)
        ours = best(args.repeat, args.timeout, known)
        theirs = best(1, args.timeout, again)
        report(name, ours, theirs, args.timeout, lambda basis: basis.exprs)
    print(f"\n{'normal forms of the algebra':52} {'ours':>8} {'sympy':>8} {'ratio':>7}  same")
    for name in EXTENDED:
        equations, parameters = SYSTEMS[name]
        domain = sp.QQ.frac_field(*parameters)
        basis = groebner(equations, mech.STATE, domain)
        ours = best(args.repeat, args.timeout, functools.partial(normal_forms, basis, domain))
        theirs = best(1, args.timeout, functools.partial(remainders, basis, domain))
        report(name, ours, theirs, args.timeout, lambda forms: forms)


def report(name: str, ours, theirs, timeout: float, exprs) -> None:
    """One line: the two (time, value) pairs, their ratio, whether the values agree."""
    (ours_time, ours_value), (theirs_time, theirs_value) = ours, theirs
    if ours_time is None:
        print(f"{name:52} {'> ' + str(int(timeout)):>8}")
    elif theirs_time is None:
        print(f"{name:52} {ours_time:8.2f} {'> ' + str(int(timeout)):>8} "
              f"{'> ' + format(timeout / ours_time, '.0f'):>7}  -")  # fmt: skip
    else:
        same = exprs(ours_value) == exprs(theirs_value)
        ratio = theirs_time / max(ours_time, 1e-9)
        print(f"{name:52} {ours_time:8.2f} {theirs_time:8.2f} {ratio:7.1f}  {same}")


#: The systems whose saturation by gamma3 is measured.
SATURATED = ("heavy top (1, B, C), centre (1, y0, z0)", "heavy top (1, B, C), centre (x0, y0, z0)")


def saturation(equations, domain, lex: bool = False) -> list[sp.Expr]:
    """The reduced grevlex basis of I : gamma3^oo, I the balances' ideal: y eliminated
    from I + (1 - y gamma3) by the block order (``elimination``), or by a lex basis (the
    way the decomposition took before)."""
    y = sp.Dummy("y")
    ideal = [*equations, 1 - y * mech.STATE[-1]]
    if not lex:
        return elimination(ideal, [y], mech.STATE, domain).exprs
    kept = [e for e in groebner(ideal, [y, *mech.STATE], domain, "lex").exprs if not e.has(y)]
    return groebner(kept, mech.STATE, domain).exprs


#: The systems whose basis is extended by gamma3, and whose algebra's normal forms are
#: measured (zero-dimensional bases).
EXTENDED = (
    "heavy top (1, B, C), centre (a, 0, 0)",
    "heavy top (1, B, C), centre (1, y0, z0)",
    "Kirchhoff (1, B, C), potential (g1^2 + b2 g2^2)/2",
)


def _products(basis) -> list[tuple[int, ...]]:
    """The monomials x_i m (m a standard monomial) the multiplication matrices reduce."""
    standard = standard_monomials(basis, mech.STATE)
    n = len(mech.STATE)
    return [tuple(e + (j == i) for j, e in enumerate(m)) for m in standard for i in range(n)]


def normal_forms(basis, domain) -> list[dict]:
    """Ours: pseudo-division over Z[p] with one scale (``NormalForms``)."""
    forms = NormalForms(basis, domain)
    return [forms.of_monomial(m) for m in _products(basis)]


def remainders(basis, domain) -> list[dict]:
    """The baseline: sympy's ``rem`` in its ring over Q(p), as the decomposition did."""
    ring = sp.polys.rings.PolyRing(mech.STATE, domain, sp.polys.orderings.grevlex)
    divisors = [ring.from_dict(p.as_dict(native=True)) for p in basis.polys]
    return [dict(ring({m: domain.one}).rem(divisors).items()) for m in _products(basis)]


if __name__ == "__main__":
    main()
