"""Potentials of the tangential part of a field on the spheres |gamma| = const.

phi(gamma) with gamma x (nu - grad phi) = 0 is what a torque's family needs
(``families``): the terms of nu are grouped by their non-polynomial factors and each
group is solved by the first construction that works, each candidate checked by the
zero test: a polynomial ansatz (a linear system solved once per degree), integration
along meridians about a coordinate axis, an ansatz in the family's declared functions,
and the radial homotopy of a gradient field.
"""

from __future__ import annotations

import functools
import itertools

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from ..model import Verdict
from . import mechanics as mech
from . import symengine_bridge
from .domain import Domain
from .mechanics import AXIS, Vector3
from .zero_test import decide


def tangential_potential(nu: Vector3, domain: Domain) -> tuple[sp.Expr, str] | None:
    """phi(gamma) with gamma x (nu - grad phi) = 0, and the construction that found it.

    Terms of nu are grouped by their non-polynomial factors and each group is
    solved on its own (a polynomial ansatz; integration along meridians for a
    group symmetric about a coordinate axis; the radial homotopy for a gradient;
    an ansatz in the family's declared functions); failing that, nu as a whole.
    """
    nu = tuple(sp.expand_mul(n) for n in nu)
    if all(n == 0 for n in nu):
        return sp.Integer(0), "zero"
    groups = _groups(nu)
    pieces = []
    for group in groups if len(groups) > 1 else []:
        found = _solve_group(group, domain)
        if found is None:
            break
        pieces.append(found)
    else:
        if pieces:
            return sp.Add(*(p for p, _ in pieces)), " + ".join(dict.fromkeys(m for _, m in pieces))
    return _solve_group(nu, domain)


def _groups(nu: Vector3) -> list[Vector3]:
    """nu split by the non-polynomial factors of its terms (sqrt(...), sin(...), ...)."""
    keyed: dict[frozenset, list[list[sp.Expr]]] = {}
    for i, component in enumerate(nu):
        for term in sp.Add.make_args(component):
            key = frozenset(_non_polynomial(term))
            keyed.setdefault(key, [[], [], []])[i].append(term)
    return [tuple(sp.Add(*terms) for terms in parts) for parts in keyed.values()]


def _non_polynomial(term: sp.Expr) -> set:
    """What makes a term non-polynomial in gamma: radical bases, functions, and the
    declared functions it involves (a gradient's components differentiate one phi
    in different directions, so they are keyed by phi, not by the derivative)."""
    found: set = set()
    for factor in sp.Mul.make_args(term):
        base, exp = factor.as_base_exp()
        if not base.free_symbols & set(AXIS) and not base.has(AppliedUndef):
            continue
        declared = base.atoms(AppliedUndef)
        if declared:
            found.update(f.func for f in declared)
        elif isinstance(factor, sp.Function) or not (exp.is_Integer and exp > 0):
            found.add(sp.expand(base) if exp.is_Rational else factor)
    return found


def _solve_group(nu: Vector3, domain: Domain) -> tuple[sp.Expr, str] | None:
    for method, construct in _CONSTRUCTIONS:
        try:
            phi = construct(nu, domain)
        except (ValueError, NotImplementedError, TypeError, sp.PolynomialError):
            phi = None
        if phi is not None and _is_potential(phi, nu, domain):
            return phi, method
    return None


def _is_potential(phi: sp.Expr, nu: Vector3, domain: Domain) -> bool:
    grad = [sp.diff(phi, g) for g in AXIS]
    residual = mech.cross(AXIS, [n - d for n, d in zip(nu, grad, strict=True)])
    test = decide({f"[{i}]": r for i, r in enumerate(residual)}, domain)
    return test.verdict is Verdict.VERIFIED


