"""The Kovalevskaya analysis of a case, on every form a case file may give its system in.

The classical tops' exponents are checked against values derived independently, not
against a printed table: no printed table of heavy-top Kovalevskaya exponents could be
reached with the search tools (queries for the heavy top's, the Kowalevski top's and the
Goryachev-Chaplygin top's exponents and resonances found only the openings of papers;
see also /work/scratch/exponents32/FINDINGS.md). Two independent derivations stand in:

* by hand, for the balances with the angular velocity along a principal axis k (they
  exist where the centre of mass lies in the plane orthogonal to it): omega = +-2i e_k,
  gamma a null eigenvector of hat(omega) with eigenvalue 2, and the characteristic
  polynomial (lambda + 1)(lambda - 2)(lambda - 3)(lambda - 4)(lambda^2 - lambda + sigma),
  sigma = 2 (2 I_k - I_i)(I_j - I_k) / (I_i I_j) ... written below for r = e1, inertia
  (1, b, c) and k = 3: sigma = 2 (2c - 1)(b - c) / b, so that Kovalevskaya's (2, 2, 1)
  (b = 1, c = 1/2) has sigma = 0 (exponents 0, 1) and Goryachev-Chaplygin's (4, 4, 1)
  (b = 1, c = 1/4) has sigma = -3/4 (exponents -1/2, 3/2);
* in the test itself, with plain sympy: each balance the analysis reports is put back
  into v(c) + w c = 0, and the eigenvalues of Dv(c) + diag(w) at it, computed by
  ``Matrix.eigenvals``, must be the exponents reported, with their multiplicities.
"""

from __future__ import annotations

import time
from collections import Counter

import mpmath
import pytest
import sympy as sp

from registry.discovery import exponents as exponents_module
from registry.discovery.exponents import (
    NO_BALANCE,
    _generic_verdict,
    analyse_case,
    case_field,
    exponent_options,
    refused,
    refused_by,
)
from registry.discovery.painleve_strata import Strata
from registry.errors import ExponentError
from registry.execution.executor import GRACE, LocalPool
from registry.language.casefile import load_case
from registry.presentation.exponents_output import exponents_text
from tests.helpers.clocks import cpu_bound
from tests.helpers.samples import CASES, CLASSICAL, FAMILIES, TEST_DATA

EXPONENTS = TEST_DATA / "exponents"
HALF = sp.Rational(1, 2)


def analysed(path, weights=None, free=(), budget=600):
    case = load_case(path)
    return case, analyse_case(case, exponent_options(case, weights, free), budget=budget)


def spectra(document) -> list[list[str]]:
    return [b["exponents"] for b in document["balances"]]


def independently(case, document, weights=None) -> None:
    """Every reported balance solves v(c) + w c = 0 (v the leading part, the field where
    it is homogeneous), and plain sympy's eigenvalues of Dv(c) + diag(w) there are the
    reported exponents, with multiplicities."""
    options = exponent_options(case, weights)
    found = case_field(case, options)
    names = {str(x): x for x in (*found.variables, *found.parameters)}
    field = found.field
    if "leading" in document:  # a field that is not homogeneous: its leading part
        field = tuple(
            sp.sympify(document["leading"][str(x)], locals=names) for x in found.variables
        )
    matrix = sp.Matrix(field).jacobian(found.variables) + sp.diag(*found.weights)
    for b in document["balances"]:
        point = {names[x]: sp.sympify(v, locals=names) for x, v in b["point"].items()}
        residual = [
            sp.simplify(v.xreplace(point) + w * point[x])
            for x, v, w in zip(found.variables, field, found.weights, strict=True)
        ]
        assert residual == [0] * len(residual), b["point"]
        eigen = matrix.xreplace(point).eigenvals()
        mine = Counter(sp.nsimplify(sp.sympify(e)) for e in b["exponents"])
        theirs = Counter({sp.nsimplify(sp.simplify(e)): m for e, m in eigen.items()})
        assert mine == theirs, (b["point"], mine, theirs)


def test_kovalevskaya_top_has_integer_exponents_and_passes_the_painleve_test():
    case, result = analysed(CLASSICAL / "kovalevskaya-top.toml")
    d = result.document
    assert (
        spectra(d) == [["-1", "0", "1", "2", "3", "4"]] * 2 + [["-1", "-1", "2", "2", "3", "4"]] * 2
    )
    assert d["all_integer"] and d["painleve"] == {
        "passes": True,
        "compatible": True,
        "conditions": [],
    }
    assert d["degrees"] == [1, 2, 3, 4] and d["homogeneous"]
    assert [b["dimension"] for b in d["balances"]] == [1, 1, 0, 0]  # a family, once
    independently(case, d)


def test_goryachev_chaplygin_top_has_half_integer_exponents():
    case, result = analysed(CLASSICAL / "goryachev-chaplygin-top.toml")
    d = result.document
    assert sorted(map(tuple, spectra(d))) == [
        ("-1", "-1/2", "3/2", "2", "3", "4"),
        ("-1", "-1/2", "3/2", "2", "3", "4"),
        ("-2", "-1", "2", "3", "3", "4"),
        ("-2", "-1", "2", "3", "3", "4"),
    ]
    assert not d["all_integer"] and d["all_rational"] and not d["painleve"]["passes"]
    assert "needs every exponent to be an integer: it fails" in d["statement"]
    independently(case, d)


