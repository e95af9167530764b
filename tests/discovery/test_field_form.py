"""The normal form identification compares: dgamma/dt = gamma x A L after the shift
L = M + A^-1 g(gamma)."""

from __future__ import annotations

import sympy as sp

from registry.discovery.identification.field_form import L_STATE, field_form
from tests.helpers.catalog import catalog_case
from tests.helpers.samples import family


def test_a_torque_form_needs_no_shift_and_reads_its_inverse_inertia():
    form = field_form(catalog_case("kovalevskaya-1889-heavy-top").dynamics)
    c = sp.Symbol("C", positive=True)
    assert form.kinetic == sp.diag(1 / (2 * c), 1 / (2 * c), 1 / c)
    assert form.shift == (0, 0, 0)


def test_a_hamiltonian_with_m_gamma_terms_is_shifted_to_the_normal_form():
    form = field_form(catalog_case("wolf-2003-e3-goryachev-chaplygin").dynamics)
    assert form.shifted and any(form.shift)
    # in normal form dgamma/dt has no term free of L
    for f in form.field[3:]:
        assert all(
            sum(m[:3]) == 1
            for m in sp.Poly(f, *L_STATE, *sp.symbols("gamma1:4", real=True)).monoms()
        )


def test_a_field_that_is_not_polynomial_has_no_form():
    assert field_form(catalog_case("yehia-2003-kovalevskaya-b").dynamics) is None


def test_a_component_that_is_zero_has_no_term_in_the_support():
    form = field_form(catalog_case("lagrange-1788-heavy-top").dynamics)
    assert form.field[2] == 0  # dL3/dt = 0 for the symmetric top
    assert not any(component == 2 for component, _ in form.support())
    assert (0, (0, 0, 0, 0, 1, 0)) in form.support()  # a gamma2 in dL1/dt
    assert ("L", 0, 0) not in form.profile()  # nor a constant term in the profile


def test_coefficients_written_apart_cancel_in_the_angular_velocity():
    # a moment w**2/4 + 1 enters dgamma/dt as 1/(w**2/4 + 1) in one component and as
    # 4/(w**2 + 4) in another: the same coefficient, so the form is found
    from registry.language.forms import with_values

    case = family("quadric-moments")
    a, c = case.parameters["a"], case.parameters["c"]
    w = sp.Symbol("w1", real=True)
    on_curve = with_values(case, {a: 2 * w / (w**2 + 1), c: w**2 / 4 + sp.Rational(1, 4)})
    form = field_form(on_curve.dynamics)
    assert form is not None and form.kinetic is not None
    assert sp.cancel(form.kinetic[0, 0] - 4 / (w**2 + 4)) == 0 == form.kinetic[0, 1]
