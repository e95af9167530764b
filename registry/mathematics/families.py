"""Which of the reference paper's families a torque belongs to, with the functions found.

The paper's families (Sec. 4) and the Casimir each one carries:

* constant mu = mu0 (gyrostat) and affine mu = T gamma + e with T symmetric:
  special cases of the next one;
* mu = psi(gamma) gamma + grad phi(gamma), eq. (4.2): C = s + phi, eq. (4.3);
* mu = a(s) grad phi(gamma) + b(gamma, s) gamma: C = int ds/a + phi, eq. (4.4);
* mu along one axis, mu_k = beta(gamma_k) delta(s): C = int ds/delta + int beta.

Recognising a family means finding its functions. The torque's dependence on
s is separated first (gamma x mu = a(s) gamma x nu(gamma)); then phi is a
potential of the tangential part of nu on the spheres |gamma| = const, found by
the constructions in ``tangential_potential``. Every candidate is checked by
the zero test before it is used.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.polys.domains import QQ
from sympy.polys.matrices import DomainMatrix

from ..model import Verdict
from . import mechanics as mech
from . import symengine_bridge
from .mechanics import AXIS, MOMENTUM, s
from .zero_test import Domain, decide

Vector = tuple[sp.Expr, sp.Expr, sp.Expr]


@dataclass(frozen=True)
class Family:
    """A torque's family in the paper's classification and the functions that exhibit it.

    ``name`` is one of ``constant``, ``affine``, ``psi-gamma-grad-phi``,
    ``a(s)-grad-phi``, ``axis``, ``none``. For the last three families,
    mu = a(s) (psi gamma + grad phi) up to a multiple of gamma, so a Casimir
    is C = int ds/a + phi (``casimir``).
    """

    name: str
    phi: sp.Expr | None = None
    psi: sp.Expr | None = None  # the multiple of gamma: psi, or b = a psi in the a(s) family
    a: sp.Expr | None = None
    axis: int | None = None
    casimir: sp.Expr | None = None
    method: str = ""
    reason: str = ""


#: Families already recognised in this process, by torque and domain (a catalog often
#: holds several cases with one torque: a claim, its correction, a variant).
_RECOGNISED: dict[tuple, Family] = {}


def recognise(mu: Sequence[sp.Expr], domain: Domain) -> Family:
    """The family of the torque ``mu`` and, when found, its Casimir C(gamma, s)."""
    mu = tuple(sp.sympify(m) for m in mu)
    key = (
        mu,
        domain.parameters,
        tuple(sorted((name, f, args) for name, (f, args) in domain.functions.items())),
        domain.nonzero,
        domain.on,
        domain.defined,
    )
    found = _RECOGNISED.get(key)
    if found is None:
        found = _recognise(mu, domain)
        if len(_RECOGNISED) >= 64:
            _RECOGNISED.clear()
        _RECOGNISED[key] = found
    return found


def _recognise(mu: Vector, domain: Domain) -> Family:
    shape = _shape(mu)
    if shape == "none":
        return Family("none", reason="the torque depends on M other than through s")
    if shape == "constant":
        phi = mech.dot(mu, AXIS)
        return Family(
            "constant",
            phi=phi,
            psi=sp.Integer(0),
            a=sp.Integer(1),
            casimir=s + phi,
            method="mu0 . gamma",
        )
    separated = separate_s(mu, domain)
    if separated is None:
        return Family(shape, reason="gamma x mu does not factor as a(s) times a field of gamma")
    a, nu = separated
    found = tangential_potential(nu, domain)
    if found is None:
        return Family(shape, a=a, reason="no potential found for the tangential part of mu")
    phi, method = found
    antiderivative = _antiderivative(1 / a, domain)
    if antiderivative is None:
        return Family(shape, a=a, phi=phi, reason=f"no closed form for int ds/({a})")
    # the multiple of gamma: psi for a = 1, b(gamma, s) = psi a in the a(s) family
    psi = _combined(
        mech.dot([m - a * sp.diff(phi, g) for m, g in zip(mu, AXIS, strict=True)], AXIS)
        / mech.dot(AXIS, AXIS)
    )
    if shape == "general":
        shape = "psi-gamma-grad-phi" if a == 1 else "a(s)-grad-phi"
    casimir = antiderivative + phi
    condition = mech.casimir_system(mu, casimir)
    if decide({f"[{i}]": c for i, c in enumerate(condition)}, domain).verdict is not (
        Verdict.VERIFIED
    ):
        return Family(shape, phi=phi, psi=psi, a=a, reason="the candidate Casimir did not re-check")
    return Family(
        shape,
        phi=phi,
        psi=psi,
        a=a,
        axis=_single_axis(mu),
        casimir=casimir,
        method=method,
    )


def _combined(expr: sp.Expr) -> sp.Expr:
    """One fraction, factored: expanding first (symengine) makes sympy's cancellation
    several times cheaper than cancelling the unexpanded form."""
    return sp.factor(sp.together(symengine_bridge.expand(expr)))


def _integral(f: sp.Expr, x: sp.Symbol) -> sp.Expr | None:
    """int f dx in closed form or None: sympy's heuristic integrator first (often several
    times faster), then the full algorithm. Callers check the result."""
    for risch in (False, None):
        found = _closed_form(sp.integrate(f, x, risch=risch))
        if found is not None:
            return found
    return None


def _shape(mu: Vector) -> str:
    """The family the form of mu suggests, before any function is found."""
    if any(m.has(*MOMENTUM) for m in mu):
        return "none"
    state = {*AXIS, s}
    if not any(m.free_symbols & state or m.has(AppliedUndef) for m in mu):
        return "constant"
    if _is_affine(mu):
        return "affine"
    if _single_axis(mu) is not None and any(m.has(s) for m in mu):
        return "axis"
    return "general"


def _is_affine(mu: Vector) -> bool:
    return all(
        not m.has(s, AppliedUndef)
        and m.is_polynomial(*AXIS)
        and sp.Poly(m, *AXIS).total_degree() <= 1
        for m in mu
    )


def _single_axis(mu: Vector) -> int | None:
    nonzero = [i for i, m in enumerate(mu) if m != 0]
    return nonzero[0] if len(nonzero) == 1 else None


def _antiderivative(f: sp.Expr, domain: Domain) -> sp.Expr | None:
    """int f ds in closed form, checked by differentiating it back, or None.

    sympy can return a wrong antiderivative for symbols with assumptions (0 for
    int ds/(s**2 + k) with real s, k), so a candidate counts only if d/ds of it is f;
    failing that, the integral is retried with symbols free of assumptions.
    """
    f = sp.cancel(f)
    if not f.has(s):
        return f * s
    plain = {x: sp.Symbol(x.name) for x in f.free_symbols if isinstance(x, sp.Symbol)}
    back = {v: k for k, v in plain.items()}
    for attempt in (
        lambda: sp.integrate(f, s),
        lambda: sp.integrate(f.xreplace(plain), plain[s]).xreplace(back),
    ):
        candidate = _closed_form(attempt())
        if candidate is None:
            continue
        check = decide({"d/ds - f": sp.diff(candidate, s) - f}, domain)
        if check.verdict is Verdict.VERIFIED:
            return candidate
    return None


def _closed_form(result: sp.Expr) -> sp.Expr | None:
    """An integral's result with the generic branch of any Piecewise, None if unevaluated.

    sympy guards antiderivatives with conditions such as r != |z|; the first
    branch is the generic one. Every use is re-checked by the zero test anyway.
    """
    if result.has(sp.Integral):
        return None
    generic = result.replace(lambda e: isinstance(e, sp.Piecewise), lambda e: e.args[0].expr)
    return None if generic.has(sp.zoo, sp.nan, sp.oo) else generic


# --- separating the dependence on s -------------------------------------------


def separate_s(mu: Vector, domain: Domain) -> tuple[sp.Expr, Vector] | None:
    """(a(s), nu(gamma)) with gamma x mu = a(s) gamma x nu, or None.

    a(s) is read off a component of gamma x mu: its factors that depend on s
    alone, else its ratio to the same component at a fixed s. The candidate is
    accepted only when d/ds of (gamma x mu)/a vanishes identically.
    """
    if not any(m.has(s) for m in mu):
        return sp.Integer(1), mu
    w = mech.cross(AXIS, mu)
    for a in _candidate_factors(w):
        quotient = [sp.cancel(c / a) for c in w]
        test = decide({f"d/ds[{i}]": sp.diff(q, s) for i, q in enumerate(quotient)}, domain)
        if test.verdict is not Verdict.VERIFIED:
            continue
        for s0 in (0, 1, 2):
            nu = tuple(sp.cancel(m / a).subs(s, s0) for m in mu)
            if not any(n.has(sp.zoo, sp.nan, sp.oo) for n in nu):
                return sp.factor(a), nu
    return None


def _candidate_factors(w: Vector):
    state = set(AXIS) | set(MOMENTUM)
    for c in w:
        if c == 0:
            continue
        factored = sp.factor(c)
        factors = sp.Mul.make_args(factored)
        s_only = [f for f in factors if f.has(s) and not (f.free_symbols & state)]
        if s_only:
            yield sp.Mul(*s_only)
        for s0 in (0, 1, 2):
            at = c.subs(s, s0)
            if at != 0 and not at.has(sp.zoo, sp.nan):
                ratio = sp.cancel(c / at)
                if not ratio.free_symbols & state:
                    yield ratio
        return


# --- potentials of the tangential part --------------------------------------


def tangential_potential(nu: Vector, domain: Domain) -> tuple[sp.Expr, str] | None:
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


def _groups(nu: Vector) -> list[Vector]:
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


def _solve_group(nu: Vector, domain: Domain) -> tuple[sp.Expr, str] | None:
    for method, construct in _CONSTRUCTIONS:
        try:
            phi = construct(nu, domain)
        except (ValueError, NotImplementedError, TypeError, sp.PolynomialError):
            phi = None
        if phi is not None and _is_potential(phi, nu, domain):
            return phi, method
    return None


def _is_potential(phi: sp.Expr, nu: Vector, domain: Domain) -> bool:
    grad = [sp.diff(phi, g) for g in AXIS]
    residual = mech.cross(AXIS, [n - d for n, d in zip(nu, grad, strict=True)])
    test = decide({f"[{i}]": r for i, r in enumerate(residual)}, domain)
    return test.verdict is Verdict.VERIFIED


def _polynomial_ansatz(nu: Vector, domain: Domain) -> sp.Expr | None:
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

    def construct(nu: Vector, domain: Domain) -> sp.Expr | None:
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


def _radial_homotopy(nu: Vector, domain: Domain) -> sp.Expr | None:
    """phi(gamma) = int_0^1 nu(t gamma) . gamma dt, the potential of a gradient field."""
    t = sp.Symbol("t", positive=True)
    integrand = mech.dot([n.subs({g: t * g for g in AXIS}, simultaneous=True) for n in nu], AXIS)
    return _closed_form(sp.integrate(sp.expand(integrand), (t, 0, 1)))


def _declared_functions(nu: Vector, domain: Domain) -> sp.Expr | None:
    """phi as a combination of the family's declared functions of gamma found in nu."""
    candidates = sorted(
        {f for n in nu for f in n.atoms(AppliedUndef) if set(f.args) <= set(AXIS)},
        key=str,
    )
    if not candidates:
        return None
    coeffs = sp.symbols(f"k0:{len(candidates)}", cls=sp.Dummy)
    phi = sp.Add(*(c * f for c, f in zip(coeffs, candidates, strict=True)))
    grad = [sp.diff(phi, g) for g in AXIS]
    residual = mech.cross(AXIS, [n - d for n, d in zip(nu, grad, strict=True)])
    derivs = sorted({d for r in residual for d in sp.expand(r).atoms(sp.Derivative)}, key=str)
    if not derivs:
        return None
    stand_ins = sp.symbols(f"d0:{len(derivs)}", cls=sp.Dummy)
    flat = [sp.expand(r).xreplace(dict(zip(derivs, stand_ins, strict=True))) for r in residual]
    equations = [c for r in flat if r != 0 for c in sp.Poly(r, *stand_ins, *AXIS).coeffs()]
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