def test_lagrange_top_passes_for_every_moment_and_height():
    case, result = analysed(CLASSICAL / "lagrange-top.toml")
    d = result.document
    assert spectra(d) == [["-1", "0", "1", "2", "3", "4"]] * 2
    assert d["painleve"]["passes"] and d["parameters"] == ["A", "C", "z"]
    assert "for generic values of A, C, z" in d["statement"]


def test_euler_top_as_a_heavy_top_without_gravity():
    """Moments (1, 2, 3), no potential: four balances with gamma = 0 and exponents
    -1, 1, 2, 2, 2, 3 (the free body's -1, 2, 2 and the gamma block's 1, 2, 3)."""
    case, result = analysed(EXPONENTS / "euler-top-123.toml")
    d = result.document
    assert spectra(d) == [["-1", "1", "2", "2", "2", "3"]] * 4
    assert all(b["point"]["gamma1"] == "0" for b in d["balances"])
    independently(case, d)


def test_a_system_given_by_its_hamiltonian_and_bracket():
    case, result = analysed(EXPONENTS / "euler-bracket.toml")
    assert spectra(result.document) == [["-1", "2", "2"]] * 4
    assert result.document["weights"] == {"M": 1}
    independently(case, result.document)


def test_a_system_given_by_its_equations_with_a_logarithmic_branch():
    case, result = analysed(EXPONENTS / "log-branch.toml", {"x": 1, "y": 3, "z": 2})
    d = result.document
    assert spectra(d) == [["-1", "4", "8"]]
    assert d["all_integer"] and not d["painleve"]["passes"]
    assert d["painleve"]["conditions"] == [
        {"balance": 1, "resonance": 8, "condition": "-f4**2 = 0", "missing": 0}
    ]
    assert d["balances"][0]["painleve"]["resonances"][1]["conditions"] == ["-f4**2 = 0"]
    assert "does not have the Painlevé property" in d["statement"]
    independently(case, d, {"x": 1, "y": 3, "z": 2})


def test_todas_lattice_branches_in_flaschkas_variables_and_passes_in_their_squares():
    """The open Toda lattice of three particles. In Flaschka's a_k, b_k (weights 1) the
    traces of L, L**2, L**3 have degrees 1, 2, 3, which Yoshida's theorem puts among the
    exponents; where one a_k vanishes at the balance, a_k' = a_k (b_(k+1) - b_k) with
    b_(k+1) - b_k = 1/(2t) makes a_k grow like t**(1/2): exponent 3/2, and the ARS test
    fails. In u_k = a_k**2 (weights u: 2, b: 1), meromorphic, every exponent is an
    integer and the test passes."""
    case, result = analysed(TEST_DATA / "any-form" / "toda-flaschka.toml")
    d = result.document
    assert len(d["balances"]) == 8 and all("-1" in e for e in spectra(d))
    assert d["degrees"] == [1, 2, 3]
    branched = [b for b in d["balances"] if "0" in (b["point"]["a1"], b["point"]["a2"])]
    assert len(branched) == 4
    assert all(b["exponents"] == ["-1", "1", "1", "3/2", "2"] for b in branched)
    assert d["all_rational"] and not d["all_integer"] and not d["painleve"]["passes"]
    independently(case, d)
    case, result = analysed(EXPONENTS / "toda-squares.toml")
    d = result.document
    assert d["weights"] == {"u1": 2, "u2": 2, "b": 1}
    assert sorted(map(tuple, spectra(d))) == [
        ("-1", "1", "1", "2", "3"),
        ("-1", "1", "1", "2", "3"),
        ("-2", "-1", "1", "2", "3"),
    ]
    assert d["all_integer"] and d["painleve"]["passes"] and d["degrees"] == [1, 2, 3]
    independently(case, d)


def is_zero(number: sp.Expr) -> bool:
    """Exactly, for an algebraic number: its minimal polynomial is t."""
    number = sp.expand(number)
    t = sp.Dummy("t")
    return number == 0 or sp.minimal_polynomial(number, t) == t


