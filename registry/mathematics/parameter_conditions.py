"""Parameter conditions under which a failed identity holds.

The residual is brought to the normal form of the zero test (radicals and
transcendental terms as new symbols, numerator reduced modulo the radical
relations). It vanishes identically exactly when every coefficient of that
numerator, as a polynomial in the state variables and those symbols, vanishes:
a polynomial system in the parameters, which sympy solves. Branches that break
the declared assumptions (a positive parameter set to zero) or make a moment
of inertia vanish are dropped, and every branch kept is re-checked by the zero
test with its values substituted.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import sympy as sp

from ..model import Verdict
from .domain import Domain
from .mechanics import STATE, s
from .normal_form import Atoms, numerator, reduce_radical
from .zero_test import decide

Branch = dict[sp.Symbol, sp.Expr]


@dataclass(frozen=True)
class ConditionSearch:
    """The solution branches found (most general first), or why there are none."""

    branches: tuple[Branch, ...] = ()
    reason: str = ""


def parameter_conditions(
    residuals: Mapping[str, sp.Expr], domain: Domain, protected: Sequence[sp.Expr] = ()
) -> ConditionSearch:
    """Parameter values under which every residual vanishes identically."""
    if domain.functions:
        return ConditionSearch(reason="not sought for families of arbitrary functions")
    params = sorted(domain.parameters, key=str)
    if not params:
        return ConditionSearch(reason="the case has no parameters")
    equations = _coefficient_equations(residuals.values(), set(params))
    if equations is None:
        return ConditionSearch(reason="the residual is not polynomial in its normal form")
    if any(eq.is_number for eq in equations):
        return ConditionSearch(reason="no parameter values found that make the residual vanish")
    equations = {_vanishing_factors(eq) for eq in equations}
    if any(eq.is_number for eq in equations):
        return ConditionSearch(
            reason="no admissible parameter values found that make the residual vanish"
        )
    unknowns = [p for p in params if any(eq.has(p) for eq in equations)]
    try:
        solutions = sp.solve(sorted(equations, key=sp.default_sort_key), unknowns, dict=True)
    except NotImplementedError:
        return ConditionSearch(reason="sympy cannot solve the parameter system")
    kept = [b for b in solutions if _admissible(b, protected)]
    kept = [b for b in kept if _holds(residuals, domain, b)]
    kept.sort(key=lambda b: (len(b), sp.default_sort_key(tuple(b.items()))))
    if not kept:
        return ConditionSearch(
            reason="no admissible parameter values found that make the residual vanish"
        )
    return ConditionSearch(tuple(kept))


def _coefficient_equations(residuals, params: set[sp.Symbol]) -> set[sp.Expr] | None:
    """The coefficients, in the state and atom symbols, of every normalised numerator."""
    equations: set[sp.Expr] = set()
    state = set(STATE) | {s}
    for expr in residuals:
        atoms = Atoms()
        numer = numerator(atoms.rewrite(expr))
        for rho, q, base in atoms.relations():
            numer = reduce_radical(numer, rho, q, base)
        constants = _constant_atoms(atoms, state)
        gens = sorted(numer.free_symbols - params - set(constants), key=str)
        if not gens:
            coefficients = [numer]
        else:
            try:
                coefficients = sp.Poly(numer, *gens).coeffs()
            except sp.PolynomialError:
                return None
        for c in coefficients:
            c = sp.factor(c.xreplace(constants))
            if c != 0:
                equations.add(_strip_constant_factor(c))
    return equations


def _constant_atoms(atoms: Atoms, state: set) -> dict[sp.Symbol, sp.Expr]:
    """Atom symbols standing for expressions of the parameters alone, with their values."""
    values = {}
    for (base, q), rho in atoms.radicals.items():
        if not base.free_symbols & state:
            values[rho] = base ** sp.Rational(1, q)
    for key, tau in atoms.others.items():
        if not key.free_symbols & state:
            values[tau] = key
    return values


def _strip_constant_factor(expr: sp.Expr) -> sp.Expr:
    coeff, rest = expr.as_coeff_Mul()
    return rest if coeff != 0 else expr


def _vanishing_factors(expr: sp.Expr) -> sp.Expr:
    """The factors of an equation that can vanish: those nonzero by the parameters'
    assumptions are dropped (A*B*S12 = 0 with A, B positive is S12 = 0), which keeps
    the system small for the solver; 1 when none can."""
    return sp.Mul(*(f for f in sp.Mul.make_args(expr) if not f.is_nonzero))


def _admissible(branch: Branch, protected: Sequence[sp.Expr]) -> bool:
    """No positive or nonzero parameter set to an impossible value, no zero inertia."""
    for param, value in branch.items():
        if param.is_positive and (value.is_positive is False or value == 0):
            return False
        if param.is_nonzero and value == 0:
            return False
        if param.is_integer and value.is_number and value.is_integer is False:
            return False
        if value.has(sp.I) or not value.is_real and value.is_real is not None:
            return False
    return all(sp.simplify(p.xreplace(branch)) != 0 for p in protected)


def _holds(residuals: Mapping[str, sp.Expr], domain: Domain, branch: Branch) -> bool:
    """Whether the residuals vanish with the branch's values substituted, on the same
    domain as the original check (its level set, nonzero moments, and the points where
    the case's expressions must be defined), restricted to the remaining parameters."""

    def put(exprs: tuple[sp.Expr, ...]) -> tuple[sp.Expr, ...]:
        return tuple(sp.sympify(e).xreplace(branch) for e in exprs)

    substituted = {k: sp.sympify(e).xreplace(branch) for k, e in residuals.items()}
    narrowed = replace(
        domain,
        parameters=tuple(p for p in domain.parameters if p not in branch),
        nonzero=put(domain.nonzero),
        on=put(domain.on),
        defined=put(domain.defined),
    )
    return decide(substituted, narrowed).verdict is Verdict.VERIFIED


def equations_text(branch: Branch, to_text) -> list[str]:
    """A branch as equations of the case-file language, e.g. ``['N = 0']``."""
    return [
        f"{to_text(p)} = {to_text(v)}" for p, v in sorted(branch.items(), key=lambda i: str(i[0]))
    ]
