"""Parameter conditions under which a failed identity holds.

On a level set, its equations are first solved, one by one, for a state variable
each is linear in, and substituted (``on_level_set``). The residual is then brought
to the normal form of the zero test (radicals and transcendental terms as new
symbols, numerator reduced modulo the radicals' relations and sin**2 + cos**2 = 1).
It vanishes identically exactly when every coefficient of that
numerator, as a polynomial in the state variables and those symbols, vanishes:
a polynomial system in the parameters. Every component of its solution set is
found (``components``): a product vanishes when any of its factors does, so the
system is split on the factors of its Gröbner basis until every element is
irreducible, and each component is solved for the leading variables of its
lexicographic basis (the others stay free: its most general solution). Components
contained in others are dropped, and so are branches that break the declared
assumptions (a positive parameter set to zero) or make a moment of inertia
vanish; every branch kept is re-checked by the zero test with its values
substituted.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import sympy as sp

from ..model import Verdict
from .domain import Domain
from .factoring import factor, factor_list
from .normal_form import CONSTANTS, Atoms, numerator_poly, relation_polys
from .zero_test import decide

Branch = dict[sp.Symbol, sp.Expr]

#: pi and E, which the normal form keeps as indeterminates, and their values.
_VALUES = {symbol: value for value, symbol in CONSTANTS.items()}
_CONSTANT_SYMBOLS = set(_VALUES)


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
    on_set = on_level_set(residuals.values(), domain)
    if on_set is None:
        return ConditionSearch(
            reason="not sought on this level set: no equation of it is linear in a variable"
        )
    equations = _coefficient_equations(on_set, set(params), domain)
    if equations is None:
        return ConditionSearch(reason="the residual is not polynomial in its normal form")
    if any(eq.is_number for eq in equations):
        return ConditionSearch(reason="no parameter values found that make the residual vanish")
    equations = {_vanishing_factors(eq) for eq in equations}
    if any(eq.is_number for eq in equations):
        return ConditionSearch(
            reason="no admissible parameter values found that make the residual vanish"
        )
    try:
        solutions = solve_components(sorted(equations, key=sp.default_sort_key), params)
    except NotImplementedError:
        return ConditionSearch(reason="sympy cannot solve the parameter system")
    except TooManyBranches as exc:
        return ConditionSearch(reason=str(exc))
    kept = [b for b in solutions if _admissible(b, protected)]
    kept = [b for b in kept if _holds(residuals, domain, b)]
    kept = most_general(kept)
    if not kept:
        return ConditionSearch(
            reason="no admissible parameter values found that make the residual vanish"
        )
    return ConditionSearch(tuple(kept))


def solve_components(equations: Sequence[sp.Expr], params: Sequence[sp.Symbol]) -> list[Branch]:
    """The most general solution of every component of ``equations = 0`` (a polynomial
    system in ``params``), each as values of some parameters in terms of the others.

    A system that is not polynomial over Q in the parameters (a radical of a parameter
    in a coefficient) goes to ``sympy.solve`` whole, after the split on factors.
    """
    gens = [p for p in params if any(eq.has(p) for eq in equations)]
    try:
        polys = [sp.Poly(eq, *gens, domain=sp.QQ) for eq in equations]
    except (sp.PolynomialError, sp.CoercionFailed, sp.GeneratorsNeeded):
        return _solve_by_factors(equations, gens)
    found: list[Branch] = []
    for basis in components([p.as_expr() for p in polys], gens):
        unknowns = _leading_variables(basis, gens)
        for branch in sp.solve(list(basis), unknowns, dict=True):
            if branch not in found:
                found.append(branch)
    return found


def components(equations: Sequence[sp.Expr], gens: Sequence[sp.Symbol]) -> list[tuple]:
    """The components of ``equations = 0`` over the declared assumptions, each as the
    reduced lexicographic Gröbner basis (in ``gens``, largest first) of an ideal whose
    elements are irreducible, none contained in another, in a deterministic order.

    An equation that factors splits the system into one branch per factor that can
    vanish (factors nonzero by the parameters' assumptions, such as a positive
    parameter, are dropped; an equation with none leaves no solution), the other
    equations that the factor divides dropped from its branch. A system whose
    equations are irreducible is replaced by its Gröbner basis, which is split again
    where one of its elements factors, until none does.

    >>> a, b, c = sp.symbols("a b c")
    >>> components([a * b, a * (c - 1)], [a, b, c])
    [(a,), (b, c - 1)]
    """
    factors = _Factors(gens)
    done: list[tuple] = []
    seen: set[frozenset] = set()
    stack = [tuple(equations)]
    while stack:
        system = stack.pop()
        if frozenset(system) in seen:
            continue
        seen.add(frozenset(system))
        if len(seen) > MAX_BRANCHES:
            raise TooManyBranches(
                f"the parameter system splits into more than {MAX_BRANCHES} branches"
            )
        branches = _split(system, factors)
        if branches is not None:
            stack.extend(branches)
            continue
        basis = tuple(sp.groebner(system, *gens, order="lex").exprs)
        if any(e.is_number for e in basis):
            continue
        branches = _split(basis, factors)
        if branches is None:
            done.append(basis)
        elif frozenset(basis) not in seen:
            stack.append(basis)
    done = list(dict.fromkeys(done))
    ideals = {key: sp.groebner(key, *gens, order="lex") for key in done}
    general = [
        key
        for key in done
        if not any(
            other != key and _contains(ideals[key], other) and not _contains(ideals[other], key)
            for other in done
        )
    ]
    return sorted(general, key=lambda key: (len(key), sp.default_sort_key(key)))


#: The most systems ``components`` visits before it gives up (each a Gröbner basis).
MAX_BRANCHES = 512


class TooManyBranches(Exception):
    """The split on factors would visit more systems than ``MAX_BRANCHES``."""


class _Factors:
    """The irreducible factors that can vanish of each equation (memoized), each in one
    normal form (positive leading coefficient in ``gens``) so that a factor shared by two
    equations is recognised."""

    def __init__(self, gens: Sequence[sp.Symbol]):
        self.gens = list(gens)
        self.known: dict[sp.Expr, tuple[sp.Expr, ...]] = {}

    def __call__(self, expr: sp.Expr) -> tuple[sp.Expr, ...]:
        if expr not in self.known:
            parts = []
            for f, _ in factor_list(expr, self.gens):
                if not f.is_nonzero and f not in parts:
                    parts.append(f)
            self.known[expr] = tuple(parts)
        return self.known[expr]


def _split(system: tuple, factors: _Factors) -> list[tuple] | None:
    """One branch per vanishing factor of the first equation of ``system`` that factors
    (or has a factor that cannot vanish), or None when every equation is irreducible."""
    for i, equation in enumerate(system):
        vanishing = factors(equation)
        if len(vanishing) == 1 and sp.expand(vanishing[0] - equation) == 0:
            continue
        others = system[:i] + system[i + 1 :]
        return [
            tuple(sorted({f, *(e for e in others if f not in factors(e))}, key=sp.default_sort_key))
            for f in vanishing
        ]
    return None


def _contains(ideal: sp.GroebnerBasis, generators: tuple) -> bool:
    """Whether every generator lies in ``ideal``: then the ideal's zero set lies in
    theirs (the ideal's branch is a special case of theirs)."""
    return all(ideal.contains(g) for g in generators)


def _leading_variables(basis: tuple, gens: Sequence[sp.Symbol]) -> list[sp.Symbol]:
    """The largest variable of each element of a lexicographic basis: the parameters
    its branch fixes in terms of the others."""
    return [g for g in gens if any(next(h for h in gens if e.has(h)) == g for e in basis)]


#: The most systems ``_solve_by_factors`` splits a non-polynomial system into.
MAX_SPLITS = 64


def _solve_by_factors(equations: Sequence[sp.Expr], gens: Sequence[sp.Symbol]) -> list[Branch]:
    """``sympy.solve`` on every choice of one vanishing factor per equation, for systems
    that are not polynomial in the parameters (up to ``MAX_SPLITS`` choices, else on
    the system whole)."""
    systems: list[tuple[sp.Expr, ...]] = [()]
    for eq in equations:
        factors = [f for f in sp.Mul.make_args(factor(eq)) if not f.is_number]
        factors = [f.base if f.is_Pow and f.exp.is_positive else f for f in factors]
        factors = [f for f in factors if not f.is_nonzero] or [eq]
        systems = [(*s, f) for s in systems for f in factors]
        if len(systems) > MAX_SPLITS:
            systems = [tuple(equations)]
            break
    found: list[Branch] = []
    for system in systems:
        unknowns = [g for g in gens if any(e.has(g) for e in system)]
        for branch in sp.solve(sorted(set(system), key=sp.default_sort_key), unknowns, dict=True):
            if branch not in found:
                found.append(branch)
    return found


def most_general(branches: Sequence[Branch]) -> list[Branch]:
    """The branches that are not special cases of another (whose equations all hold
    with the branch's values substituted), most general (fewest equations) first."""
    ordered = sorted(branches, key=lambda b: (len(b), sp.default_sort_key(tuple(b.items()))))
    kept: list[Branch] = []
    for branch in ordered:
        if not any(_special_case(branch, general) for general in kept):
            kept.append(branch)
    return kept


def _special_case(branch: Branch, general: Branch) -> bool:
    """Whether ``general``'s equations hold identically under ``branch``'s values."""
    return all(sp.simplify(sp.sympify(p - v).xreplace(branch)) == 0 for p, v in general.items())


def on_level_set(residuals: Iterable[sp.Expr], domain: Domain) -> list[sp.Expr] | None:
    """The residuals on the domain's level set, as functions of the variables it leaves
    free: each equation, in turn, solved for a state variable it is linear in (with a
    coefficient that does not vanish identically) and substituted into the residuals and
    the equations after it; None when an equation is linear in none. A branch found on
    the result is re-checked on the level set itself (``_holds``)."""
    exprs = [domain.expanded(e) for e in residuals]
    equations = [domain.expanded(e) for e in domain.on]
    while equations:
        eq = sp.expand(sp.numer(sp.together(equations.pop(0))))
        if eq == 0:
            continue
        solved = _solve_linear(eq, domain.state)
        if solved is None:
            return None
        exprs = [e.xreplace(solved) for e in exprs]
        equations = [e.xreplace(solved) for e in equations]
    return exprs


def _solve_linear(eq: sp.Expr, state: Sequence[sp.Symbol]) -> dict[sp.Symbol, sp.Expr] | None:
    """{v: value} for the first state variable ``eq`` is linear in, or None."""
    for v in state:
        if not eq.has(v):
            continue
        coefficient = sp.expand(eq.diff(v))
        if coefficient == 0 or coefficient.has(v):
            continue
        rest = sp.expand(eq - coefficient * v)
        if rest.has(v):
            continue
        return {v: -rest / coefficient}
    return None


def _coefficient_equations(
    residuals, params: set[sp.Symbol], domain: Domain
) -> set[sp.Expr] | None:
    """The coefficients, in the state and atom symbols, of every normalised numerator
    (radicals and sin, cos pairs reduced by their relations first), read off the sparse
    polynomial the zero test's normal form builds (no expression is expanded)."""
    equations: set[sp.Expr] = set()
    state = set(domain.state) | set(domain.shorthands)
    for expr in residuals:
        atoms = Atoms(domain.shorthands)
        try:
            numer, ring = numerator_poly(atoms.rewrite(expr), atoms)
        except ValueError:
            return None  # not a rational function of its atoms
        relations = relation_polys(atoms, ring)
        if relations and numer:
            numer = numer.rem(relations)
        constants = _constant_atoms(atoms, state)
        inside = [g in params or g in constants or g in _CONSTANT_SYMBOLS for g in ring.symbols]
        groups: dict[tuple, dict] = {}
        for exps, c in numer.items():
            key = tuple(e for e, p in zip(exps, inside, strict=True) if not p)
            mono = tuple(e if p else 0 for e, p in zip(exps, inside, strict=True))
            groups.setdefault(key, {})[mono] = c
        for terms in groups.values():
            c = factor(ring(terms).as_expr().xreplace(_VALUES).xreplace(constants))
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