def test_a_field_unchanged_by_translating_its_parameters_is_analysed_with_one_fewer():
    """Kirchhoff's equations with moments (1, 2, 3) and the potential sum a_i gamma_i**2/2
    involve a1, a2, a3 only through their differences (gamma . gamma is a Casimir). The
    field is analysed at a3 = 0 and written back: at values of a1, a2, a3 with a3 != 0,
    every balance solves the case's own equations, and its exponents are the eigenvalues
    of the case's own Kovalevskaya matrix there (the characteristic polynomials agree,
    exactly)."""
    weights = {"M": 1, "gamma": 1}
    case, result = analysed(EXPONENTS / "kirchhoff-123-potential.toml", weights)
    d = result.document
    assert d["parameters"] == ["a1", "a2", "a3"] and len(d["balances"]) == 16
    (note,) = [n for n in d["notes"] if "for every t" in n]
    assert "a1 -> a1 + t, a2 -> a2 + t, a3 -> a3 + t" in note and "with a3 = 0" in note
    assert "a1 - a3 for a1, a2 - a3 for a2" in note
    assert "for generic values of a1, a2, a3" in d["statement"]
    found = case_field(case, exponent_options(case, weights))
    names = {str(x): x for x in (*found.variables, *found.parameters)}
    matrix = sp.Matrix(found.field).jacobian(found.variables) + sp.diag(*found.weights)
    lam = sp.Symbol("lam")
    a1, a2, a3 = found.parameters
    for values in ({a1: 5, a2: 2, a3: -1}, {a1: sp.Rational(-3, 2), a2: 7, a3: sp.Rational(1, 3)}):
        for b in d["balances"]:
            point = {
                names[x]: sp.sympify(v, locals=names).xreplace(values)
                for x, v in b["point"].items()
            }
            at = {**point, **values}
            for x, v, w in zip(found.variables, found.field, found.weights, strict=True):
                assert is_zero(v.xreplace(at) + w * point[names[str(x)]])
            theirs = sp.Poly(matrix.xreplace(at).charpoly(lam).as_expr(), lam)
            mine = sp.Poly(
                sp.Mul(
                    *(lam - sp.sympify(e, locals=names).xreplace(values) for e in b["exponents"])
                ),
                lam,
            )
            assert all(is_zero(c) for c in (mine - theirs).all_coeffs())
    # a generic exponent varies with a1 - a3 and a2 - a3: the test fails for generic values
    assert not d["all_rational"] and d["painleve"]["passes"] is False


def test_neumanns_problem_passes_the_test_for_generic_potentials():
    """Neumann's problem on e(3) (unit moments, potential sum a_i gamma_i**2/2), weights 1:
    one family of balances with exponents -1, 0, 1, 2, 2, 2, and every compatibility
    condition holds, for generic a1, a2, a3. Over Q(a1, a2, a3) this ran past 300 s; with
    a3 = 0 (a translation of the a_i keeps the field) it takes seconds."""
    case, result = analysed(EXPONENTS / "neumann.toml", {"M": 1, "gamma": 1})
    d = result.document
    assert spectra(d) == [["-1", "0", "1", "2", "2", "2"]]
    assert d["painleve"]["passes"] is True and d["degrees"] == [1, 2]
    assert d["parameters"] == ["a1", "a2", "a3"]
    assert "a1, a2, a3" in d["statement"]


def test_a_field_that_is_not_homogeneous_is_analysed_through_its_leading_part():
    """Kovalevskaya's top on so(4) (Hamiltonian with kappa): under M: 1, gamma: 2 the
    bracket's kappa terms have lower shift; the leading part is Kovalevskaya's e(3) top,
    and the statement says so."""
    case, result = analysed(CASES / "so4" / "komarov-1990-so4-kovalevskaya.toml")
    d = result.document
    assert d["weights"] == {"M": 1, "gamma": 2} and d["homogeneous"] is False
    assert "kappa" not in d["leading"]["gamma1"] and "kappa" in str(case_field(
        case, exponent_options(case)).field)  # fmt: skip
    assert spectra(d)[:2] == [["-1", "0", "1", "2", "3", "4"]] * 2
    assert d["statement"].startswith(
        "The field is not weighted-homogeneous under weights M: 1, gamma: 2: its balances "
        "and exponents are those of its leading part"
    )
    assert "applied to the leading part" in d["statement"]
    assert d["painleve"]["passes"]  # the kappa terms enter the series and pass


def test_a_single_case_takes_under_two_seconds():
    case = load_case(CLASSICAL / "kovalevskaya-top.toml")
    options = exponent_options(case)
    with cpu_bound(2.0) as used:
        analyse_case(case, options)
    assert used.seconds < 2.0


def test_the_default_weights_are_the_grading_under_which_the_field_is_homogeneous():
    clebsch = load_case(CLASSICAL / "clebsch.toml")  # a quadratic potential: M: 1, gamma: 1
    assert exponent_options(clebsch).weights == (("M", 1), ("gamma", 1))
    komarov = load_case(CASES / "so4" / "komarov-1990-so4-kovalevskaya.toml")
    assert exponent_options(komarov).weights == (("M", 1), ("gamma", 2))
    assert exponent_options(komarov, {"gamma": 1}).weights == (("M", 1), ("gamma", 1))


def test_a_state_whose_own_weights_drop_a_component_gets_weights_that_keep_every_one():
    """Hénon and Heiles's system: under its variables' own weight 1, dx/dt = px is of
    lower order than dpx/dt = -2xy and the leading part has no balance; by default the
    analysis takes x, y: 2 and px, py: 3 (``leading_weights``) and finds the three
    balances, x = +-3 sqrt(2 - e), y = -3 and x = 0, y = -6/e."""
    case = load_case(FAMILIES / "henon-heiles.toml")
    options = exponent_options(case)
    assert options.weights == (("x", 2), ("y", 2), ("px", 3), ("py", 3))
    document = analyse_case(case, options).document
    assert len(document["balances"]) == 3
    assert {b["point"]["y"] for b in document["balances"]} == {"-3", "-6/e"}


