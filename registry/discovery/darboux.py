"""Darboux polynomials: invariant relations F = 0 of a system, dF/dt = K F.

A search for relations (``registry discover --relations``) is an integral search whose
equations are X(F) - K F = 0, the cofactor K a combination of state monomials with
unknown coefficients that are sought like free parameters (``search``); its special
sets are the cofactors that carry Darboux polynomials. Here: the general cofactor (which
monomials it may have, by the Newton polytope of the field) and the proof of each
relation found.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import sympy as sp
from sympy.polys.rings import PolyElement

from ..errors import DiscoveryError
from ..language.printer import to_text
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.factoring import factor
from ..mathematics.grading import homogeneous_weights, per_variable
from ..mathematics.zero_test import decide
from ..model import IntegralSet, SearchOptions, Verdict
from .ansatz import PolynomialSystem, weighted_monomials


def general_cofactor(
    system: PolynomialSystem,
    options: SearchOptions,
    m: CaseMechanics,
    undecided: list[str] | None = None,
) -> tuple[sp.Expr, list[sp.Symbol]]:
    """The general cofactor of Darboux polynomials of the field of ``system`` (built
    without splitting along symmetries): a combination, with unknown coefficients
    K_<monomial>, of the state monomials of the weight by which the field raises the
    weighted degree that its Newton polytope allows (``cofactor_monomials``; in a ring
    with inverses or roots, every one of that weight). Monomials of lower weight that the
    polytope allows are named in ``undecided``."""
    shift = system.shift()
    if shift < 0:
        raise DiscoveryError("the field lowers the weighted degree: no cofactor is polynomial")
    dynamics = m.dynamics
    weights = per_variable(options.weights, dynamics.vectors, dynamics.variables)
    if system.space.extended:
        monomials = weighted_monomials(shift, weights)
    else:
        monomials = cofactor_monomials(system.field, system.n, system.weights)
    # parts of lower weight (a field that is not weighted-homogeneous) make the search an
    # eigenvalue problem (a constant part is an eigenvalue of the linear part): only the
    # top weight is searched, and the search says what it left out
    lower = [e for e in monomials if sum(a * w for a, w in zip(e, weights, strict=True)) < shift]
    monomials = [e for e in monomials if e not in lower]
    if lower and undecided is not None:
        better = homogeneous_weights(
            m.field, dynamics.vectors, dynamics.shorthands, dynamics.variables
        )
        text = None if better is None else ",".join(f"{n}={w}" for n, w in better)
        hint = (
            f"; it is for {text}: search with --weights {text}"
            if better is not None and dict(better) != dict(options.weights)
            else ""
        )
        undecided.append(
            f"cofactors with parts of weight below {shift} ({len(lower)} monomials the field's "
            "Newton polytope allows; the field is not weighted-homogeneous for these weights"
            f"{hint}) are not searched"
        )
    coefficients, cofactor = [], sp.Integer(0)
    for exps in monomials:
        monomial = sp.Mul(*(x**e for x, e in zip(dynamics.variables, exps, strict=True)))
        k = sp.Symbol("K_" + (str(monomial).replace("**", "").replace("*", "_")), real=True)
        if k.name in m.case.parameters:
            raise DiscoveryError(f"the case names a parameter {k.name}, the cofactor's own name")
        coefficients.append(k)
        cofactor += k * monomial
    return cofactor, coefficients


def cofactor_monomials(field: Sequence[PolyElement], n: int, weights: Sequence[int]) -> list:
    """The state monomials a cofactor K of a polynomial field X can have: X(F) = K F
    gives Newton(K) + Newton(F) = Newton(X(F)) (Ostrowski), and X(F) = sum dF/dx_i X_i
    lies in Newton(F) + N with N = conv{exps(m) - e_i : m a monomial of X_i}, so that
    Newton(K) lies in N (cancellation of Minkowski sums), for every F and every value of
    the parameters (a coefficient that vanishes only shrinks N). A monomial is dropped
    only where a direction d separates it from N exactly (d.p > max of d over N), d in
    {-1, 0, 1}^n and +-the weights: a superset of N's lattice points, in integers. A
    weighted-homogeneous field has its cofactors of one weight; a field whose torque
    has terms of several degrees (s^2) gets cofactors of every weight it needs, not
    only the largest."""
    import numpy as np

    vertices = set()
    for i, y in enumerate(field):
        for m in y.monoms():
            e = list(m[:n])
            e[i] -= 1
            vertices.add(tuple(e))
    if not vertices:
        return []
    directions = [d for d in itertools.product((-1, 0, 1), repeat=n) if any(d)]
    w = tuple(weights)
    directions += [w, tuple(-x for x in w)]
    dirs = np.array(directions, dtype=np.int64)
    top = (np.array(sorted(vertices), dtype=np.int64) @ dirs.T).max(axis=0)
    highest = int(max(sum(a * b for a, b in zip(v, w, strict=True)) for v in vertices))
    candidates = [e for d in range(highest + 1) for e in weighted_monomials(d, w)]
    inside = ((np.array(candidates, dtype=np.int64) @ dirs.T) <= top).all(axis=1)
    return [c for c, ok in zip(candidates, inside, strict=True) if ok]


def proven_relations(
    m: CaseMechanics,
    when: tuple[str, ...],
    found: Sequence[sp.Expr],
    cofactor: sp.Expr,
    coefficients: Sequence[sp.Symbol],
    undecided: list[str],
) -> IntegralSet:
    """The Darboux polynomials ``found``, each proven by the zero test on dF/dt - K F (K
    the cofactor of the field itself); one not proven is not reported but named in
    ``undecided``, and the search is then not complete."""
    kept = []
    for f in found:
        residual = m.time_derivative(f) - cofactor * f
        verdict = decide({"dF/dt - K F": residual}, m.domain).verdict
        if verdict is Verdict.VERIFIED:
            kept.append(to_text(f))
        else:
            where = f" where {', '.join(when)}" if when else ""
            undecided.append(
                f"invariant relation {to_text(f)} = 0{where} found but not proven ({verdict})"
            )
    # factored where the cofactor is determined (a general one, with its unknown
    # coefficients, is written out: factoring it is costly and tells nothing)
    known = not (cofactor.free_symbols & set(coefficients))
    shown = factor(cofactor) if known else cofactor
    return IntegralSet(when, len(kept), tuple(kept), (), cofactor=to_text(shown))
