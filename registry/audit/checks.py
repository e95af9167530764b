"""The checks: each a small function stating one mathematical claim about a case.

A check returns a ``CheckResult`` (verdict, method, witness, time), never a
bare bool. Case checks take the case's ``CaseMechanics``; claim checks also take
the claim. The symbolic objects (Pi_mu, the vector field, H) and the residuals are
built once per case in ``CaseMechanics`` and shared by every check and correction.
A new check is one more decorated function here (``@check``).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace

import sympy as sp

from ..dynamics import Dynamics
from ..mathematics import flow, symengine_bridge
from ..mathematics import mechanics as mech
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.factoring import factor
from ..mathematics.zero_test import ZeroTest, decide
from ..model import Case, CheckResult, Claim, ClaimKind, Verdict


@dataclass(frozen=True)
class CheckSpec:
    """A registered check: its name, function, and whether it runs per claim."""

    name: str
    run: Callable[..., CheckResult]
    per_claim: bool
    cost: str  # "cheap" or "expensive", a note for schedulers and readers
    applies: Callable[[Claim], bool] = lambda claim: True
    #: Why the check does not apply to a case ("" where it does): a check whose statement
    #: holds by definition for the case, or that asks about something the system does not
    #: have (a bracket, a Hamiltonian), is left out, never reported as verified.
    inapplicable: Callable[[Dynamics], str] = lambda dynamics: ""

    @property
    def statement(self) -> str:
        return (self.run.__doc__ or "").strip().splitlines()[0]


CHECKS: dict[str, CheckSpec] = {}


def check(
    name: str, *, per_claim: bool = False, cost: str = "cheap", applies=None, inapplicable=None
):
    """Register a check under ``name``; its one-line docstring states the claim."""

    def register(fn):
        CHECKS[name] = CheckSpec(
            name,
            fn,
            per_claim,
            cost,
            applies or (lambda claim: True),
            inapplicable or (lambda case: ""),
        )
        return fn

    return register


def not_applicable(case: Case) -> dict[str, str]:
    """The checks that do not apply to ``case``, each with the reason."""
    found = {name: spec.inapplicable(case.dynamics) for name, spec in CHECKS.items()}
    return {name: reason for name, reason in found.items() if reason}


def _needs_bracket(dynamics: Dynamics) -> str:
    if dynamics.bracket is None:
        return "not applicable: the system has no Poisson bracket (it is given by its equations)"
    return ""


def _needs_hamiltonian(dynamics: Dynamics) -> str:
    if dynamics.hamiltonian is None:
        return "not applicable: the system has no Hamiltonian (it is given by its equations)"
    return ""


def _needs_c1(dynamics: Dynamics) -> str:
    if dynamics.c1 is None:
        return (
            "not applicable: C1 is the Casimir of the brackets of e(3), so(4) and so(3,1); "
            "this system's bracket is another"
            if dynamics.bracket is not None
            else _needs_bracket(dynamics)
        )
    return ""


def _given_on_its_own(dynamics: Dynamics) -> str:
    if dynamics.from_bracket:
        return (
            "not applicable: the case gives H (system.hamiltonian), and its vector field "
            "is defined as Pi grad H"
        )
    return _needs_bracket(dynamics) or _needs_hamiltonian(dynamics)


def _result(
    name: str,
    m: CaseMechanics,
    test: ZeroTest,
    residuals: Mapping[str, sp.Expr],
    started: float,
    claim: str | None = None,
    reason: str | None = None,
) -> CheckResult:
    residual = None
    if test.verdict is Verdict.REFUTED and test.component is not None:
        residual = _text(readable(residuals[test.component], m.dynamics.shorthands))
    return CheckResult(
        check=name,
        verdict=test.verdict,
        method=test.method,
        claim=claim,
        reason=test.reason if reason is None else reason,
        residual=residual,
        witness=test.witness,
        seconds=time.perf_counter() - started,
    )


#: Residuals larger than this (in sympy operations, expanded) are not factored fully
#: (multivariate factoring costs more than the audit of the case, and rarely shortens
#: such residuals); only their common factors are pulled out.
FACTOR_LIMIT = 100

#: Residuals larger than this are shown as computed.
COMBINE_LIMIT = 3000


def readable(expr: sp.Expr, shorthands=mech.SHORTHANDS) -> sp.Expr:
    """A residual in a form a person can read: shorthands (s) written out, combined and
    factored (a pure function of its arguments, remembered for the residuals refuted
    again: a correction re-checked, a variant of a case with the same residual)."""
    return _readable(expr, tuple(dict(shorthands).items()), symengine_bridge.ENABLED)


@functools.lru_cache(maxsize=256)
def _readable(
    expr: sp.Expr, shorthands: tuple[tuple[sp.Symbol, sp.Expr], ...], symengine: bool
) -> sp.Expr:
    expanded = symengine_bridge.expand(expr.subs(dict(shorthands)))
    size = sp.count_ops(expanded)
    if size > COMBINE_LIMIT:
        return expr
    combined = sp.together(expanded)
    return factor(combined) if size <= FACTOR_LIMIT else sp.factor_terms(combined)


def _text(expr: sp.Expr) -> str:
    """An expression in the case-file language where possible (sympy's form otherwise)."""
    from ..language.printer import to_text

    try:
        return to_text(expr)
    except ValueError:
        return sp.sstr(expr)


def _decide(m: CaseMechanics, name: str, residuals, claim: Claim | None = None) -> ZeroTest:
    """The zero test on the case's domain, or on the claim's level set where the claim
    itself must be defined."""
    domain = m.domain if claim is None else m.claim_domain(claim)
    return decide(residuals, domain, seed=m.seed(name, None if claim is None else claim.label))


@check("jacobi", cost="expensive", inapplicable=_needs_bracket)
def jacobi(m: CaseMechanics) -> CheckResult:
    """Pi satisfies the Jacobi identity, i.e. it is a Poisson tensor (every component)."""
    started = time.perf_counter()
    residuals = m.jacobiator
    return _result("jacobi", m, _decide(m, "jacobi", residuals), residuals, started)


@check("energy", inapplicable=_needs_hamiltonian)
def energy(m: CaseMechanics) -> CheckResult:
    """The Hamiltonian H (M.I^-1 M/2 + U, or the case's own) is conserved: dH/dt = 0."""
    started = time.perf_counter()
    residuals = {"dH/dt": m.time_derivative(m.hamiltonian)}
    return _result("energy", m, _decide(m, "energy", residuals), residuals, started)


@check("c1", inapplicable=_needs_c1)
def c1(m: CaseMechanics) -> CheckResult:
    """C1 = (kappa |M|^2 + |gamma|^2)/2 is a Casimir of Pi: Pi grad C1 = 0."""
    started = time.perf_counter()
    residuals = m.casimir_residual(m.c1)
    return _result("c1", m, _decide(m, "c1", residuals), residuals, started)


@check("hamiltonian", inapplicable=_given_on_its_own)
def hamiltonian(m: CaseMechanics) -> CheckResult:
    """System (2.2) is Hamiltonian for Pi: its vector field equals Pi grad H."""
    started = time.perf_counter()
    dynamics = m.dynamics
    # Pi grad H (``flow.hamiltonian_field``) from the gradient of H that energy computed
    generated = flow.apply_bivector(dynamics.bracket, m.gradient(dynamics.hamiltonian))
    residuals = {
        f"X-Pi grad H[{v}]": x - y
        for v, x, y in zip(dynamics.variables, m.field, generated, strict=True)
    }
    return _result("hamiltonian", m, _decide(m, "hamiltonian", residuals), residuals, started)


#: The claim kinds whose expression is an integral, checked as one (and as a Casimir).
CONSERVED = (ClaimKind.INTEGRAL, ClaimKind.CASIMIR)


@check("invariant", per_claim=True, applies=lambda claim: bool(claim.on))
def invariant(m: CaseMechanics, claim: Claim) -> CheckResult:
    """The claim's level set is invariant under the flow: dg/dt = 0 where every g = 0."""

    def compute() -> CheckResult:
        started = time.perf_counter()
        residuals = {f"d/dt({eq.text})": m.time_derivative(eq.expr) for eq in claim.on}
        test = _decide(m, "invariant", residuals, claim)
        return _result("invariant", m, test, residuals, started, claim.label)

    return m.once(("invariant", claim.label), compute)


@check("integral", per_claim=True, applies=lambda claim: claim.kind in CONSERVED)
def integral(m: CaseMechanics, claim: Claim) -> CheckResult:
    """The claimed expression I is conserved: dI/dt = 0 along the flow (on its level set)."""
    started = time.perf_counter()
    residuals = m.integral_residual(claim.expression.expr)
    test = _decide(m, "integral", residuals, claim)
    reason = None
    if test.verdict is Verdict.VERIFIED and claim.on:
        kept = invariant(m, claim)
        if kept.verdict is not Verdict.VERIFIED:
            why = (
                "the flow does not keep the level set invariant"
                if kept.verdict is Verdict.REFUTED
                else "could not decide whether the flow keeps the level set invariant"
            )
            test = ZeroTest(Verdict.INCONCLUSIVE, test.method)
            reason = f"dI/dt vanishes on the level set, but {why}"
    return _result("integral", m, test, residuals, started, claim.label, reason)


@check(
    "casimir",
    per_claim=True,
    applies=lambda claim: claim.kind in CONSERVED,
    inapplicable=_needs_bracket,
)
def casimir(m: CaseMechanics, claim: Claim) -> CheckResult:
    """The claimed expression I is a Casimir of Pi: Pi grad I = 0 (on its level set)."""
    started = time.perf_counter()
    residuals = m.casimir_residual(claim.expression.expr)
    test = _decide(m, "casimir", residuals, claim)
    return _result("casimir", m, test, residuals, started, claim.label)


@check("measure", per_claim=True, applies=lambda claim: claim.kind is ClaimKind.MEASURE)
def measure(m: CaseMechanics, claim: Claim) -> CheckResult:
    """The claimed rho is the density of an invariant measure: div(rho v) = 0 (Liouville's
    equation; on the claim's level set)."""
    started = time.perf_counter()
    residuals = m.measure_residual(claim.expression.expr)
    test = _decide(m, "measure", residuals, claim)
    return _result("measure", m, test, residuals, started, claim.label)


@check("relation", per_claim=True, applies=lambda claim: claim.kind is ClaimKind.RELATION)
def relation(m: CaseMechanics, claim: Claim) -> CheckResult:
    """The zero set of the claimed F is invariant: dF/dt vanishes where F = 0 (and on the
    claim's level set); for a polynomial F, the cofactor K of dF/dt = K F is reported."""
    started = time.perf_counter()
    f = claim.expression.expr
    rate = m.integral_residual(f)["dI/dt"]  # shared with an integral claim of the same F
    residuals = {"dF/dt": rate}
    test = decide(residuals, m.relation_domain(claim), seed=m.seed("relation", claim.label))
    found = _result("relation", m, test, residuals, started, claim.label)
    if test.verdict is Verdict.VERIFIED:
        cofactor = _cofactor(m, f, rate)
        if cofactor is not None:
            found = replace(found, detail=f"cofactor K = {_text(cofactor)} (dF/dt = K F)")
    return found


def _cofactor(m: CaseMechanics, f: sp.Expr, rate: sp.Expr) -> sp.Expr | None:
    """K with dF/dt = K F, where F and dF/dt are polynomials in the state and F divides
    dF/dt exactly; None otherwise (K is then no polynomial, or F is not one)."""
    state = m.dynamics.variables
    try:
        numerator = sp.Poly(m.dynamics.expanded(rate).expand(), *state)
        divisor = sp.Poly(m.dynamics.expanded(f).expand(), *state)
    except sp.PolynomialError:
        return None
    if divisor.is_zero:
        return None
    quotient, remainder = numerator.div(divisor)
    return quotient.as_expr() if remainder.is_zero else None