def test_where_no_weights_keep_every_component_those_that_keep_the_most_are_taken():
    """Rössler's system: no weights keep a leading term in all three components, and the
    variables' own weight 1 keeps one only (dz/dt = xz: no balance, a vacuous pass).
    x: 1, y, z: 2 keep two; the balance x = -2/t, z = -2/t² forces a logarithm in y
    (dy/dt = x + a y ~ -2/t), the compatibility condition at the resonance 2: the test
    fails for every value, and the stratification says so, complete."""
    case = load_case(EXPONENTS / "rossler.toml")
    options = exponent_options(case, free=["a", "b", "c"])
    assert options.weights == (("x", 1), ("y", 2), ("z", 2))
    result = analyse_case(case, options, budget=60)
    (balance,) = result.document["balances"]
    assert balance["point"] == {"x": "-2", "y": "0", "z": "-2"}
    assert balance["exponents"] == ["-1", "2", "2"]
    found = result.document["painleve_sets"]
    assert found["passing"] == [] and found["complete"]


def test_a_set_without_balances_passes_vacuously_and_says_so():
    """Lorenz's system at sigma = 0: x is a constant and the leading part (dx/dt =
    sigma y, dy/dt = -xz, dz/dt = xy) has no balance, so the test has nothing to check
    there; the set is listed (the list must hold it to be complete) with that note, and
    the other sets, with balances, without it."""
    case = load_case(FAMILIES / "lorenz.toml")
    result = analyse_case(case, exponent_options(case, free=["sigma", "r", "b"]))
    passing = result.document["painleve_sets"]["passing"]
    (vacuous,) = [s for s in passing if s["when"] == ["sigma = 0"]]
    assert vacuous["exponents"] == [] and NO_BALANCE in vacuous["notes"]
    others = [s for s in passing if s is not vacuous]
    assert len(others) == 3 and all(s["exponents"] and NO_BALANCE not in s["notes"] for s in others)
    text = exponents_text(result)
    assert "  sigma = 0 (r, b free)\n      no balance: the test has nothing to check" in text
    # the generic members' exponents are integers and their own series is not computed,
    # but the complete list holds no set as large as the space: they fail
    assert result.document["painleve_sets"]["complete"]
    assert "Painlevé (ARS) test for generic values: fails" in text
    assert result.document["painleve"]["passes"] is False
    assert [b["painleve"]["compatible"] for b in result.document["balances"]] == [None] * len(
        result.document["balances"]
    )


def test_a_family_passing_on_the_whole_space_passes_for_generic_values():
    """Lagrange's tops (1, 1, 1/lam), centre z on the axis, lam and z free: with two
    parameters the family's own analysis computes no series, but the stratification
    computes it over Q(lam, z) and passes on the whole space, so the generic members
    pass; with the list cut short, nothing is said (``_generic_verdict``)."""
    case = load_case(FAMILIES / "lagrange-lam.toml")
    result = analyse_case(case, exponent_options(case, free=["lam", "z"]))
    ((whole,),) = [[s for s in result.document["painleve_sets"]["passing"] if not s["when"]]]
    assert whole["free"] == ["lam", "z"] and whole["painleve"]["passes"] is True
    assert result.document["painleve"]["passes"] is True
    assert "  every value (lam, z free)" in exponents_text(result)
    lam = sp.Symbol("lam")
    cut_short = Strata((lam,), passing=(), undecided=("lam = 1",), visited=1)
    assert _generic_verdict(cut_short) is None
    assert _generic_verdict(Strata((lam,), passing=(), undecided=(), visited=1)) is False


def test_options_name_their_problems_with_the_file():
    path = CLASSICAL / "kovalevskaya-top.toml"
    case = load_case(path)
    with pytest.raises(ExponentError) as info:
        exponent_options(case, {"omega": 1}, ["q"])
    assert str(info.value).splitlines() == [
        f"{path}: --weights: names a vector the case's state does not have (its vectors: "
        "M, gamma): 'omega'",
        f"{path}: --free: names a parameter the case does not declare (its parameters: c): 'q'",
    ]


def test_a_system_that_is_not_polynomial_is_refused_naming_each_component():
    path = EXPONENTS / "non-polynomial.toml"
    case = load_case(path)
    with pytest.raises(ExponentError) as info:
        case_field(case, exponent_options(case))
    lines = str(info.value).splitlines()
    assert [line.split(": ")[1] for line in lines] == ["dM1/dt", "dM2/dt"]
    assert lines[0].startswith(
        f"{path}: dM1/dt: not a polynomial in the state variables (divided by a function of "
        "gamma1, gamma2), nor a polynomial divided by one: the analysis seeks balances "
        "x = c t^(-w) of a polynomial or rational field: '"
    )
    assert isinstance(info.value, ValueError) and info.value.file == str(path)


def test_arbitrary_functions_and_dominating_terms_are_refused():
    family = load_case(CASES / "bcc-family-psi-grad-phi.toml")
    with pytest.raises(ExponentError, match="functions: arbitrary functions leave"):
        analyse_case(family, exponent_options(family))
    clebsch = load_case(CLASSICAL / "clebsch.toml")
    with pytest.raises(ExponentError) as info:
        analyse_case(clebsch, exponent_options(clebsch, {"gamma": 2}))
    assert "field: terms of shift 3 > 1 dominate dx/dt under these weights" in str(info.value)


def test_a_family_must_free_every_parameter_of_its_field():
    case = load_case(CLASSICAL / "lagrange-top.toml")
    with pytest.raises(ExponentError) as info:
        analyse_case(case, exponent_options(case, free=["A"]))
    assert str(info.value).endswith(
        "--free: every other parameter of the field must be free too, or be fixed in the "
        "case (the special values of a family are sought over Q(free)): 'C, z'"
    )


