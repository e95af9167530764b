"""The mechanics module against the paper's own statements (Sec. 2 and 3)."""

import pytest
import sympy as sp

from registry.mathematics import mechanics as mech
from registry.mathematics.mechanics import AXIS, MOMENTUM, S_VALUE, gamma2, gamma3, s

A, B, C = sp.symbols("A B C", positive=True)
INERTIA = (A, B, C)
U = sp.Function("U")(*AXIS)


def zero(expr) -> bool:
    return sp.simplify(sp.expand(sp.sympify(expr).subs(s, S_VALUE).doit())) == 0


def generic_mu(depends_on_s: bool = True):
    args = (*AXIS, s) if depends_on_s else AXIS
    return tuple(sp.Function(f"mu{i}")(*args) for i in (1, 2, 3))


def test_poisson_tensor_is_the_papers_matrix():
    pi = mech.poisson_tensor((0, 0, 0))
    M1, M2, M3 = MOMENTUM
    assert pi[0, :] == sp.Matrix([[0, -M3, M2, 0, -gamma3, gamma2]])
    assert pi[3, :] == sp.Matrix([[0, -gamma3, gamma2, 0, 0, 0]])
    assert pi == -pi.T


def test_vector_field_is_hamiltonian_for_any_torque():
    """Theorem (iii): (2.2) is Pi_mu grad H, whatever mu (even depending on M)."""
    mu = (MOMENTUM[0] * gamma2, s**2, sp.Function("f")(*MOMENTUM, *AXIS))
    field = mech.vector_field(INERTIA, U, mu)
    generated = mech.hamiltonian_vector_field(mech.poisson_tensor(mu), mech.hamiltonian(INERTIA, U))
    assert all(zero(a - b) for a, b in zip(field, generated, strict=True))


def test_h_and_c1_are_conserved_and_c2_is_not():
    mu = generic_mu()
    field = mech.vector_field(INERTIA, U, mu)
    assert zero(mech.time_derivative(mech.hamiltonian(INERTIA, U), field))
    assert zero(mech.time_derivative(mech.C1, field))
    # dC2/dt = gamma . (mu x I^-1 M) (Sec. 2): not zero in general
    expected = mech.dot(AXIS, mech.cross(mu, mech.angular_velocity(INERTIA)))
    assert zero(mech.time_derivative(mech.C2, field) - expected)
    assert not zero(expected)


def test_c1_is_a_casimir_of_pi_mu():
    assert all(zero(c) for c in mech.casimir_system(generic_mu(), mech.C1))


def test_jacobiator_has_twenty_components_and_vanishes_for_kks():
    jac = mech.jacobiator(mech.poisson_tensor((0, 0, 0)))
    assert len(jac) == 20
    assert all(zero(v) for v in jac.values())


def test_jacobi_reduces_to_the_jacobi_condition_equation():
    """For mu(gamma, s) the Jacobiator vanishes exactly where (3.2) does: its component
    J[M1,M2,M3] is the left-hand side of (3.2), and the other 19 vanish identically."""
    mu = generic_mu()
    condition = mech.jacobi_condition(mu)
    assert not zero(condition)  # a generic mu(gamma, s) is not Poisson
    ratios = {
        key: sp.simplify(value.subs(s, S_VALUE).doit() / condition.subs(s, S_VALUE).doit())
        for key, value in mech.jacobiator(mech.poisson_tensor(mu)).items()
    }
    assert len(ratios) == 20
    assert ratios == {key: 1 if key == (0, 1, 2) else 0 for key in ratios}
    first, last = mech.jacobi_reduced(mu)
    assert all(zero(c) for c in first)  # gamma x grad_M mu_k = 0 holds for mu(gamma, s)
    assert zero(last - condition)


def test_a_torque_depending_on_m_breaks_the_first_jacobi_equations():
    first, _ = mech.jacobi_reduced((MOMENTUM[0], 0, 0))
    assert not all(zero(c) for c in first)


def test_symmetric_affine_torques_are_poisson_and_others_are_not():
    """Sec. 4.1: mu = T gamma + e satisfies (4.1) iff T is symmetric."""
    t = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"T{i + 1}{j + 1}"))
    mu = tuple(t * sp.Matrix(AXIS))
    condition = sp.expand(mech.jacobi_condition(mu))
    assert condition != 0
    symmetric = {t[1, 0]: t[0, 1], t[2, 0]: t[0, 2], t[2, 1]: t[1, 2]}
    assert sp.expand(condition.subs(symmetric)) == 0


def test_casimir_condition_equation_matches_the_system():
    """(3.4) is the second half of (3.3) for C = C(gamma, s)."""
    mu = generic_mu()
    c = sp.Function("C")(*AXIS, s)
    system = mech.casimir_system(mu, c)
    assert all(zero(x) for x in system[3:])  # gamma x grad_M C = 0 for C(gamma, s)
    condition = mech.casimir_condition(mu, c)
    for x, y in zip(system[:3], condition, strict=True):
        assert zero(x + y) or zero(x - y)


def test_s_casimir_for_psi_gamma_plus_grad_phi():
    """(4.3): C = s + phi is a Casimir for mu = psi gamma + grad phi."""
    phi = sp.Function("phi")(*AXIS)
    psi = sp.Function("psi")(*AXIS)
    mu = tuple(psi * g + sp.diff(phi, g) for g in AXIS)
    assert zero(mech.jacobi_condition(mu))
    assert all(zero(c) for c in mech.casimir_system(mu, s + phi))


@pytest.mark.parametrize("var", mech.STATE)
def test_total_diff_of_s_is_the_chain_rule(var):
    assert sp.expand(mech.total_diff(s, var) - sp.diff(S_VALUE, var)) == 0
