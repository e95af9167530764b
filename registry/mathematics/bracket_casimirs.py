"""The polynomial Casimirs of low degree of a Poisson bracket given entry by entry.

A search on a system with its own bracket must know the bracket's Casimirs, as it knows
|gamma|^2 on e(3): they are integrals of every Hamiltonian on that bracket, and an
integral that is one is nothing new. C is a Casimir when Pi grad C = 0; with C a sum of
the monomials of degree 1..``degree`` in the state with unknown coefficients, the
components of Pi grad C are polynomial where Pi is, and every coefficient of every
component must vanish: a linear system over Q(parameters), whose solutions are the
Casimirs of that degree (the rank is that of generic parameter values). The caller
proves each one again with the audit's zero test before it counts.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Sequence

import sympy as sp

#: Degree of the Casimirs sought: the brackets the literature writes (Lie-Poisson brackets
#: of e(3), so(4), two fields, Bobenko's (l, g)) have their Casimirs among quadrics.
CASIMIR_DEGREE = 2


def polynomial_casimirs(
    pi: sp.MatrixBase,
    variables: Sequence[sp.Symbol],
    degree: int = CASIMIR_DEGREE,
) -> list[sp.Expr]:
    """A basis of the polynomial Casimirs of ``pi`` of degree 1..``degree`` without
    constant term (module docstring), each with integer coefficients where the
    parameters allow; empty where ``pi`` is not polynomial in ``variables``. Solved once
    per bracket in a process (a search asks for them several times)."""
    return list(_casimirs(sp.ImmutableMatrix(pi), tuple(variables), degree))


@functools.lru_cache(maxsize=32)
def _casimirs(
    pi: sp.ImmutableMatrix, variables: tuple[sp.Symbol, ...], degree: int
) -> tuple[sp.Expr, ...]:
    if not all(sp.sympify(e).is_polynomial(*variables) for e in pi):
        return ()
    monomials = [
        sp.Mul(*combo)
        for d in range(1, degree + 1)
        for combo in itertools.combinations_with_replacement(variables, d)
    ]
    unknowns = sp.symbols(f"c0:{len(monomials)}")
    candidate = sum((c * m for c, m in zip(unknowns, monomials, strict=True)), sp.Integer(0))
    gradient = sp.Matrix([sp.diff(candidate, v) for v in variables])
    equations: list[sp.Expr] = []
    for component in pi * gradient:
        poly = sp.Poly(sp.expand(component), *variables)
        equations.extend(c for c in poly.coeffs() if c != 0)
    if not equations:
        return ()
    matrix, _ = sp.linear_eq_to_matrix(equations, unknowns)
    basis = []
    for vector in matrix.nullspace():
        expr = sp.expand(sum((v * m for v, m in zip(vector, monomials, strict=True)), 0))
        basis.append(_primitive(expr, variables))
    return tuple(basis)


def _primitive(expr: sp.Expr, variables: Sequence[sp.Symbol]) -> sp.Expr:
    """The Casimir without its content in the variables (a nonzero factor of the
    parameters does not change what it is), with a positive leading coefficient."""
    numer = sp.numer(sp.together(expr))
    _, primitive = sp.Poly(numer, *variables).primitive()
    if primitive.LC().could_extract_minus_sign():
        primitive = -primitive
    return primitive.as_expr()