def test_past_its_budget_an_analysis_establishes_nothing():
    case = load_case(CLASSICAL / "kovalevskaya-top.toml")
    result = analyse_case(case, exponent_options(case), budget=1e-6)
    assert not result.decided and "time budget exceeded" in result.document["reason"]
    assert result.statement.startswith("Nothing is established")
    assert not refused(case, exponent_options(case), "why").decided


def test_out_of_time_with_a_parameter_a_witness_shows_the_test_failing_for_generic_values():
    """The heavy top with moments (2, 3, 4) and centre (1, 2, a): its balances over Q(a)
    take minutes (261 s once), so the analysis runs out of time; at one rational a, a
    simple balance with exponents that are not rational shows the test failing for
    generic a. The witness is checked again numerically, apart from the exact code: each
    root theta gives a point solving v(c) + w c = 0, whose Kovalevskaya matrix has no
    eigenvalue 0 and one off the integers."""
    case, result = analysed(EXPONENTS / "heavy-top-centre-a.toml", budget=8)
    d = result.document
    assert not result.decided and d["budget"] == 8
    assert d["reason"] == "time budget exceeded (8 s) before the analysis ended"
    assert result.passes is False and d["painleve"]["passes"] is False
    assert "degrees" not in d and d["balances"] == []  # nothing generic is claimed
    w = d["witness"]
    assert list(w["values"]) == ["a"] and w["rational"] == ["-1", "2", "3", "4"]
    assert w["not_rational"] == 2
    assert "-1, 2, 3, 4 and 2 that are not rational" in result.statement
    assert "fails for generic values of a: at a = " in result.statement
    assert "nor the degrees Yoshida's theorem allows" in result.statement
    assert "fails (by a simple balance at a = " in exponents_text(result)
    witnessed_numerically(case_field(case, exponent_options(case)), w)


def witnessed_numerically(found, w) -> None:
    """A witness checked apart from the exact code: at its parameter values, each root
    theta of its polynomial gives a point solving v(c) + w c = 0, whose Kovalevskaya
    matrix has no eigenvalue 0 (a simple balance) and one off the integers."""
    values = {p: sp.Rational(w["values"][str(p)]) for p in found.parameters}
    field = sp.Matrix([f.xreplace(values) for f in found.field])
    state = sp.Matrix(found.variables)
    matrix = field.jacobian(state) + sp.diag(*found.weights)
    g = sp.Poly(sp.sympify(w["root_of"].removesuffix(" = 0")), sp.Symbol("theta"))
    named = {str(x): x for x in found.variables}
    point = {named[k]: sp.sympify(v) for k, v in w["point"].items()}
    for root in g.nroots(n=30):
        at = {x: sp.N(v.subs(sp.Symbol("theta"), root), 30) for x, v in point.items()}
        residual = (field + sp.diag(*found.weights) * state).subs(at)
        assert max(abs(r) for r in residual) < 1e-15
        numeric = mpmath.matrix([[complex(e) for e in row] for row in matrix.subs(at).tolist()])
        eigenvalues = mpmath.eig(numeric)[0]
        assert min(abs(e) for e in eigenvalues) > 1e-3
        assert max(abs(e - round(e.real)) for e in eigenvalues) > 1e-3


def test_a_witness_of_a_reduced_field_names_the_cases_own_values(monkeypatch):
    """Kirchhoff's equations with moments (1, b, c) and the potential sum a_i gamma_i**2/2
    are analysed at a3 = 0 (a translation of the a_i keeps the field). With nine tenths
    of a 4 s budget kept for the witness, the analysis over Q(a1, a2, b, c) (about 2 s)
    runs out, and the witness is given at values of the case's own five parameters,
    a3 = 0 among them; its balance solves the case's equations there, with an exponent
    off the integers."""
    monkeypatch.setattr(exponents_module, "WITNESS_SHARE", 0.9)
    weights = {"M": 1, "gamma": 1}
    case, result = analysed(EXPONENTS / "kirchhoff-1bc-potential.toml", weights, budget=4)
    d = result.document
    assert not result.decided and d["painleve"]["passes"] is False
    w = d["witness"]
    assert set(w["values"]) == {"a1", "a2", "a3", "b", "c"} and w["values"]["a3"] == "0"
    assert "fails for generic values of a1, a2, a3, c, b: at " in result.statement
    witnessed_numerically(case_field(case, exponent_options(case, weights)), w)


def test_a_family_out_of_time_with_one_free_parameter_is_shown_failing_by_a_witness():
    """The same top as a family in a: its analysis over Q(a) runs out of time, and the
    reserve of the budget finds the witness that a single system would, now for the
    generic members of the family; without the witness (a budget too small for it),
    nothing is established, as before."""
    case, result = analysed(EXPONENTS / "heavy-top-centre-a.toml", free=["a"], budget=8)
    d = result.document
    assert not result.decided and result.passes is False and d["free"] == ["a"]
    assert list(d["witness"]["values"]) == ["a"] and d["witness"]["not_rational"] == 2
    assert "fails for generic values of a: at a = " in result.statement
    assert "fails (by a simple balance at a = " in exponents_text(result)
    short = analyse_case(case, exponent_options(case, free=["a"]), budget=0.2)
    assert not short.decided and short.passes is None and "witness" not in short.document
    assert short.statement.startswith("Nothing is established")