def _polynomial_ansatz(nu: Vector3, domain: Domain) -> sp.Expr | None:
    """phi as a polynomial one degree above nu: gamma x grad phi = gamma x nu is a
    linear system for phi's coefficients, with a rational matrix that depends only
    on the degree (solved once, see ``_ansatz_system``)."""
    if not all(n.is_polynomial(*AXIS) for n in nu):
        return None
    degree = max(sp.Poly(n, *AXIS).total_degree() for n in nu if n != 0) + 1
    monomials, rows, solution = _ansatz_system(degree)
    target = [sp.S.Zero] * len(rows)
    for k, component in enumerate(mech.cross(AXIS, nu)):
        for exps, coeff in sp.Poly(symengine_bridge.expand(component), *AXIS).terms():
            if coeff == 0:
                continue
            if (k, exps) not in rows:
                return None  # gamma x nu has a term no polynomial phi produces
            target[rows[k, exps]] = coeff
    terms = []
    for column, weights in solution:
        value = sp.Add(*(w * target[r] for r, w in weights))
        terms.append(value * sp.Mul(*(g**e for g, e in zip(AXIS, monomials[column], strict=True))))
    return sp.expand(sp.Add(*terms))


@functools.lru_cache(maxsize=8)
def _ansatz_system(degree: int):
    """The linear system gamma x grad phi = b for phi = sum_j c_j m_j, m_j the monomials
    of degrees 1..degree: the monomials' exponents, the row of each (component,
    monomial) of b, and for each pivot coefficient c_j its weights on b's rows (a
    particular solution, the free coefficients set to 0)."""
    monomials = [e for d in range(1, degree + 1) for e in _exponents(d)]
    rows = {(k, e): i for i, (k, e) in enumerate(itertools.product(range(3), monomials))}
    n, m = len(monomials), len(rows)
    matrix = [[QQ(0)] * (n + m) for _ in range(m)]
    for j, exps in enumerate(monomials):
        phi = sp.Mul(*(g**e for g, e in zip(AXIS, exps, strict=True)))
        field = mech.cross(AXIS, [sp.diff(phi, g) for g in AXIS])
        for k, component in enumerate(field):
            for term_exps, coeff in sp.Poly(component, *AXIS).terms():
                if coeff:
                    matrix[rows[k, term_exps]][j] = QQ(int(coeff))
    for i in range(m):
        matrix[i][n + i] = QQ(1)
    reduced, pivots = DomainMatrix(matrix, (m, n + m), QQ).rref()
    reduced = reduced.to_Matrix()
    solution = []
    for i, column in enumerate(pivots):
        if column >= n:
            break
        weights = [(r, reduced[i, n + r]) for r in range(m) if reduced[i, n + r] != 0]
        solution.append((column, weights))
    return monomials, rows, solution


def _exponents(degree: int) -> list[tuple[int, int, int]]:
    """The exponents of the monomials of gamma of the given total degree."""
    return [
        (a, b, degree - a - b) for a in range(degree, -1, -1) for b in range(degree - a, -1, -1)
    ]


def _meridian(axis: int):
    """Integration along meridians about coordinate axis ``axis``.

    For nu symmetric about the axis with no azimuthal component, phi depends on
    z = gamma_axis and r = |gamma| only, and d phi/dz along a meridian is
    nu . d gamma/dz = nu_z - z (gamma_a nu_a + gamma_b nu_b)/rho**2.
    """
    a, b = (i for i in range(3) if i != axis)
    ga, gb, z = AXIS[a], AXIS[b], AXIS[axis]

    def construct(nu: Vector3, domain: Domain) -> sp.Expr | None:
        swirl = ga * nu[b] - gb * nu[a]
        if decide({"swirl": swirl}, domain).verdict is not Verdict.VERIFIED:
            return None
        rho = sp.Symbol("rho", positive=True)
        r = sp.Symbol("r", positive=True)
        slope = nu[axis] - z * (ga * nu[a] + gb * nu[b]) / (ga**2 + gb**2)
        on_meridian = sp.cancel(slope.subs({ga: rho, gb: 0}))
        h = _integral(on_meridian.subs(rho, sp.sqrt(r**2 - z**2)), z)
        if h is None:
            return None
        # back to the cylindrical radius: r**2 = rho**2 + z**2, and for rho > 0
        # asin(z/r) = atan(z/rho), the form in which the paper writes such terms
        h = h.subs(r, sp.sqrt(rho**2 + z**2))
        h = h.replace(
            lambda e: isinstance(e, sp.asin) and e.args[0] == z / sp.sqrt(rho**2 + z**2),
            lambda e: sp.atan(z / rho),
        )
        h = sp.expand(sp.cancel(h))
        return h.subs(rho, sp.sqrt(ga**2 + gb**2))

    return construct


