"""The audit notices when a true claim is changed: a sign, a coefficient, a level set,
a torque that depends on M. Mutations are generated from the case files, not tuned."""

from dataclasses import replace
from pathlib import Path

import pytest
import sympy as sp

from registry import Verdict, audit_case, load_case
from registry.language.forms import with_system
from registry.language.printer import to_text
from registry.mathematics.mechanics import M1, gamma1
from registry.model import Claim, Expression, System

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"
TRUE_CASES = [
    "zhukovsky-gyrostat",
    "grioli-1957-charged-body",
    "pleshakov-2007-generalized-grioli",
    "yehia-2003-cyclic",
    "yehia-2003-kovalevskaya-a",
    "bcc-yehia-b-corrected-casimir",
    "bcc-yehia-b-corrected-torque",
    "a-s-family",
    "axis-torque",
    "borisov-mamaev-1997",
]


def with_expression(claim: Claim, expr: sp.Expr) -> Claim:
    return replace(claim, expression=Expression(to_text(expr), expr))


def terms(expr: sp.Expr) -> list[sp.Expr]:
    return list(sp.Add.make_args(sp.expand(expr)))


def non_constant_terms(expr: sp.Expr) -> list[sp.Expr]:
    """Terms that depend on the state: changing a constant term changes nothing."""
    from registry.mathematics.mechanics import STATE, s

    return [t for t in terms(expr) if t.free_symbols & {*STATE, s}]


def audit_claim(case, claim):
    audit = audit_case(replace(case, claims=(claim,)), checks=["integral", "casimir"])
    return audit.result("integral", claim.label), audit.result("casimir", claim.label)


def mutate(expr: sp.Expr, mutation: str) -> sp.Expr:
    """``expr`` with its last non-constant term's sign flipped or coefficient changed.

    When that term is the only one, scaling it would scale the whole claim (and c*I is
    as conserved as I), so the change is made non-scalar: the term's change is
    multiplied by (1 + gamma1)."""
    candidates = non_constant_terms(expr)
    # the last term, to avoid always mutating the leading s
    term = candidates[-1]
    change = -2 * term if mutation == "sign" else term / 3
    if len(candidates) == 1:
        change *= 1 + gamma1
    return expr + change


@pytest.mark.parametrize("case_id", TRUE_CASES)
@pytest.mark.parametrize("mutation", ["sign", "coefficient"])
def test_changing_a_term_of_a_true_claim_is_refuted(case_id, mutation):
    case = load_case(CASES / f"{case_id}.toml")
    claim = case.claims[0]
    integral, casimir = audit_claim(case, claim)
    assert (integral.verdict, casimir.verdict) == (Verdict.VERIFIED, Verdict.VERIFIED)
    changed = mutate(claim.expression.expr, mutation)
    assert sp.expand(changed - claim.expression.expr) != 0
    integral, casimir = audit_claim(case, with_expression(claim, changed))
    assert casimir.verdict is Verdict.REFUTED
    assert casimir.witness is not None
    assert integral.verdict is Verdict.REFUTED
    assert integral.witness is not None


def test_a_constant_multiple_of_a_one_term_casimir_stays_a_casimir():
    case = load_case(CASES / "borisov-mamaev-1997.toml")
    claim = case.claims[0]
    expr = claim.expression.expr
    assert len(non_constant_terms(expr)) == 1
    for factor in (-1, sp.Rational(4, 3)):
        integral, casimir = audit_claim(case, with_expression(claim, factor * expr))
        assert casimir.verdict is Verdict.VERIFIED
        assert integral.verdict is Verdict.VERIFIED


@pytest.mark.parametrize("case_id", TRUE_CASES)
def test_making_the_torque_depend_on_m_breaks_jacobi(case_id):
    case = load_case(CASES / f"{case_id}.toml")
    mu = list(case.system.torque)
    mu[0] = Expression(f"{mu[0].text} + M1", mu[0].expr + M1)
    broken = with_system(case, replace(case.system, torque=tuple(mu)))
    audit = audit_case(broken, checks=["jacobi", "energy"])
    assert audit.result("jacobi").verdict is Verdict.REFUTED
    assert audit.result("energy").verdict is Verdict.VERIFIED  # H stays conserved for any mu


def test_dropping_the_level_set_refutes_a_claim_that_holds_only_there():
    case = load_case(CASES / "goryachev-chaplygin-1900.toml")
    (claim,) = case.claims
    assert claim.on
    on_set = audit_case(case).result("integral", claim.label)
    assert on_set.verdict is Verdict.VERIFIED
    integral, _ = audit_claim(case, replace(claim, on=()))
    assert integral.verdict is Verdict.REFUTED


def test_a_level_set_the_flow_leaves_makes_a_vanishing_residual_inconclusive():
    case = load_case(CASES / "goryachev-chaplygin-1900.toml")
    (claim,) = case.claims
    # M1 = 0 is not invariant; K's derivative happens to vanish nowhere special there,
    # so use a claim that vanishes on the set: I = M1 itself
    from registry.model import Equation

    m1 = Equation("M1 = 0", M1, sp.Integer(0))
    probe = replace(claim, expression=Expression("M1**2", M1**2), on=(m1,))
    audit = audit_case(replace(case, claims=(probe,)))
    assert audit.result("invariant", claim.label).verdict is Verdict.REFUTED
    integral = audit.result("integral", claim.label)
    assert integral.verdict is Verdict.INCONCLUSIVE
    assert "does not keep the level set invariant" in integral.reason


def test_changing_the_inertia_of_a_kovalevskaya_case_is_noticed():
    case = load_case(CASES / "goryachev-chaplygin-1900.toml")
    inertia = list(case.system.inertia)
    c = case.parameters["C"]
    inertia[0] = Expression("3*C", 3 * c)
    inertia[1] = Expression("3*C", 3 * c)
    changed = with_system(case, System(tuple(inertia), case.system.potential, case.system.torque))
    assert audit_case(changed).result("integral", "K").verdict is Verdict.REFUTED