def test_a_family_whose_sets_leave_its_generic_test_unknown_is_shown_failing_by_a_witness():
    """The top with its centre at (1, b, a), a and b free: within 8 s neither
    stratification is complete, so the sets do not decide the generic members' test;
    a simple balance at rational (a, b) with exponents that are not rational decides
    that it fails. The document stays a family's (its sets, as far as they went), and
    its statement, text and verdict say where the failure comes from."""
    _, result = analysed(EXPONENTS / "heavy-top-centre-ab.toml", free=["a", "b"], budget=8)
    d = result.document
    assert result.decided and not d["painleve_sets"]["complete"]
    assert d["balances"] == [] and d["all_integer"] is None  # generic: not analysed
    assert result.passes is False and d["painleve"]["passes"] is False
    w = d["witness"]
    assert sorted(w["values"]) == ["a", "b"] and w["rational"] == ["-1", "2", "3", "4"]
    assert all(sp.Rational(v).q > 1 for v in w["values"].values())  # not integers
    assert "fails for generic values of a, b: at a = " in result.statement
    assert "nothing else is established" not in result.statement  # the sets are
    text = exponents_text(result)
    assert "Painlevé (ARS) test for generic values: fails (by a simple balance at a = " in text
    assert "(by the sets below)" not in text


def test_weights_that_leave_no_leading_part_are_refused_naming_the_default_ones():
    """Beside a search the analysis takes the search's weights, M: 1, gamma: 2, under
    which the terms M gamma of Grioli's affine torque dominate dx/dt; the refusal names
    the case's default weights, M: 1, gamma: 1, under which they lead. Nothing is added
    where no weights give a leading part (the axis torque's M gamma^k would need
    k w_gamma <= 1) or where the weights refused are the default ones."""
    grioli = load_case(CASES / "grioli-1957-charged-body.toml")
    options = exponent_options(grioli, {"M": 1, "gamma": 2})
    with pytest.raises(ExponentError) as info:
        analyse_case(grioli, options)
    reason = refused_by(grioli, options, info.value).document["reason"]
    assert reason.startswith(str(info.value))
    assert reason.endswith(
        "\nunder its default weights, M=1,gamma=1, the field has a leading part "
        "(registry exponents grioli-1957-charged-body)"
    )
    axis = load_case(CASES / "axis-torque.toml")  # no weights: its default fails too
    yehia = load_case(CASES / "yehia-2003-kovalevskaya-a.toml")  # its default refused
    for case, weights in ((axis, {"M": 1, "gamma": 1}), (yehia, None)):
        options = exponent_options(case, weights)
        with pytest.raises(ExponentError) as info:
            analyse_case(case, options)
        assert refused_by(case, options, info.value).document["reason"] == str(info.value)


def test_in_a_local_worker_an_analysis_is_the_same_and_refuses_the_same():
    """With local worker processes one system is analysed in a worker, which is killed
    past its budget: the document is the one made here, and a refusal still names the
    file and the problem."""
    case = load_case(CLASSICAL / "goryachev-chaplygin-top.toml")
    options = exponent_options(case)
    here = analyse_case(case, options, budget=120).document
    there = analyse_case(case, options, budget=120, executor=LocalPool(1)).document
    assert {k: v for k, v in there.items() if k != "seconds"} == {
        k: v for k, v in here.items() if k != "seconds"
    }
    assert there["decided"] and any("1/2" in e for e in there["balances"][-1]["exponents"])
    clebsch = load_case(CLASSICAL / "clebsch.toml")
    with pytest.raises(ExponentError) as info:
        analyse_case(
            clebsch, exponent_options(clebsch, {"gamma": 2}), budget=60, executor=LocalPool(1)
        )
    assert str(info.value).startswith(f"{clebsch.path}: field: terms of shift 3 > 1 dominate")


@pytest.mark.slow  # about 30 s: the budget, and the grace before the kill
def test_an_analysis_stuck_in_flint_past_its_budget_ends_when_its_worker_is_killed():
    """Manakov's so(4) body with its four moments symbolic: its balances over Q(j1, ...,
    j4) go into a fraction-free elimination in FLINT, where the timer's signal waits for
    the product in C to end (in this process, a 25 s budget ran to about 50 s). In a
    worker the analysis ends at its budget and the grace, and says why."""
    case = load_case(CASES / "so4" / "manakov-1976-so4-free-body.toml")
    begun = time.monotonic()
    result = analyse_case(case, exponent_options(case), budget=25, executor=LocalPool(1))
    assert time.monotonic() - begun < 25 + GRACE + 5
    assert not result.decided and result.document["budget"] == 25
    assert result.document["reason"] == "time budget exceeded (25 s) before the analysis ended"


