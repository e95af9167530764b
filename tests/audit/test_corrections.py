"""Corrections against the paper's printed formulas, each re-checked here independently:
by 50-digit evaluation at random points, not by the registry's own zero test."""

from dataclasses import replace

import pytest
import sympy as sp

from registry import Verdict, audit_case, load_case
from registry.language.parser import Namespace, parse_expression
from registry.mathematics import mechanics as mech
from tests.helpers.independent_checks import (
    casimir_residual,
    independent_of_c1,
    jacobi_residual,
    vanishes_numerically,
)
from tests.helpers.samples import CASES, CLASSICAL


def load(case_id):
    return load_case(CASES / f"{case_id}.toml")


def parse(case, text):
    return parse_expression(text, Namespace(dict(case.parameters), dict(case.functions)))


@pytest.fixture(scope="module")
def case_b():
    case = load("yehia-2003-kovalevskaya-b")
    return case, audit_case(case)


def test_case_b_gets_the_papers_conditions(case_b):
    _, audit = case_b
    (found,) = [c for c in audit.conditions if c.target == "I2"]
    assert found.branches == (("N = 0",),)


def test_case_b_corrected_casimir_is_the_papers_up_to_a_function_of_gamma_squared(case_b):
    case, audit = case_b
    (fix,) = [c for c in audit.corrections if c.kind == "casimir" and c.claim == "I2"]
    ours = parse(case, fix.expression)
    paper = load("bcc-yehia-b-corrected-casimir").claim("C").expression.expr
    assert vanishes_numerically(case, casimir_residual(case, case.system.torque_exprs, ours))
    difference = ours - paper
    # d/dM of the difference vanishes and its gamma-gradient is parallel to gamma
    grad = mech.gradient(difference)
    assert vanishes_numerically(case, [*grad[:3], *mech.cross(mech.AXIS, grad[3:])])


def test_case_b_corrected_torque_changes_mu3_only_and_is_the_papers(case_b):
    case, audit = case_b
    (fix,) = [c for c in audit.corrections if c.kind == "torque"]
    assert fix.changed == (2,)
    assert fix.torque[:2] == tuple(e.text for e in case.system.torque[:2])
    torque = [parse(case, t) for t in fix.torque]
    paper = load("bcc-yehia-b-corrected-torque").system.torque_exprs
    assert vanishes_numerically(case, [torque[2] - paper[2]])
    claim = case.claim("I2").expression.expr
    assert vanishes_numerically(case, casimir_residual(case, torque, claim))
    assert vanishes_numerically(case, jacobi_residual(torque))


def test_affine_nonsymmetric_is_poisson_for_a_symmetric_matrix():
    audit = audit_case(load("affine-nonsymmetric"))
    (found,) = [c for c in audit.conditions if c.target == "jacobi"]
    assert found.branches == (("T12 = T21", "T13 = T31", "T23 = T32"),)
    # no Casimir is offered for a torque whose Pi_mu is not Poisson
    assert not [c for c in audit.corrections if c.kind == "casimir"]


def test_a_case_without_claims_gets_its_second_casimir_discovered():
    case = load("yehia-2003-kovalevskaya-a")
    bare = replace(case, claims=())
    audit = audit_case(bare)
    (found,) = [c for c in audit.corrections if c.kind == "casimir"]
    assert found.claim is None
    expr = parse(case, found.expression)
    assert vanishes_numerically(case, casimir_residual(case, case.system.torque_exprs, expr))
    assert independent_of_c1(case, expr)


TRUE_CASES = [
    "zhukovsky-gyrostat",
    "grioli-1957-charged-body",
    "yehia-2003-cyclic",
    "yehia-2003-kovalevskaya-a",
    "axis-torque",
    "borisov-mamaev-1997",
]


