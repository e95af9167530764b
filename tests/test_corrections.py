"""Repairs against the paper's printed formulas, each re-checked here independently:
by 50-digit evaluation at random points, not by the registry's own zero test."""

import random
from dataclasses import replace
from pathlib import Path

import pytest
import sympy as sp

from registry import Verdict, audit_case, load_case, parse_case_text
from registry.checks import Mechanics
from registry.language.parser import Namespace, parse_expression
from registry.mathematics import families
from registry.mathematics import mechanics as mech
from registry.mathematics.families import recognise
from registry.mathematics.zero_test import Domain, decide

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"


def load(case_id):
    return load_case(CASES / f"{case_id}.toml")


def parse(case, text):
    return parse_expression(text, Namespace(dict(case.parameters), dict(case.functions)))


def random_point(case, rng):
    """A random real point (50 digits) away from the singular sets, parameters included."""
    point = {}
    for sym in case.parameters.values():
        point[sym] = sp.Float(
            rng.uniform(0.5, 2.0) * (1 if sym.is_positive else rng.choice([-1, 1])), 50
        )
    for v in mech.STATE:
        point[v] = sp.Float(rng.uniform(0.3, 1.3) * rng.choice([-1, 1]), 50)
    point[mech.s] = sum(point[m] * point[g] for m, g in zip(mech.MOMENTUM, mech.AXIS, strict=True))
    return point


def vanishes_numerically(case, exprs, points=5, seed=7):
    rng = random.Random(seed)
    for _ in range(points):
        point = random_point(case, rng)
        for e in exprs:
            value = sp.N(sp.sympify(e).xreplace(point), 50)
            if abs(value) > sp.Float("1e-30"):
                return False
    return True


def independent_of_c1(case, expr) -> bool:
    """Some d/dM_i of ``expr`` is not zero: ``expr`` is not a function of gamma alone
    (as C1 = |gamma|^2/2 is, which satisfies every Casimir system trivially)."""
    return not vanishes_numerically(case, [mech.total_diff(expr, v) for v in mech.MOMENTUM])


def casimir_residual(case, torque, expr):
    pi = mech.poisson_tensor(torque)
    return list(pi * sp.Matrix(mech.gradient(expr)))


def jacobi_residual(torque):
    return list(mech.jacobiator(mech.poisson_tensor(torque)).values())


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


EXPECTED_FAMILIES = {
    "zhukovsky-gyrostat": "constant",
    "grioli-1957-charged-body": "affine",
    "pleshakov-2007-generalized-grioli": "affine",
    "affine-nonsymmetric": "affine",
    "yehia-2003-cyclic": "psi-gamma-grad-phi",
    "yehia-2003-kovalevskaya-a": "psi-gamma-grad-phi",
    "yehia-2003-kovalevskaya-b": "psi-gamma-grad-phi",
    "a-s-family": "a(s)-grad-phi",
    "axis-torque": "axis",
    "borisov-mamaev-1997": "axis",
    "bcc-family-psi-grad-phi": "psi-gamma-grad-phi",
    "bcc-family-a-s": "a(s)-grad-phi",
    "bcc-family-axis": "axis",
}


@pytest.mark.parametrize("case_id, name", EXPECTED_FAMILIES.items())
def test_families_are_recognised_with_a_casimir_where_poisson(case_id, name):
    case = load(case_id)
    m = Mechanics(case)
    family = recognise(m.mu, m.domain)
    assert family.name == name
    if case_id == "affine-nonsymmetric":
        assert family.casimir is None
        return
    assert family.casimir is not None
    # symbolically, on the case's domain (the only way for arbitrary functions phi, psi, a)
    system = mech.casimir_system(m.mu, family.casimir)
    residuals = {f"(3.3)[{i}]": r for i, r in enumerate(system)}
    assert decide(residuals, m.domain).verdict is Verdict.VERIFIED
    grad_m = {f"d/d{v}": mech.total_diff(family.casimir, v) for v in mech.MOMENTUM}
    assert decide(grad_m, m.domain).verdict is Verdict.REFUTED  # independent of C1
    if not case.functions:
        assert vanishes_numerically(case, casimir_residual(case, m.mu, family.casimir))
        assert not vanishes_numerically(case, [mech.total_diff(family.casimir, mech.M1)])


def _random_polynomial(rng: random.Random, degree: int) -> sp.Expr:
    g, p = mech.AXIS, sp.Symbol("p", real=True)
    return sp.Add(
        *(
            sp.Rational(rng.randint(-7, 7), rng.randint(1, 4))
            * (p if rng.random() < 0.3 else 1)
            * sp.Mul(*(rng.choice(g) for _ in range(rng.randint(0, degree))))
            for _ in range(6)
        )
    )


@pytest.mark.parametrize("seed", range(8))
def test_polynomial_ansatz_finds_phi_of_a_random_psi_gamma_plus_grad_phi(seed):
    rng = random.Random(seed)
    phi, psi = _random_polynomial(rng, 4), _random_polynomial(rng, 2)
    nu = tuple(sp.expand(psi * g + sp.diff(phi, g)) for g in mech.AXIS)
    found = families._polynomial_ansatz(nu, Domain())
    assert found is not None
    # the tangential parts agree: gamma x (nu - grad found) = 0 identically
    tangential = [n - sp.diff(found, g) for n, g in zip(nu, mech.AXIS, strict=True)]
    rest = mech.cross(mech.AXIS, tangential)
    assert all(sp.expand(r) == 0 for r in rest)


def test_a_rotation_field_has_no_tangential_potential():
    g1, g2, g3 = mech.AXIS
    k = sp.Symbol("k", positive=True)
    domain = Domain(parameters=(k,))
    assert families.tangential_potential((-k * g2, k * g1, sp.Integer(0)), domain) is None
    assert families.tangential_potential((g3 - g2, g1, g1 * g2), domain) is None


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
def test_mutated_claims_get_valid_repairs_or_none(case_id):
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


def test_a_claim_no_torque_can_repair_gets_only_the_cases_own_casimir():
    case = load("zhukovsky-gyrostat")
    claim = case.claims[0]
    from registry.model import Expression

    expr = mech.M1**2  # depends on M other than through s: no torque makes it a Casimir
    audit = audit_case(
        replace(case, claims=(replace(claim, expression=Expression("M1**2", expr)),))
    )
    assert audit.result("casimir", claim.label).verdict is Verdict.REFUTED
    # the repair step ran: the torque's family is recorded, and the claim is offered the
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


def test_exported_corrected_case_loads_and_is_verified(tmp_path):
    from registry.language.case_writer import corrected_case_text

    case, audit = load("yehia-2003-kovalevskaya-b"), None
    audit = audit_case(case)
    (fix,) = [c for c in audit.corrections if c.kind == "torque"]
    text = corrected_case_text(case, fix, run=1)
    fixed = parse_case_text(text, "exported.toml")
    assert fixed.id == "yehia-2003-kovalevskaya-b-corrected-torque"
    result = audit_case(fixed, checks=["jacobi", "casimir"])
    assert result.result("jacobi").verdict is Verdict.VERIFIED
    assert result.result("casimir", "I2").verdict is Verdict.VERIFIED