def test_the_symmetric_top_family_selects_kovalevskaya_and_names_goryachev_chaplygin():
    """A = B = n C, centre of mass in the equatorial plane: n = 1 and n = 2 pass the
    Painlevé test, n = 4 is the one value with half-integer exponents, and the lists are
    complete; within ten seconds of CPU time."""
    case = load_case(FAMILIES / "symmetric-top-n.toml")
    options = exponent_options(case, free=["n"])
    with cpu_bound(10.0) as used:
        result = analyse_case(case, options)
    assert used.seconds < 10.0
    d = result.document
    found = [(s["kind"], s["when"]) for s in d["special"]]
    assert found[:3] == [
        ("integer", ["n = 1"]),
        ("integer", ["n = 2"]),
        ("half-integer", ["n = 4"]),
    ]
    assert [s["painleve"]["passes"] for s in d["special"][:3]] == [True, True, False]
    assert d["complete"] == {"integer": True, "half_integer": True, "rational": True}
    assert (
        "is an integer exactly at: n = 1 (ARS test passes); n = 2 (ARS test passes)"
        in (d["statement"])
    )


@pytest.mark.parametrize("kappa", ["1", "-1"])
def test_the_symmetric_top_on_so4_and_so31_selects_komarov_s_case(tmp_path, kappa):
    """The same family on {gamma_i, gamma_j} = kappa e_ijk M_k (kappa = 1: so(4), -1:
    so(3,1)): the kappa terms have lower shift, so the balances and exponents are the
    e(3) family's and the statement says they are the leading part's; the Painlevé test
    runs on the whole field and passes at n = 2 (Kovalevskaya's case on so(4) and so(3,1),
    Komarov 1981) and n = 1, fails at n = 4; complete, within ten seconds of CPU time."""
    text = (FAMILIES / "so4-symmetric-top-n.toml").read_text(encoding="utf-8")
    path = tmp_path / "family.toml"
    path.write_text(text.replace('kappa = "1"', f'kappa = "{kappa}"'), encoding="utf-8")
    case = load_case(path)
    with cpu_bound(10.0) as used:
        result = analyse_case(case, exponent_options(case, free=["n"]))
    assert used.seconds < 10.0
    d = result.document
    assert d["homogeneous"] is False and "kappa" not in str(d["leading"])
    found = [(s["kind"], s["when"], s.get("painleve", {}).get("passes")) for s in d["special"]]
    assert found[:3] == [
        ("integer", ["n = 1"], True),
        ("integer", ["n = 2"], True),
        ("half-integer", ["n = 4"], False),
    ]
    assert d["special"][1]["exponents"] == (
        [["-1", "0", "1", "2", "3", "4"]] * 2 + [["-1", "-1", "2", "2", "3", "4"]] * 2
    )
    assert d["complete"] == {"integer": True, "half_integer": True, "rational": True}
    assert d["statement"].startswith(
        "The field is not weighted-homogeneous under weights M: 1, gamma: 2: its balances "
        "and exponents are those of its leading part"
    )
    assert (
        "is an integer exactly at: n = 1 (ARS test passes); n = 2 (ARS test passes)"
        in (d["statement"])
    )


def kirchhoff_family(name):
    """The special sets (kind, values, ARS verdict) and completeness of a Kirchhoff
    family in t, with its statement."""
    case = load_case(FAMILIES / f"{name}.toml")
    d = analyse_case(case, exponent_options(case, free=["t"])).document
    found = [(s["kind"], s["when"], s.get("painleve", {}).get("passes")) for s in d["special"]]
    return found, d["complete"], d["statement"]


def test_the_axisymmetric_kirchhoff_family_selects_kirchhoff_s_case():
    """Moments (1, 1, 1/3), potential (gamma1^2 + t gamma2^2)/2: every exponent is an
    integer exactly at t = 1 (Kirchhoff's case, b1 = b2), where the ARS test passes."""
    found, complete, statement = kirchhoff_family("kirchhoff-axisymmetric-t")
    assert [f for f in found if f[0] != "rational"] == [("integer", ["t = 1"], True)]
    assert complete["integer"] and complete["half_integer"]
    assert "every exponent of every balance is an integer exactly at: t = 1 (ARS" in statement


@pytest.mark.slow  # about 30 s of computing
def test_the_kirchhoff_family_with_distinct_moments_selects_clebsch_s_condition():
    """Moments (1, 1/2, 1/3): every exponent is an integer exactly on Clebsch's
    condition (b2 - b3)/a1 + (b3 - b1)/a2 + (b1 - b2)/a3 = 0, t = 1/4, where the ARS
    test passes (Clebsch's case is algebraically integrable, Kötter 1892)."""
    found, complete, statement = kirchhoff_family("kirchhoff-clebsch-t")
    assert [f for f in found if f[0] != "rational"] == [("integer", ["t = 1/4"], True)]
    assert complete["integer"] and complete["half_integer"]
    assert "no value makes every exponent of every balance half an integer" in statement


def test_a_family_s_painleve_verdict_is_that_of_its_generic_members(tmp_path):
    """Lagrange's top A = B = 1, C = 2 with the centre of mass c on the axis, c free:
    integer exponents for every c and every condition holding over Q(c), so the test
    passes for generic c, in the document as in its statement."""
    path = tmp_path / "lagrange-c.toml"
    path.write_text(
        'id = "family-lagrange-c"\ntitle = "Lagrange top, centre c on the axis"\n'
        '[source]\ncitation = "Test family"\n[parameters]\nc = "positive"\n'
        '[system]\ninertia = ["1", "1", "2"]\npotential = "c*gamma3"\n',
        encoding="utf-8",
    )
    _, result = analysed(path, free=["c"])
    d = result.document
    assert [(s["kind"], s["when"]) for s in d["special"]] == [("integer", []), ("rational", [])]
    assert spectra(d) == [["-1", "0", "1", "2", "3", "4"]] * 2
    assert d["painleve"]["passes"] is True and d["painleve"]["conditions"] == []
    assert result.passes
    assert "passes for generic values" in result.statement


