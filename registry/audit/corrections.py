"""Corrections of failed claims, each re-checked by the same checks before it is reported.

* A corrected Casimir for the case's own torque (where Pi_mu is Poisson): the
  Casimir of the torque's family (``mathematics.families``), independent of C1.
* A corrected torque for a claimed Casimir I(gamma, s): by the Casimir condition
  equation (3.4), I is a Casimir of Pi_mu' for mu' = grad_gamma I / d_s I + lambda gamma;
  lambda is chosen so that as many components of mu as possible stay unchanged.
* Parameter conditions (``mathematics.parameter_conditions``) under which a refuted
  claim, or a failing Jacobi identity, holds.

The torque's family, the corrected Casimir and the corrected torque are the reference
paper's, for its bracket e(3) (kappa = 0; any Hamiltonian, since a Casimir does not
depend on H). On so(4) and so(3,1) they do not apply, and the family record says so;
the parameter conditions apply to every case.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import sympy as sp

from ..language.forms import with_torque
from ..language.printer import to_text
from ..mathematics import flow
from ..mathematics import mechanics as mech
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.domain import Domain
from ..mathematics.factoring import factor
from ..mathematics.families import Family, recognise
from ..mathematics.mechanics import AXIS, MOMENTUM
from ..mathematics.parameter_conditions import equations_text, parameter_conditions
from ..mathematics.zero_test import decide
from ..model import (
    CheckResult,
    Claim,
    ClaimKind,
    Conditions,
    Correction,
    Expression,
    FamilyRecord,
    Verdict,
)
from .checks import casimir, jacobi


def corrected_casimir(
    m: CaseMechanics, family: Family, claim: str | None = None
) -> Correction | None:
    """The family's Casimir C(gamma, s), if Pi_mu is Poisson and C re-checks as a Casimir
    that is independent of C1 (grad_M C is not identically zero)."""
    if family.casimir is None:
        return None
    expr = tidy(_prettier(family.casimir))
    probe = Claim("corrected Casimir", ClaimKind.CASIMIR, Expression(to_text(expr), expr))
    check = casimir(m, probe)
    independent = decide(
        {f"d/d{v}": flow.total_diff(expr, v, mech.SHORTHANDS) for v in MOMENTUM}, m.domain
    )
    if check.verdict is not Verdict.VERIFIED or independent.verdict is not Verdict.REFUTED:
        return None
    return Correction(
        kind="casimir",
        claim=claim,
        expression=to_text(expr),
        method=f"{family.name}: {family.method}",
        checks={"casimir": check.verdict},
    )


def _prettier(expr: sp.Expr) -> sp.Expr:
    """A simpler Casimir with the same level sets: exp(C) when C is a sum of logarithms."""
    if expr.has(sp.log):
        candidate = sp.simplify(sp.exp(expr))
        if not candidate.has(sp.log, sp.exp):
            return candidate
    return expr


def corrected_torque(m: CaseMechanics, claim: Claim) -> Correction | None:
    """mu' under which the claimed I is a Casimir, changing as few components as it can.

    Needs I = I(gamma, s) with d_s I != 0. The result is reported only if Pi_mu'
    satisfies the Jacobi identity and I re-checks as a Casimir of Pi_mu'.
    """
    i = claim.expression.expr
    grad_m = [flow.total_diff(i, v, mech.SHORTHANDS) for v in MOMENTUM]
    # I depends on M through s only: grad_M I = (d_s I) gamma
    ds_i = sp.cancel(mech.dot(grad_m, AXIS) / mech.dot(AXIS, AXIS))
    through_s = mech.cross(AXIS, grad_m)
    if (
        decide(
            {"gamma x grad_M I": through_s[0], "1": through_s[1], "2": through_s[2]}, m.domain
        ).verdict
        is not Verdict.VERIFIED
    ):
        return None
    if decide({"d_s I": ds_i}, m.domain).verdict is not Verdict.REFUTED:
        return None  # d_s I = 0: no torque makes I a Casimir independent of C1
    grad_g = [
        flow.total_diff(i, g, mech.SHORTHANDS) - ds_i * mv
        for g, mv in zip(AXIS, MOMENTUM, strict=True)
    ]
    w = [sp.cancel(g / ds_i) for g in grad_g]  # grad_gamma I / d_s I, at fixed s
    lam, kept = _best_lambda(m, w)
    own = m.dynamics.torque
    assert own is not None  # corrections are sought only for the paper's Pi_mu
    new = [own[k] if k in kept else _expression(tidy(w[k] + lam * AXIS[k])) for k in range(3)]
    torque = (new[0], new[1], new[2])
    changed = tuple(k for k in range(3) if k not in kept)
    corrected = CaseMechanics(with_torque(m.case, torque))
    poisson = jacobi(corrected)
    holds = casimir(corrected, claim)
    if poisson.verdict is not Verdict.VERIFIED or holds.verdict is not Verdict.VERIFIED:
        return None
    return Correction(
        kind="torque",
        claim=claim.label,
        torque=(torque[0].text, torque[1].text, torque[2].text),
        changed=changed,
        method="mu' = grad_gamma I / d_s I + lambda gamma",
        checks={"jacobi": poisson.verdict, "casimir": holds.verdict},
    )


def _expression(expr: sp.Expr) -> Expression:
    return Expression(to_text(expr), expr)


def _best_lambda(m: CaseMechanics, w: list[sp.Expr]) -> tuple[sp.Expr, set[int]]:
    """lambda making the most components of mu' equal to those of mu, and which ones.

    Component k stays unchanged for lambda_k = (mu_k - w_k)/gamma_k; components whose
    lambda_k agree identically can stay unchanged together.
    """
    mu = m.mu
    assert mu is not None  # corrections are sought only for the paper's Pi_mu
    lams = [sp.cancel((mu[k] - w[k]) / AXIS[k]) for k in range(3)]
    agree = {k: {k} for k in range(3)}
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if decide({"d": lams[i] - lams[j]}, m.domain).verdict is Verdict.VERIFIED:
            agree[i].add(j)
            agree[j].add(i)
    best = max(range(3), key=lambda k: (len(agree[k]), -sp.count_ops(lams[k])))
    return lams[best], agree[best]


#: Expressions larger than this (sympy operations) are reported as computed.
TIDY_LIMIT = 2000


def tidy(expr: sp.Expr) -> sp.Expr:
    """A readable form of a derived expression (s kept as s), if shorter than the input.

    Terms are grouped by their radicals and functions, each group is combined and
    factored, and common factors are pulled out: the forms in which papers write
    such expressions (e.g. the paper's mu3' = -C gamma3 (3n + ... - N(gamma3**2 + 1)/rho**3)).
    """
    if sp.count_ops(expr) > TIDY_LIMIT:
        return expr
    combined = factor(sp.cancel(sp.expand(expr)))  # one fraction: like radicals merge
    groups: dict[frozenset, list[sp.Expr]] = {}
    for term in sp.Add.make_args(sp.expand(combined)):
        groups.setdefault(_irrational_parts(term), []).append(term)
    parts = [factor(sp.cancel(sp.Add(*terms))) for terms in groups.values()]
    return min([expr, combined, sp.factor_terms(sp.Add(*parts))], key=sp.count_ops)


def _irrational_parts(term: sp.Expr) -> frozenset:
    return frozenset(
        a
        for a in sp.preorder_traversal(term)
        if isinstance(a, sp.Function) or a.is_Pow and a.exp.is_Rational and not a.exp.is_Integer
    )


def holds_when(
    residuals, m: CaseMechanics, target: str, domain: Domain | None = None
) -> Conditions:
    """The parameter conditions under which ``residuals`` vanish (on ``domain``, default
    the case's), as case-file equations."""
    found = parameter_conditions(residuals, domain or m.domain, m.dynamics.nonzero)
    branches = tuple(tuple(equations_text(b, to_text)) for b in found.branches)
    return Conditions(target, branches, found.reason)


def family_record(family: Family) -> FamilyRecord:
    """The family as text, for storage and output."""

    def text(expr: sp.Expr | None) -> str | None:
        return None if expr is None else to_text(expr)

    return FamilyRecord(
        family.name,
        phi=text(family.phi),
        psi=text(family.psi),
        a=text(family.a),
        casimir=text(family.casimir),
        method=family.method,
        reason=family.reason,
    )


#: Why the paper's corrections are not sought on a deformed bracket.
NOT_E3 = (
    "not applicable: the torque families, corrected Casimirs and corrected torques are the "
    "reference paper's, for the bracket of e(3) (kappa = 0); this case has kappa = {}"
)
#: Why they are not sought where the bracket is not the paper's Pi_mu at all.
NO_TORQUE = (
    "not applicable: the torque families, corrected Casimirs and corrected torques are the "
    "reference paper's, for its bracket Pi_mu of e(3); this system has no gyroscopic torque "
    "in that bracket"
)


def corrections(
    m: CaseMechanics, results: Sequence[CheckResult]
) -> tuple[FamilyRecord, tuple[Correction, ...], tuple[Conditions, ...]]:
    """The family of the torque, the corrections of every refuted claim and the conditions
    under which failed identities hold, for an audited case."""
    verdict = {(r.check, r.claim): r.verdict for r in results}
    mu = m.mu
    e3 = mu is not None and m.kappa == 0
    if mu is None:
        family = Family("none", reason=NO_TORQUE)
    elif e3:
        family = recognise(mu, m.domain)
    else:
        family = Family("none", reason=NOT_E3.format(m.dynamics.kappa.text))
    corrections: list[Correction] = []
    conditions: list[Conditions] = []
    poisson = verdict.get(("jacobi", None))
    if poisson is Verdict.REFUTED:
        conditions.append(holds_when(m.jacobiator, m, "jacobi"))
    refuted = [c for c in m.case.claims if verdict.get((str(c.kind), c.label)) is Verdict.REFUTED]
    own = None
    if e3 and poisson is Verdict.VERIFIED and (refuted or not m.case.claims):
        own = corrected_casimir(m, family)  # needed only where it is reported
    if own is not None and not m.case.claims:
        corrections.append(own)
    for claim in refuted:
        if own is not None:
            corrections.append(replace(own, claim=claim.label))
        if e3 and verdict.get(("casimir", claim.label)) is Verdict.REFUTED:
            new_torque = corrected_torque(m, claim)
            if new_torque is not None:
                corrections.append(new_torque)
        residuals, domain = decided_on(m, claim)
        conditions.append(holds_when(residuals, m, claim.label, domain))
    return family_record(family), tuple(corrections), tuple(conditions)


def decided_on(m: CaseMechanics, claim: Claim) -> tuple[Mapping[str, sp.Expr], Domain]:
    """The residuals the check of a claim's kind decided, and where (memoized by
    CaseMechanics: read, not recomputed)."""
    expr = claim.expression.expr
    if claim.kind is ClaimKind.INTEGRAL:
        return m.integral_residual(expr), m.claim_domain(claim)
    if claim.kind is ClaimKind.CASIMIR:
        return m.casimir_residual(expr), m.claim_domain(claim)
    if claim.kind is ClaimKind.MEASURE:
        return m.measure_residual(expr), m.claim_domain(claim)
    return {"dF/dt": m.integral_residual(expr)["dI/dt"]}, m.relation_domain(claim)
