"""Zero testing: does a residual vanish identically (on a level set)?

The decision is made in stages, cheapest first, and the stage is recorded:

1. *Exact probes.* Evaluate at random exact points (rational where the
   case's radicals allow it; ``sampling``), with ``certified_evaluation.evaluate``.
   A value proven nonzero refutes the identity, and the point is the witness.
2. *Proof.* Put the residual in a normal form that is complete for its class
   (``normal_form``):
   radicals b**(p/q) become new symbols rho with rho**q = b, transcendental
   terms and arbitrary functions become new symbols, the result is a rational
   function whose numerator is reduced modulo the radical relations (and the
   level-set equations, by a Groebner basis). A zero remainder is a proof.
   As a last resort, a small residual is handed to ``sympy.simplify``.
3. Otherwise the residual vanished at every probe but no proof was found:
   ``inconclusive``, never ``verified``.
"""

from __future__ import annotations

import functools
import random
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from ..model import Verdict, Witness
from .certified_evaluation import At, OutsideDomain, Value
from .domain import Domain
from .normal_form import prove_zero
from .sampling import concrete_functions, radical_bases, sample_point, substitute_functions

#: Points where every residual must vanish before a proof is attempted.
PROBES = 4
#: Attempts to find that many points inside the domain before giving up.
MAX_ATTEMPTS = 40


@dataclass(frozen=True)
class ZeroTest:
    """The decision for a family of residuals: all zero (verified), one nonzero
    somewhere (refuted, with the witness), or undecided (inconclusive, with why)."""

    verdict: Verdict
    method: str
    reason: str = ""
    witness: Witness | None = None
    component: str | None = None


def decide(
    residuals: Mapping[str, sp.Expr],
    domain: Domain,
    *,
    probes: int = PROBES,
    seed: int = 0,
) -> ZeroTest:
    """Decide whether every residual vanishes on the domain (stages in the module doc)."""
    live = {k: e for k, e in residuals.items() if e != 0}
    if not live:
        return ZeroTest(Verdict.VERIFIED, "identically zero")
    rng = random.Random(seed)
    # one probe first: a false identity is almost always refuted there, and a true
    # one goes straight to its proof; the other probes are spent only if that fails
    probe = _probe(live, domain, 1, rng)
    if probe is not None:
        return probe
    methods = set()
    for label, expr in live.items():
        method = _proven(
            expr, tuple(domain.on), tuple(domain.shorthands.items()), domain.state
        ) or _simplified_to_zero(expr, domain)
        if method is None:
            more = _probe(live, domain, probes - 1, rng) if probes > 1 else None
            if more is not None:
                return more
            return ZeroTest(
                Verdict.INCONCLUSIVE,
                "exact probes",
                reason=f"vanishes at {max(probes, 1)} random points; no symbolic proof",
                component=label,
            )
        methods.add(method)
    return ZeroTest(Verdict.VERIFIED, max(methods, key=_METHOD_ORDER.index))


@functools.lru_cache(maxsize=512)
def _proven(
    expr: sp.Expr,
    on: tuple[sp.Expr, ...],
    shorthands: tuple[tuple[sp.Symbol, sp.Expr], ...],
    state: tuple[sp.Symbol, ...],
) -> str | None:
    """``prove_zero``, remembered: a pure function of the residual, the level set, the
    shorthands and the state (the cases of one torque prove the same Jacobi identity, a
    correction's re-check the residual its check proved)."""
    return prove_zero(expr, on, dict(shorthands), state)


_METHOD_ORDER = ["rational normal form", "algebraic normal form", "level-set reduction", "simplify"]

#: Residuals larger than this (sympy operations) are not handed to ``simplify``.
SIMPLIFY_LIMIT = 400


def _simplified_to_zero(expr: sp.Expr, domain: Domain) -> str | None:
    """The last resort, for identities outside the normal forms' classes (such as
    sin**2 + cos**2 = 1): sympy's ``simplify``, on small residuals only and, like
    every stage, under the check's time budget."""
    if domain.on or sp.count_ops(expr) > SIMPLIFY_LIMIT:
        return None
    return "simplify" if sp.simplify(domain.expanded(expr)) == 0 else None


# --- stage 1: exact probes (points from ``sampling``) -------------------------


def _probe(live, domain: Domain, probes: int, rng: random.Random) -> ZeroTest | None:
    """Refute at a random exact point, or return None when every probe vanished.

    For a family, two concrete instances of its arbitrary functions alternate.
    """
    n_choices = 2 if domain.functions else 1
    choices = [concrete_functions(domain.functions, rng) for _ in range(n_choices)]
    instances = [{k: substitute_functions(e, f) for k, e in live.items()} for f in choices]
    bases = radical_bases(instances[0].values())
    good = 0
    for attempt in range(MAX_ATTEMPTS):
        funcs, residuals = choices[attempt % len(choices)], instances[attempt % len(choices)]
        point = sample_point(domain, rng, funcs, bases)
        if point is None:
            continue
        try:
            at = At(point)  # the point's values converted once for every residual
            values = {label: at(expr) for label, expr in residuals.items()}
        except OutsideDomain:
            continue
        for label, value in values.items():
            if value.certainly_nonzero():
                return ZeroTest(
                    Verdict.REFUTED,
                    "exact probe" if value.is_exact else "interval probe",
                    witness=_witness(point, value, label, funcs, domain),
                    component=label,
                )
        good += 1
        if good >= probes:
            return None
    if good == 0:
        return ZeroTest(
            Verdict.INCONCLUSIVE,
            "exact probes",
            reason="found no sample point where the residual is defined",
        )
    return None


def _witness(point, value: Value, label: str, funcs, domain: Domain) -> Witness:
    names = {str(k): sp.sstr(v) for k, v in point.items()}
    shown = {
        f"{name}({', '.join(map(str, args))})": sp.sstr(funcs[name].expr)
        for name, (_, args) in domain.functions.items()
    }
    return Witness(names, value.text(), value.approx(), component=label, functions=shown)