def test_the_catalog_s_new_forms_are_analysed_or_refused_with_the_reason():
    """Kovalevskaya's top in her own (omega, gamma) equations has the exponents of the
    (M, gamma) form (above): two families of balances, two isolated ones; the Chaplygin
    sleigh in (v, omega) is quadratic, with -1 and 2 (the energy's degree) at each
    balance; a system with an angle among its state is refused, and so is the Chaplygin
    ball's field, by the split: it divides by a polynomial in gamma that is not
    weighted-homogeneous."""
    heavy = CASES / "heavy-top" / "kovalevskaya-1889-heavy-top-omega-equations.toml"
    case, result = analysed(heavy)
    assert result.decided and result.document["homogeneous"] is True
    assert spectra(result.document) == (
        [["-1", "0", "1", "2", "3", "4"]] * 2 + [["-1", "-1", "2", "2", "3", "4"]] * 2
    )
    assert [b["dimension"] for b in result.document["balances"]] == [1, 1, 0, 0]
    assert result.document["degrees"] == [1, 2, 3, 4] and result.passes
    independently(case, result.document)
    sleigh = CASES / "nonholonomic" / "tenenbaum-2025-chaplygin-sleigh.toml"
    case, result = analysed(sleigh)
    assert spectra(result.document) == [["-1", "2"]] * 2 and 2 in result.document["degrees"]
    independently(case, result.document)
    disk = load_case(CASES / "nonholonomic" / "verdier-2016-vertical-rolling-disk-odelab.toml")
    with pytest.raises(ExponentError) as info:
        case_field(disk, exponent_options(disk))
    assert [p.field for p in info.value.problems] == ["dvx/dt", "dvy/dt"]
    assert "'-R*wphi*wtheta*sin(phi)'" in str(info.value)
    ball = load_case(CASES / "nonholonomic" / "gaire-2025-chaplygin-ball-code.toml")
    with pytest.raises(ExponentError) as info:
        analyse_case(ball, exponent_options(ball))
    assert len(info.value.problems) == 6
    assert all(
        p.message.startswith("divides by a polynomial that is not weighted-homogeneous")
        for p in info.value.problems
    )


def test_a_field_divided_by_gamma3_is_analysed_where_gamma3_is_not_zero():
    """Goryachev's 1916 top is Goryachev and Chaplygin's (A = B = 4C, potential a gamma1)
    with b/gamma3^2 added, a term of lower shift under (M: 1, gamma: 2). The leading part
    is Goryachev and Chaplygin's, with its four balances (above); the two with
    gamma3 = 0, where the exponents are -1/2 and 3/2, are not balances of the divided
    field (its lower term is not lower there), and are left out, saying so."""
    case, result = analysed(CASES / "heavy-top" / "goryachev-1916-heavy-top.toml")
    d = result.document
    assert d["denominators"] == ["gamma3"] and d["homogeneous"] is False
    assert spectra(d) == [["-2", "-1", "2", "3", "3", "4"]] * 2
    assert all(sp.sympify(b["point"]["gamma3"]) != 0 for b in d["balances"])
    assert (
        "it divides by gamma3, and its balances are those where none of these" in (d["statement"])
    )
    assert not d["painleve"]["passes"]
    independently(case, d)


def test_the_reference_paper_s_borisov_mamaev_case_is_analysed_but_not_as_a_family():
    """Borisov and Mamaev's field divides by a power of gamma3 (the reference paper's
    case); its balances solve the divided equations and their exponents are sympy's
    eigenvalues of the Kovalevskaya matrix there. The special values of a divided
    field are not sought: --free is refused, naming the components."""
    case, result = analysed(CASES / "borisov-mamaev-1997.toml")
    d = result.document
    assert result.decided and d["denominators"] and d["balances"]
    independently(case, d)
    with pytest.raises(ExponentError) as info:
        case_field(case, exponent_options(case, free=list(case.parameters)))
    assert "are sought for polynomial fields only" in str(info.value)


def test_bobylev_s_conditions_are_written_in_the_square_roots_of_the_balance():
    """Bobylev's top (A = 2C, the centre on the first axis): the conditions that fail at
    its balances over Q(B, C, a) are written at each balance in the square roots that
    balance has, each coefficient factored (radsimp wrote them over a denominator of
    degree 33 and took 0.3 s each)."""
    _, result = analysed(CASES / "heavy-top" / "bobylev-1896-heavy-top.toml")
    conditions = [c["condition"] for c in result.document["painleve"]["conditions"]]
    assert conditions and all(len(c) < 120 for c in conditions)
    shown = "-sqrt(2)*a*f1**2*sqrt(-1/(B**2 - 3*B*C + 2*C**2))*(B - C)**2/(2*B*C) = 0"
    assert shown in conditions
