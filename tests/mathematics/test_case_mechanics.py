"""The symbolic objects of one case: built once, and the residuals of a claim computed
once per case, so that the corrections of a refuted claim reuse what its check computed."""

from dataclasses import replace

import pytest
import sympy as sp

from registry import ClaimKind, Verdict, audit_case, load_case
from registry.mathematics import mechanics
from registry.mathematics.case_mechanics import CaseMechanics
from registry.model import Expression
from tests.helpers.samples import YEHIA_B, ZHUKOVSKY, case_file


def test_the_objects_of_a_case_are_the_papers():
    case = load_case(case_file(ZHUKOVSKY))
    m = CaseMechanics(case)
    system = case.system
    assert m.pi == mechanics.poisson_tensor(system.torque_exprs)
    assert m.field == mechanics.vector_field(
        system.inertia_exprs, system.potential.expr, system.torque_exprs
    )
    assert len(m.jacobiator) == 20
    assert m.domain.nonzero == system.inertia_exprs
    assert m.jacobiator is m.jacobiator  # built once


def test_residuals_are_the_time_derivative_and_pi_grad():
    case = load_case(case_file(ZHUKOVSKY))
    m = CaseMechanics(case)
    expr = case.claims[0].expression.expr
    (dt,) = m.integral_residual(expr).values()
    assert sp.expand(dt - mechanics.time_derivative(expr, m.field)) == 0
    casimir = list(m.casimir_residual(expr).values())
    expected = m.pi * sp.Matrix(mechanics.gradient(expr))
    assert [sp.expand(a - b) for a, b in zip(casimir, expected, strict=True)] == [0] * 6
    assert list(m.casimir_residual(expr)) == [f"Pi grad[{v}]" for v in mechanics.STATE]


def test_residuals_are_memoized_and_read_only():
    m = CaseMechanics(load_case(case_file(ZHUKOVSKY)))
    expr = mechanics.gamma1 * mechanics.M1
    assert m.integral_residual(expr) is m.integral_residual(expr)
    assert m.casimir_residual(expr) is m.casimir_residual(expr)
    with pytest.raises(TypeError):
        m.casimir_residual(expr)["extra"] = sp.Integer(0)  # type: ignore[index]


@pytest.fixture
def asked(monkeypatch):
    """Every residual asked of a CaseMechanics: (mechanics, kind, expression, computed)."""
    calls: list[tuple[CaseMechanics, str, sp.Expr, bool]] = []
    original = CaseMechanics._residual

    def recording(self, kind, expr, compute):
        calls.append((self, kind, expr, (kind, expr) not in self._residuals))
        return original(self, kind, expr, compute)

    monkeypatch.setattr(CaseMechanics, "_residual", recording)
    return calls


def asked_of(calls, kind: str, expr: sp.Expr) -> list[bool]:
    """Whether each request of this residual of the audited case computed it."""
    first = calls[0][0]  # the audited case's mechanics is the first one asked
    return [computed for m, k, e, computed in calls if m is first and (k, e) == (kind, expr)]


def test_the_corrections_of_a_refuted_casimir_reuse_its_residual(asked):
    case = load_case(case_file(YEHIA_B))
    expr = case.claim("I2").expression.expr
    audit = audit_case(case)
    assert audit.result("casimir", "I2").verdict is Verdict.REFUTED
    assert [c for c in audit.conditions if c.target == "I2"]  # its conditions were sought
    # asked by the check, then by the corrections: computed the first time only
    assert asked_of(asked, "casimir", expr) == [True, False]


def test_the_corrections_of_a_refuted_integral_reuse_its_residual(asked):
    case = load_case(case_file(ZHUKOVSKY))
    expr = mechanics.M1 * mechanics.gamma2  # not conserved
    claim = replace(
        case.claims[0], kind=ClaimKind.INTEGRAL, expression=Expression("M1*gamma2", expr)
    )
    audit = audit_case(replace(case, claims=(claim,)))
    assert audit.result("integral", claim.label).verdict is Verdict.REFUTED
    assert [c for c in audit.conditions if c.target == claim.label]
    assert asked_of(asked, "integral", expr) == [True, False]


def test_gradients_are_shared_by_the_checks_of_a_case_and_not_across_cases():
    """dI/dt and Pi grad I of a claim read one gradient, computed once per case; another
    case (another field, the same expression) computes its own, and its time derivative is
    along its own field."""
    case = load_case(case_file(ZHUKOVSKY))
    m = CaseMechanics(case)
    expr = case.claims[0].expression.expr
    assert m.gradient(expr) is m.gradient(expr)
    assert m.gradient(expr) == mechanics.gradient(expr)
    m.integral_residual(expr), m.casimir_residual(expr)
    assert list(m._gradients) == [expr]  # one gradient for both residuals
    other = CaseMechanics(load_case(case_file(YEHIA_B)))
    assert other.gradient(expr) is not m.gradient(expr)
    (mine,) = m.integral_residual(expr).values()
    (theirs,) = other.integral_residual(expr).values()
    assert sp.expand(theirs - mechanics.time_derivative(expr, other.field)) == 0
    assert sp.expand(mine - theirs) != 0  # each case's own field