@pytest.mark.parametrize("case_id", TRUE_CASES)
def test_mutated_claims_get_valid_corrections_or_none(case_id):
    case = load(case_id)
    claim = case.claims[0]
    expr = claim.expression.expr
    mutated_expr = expr + mech.gamma1 * mech.gamma2 * mech.gamma3  # not a Casimir
    from registry.language.printer import to_text
    from registry.model import Expression

    mutated = replace(
        case, claims=(replace(claim, expression=Expression(to_text(mutated_expr), mutated_expr)),)
    )
    audit = audit_case(mutated)
    assert audit.result("casimir", claim.label).verdict is Verdict.REFUTED
    for fix in audit.corrections:
        if fix.kind == "casimir":
            c = parse(case, fix.expression)
            assert vanishes_numerically(case, casimir_residual(case, case.system.torque_exprs, c))
            assert independent_of_c1(case, c)
        else:
            torque = [parse(case, t) for t in fix.torque]
            assert vanishes_numerically(case, casimir_residual(case, torque, mutated_expr))
            assert vanishes_numerically(case, jacobi_residual(torque))
    # the derived Casimir of a Poisson torque is always offered
    assert any(f.kind == "casimir" for f in audit.corrections)


def test_a_claim_no_torque_can_correct_gets_only_the_cases_own_casimir():
    case = load("zhukovsky-gyrostat")
    claim = case.claims[0]
    from registry.model import Expression

    expr = mech.M1**2  # depends on M other than through s: no torque makes it a Casimir
    audit = audit_case(
        replace(case, claims=(replace(claim, expression=Expression("M1**2", expr)),))
    )
    assert audit.result("casimir", claim.label).verdict is Verdict.REFUTED
    # the correction step ran: the torque's family is recorded, and the claim is offered the
    # case's own Casimir (a valid one, independent of C1) ...
    assert audit.family is not None
    assert audit.family.name == "constant"
    (fix,) = [f for f in audit.corrections if f.claim == claim.label]
    assert fix.kind == "casimir"
    c = parse(case, fix.expression)
    assert vanishes_numerically(case, casimir_residual(case, case.system.torque_exprs, c))
    assert independent_of_c1(case, c)
    # ... but no corrected torque
    assert not [f for f in audit.corrections if f.kind == "torque"]


#: The conditions of the classical test cases' refuted claims, as the solver before the
#: split into components gave them, plus the one branch it missed: a spherical
#: Zhukovsky-Volterra gyrostat (A = B = C) keeps |M|^2, since then dM/dt = k x M / C.
CLASSICAL_CONDITIONS = {
    ("clebsch", "F-sign"): (("a1 = a3", "a2 = a3"),),
    ("free-top", "M1-false"): (("B = C",),),
    ("zhukovsky-volterra-gyrostat", "M-false"): (
        ("A = C", "B = C"),
        ("A = B", "k1 = 0", "k2 = 0"),
        ("A = C", "k1 = 0", "k3 = 0"),
        ("B = C", "k2 = 0", "k3 = 0"),
        ("k1 = 0", "k2 = 0", "k3 = 0"),
    ),
    ("zhukovsky-volterra-gyrostat", "area-no-k"): (("k1 = 0", "k2 = 0", "k3 = 0"),),
}


@pytest.mark.parametrize("key", sorted(CLASSICAL_CONDITIONS), ids=lambda k: f"{k[0]}:{k[1]}")
def test_every_branch_of_a_classical_condition_is_found_and_holds(key):
    case_id, label = key
    case = load_case(CLASSICAL / f"{case_id}.toml")
    audit = audit_case(case)
    (found,) = [c for c in audit.conditions if c.target == label]
    assert found.branches == CLASSICAL_CONDITIONS[key]
    claim = case.claim(label)
    torque = case.system.torque_exprs
    h = mech.hamiltonian(case.system.inertia_exprs, case.system.potential.expr)
    field = casimir_residual(case, torque, h)  # Pi_mu grad H: the equations of motion
    rate = sum(d * f for d, f in zip(mech.gradient(claim.expression.expr), field, strict=True))
    kept = (
        casimir_residual(case, torque, claim.expression.expr)
        if str(claim.kind) == "casimir"
        else [rate]
    )
    for branch in found.branches:
        values = dict(tuple(parse(case, side) for side in eq.split(" = ")) for eq in branch)
        assert vanishes_numerically(case, [sp.sympify(e).xreplace(values) for e in kept]), branch
