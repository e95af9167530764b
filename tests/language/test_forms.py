"""The forms a case file may give its system in, each turned into one ``Dynamics``
(``registry/language/forms.py``): the paper's equations (2.2) and Pi_mu, a Hamiltonian's
Pi grad H, parameter values put in, and the columns the store keeps."""

from __future__ import annotations

import sympy as sp

from registry.language import forms
from registry.language.casefile import load_case, parse_case_text
from registry.mathematics import mechanics as mech
from tests.helpers.samples import CASES, FAMILIES

SO4 = """id = "so4-form"
title = "Kovalevskaya's H on so(4)"
[source]
citation = "test"
[parameters]
c = "real"
kappa = "real"
[system]
hamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"
kappa = "kappa"
"""


def test_the_papers_form_is_its_equations_and_its_modified_bracket():
    case = load_case(CASES / "yehia-2003-kovalevskaya-b.toml")
    d = case.dynamics
    mu = case.system.torque_exprs
    assert d.bracket == mech.poisson_tensor(mu)
    inertia, potential = case.system.inertia_exprs, case.system.potential.expr
    assert d.field == mech.vector_field(inertia, potential, mu)
    assert d.hamiltonian == mech.hamiltonian(inertia, potential) and not d.from_bracket
    assert [g.name for g in d.given] == ["A", "B", "C", "U", "mu1", "mu2", "mu3"]
    # the potential has terms of degree 2 in gamma: the grading is M: 1, gamma: 1
    assert d.nonzero == inertia and d.grading == (("M", 1), ("gamma", 1))


def test_a_hamiltonian_form_is_pi_grad_h_and_names_kappa():
    case = parse_case_text(SO4)
    d = case.dynamics
    assert d.from_bracket and d.kappa.text == "kappa" and d.nonzero == ()
    generated = mech.hamiltonian_vector_field(d.bracket, d.hamiltonian)
    assert all(sp.expand(a - b) == 0 for a, b in zip(d.field, generated, strict=True))
    assert [g.name for g in d.given] == ["H", "mu1", "mu2", "mu3", "kappa"]
    # the grading is found when first asked (listing or reporting a case never needs it):
    # kappa != 0 and a quadratic part in gamma leave only equal weights
    assert "grading" not in vars(d)
    assert d.grading == (("M", 1), ("gamma", 1)) and "grading" in vars(d)
    free_body = parse_case_text(SO4.replace("2*c*gamma1", "0").replace('"kappa"\n', '"0"\n'))
    assert free_body.dynamics.grading == (("M", 1), ("gamma", 2))


def test_parameter_values_are_put_in_where_the_case_is_defined():
    case = parse_case_text(SO4)
    c, kappa = case.parameters["c"], case.parameters["kappa"]
    at = forms.with_values(case, {kappa: sp.Integer(0)})
    assert at is not None and at.dynamics.kappa.expr == 0 and "kappa" not in at.parameters
    assert at.claims == () and at.dynamics.field != case.dynamics.field
    positive = load_case(CASES / "goryachev-chaplygin-1900.toml")
    assert forms.with_values(positive, {positive.parameters["C"]: sp.Integer(-1)}) is None
    assert forms.with_values(case, {c: 1 / (kappa - kappa)}) is None  # undefined


def test_values_that_bring_a_parameter_in_declare_it_real():
    # a component of a search's locus parametrised by a new parameter (c = w**2 + 1)
    case = parse_case_text(SO4)
    w = sp.Symbol("w", real=True)
    at = forms.with_values(case, {case.parameters["c"]: w**2 + 1})
    assert at is not None and at.parameters["w"] == w and "c" not in at.parameters
    assert str(at.assumptions["w"]) == "real" and w in at.dynamics.parameters
    assert at.assumptions["kappa"] == case.assumptions["kappa"]


def test_values_are_put_in_a_system_given_by_its_equations_or_its_bracket():
    """A state of its own: the values go into the equations (and the definitions), or
    into the bracket and the Hamiltonian. Before, only the paper's forms were changed,
    and a search kept Lorenz's sigma in the field at sigma = 0."""
    lorenz = load_case(FAMILIES / "lorenz.toml")
    sigma = lorenz.parameters["sigma"]
    at = forms.with_values(lorenz, {sigma: sp.Integer(0)})
    assert at is not None and "sigma" not in at.parameters
    x = at.dynamics.variables[0]
    assert at.dynamics.field[0] == 0 and not any(f.has(sigma) for f in at.dynamics.field)
    assert at.system.equations[0].text == "0" and x in at.dynamics.field[1].free_symbols
    text = """id = "bracket-form"
title = "a rigid body on so(3) given by its bracket, with a parameter"
[source]
citation = "test"
[parameters]
k = "real"
[system]
variables = ["M1", "M2", "M3"]
hamiltonian = "(M1**2 + 2*M2**2 + 3*M3**2)/2"
[system.definitions]
q = "k*M3"
[system.bracket]
"M1, M2" = "q"
"M2, M3" = "M1"
"M3, M1" = "M2"
"""
    case = parse_case_text(text)
    k = case.parameters["k"]
    at = forms.with_values(case, {k: sp.Integer(2)})
    assert at is not None and not any(f.has(k) for f in at.dynamics.field)
    assert [v.text for _, _, v in at.system.bracket] == ["2*M3", "M1", "M2"]
    assert [(n, e.text) for n, e in at.system.definitions] == [("q", "2*M3")]


def test_the_store_keeps_the_forms_fields_as_written():
    case = load_case(CASES / "zhukovsky-gyrostat.toml")
    columns = forms.columns(case.system)
    assert columns["inertia"] == [e.text for e in case.system.inertia]
    assert columns["hamiltonian"] is None and columns["kappa"] == "0"
    texts = forms.stored_texts(case.system)
    assert texts["potential"] == case.system.potential.text and "hamiltonian" not in texts


def test_a_level_set_at_parameter_values_has_them_put_in_and_its_text_rewritten():
    k1, k2, g1, g2, s = sp.symbols("k1 k2 gamma1 gamma2 s")
    from registry.model import Equation

    level = Equation("s + k1*gamma1 + k2*gamma2 = 0", s + k1 * g1 + k2 * g2, sp.Integer(0))
    at = forms.equation_with_values(level, {k1: sp.Integer(0)})
    assert sp.expand(at.expr - (s + k2 * g2)) == 0
    assert "k1" not in at.text and at.text.endswith(" = 0")
    assert forms.equation_with_values(level, {}) is level