def _radial_homotopy(nu: Vector3, domain: Domain) -> sp.Expr | None:
    """phi(gamma) = int_0^1 nu(t gamma) . gamma dt, the potential of a gradient field.

    Not tried on a family's arbitrary functions: no closed form integrates f(t gamma)
    along the rays for an unknown f (and sympy spends seconds finding that out)."""
    if any(n.has(AppliedUndef) for n in nu):
        return None
    t = sp.Symbol("t", positive=True)
    integrand = mech.dot([n.subs({g: t * g for g in AXIS}, simultaneous=True) for n in nu], AXIS)
    return closed_form(sp.integrate(sp.expand(integrand), (t, 0, 1)))


def _declared_functions(nu: Vector3, domain: Domain) -> sp.Expr | None:
    """phi as a combination of the family's declared functions of gamma found in nu:
    the functions themselves, else each also times gamma1, gamma2, gamma3 (Yehia's
    torques, mu = -(div l) gamma + grad(l . gamma), have phi = l . gamma)."""
    functions = sorted(
        {f for n in nu for f in n.atoms(AppliedUndef) if set(f.args) <= set(AXIS)},
        key=str,
    )
    if not functions:
        return None
    with_axis = [f * g for f in functions for g in AXIS]
    return _combination(nu, functions, functions) or _combination(
        nu, functions, functions + with_axis
    )


def _combination(nu: Vector3, functions, candidates) -> sp.Expr | None:
    """phi = sum of k_i candidates_i with gamma x (nu - grad phi) = 0: a linear system for
    the k_i once the functions and their derivatives stand as independent unknowns."""
    coeffs = sp.symbols(f"k0:{len(candidates)}", cls=sp.Dummy)
    phi = sp.Add(*(c * f for c, f in zip(coeffs, candidates, strict=True)))
    grad = [sp.diff(phi, g) for g in AXIS]
    residual = [
        sp.expand(r) for r in mech.cross(AXIS, [n - d for n, d in zip(nu, grad, strict=True)])
    ]
    derivs = sorted({d for r in residual for d in r.atoms(sp.Derivative)}, key=str)
    unknowns = [*derivs, *functions]  # derivatives first: they contain the functions
    stand_ins = sp.symbols(f"d0:{len(unknowns)}", cls=sp.Dummy)
    flat = residual
    for unknown, stand_in in zip(unknowns, stand_ins, strict=True):
        flat = [r.xreplace({unknown: stand_in}) for r in flat]
    try:
        equations = [c for r in flat if r != 0 for c in sp.Poly(r, *stand_ins, *AXIS).coeffs()]
    except sp.PolynomialError:
        return None
    if not equations or any(e.has(AppliedUndef, sp.Derivative) for e in equations):
        return None
    solutions = sp.solve(equations, coeffs, dict=True)
    if not solutions:
        return None
    return phi.xreplace(solutions[0]).xreplace({c: 0 for c in coeffs})


_CONSTRUCTIONS = [
    ("polynomial ansatz", _polynomial_ansatz),
    ("meridian integration about gamma3", _meridian(2)),
    ("meridian integration about gamma1", _meridian(0)),
    ("meridian integration about gamma2", _meridian(1)),
    ("declared functions", _declared_functions),
    ("radial homotopy", _radial_homotopy),
]


def _integral(f: sp.Expr, x: sp.Symbol) -> sp.Expr | None:
    """int f dx in closed form or None: sympy's heuristic integrator first (often several
    times faster), then the full algorithm. Callers check the result."""
    for risch in (False, None):
        found = closed_form(sp.integrate(f, x, risch=risch))
        if found is not None:
            return found
    return None


def closed_form(result: sp.Expr) -> sp.Expr | None:
    """An integral's result with the generic branch of any Piecewise, None if unevaluated.

    sympy guards antiderivatives with conditions such as r != |z|; the first
    branch is the generic one. Every use is re-checked by the zero test anyway.
    """
    if result.has(sp.Integral):
        return None
    generic = result.replace(lambda e: isinstance(e, sp.Piecewise), lambda e: e.args[0].expr)
    return None if generic.has(sp.zoo, sp.nan, sp.oo) else generic
