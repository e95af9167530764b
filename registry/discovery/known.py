"""What a search already knows of a system: the integrals every member has (H, the
bracket's Casimirs, the torque family's Casimir) and the case's own claims, each proven
before it counts; an integral found is new only when it is none of these (``novelty``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import sympy as sp
from sympy import QQ

from ..audit.case_audit import audit_case
from ..errors import DiscoveryError
from ..language.printer import to_text
from ..mathematics.bracket_casimirs import polynomial_casimirs
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.families import recognise
from ..mathematics.zero_test import decide
from ..model import Case, IntegralSet, IntegralStatus, Verdict
from . import novelty
from .ansatz import PolynomialSystem
from .integrals import Generator
from .linear import Field


def known_integrals(m: CaseMechanics) -> list[tuple[str, sp.Expr]]:
    """H and the bracket's known Casimirs, named: those of the system's ``casimirs`` that
    are Casimirs of its bracket (on e(3) |gamma|^2, for every torque; on so(4) and
    so(3,1) kappa |M|^2 + |gamma|^2 and s, which a torque may destroy; for a bracket
    given entry by entry, its polynomial Casimirs of degree <= 2: each decided by the
    zero test) and, on e(3), the Casimir of the torque's family (s where there is no
    torque)."""
    dynamics = m.dynamics
    named: list[tuple[str, sp.Expr]] = []
    if m.hamiltonian is not None:
        named.append(("H", m.hamiltonian))
    casimirs = list(dynamics.casimirs)
    if dynamics.bracket is not None and not casimirs:  # a bracket of its own: its quadrics
        found = polynomial_casimirs(dynamics.bracket, dynamics.variables)
        casimirs = [(to_text(c), c) for c in found]
    for name, expr in casimirs:
        if decide(m.casimir_residual(expr), m.domain).verdict is Verdict.VERIFIED:
            named.append((name, expr))
    if m.mu is not None and m.kappa == 0:
        family = recognise(m.mu, m.domain)
        if family.casimir is not None:
            named.append((to_text(sp.expand(family.casimir)), family.casimir))
    return named


def known_generators(
    m: CaseMechanics, system: PolynomialSystem
) -> tuple[list[Generator], list[str]]:
    """The known integrals (``known_integrals``) as generators of the trivial integrals,
    and their names. Non-polynomial ones cannot lie in the ansatz and generate nothing
    there."""
    gens, names = [], []
    for name, expr in known_integrals(m):
        names.append(name)
        try:
            poly = system.polynomial(expr, what="known integral")
        except DiscoveryError:
            continue
        if poly:
            gens.append(Generator(poly, system.weight(poly)))
    return gens, names


def named(
    case: Case,
    m: CaseMechanics,
    system: PolynomialSystem,
    params: Sequence[sp.Symbol],
    found: IntegralSet,
    exprs: Sequence[sp.Expr],
) -> tuple[IntegralSet, tuple[str, ...]]:
    """``found`` with each integral said new, or equal to claims of the case (proven by
    the audit's zero test on the searched level set) modulo the known integrals; and the
    labels of the claims proven there."""
    claims = verified_claims(case, system)
    trivial = [k for name, expr in known_integrals(m) if (k := novelty.known(system, name, expr))]
    fld = Field(QQ.frac_field(*params) if params else QQ, params, {}, system.inverses)
    status = novelty.statuses(system, fld, trivial, claims, exprs)
    return replace(found, status=tuple(status)), tuple(k.name for k in claims)


def catalog_statuses(
    m: CaseMechanics,
    system: PolynomialSystem,
    params: Sequence[sp.Symbol],
    exprs: Sequence[sp.Expr],
    carried: Sequence[tuple[str, str, sp.Expr]],
) -> list[IntegralStatus | None]:
    """For each integral: the claims of catalog cases (carried into this system's
    variables, ``identification.claim_match``) it equals modulo the known integrals, as
    a ``rediscovered`` status naming them ``case-id:label``; None where it equals none."""
    trivial = [k for name, expr in known_integrals(m) if (k := novelty.known(system, name, expr))]
    claims = []
    for case_id, label, expr in carried:
        name = f"{case_id}:{label}"
        k = novelty.known(system, name, expr, claim=True, symbol=sp.Symbol(name))
        if k is not None:
            claims.append(k)
    if not claims:
        return [None] * len(exprs)
    fld = Field(QQ.frac_field(*params) if params else QQ, params, {}, system.inverses)
    out: list[IntegralStatus | None] = []
    for status in novelty.statuses(system, fld, trivial, claims, exprs):
        out.append(None if status.new else status)
    return out


def verified_claims(case: Case, system: PolynomialSystem) -> list[novelty.Known]:
    """The claims of ``case`` that hold on the searched level set (theirs contains it) and
    lie in the system's ring, each proven an integral by the audit's zero test; a claim
    the audit does not verify is not known (nothing is taken on trust)."""
    applicable = []
    for claim in case.claims:
        if not claim.kind.conserved:
            continue  # a density or an invariant relation is no integral
        try:
            inside = all(not system.polynomial(eq.expr) for eq in claim.on)
        except DiscoveryError:
            continue
        k = (
            novelty.known(system, claim.label, claim.expression.expr, claim=True)
            if inside
            else None
        )
        if k is not None:
            applicable.append((claim, k))
    if not applicable:
        return []
    audit = audit_case(
        replace(case, claims=tuple(c for c, _ in applicable)),
        checks=["integral"],
        corrections=False,
        budget=None,
    )
    return [
        k for c, k in applicable if audit.result("integral", c.label).verdict is Verdict.VERIFIED
    ]
