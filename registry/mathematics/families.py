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
the constructions of ``potentials``. Every candidate is checked by the zero test
before it is used.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef

from ..model import Verdict
from . import mechanics as mech
from . import symengine_bridge
from .domain import Domain
from .factoring import factor
from .mechanics import AXIS, MOMENTUM, Vector3, s
from .potentials import closed_form, tangential_potential
from .zero_test import decide


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


def _recognise(mu: Vector3, domain: Domain) -> Family:
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
    return factor(symengine_bridge.expand(expr))


def _shape(mu: Vector3) -> str:
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


def _is_affine(mu: Vector3) -> bool:
    return all(
        not m.has(s, AppliedUndef)
        and m.is_polynomial(*AXIS)
        and sp.Poly(m, *AXIS).total_degree() <= 1
        for m in mu
    )


def _single_axis(mu: Vector3) -> int | None:
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
        candidate = closed_form(attempt())
        if candidate is None:
            continue
        check = decide({"d/ds - f": sp.diff(candidate, s) - f}, domain)
        if check.verdict is Verdict.VERIFIED:
            return candidate
    return None


# --- separating the dependence on s -------------------------------------------


def separate_s(mu: Vector3, domain: Domain) -> tuple[sp.Expr, Vector3] | None:
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
                return factor(a), nu
    return None


def _candidate_factors(w: Vector3):
    state = set(AXIS) | set(MOMENTUM)
    for c in w:
        if c == 0:
            continue
        factored = factor(c)
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
