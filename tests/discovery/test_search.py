"""Integral searches rediscover the classical integrable cases from families that do not
name them, prove what they find, and state what they rule out.

The expected answers are the literature's: Kovalevskaya (Acta Math. 12, 1889) at
A = B = 2C with the centre of mass in the equatorial plane; the spherical top; Lagrange's
axial integral; Goryachev (1900) and Chaplygin (1901) on s = 0 at A = B = 4C; Husson
(1906): no other case of the heavy top has an extra algebraic integral; Yehia (1986)
and Komarov (1987): the Kovalevskaya gyrostat with a moment along the symmetry axis;
Clebsch (1871): quadratic potentials with (b2 - b3)/a1 + (b3 - b1)/a2 + (b1 - b2)/a3 = 0.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
import sympy as sp

from registry.discovery.identification.catalog_index import CatalogIndex
from registry.discovery.locus import same
from registry.discovery.search import discover, search_options
from registry.errors import DiscoveryError
from registry.execution.executor import InProcess, LocalPool
from registry.language.casefile import load_case, parse_case_text
from registry.language.forms import with_system
from registry.language.forms import with_values as substituted
from registry.language.parser import Namespace, parse_expression
from registry.mathematics import mechanics as mech
from registry.model import Verdict
from registry.presentation.search_output import statement
from tests.helpers.catalog import catalog_cases, catalog_index
from tests.helpers.samples import FAMILIES, family


def search(name: str, **options):
    case = family(name)
    budget = options.pop("budget", 120)
    jobs = options.pop("jobs", 1)
    executor = InProcess() if jobs == 1 else LocalPool(jobs)
    return discover(case, search_options(case, **options), budget=budget, executor=executor)


def where(found) -> dict[tuple[str, ...], tuple[str, ...]]:
    return {s.when: s.integrals for s in found.special}


def conserved_modulo_known(case, text: str, known: list[sp.Expr], on=()) -> bool:
    """Whether ``text`` is a first integral (checked here, independently of the search:
    dF/dt expanded to zero, modulo the level-set equations when given)."""
    ns = Namespace(case.parameters, case.functions)
    expr = parse_expression(text, ns)
    field = mech.vector_field(case.system.inertia_exprs, case.system.potential.expr, (0, 0, 0))
    rate = sp.expand(mech.time_derivative(expr, field).subs(mech.s, mech.S_VALUE))
    if on:
        rate = sp.reduced(rate, [sp.expand(e.subs(mech.s, mech.S_VALUE)) for e in on], *mech.STATE)[
            1
        ]
    return sp.simplify(rate) == 0


# --- the classics, rediscovered -----------------------------------------------------


def test_heavy_top_degree_four_finds_exactly_kovalevskaya_and_the_spherical_top():
    found = search("heavy-top-lam", degree=4, free=("lam",))
    assert found.complete
    assert found.generic.extra == 0
    assert set(where(found)) == {("lam = 1",), ("lam = 2",)}
    assert where(found)[("lam = 1",)] == ("M1",)
    (kovalevskaya,) = where(found)[("lam = 2",)]
    # Kovalevskaya's own integral (A = B = 1, C = 1/2, U = gamma1): the search prints it
    # in its simplest form, which is hers
    k = sp.expand(
        (sp.Symbol("M1") ** 2 - sp.Symbol("M2") ** 2 - 2 * sp.Symbol("gamma1")) ** 2
        + (2 * sp.Symbol("M1") * sp.Symbol("M2") - 2 * sp.Symbol("gamma2")) ** 2
    )
    assert sp.expand(sp.sympify(kovalevskaya) - k) == 0
    at_two = substituted(family("heavy-top-lam"), {family("heavy-top-lam").parameters["lam"]: 2})
    assert conserved_modulo_known(at_two, kovalevskaya, [])
    for s in found.special:
        assert s.casimir == (Verdict.REFUTED,)  # integrals, but no Casimirs


def test_on_s_zero_degree_three_finds_goryachev_chaplygin_and_not_kovalevskaya():
    found = search("heavy-top-lam", degree=3, free=("lam",), on=("s = 0",))
    assert found.complete
    assert set(where(found)) == {("lam = 1",), ("lam = 4",)}
    (gc,) = where(found)[("lam = 4",)]
    # Goryachev-Chaplygin: M3 (M1**2 + M2**2) - 4 C a M1 gamma3 with C = 1/4, a = 1
    assert sp.expand(sp.sympify(gc) - sp.sympify("M3*(M1**2 + M2**2) - M1*gamma3")) == 0
    assert ("lam = 2",) not in where(found)


def test_two_free_parameters_find_kovalevskaya_only_with_z0_zero_and_the_spherical_line():
    found = search("heavy-top-lam-z0", degree=4, free=("lam", "z0"))
    assert found.complete
    assert set(where(found)) == {("lam = 1",), ("lam = 2", "z0 = 0")}
    assert where(found)[("lam = 1",)] == ("M1 + M3*z0",)  # M . xi, for every z0


def test_the_lagrange_top_has_m3_for_every_lam():
    found = search("lagrange-lam", degree=3, free=("lam",))
    assert found.complete
    assert found.generic.extra == 1 and found.generic.integrals == ("M3",)
    assert found.special == ()  # the spherical top adds nothing new here: M3 already


def test_a_quartic_curve_of_symmetric_bodies_is_searched_with_a_new_parameter():
    # A = 1 + a**2 c**2 equals B = c + 3/4 on a**2 c**2 = c - 1/4, where no parameter is
    # rational in the other; through its discriminant, c = (w**2 + 1)/4, a = 2w/(w**2 + 1)
    found = search("quadric-moments", degree=2, weights={"M": 1, "gamma": 2}, free=("a", "c"))
    assert found.complete, found.coverage
    (curve,) = [s for s in found.special if any("w1" in e for e in s.when)]
    assert curve.integrals == ("M3",) and found.generic.extra == 0
    case = family("quadric-moments")
    a, c = case.parameters["a"], case.parameters["c"]
    w1 = sp.Symbol("w1", real=True)
    values = {a: sp.sympify(curve.when[0].split(" = ")[1], locals={"w1": w1})}
    values[c] = sp.sympify(curve.when[1].split(" = ")[1], locals={"w1": w1})
    # every member of the set is a symmetric body: A = B for every w1
    inertia = [sp.cancel(e.xreplace(values)) for e in case.system.inertia_exprs]
    assert sp.cancel(inertia[0] - inertia[1]) == 0
    symmetric = substituted(case, values)
    assert symmetric is not None and "w1" in symmetric.parameters
    assert symmetric.system.inertia[0].text == "w1**2/4 + 1"  # the fractions cancel


def test_another_axis_and_normalisation_give_kovalevskaya_at_a_half():
    found = search("heavy-top-axis1", degree=4, free=("a",))
    assert found.complete
    assert set(where(found)) == {("a = 1",), ("a = 1/2",)}


def test_the_kovalevskaya_gyrostat_keeps_its_moment_symbolic():
    found = search("kovalevskaya-gyrostat", degree=4, free=("lam",))
    assert found.complete
    assert set(where(found)) == {("lam = 2",)}
    (integral,) = where(found)[("lam = 2",)]
    assert "k" in integral  # the gyrostatic moment enters the integral (Yehia 1986)


def test_clebsch_condition_is_found_as_a_function_of_the_other_coefficients():
    found = search("clebsch-b3", degree=2, weights=(1, 1), free=("b3",))
    assert found.complete
    (special,) = found.special
    (equation,) = special.when
    b1, b2 = sp.symbols("b1 b2")
    assert sp.simplify(sp.sympify(equation.split("=")[1]) - (4 * b2 - b1) / 3) == 0
    assert special.extra == 1


def test_the_free_top_has_its_second_quadratic_integral_for_its_moments():
    found = search("euler-top", degree=4)
    assert found.generic.extra == 1
    (integral,) = found.generic.integrals
    assert conserved_modulo_known(family("euler-top"), integral, [])


# --- negative results, mutations, level sets -----------------------------------------


def test_an_asymmetric_heavy_top_has_no_extra_integral_up_to_degree_four():
    found = search("asymmetric-heavy-top", degree=4)
    assert found.complete and found.generic.extra == 0 and found.special == ()
    assert [d for d, _, _, extra in found.dimensions if extra] == []
    assert found.dimensions[-1][:3] == (4, 4, 4)  # H, s, H**2, |gamma|**2 and nothing else


def test_a_perturbed_special_value_loses_the_extra_integral():
    case = family("heavy-top-lam")
    lam = case.parameters["lam"]
    for value, extra in ((sp.Integer(2), 1), (sp.Rational(2001, 1000), 0), (sp.Integer(4), 0)):
        at = substituted(case, {lam: value})
        found = discover(at, search_options(at, degree=4))
        assert found.generic.extra == extra, value
        assert found.complete


def test_on_the_unit_sphere_kovalevskaya_appears_at_degree_four():
    found = search(
        "heavy-top-lam", degree=4, free=("lam",), on=("gamma1**2 + gamma2**2 + gamma3**2 = 1",)
    )
    assert set(where(found)) == {("lam = 1",), ("lam = 2",)}


def test_every_reported_integral_is_conserved_when_checked_independently():
    found = search("heavy-top-lam", degree=3, free=("lam",), on=("s = 0",))
    case = family("heavy-top-lam")
    for s in found.special:
        (equation,) = s.when
        value = sp.Rational(equation.split("=")[1])
        at = substituted(case, {case.parameters["lam"]: value})
        for text in s.integrals:
            assert conserved_modulo_known(at, text, [], on=[mech.S_VALUE])


def test_parallel_search_gives_the_same_result():
    one = search("heavy-top-lam-z0", degree=4, free=("lam", "z0"))
    two = search("heavy-top-lam-z0", degree=4, free=("lam", "z0"), jobs=2)
    assert (one.generic, one.special, one.complete) == (two.generic, two.special, two.complete)


def test_a_budget_that_runs_out_reports_what_was_proven_and_says_it_is_not_complete():
    found = search("heavy-top-lam-z0", degree=4, free=("lam", "z0"), budget=0.05)
    assert not found.complete
    assert any("time budget exceeded" in c for c in found.coverage)


# --- what cannot be searched is said clearly ------------------------------------------


def test_a_free_name_that_is_not_a_parameter_is_refused():
    with pytest.raises(DiscoveryError, match="'mu', which the case does not declare"):
        search("heavy-top-lam", free=("mu",))


def test_a_level_set_the_flow_leaves_is_refused():
    with pytest.raises(DiscoveryError, match="does not keep the level set M1 = 0 invariant"):
        search("heavy-top-lam", degree=2, on=("M1 = 0",))


def test_a_system_outside_every_ring_of_the_method_is_refused():
    case = family("euler-top")
    potential = replace(case.system.potential, text="exp(gamma1)", expr=sp.exp(mech.gamma1))
    case = with_system(case, replace(case.system, potential=potential))
    with pytest.raises(DiscoveryError, match="not rational in the state variables"):
        discover(case, search_options(case, degree=2))


def test_an_ansatz_too_large_is_refused_before_it_is_built():
    with pytest.raises(DiscoveryError, match="search at a lower --degree"):
        search("euler-top", degree=40)


# --- both arithmetic backends ----------------------------------------------------------


def test_the_pure_python_backend_finds_the_same():
    """sympy uses FLINT when python-flint is installed; without it, pure Python."""
    code = (
        "import json, registry.api as a\n"
        "r = a.discover_file('tests/data/families/heavy-top-lam.toml', free=['lam'])\n"
        "k = a.discover_file('data/cases/heavy-top/kovalevskaya-1889-heavy-top.toml')\n"
        "print(json.dumps([[list(s.when) for s in r.search.special], r.exponents.decided,\n"
        "    len(k.search.generic.integrals), k.exponents.decided]))\n"
    )
    env = {**os.environ, "SYMPY_GROUND_TYPES": "python"}
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env=env,
        check=True,
        cwd=Path(__file__).resolve().parents[2],
    )
    # the family's sets and its analysis; Kovalevskaya's quartic over Q(C, a), analysed
    assert json.loads(out.stdout) == [[["lam = 1"], ["lam = 2"]], True, 1, True]


def values_of(case, when) -> dict[sp.Symbol, sp.Expr]:
    """A special set's equations ("b = c", ...) as values of the parameters."""
    ns = Namespace(case.parameters, case.functions)
    return {
        case.parameters[lhs]: parse_expression(rhs, ns)
        for lhs, rhs in (w.split(" = ") for w in when)
    }


def all_conserved(name: str, found, on=()) -> None:
    """Every integral reported is conserved where it is reported (checked here)."""
    case = family(name)
    for special in found.special:
        sub = substituted(case, values_of(case, special.when))
        for text in special.integrals:
            assert conserved_modulo_known(sub, text, [], on), (special.when, text)


# --- several free parameters ----------------------------------------------------------


def test_three_free_parameters_give_the_four_classical_sets_and_nothing_else():
    # moments (1, b, c), centre of mass (1, 0, z0): the spherical top (M1 + z0 M3 for
    # every z0), Lagrange with the centre on the symmetry axis, Kovalevskaya with the
    # equal moments 1 = c twice b (centre (1, 0, z0) in their plane, every z0), and with
    # 1 = b twice c (z0 = 0 only); Husson (1906): no other case
    found = search("heavy-top-b-c-z0", degree=4, free=("b", "c", "z0"))
    assert found.complete and found.generic.extra == 0
    sets = where(found)
    assert set(sets) == {
        ("b = 1", "c = 1"),
        ("b = c", "z0 = 0"),
        ("b = 1/2", "c = 1"),
        ("b = 1", "c = 1/2", "z0 = 0"),
    }
    assert sets[("b = 1", "c = 1")] == ("M1 + M3*z0",)
    assert sets[("b = c", "z0 = 0")] == ("M1",)
    all_conserved("heavy-top-b-c-z0", found)


def test_a_family_with_its_special_sets_planted_by_a_change_of_parameters():
    # the (b, c, z0) top written in new parameters: b = p q**k, c = q, z0 = w + m q
    # (p, q > 0): its special sets are the preimages of the four classical ones
    rnd = random.Random()
    k, m = rnd.randint(1, 3), rnd.choice([-3, -2, -1, 1, 2, 3])
    text = (FAMILIES / "heavy-top-b-c-z0.toml").read_text()
    text = text.replace('b = "positive"', 'p = "positive"').replace(
        'c = "positive"', 'q = "positive"'
    )
    text = text.replace('z0 = "real"', 'w = "real"').replace(
        'id = "family-heavy-top-b-c-z0"', 'id = "family-planted"'
    )
    text = text.replace('inertia = ["1", "b", "c"]', f'inertia = ["1", "p*q**{k}", "q"]')
    text = text.replace(
        'potential = "gamma1 + z0*gamma3"', f'potential = "gamma1 + (w + {m}*q)*gamma3"'
    )
    case = parse_case_text(text, "planted.toml")
    found = discover(case, search_options(case, degree=4, free=("p", "q", "w")), budget=120)
    assert found.complete, (k, m, found.coverage)
    p, q, w = (case.parameters[n] for n in ("p", "q", "w"))
    expected = [
        {p: 1, q: 1},
        {p: q ** (1 - k), w: -m * q},
        {p: sp.Rational(1, 2), q: 1},
        {p: 2**k, q: sp.Rational(1, 2), w: -sp.Rational(m, 2)},
    ]
    got = [values_of(case, s.when) for s in found.special]
    assert len(got) == 4, (k, m, [s.when for s in found.special])
    for values in expected:
        assert any(same(values, g) for g in got), (k, m, values, got)


def clebsch(case) -> sp.Expr:
    """Clebsch's condition (1871) for H = (M1**2 + M2**2/B + M3**2/C)/2 + sum b_i gamma_i**2/2:
    (b2 - b3)/a1 + (b3 - b1)/a2 + (b1 - b2)/a3 = 0 with a = (1, 1/B, 1/C)."""
    B, C, b1, b2, b3 = (case.parameters[n] for n in ("B", "C", "b1", "b2", "b3"))
    return (b2 - b3) + B * (b3 - b1) + C * (b1 - b2)


def test_five_free_parameters_at_degree_two_give_clebsch_and_the_axial_cases():
    found = search(
        "kirchhoff-diagonal", degree=2, weights=(1, 1), free=("B", "C", "b1", "b2", "b3")
    )
    assert found.complete and found.generic.extra == 0
    case = family("kirchhoff-diagonal")
    sets = where(found)
    # Clebsch's hypersurface, one equation, with its quadratic integral
    (hypersurface,) = [w for w in sets if len(w) == 1]
    assert sp.cancel(clebsch(case).xreplace(values_of(case, hypersurface))) == 0
    # the axially symmetric ones (Lagrange's kind): M_i where the other two moments and
    # the other two potential coefficients are equal
    assert sets[("B = 1", "b1 = b2")] == ("M3",)
    assert sets[("B = C", "b3 = b2")] == ("M1",)
    assert sets[("C = 1", "b3 = b1")] == ("M2",)
    # every set lies on Clebsch's hypersurface (quadratic integrals need it)
    for when in sets:
        assert sp.cancel(clebsch(case).xreplace(values_of(case, when))) == 0, when
    all_conserved("kirchhoff-diagonal", found)


@pytest.mark.slow  # about 20 s of computing on two cores (over a minute when busy)
def test_five_free_parameters_on_s_zero_at_degree_four_add_chaplygins_case():
    found = search(
        "kirchhoff-diagonal",
        degree=4,
        weights=(1, 1),
        free=("B", "C", "b1", "b2", "b3"),
        on=("s = 0",),
        budget=900,
    )
    assert found.complete and found.generic.extra == 0
    case = family("kirchhoff-diagonal")
    B, C, b1, b2, b3 = (case.parameters[n] for n in ("B", "C", "b1", "b2", "b3"))
    # Chaplygin (1902): two moments twice the third (Kovalevskaya's ratio) and the
    # potential c (gamma_i**2 - gamma_j**2) in the plane of the equal ones (up to |gamma|**2)
    chaplygin = {
        (1, sp.Rational(1, 2)): b1 + b2 - 2 * b3,
        (sp.Rational(1, 2), 1): b1 + b3 - 2 * b2,
        (2, 2): b2 + b3 - 2 * b1,
    }
    quartic = {}
    for special in found.special:
        values = values_of(case, special.when)
        if sp.cancel(clebsch(case).xreplace(values)) != 0:
            quartic[(values[B], values[C])] = values
    assert set(quartic) == set(chaplygin)
    for moments, condition in chaplygin.items():
        values = quartic[moments]
        assert len(values) == 3 and sp.cancel(condition.xreplace(values)) == 0
    all_conserved("kirchhoff-diagonal", found, on=[mech.s])


# ------------------------------------------------------------- invariant relations


def test_hess_invariant_relation_is_found_with_its_cofactor_under_hess_condition():
    """Hess (1890): under his condition x0 M1 + z0 M3 = 0 is an invariant relation,
    d/dt (x0 M1 + z0 M3) = K (x0 M1 + z0 M3) with K a multiple of M2; the search for
    Darboux polynomials finds it as the one special cofactor, and nothing else."""
    case = load_case(
        Path(__file__).resolve().parents[2] / "data/cases/heavy-top/hess-1890-heavy-top.toml"
    )
    search = discover(case, search_options(case, degree=1, relations=True))
    assert search.complete and search.generic.extra == 0
    (hess,) = search.special
    assert hess.integrals == ("M1*x0 + M3*z0",)
    ns = Namespace(case.parameters, case.functions)
    cofactor = parse_expression(hess.cofactor, ns)
    assert cofactor.free_symbols & set(mech.STATE) == {mech.M2}
    f = parse_expression(hess.integrals[0], ns)
    field = mech.vector_field(
        [e.expr for e in case.system.inertia], case.system.potential.expr, (0, 0, 0)
    )
    assert sp.simplify(mech.time_derivative(f, field) - cofactor * f) == 0


def test_without_hess_condition_there_is_no_relation_and_first_integrals_are_not_new():
    """The unrestricted body: no cofactor carries a Darboux polynomial of degree 1; the
    cofactor 0 (first integrals: H, |gamma|^2, s and their level sets) is not reported."""
    case = load_case(
        Path(__file__).resolve().parents[2]
        / "data/cases/heavy-top/hess-1890-heavy-top-unrestricted.toml"
    )
    search = discover(case, search_options(case, degree=1, relations=True))
    assert search.complete and search.special == ()


def test_relations_in_a_ring_with_an_inverse_take_the_degrees_of_the_normal_form():
    """Goryachev (1916), potential a gamma1 + b/gamma3^2: the field in the ring with
    u = 1/gamma3 reduced by u gamma3 = 1 raises the degree by 1 (not by 7, as its
    unreduced form 3 M2 M3 gamma3^3 u^3 suggested): three cofactor coefficients, and the
    degree-2 search is decided (it ran out of a 120 s budget)."""
    case = load_case(
        Path(__file__).resolve().parents[2] / "data/cases/heavy-top/goryachev-1916-heavy-top.toml"
    )
    search = discover(case, search_options(case, degree=2, relations=True), budget=300)
    assert search.complete
    assert all(s.integrals == () for s in search.special)  # only the level sets of H, ...


def test_a_cofactor_with_no_real_value_is_ruled_out_and_the_search_is_complete():
    """The symmetric free top (A = B): K_M3 would need A^2 C^2 K_M3^2 + (A - C)^2 = 0,
    whose discriminant -4 A^2 C^2 (A - C)^2 is negative for generic A, C (a product of
    one-signed factors and even powers): no real cofactor, nothing undecided. Asymmetric
    moments have real irrational cofactors (the planes through the separatrices), which
    stay named: not decided over their number field."""
    root = Path(__file__).resolve().parents[2] / "data/cases/free-rigid-body"
    symmetric = load_case(root / "euler-1765-free-rigid-body-symmetric.toml")
    search = discover(symmetric, search_options(symmetric, degree=2, relations=True))
    assert search.complete, search.coverage
    asymmetric = load_case(root / "euler-1765-free-rigid-body.toml")
    search = discover(asymmetric, search_options(asymmetric, degree=2, relations=True))
    assert not search.complete
    assert any("not decided over its number field" in c for c in search.coverage)


def test_relations_for_weights_that_leave_the_field_inhomogeneous_say_which_weights_do_not():
    """Clebsch's quadratic potential at the default weights M: 1, gamma: 2 raises the
    degree by 1 and by 3: lower cofactor weights are left out and the coverage says
    which weights make the field homogeneous; with those no cofactor weight is left out
    (what stays undecided are cofactors no free parameter solves rationally)."""
    case = load_case(
        Path(__file__).resolve().parents[2]
        / "data/cases/kirchhoff/clebsch-1871-kirchhoff-quadratic.toml"
    )
    search = discover(case, search_options(case, degree=2, relations=True))
    assert not search.complete
    assert any("search with --weights M=1,gamma=1" in c for c in search.coverage)
    search = discover(case, search_options(case, degree=2, weights=(1, 1), relations=True))
    assert search.decided and not any("weight below" in c for c in search.coverage)


# --- statements that mean what they say (issue 33) -----------------------------------


def test_a_set_where_only_the_rank_drops_is_searched_but_never_called_special():
    # mu = grad phi with phi = (t1 gamma1^2 + t2 gamma2^2 + t3 gamma3^2)/2: the Casimir
    # s + phi becomes s (lower weighted degree) where t1 = t2 = t3, so the kernel of degree
    # 3 grows there; no integral beyond the known ones exists on that line
    case = family("kovalevskaya-diagonal-torque")
    searched: list[str] = []
    found = discover(
        case,
        search_options(case, degree=4, free=("t1", "t2", "t3")),
        budget=120,
        progress=lambda done, total, what: searched.append(what),
    )
    assert "t1 = t3, t2 = t3" in searched  # the rank drops there: a candidate
    assert found.complete
    assert [s.when for s in found.special] == [("t1 = 0", "t2 = 0", "t3 = 0")]
    assert all(s.extra > found.generic.extra for s in found.special)
    assert "t1 = t3" not in statement(found)


# --- every component decided (issue 33) -----------------------------------------------


def test_an_algebraic_special_point_is_searched_exactly_at_its_value():
    found = search("heavy-top-u-squared", degree=4, free=("u",))
    assert found.complete
    assert set(where(found)) == {("u = 2",), ("u = sqrt(2)",)}
    (kovalevskaya,) = where(found)[("u = sqrt(2)",)]
    assert "M1**4" in kovalevskaya


FIVE = {
    ("b = 1", "c = 1"),
    ("b = 1", "x0 = 0", "y0 = 0"),
    ("b = c", "y0 = 0", "z0 = 0"),
    ("c = 1", "x0 = 0", "z0 = 0"),
    ("x0 = 0", "y0 = 0", "z0 = 0"),
}


@pytest.mark.slow  # about 12 s of computing (half a minute when the machine is busy)
def test_five_free_parameters_of_the_heavy_top_are_complete_at_degree_four():
    # components such as 49 x0^2 = 30 z0^2 (lines over Q(sqrt(30))) and sums of squares
    # are decided at their points; Euler, Lagrange, Kovalevskaya about each axis and the
    # spherical top, and nothing else (Husson 1906)
    found = search("heavy-top-five", degree=4, free=("b", "c", "x0", "y0", "z0"), budget=600)
    assert found.complete, found.coverage
    kovalevskaya = {
        ("b = 1", "c = 1/2", "z0 = 0"),
        ("b = 1/2", "c = 1", "y0 = 0"),
        ("b = 2", "c = 2", "x0 = 0"),
    }
    assert set(where(found)) == FIVE | kovalevskaya
    all_conserved("heavy-top-five", found)


def test_five_free_parameters_of_the_heavy_top_on_s_zero_are_complete_at_degree_three():
    found = search(
        "heavy-top-five", degree=3, on=("s = 0",), free=("b", "c", "x0", "y0", "z0"), budget=600
    )
    assert found.complete, found.coverage
    chaplygin = {
        ("b = 1", "c = 1/4", "z0 = 0"),
        ("b = 1/4", "c = 1", "y0 = 0"),
        ("b = 4", "c = 4", "x0 = 0"),
    }
    assert set(where(found)) == FIVE | chaplygin


# --- identification with the catalog (issue 33) ----------------------------------------


def test_the_diagonal_torques_kovalevskaya_point_is_kovalevskayas_case_not_new():
    case = family("kovalevskaya-diagonal-torque")
    found = discover(
        case,
        search_options(case, degree=4, free=("t1", "t2", "t3")),
        budget=600,
        catalog=catalog_index(),
    )
    (point,) = found.special
    assert point.when == ("t1 = 0", "t2 = 0", "t3 = 0")
    same = {s.case: s for s in point.same_as}
    kovalevskaya = same["kovalevskaya-1889-heavy-top"]
    assert dict(kovalevskaya.values) == {"C": "1", "a": "1"}
    assert kovalevskaya.claims == ("K",)
    assert point.new == () and point.status[0].status == "rediscovered"
    said = statement(found)
    assert "kovalevskaya" in said and "(new" not in said
    # the rank-drop-only set t1 = t2 = t3 (s + t|gamma|^2/2 changes form) is not special
    assert "t1 = t3" not in said and "t1 - t3" not in said
    assert said.endswith("no other values carry more.")


def test_a_planted_integrable_member_the_catalog_does_not_hold_is_reported_new():
    # the same family against a catalog without Kovalevskaya's top: its integral is new
    case = family("kovalevskaya-diagonal-torque")
    others = CatalogIndex.of(
        c
        for c in catalog_cases()
        if c.id in ("lagrange-1788-heavy-top", "euler-1765-free-rigid-body")
    )
    found = discover(
        case, search_options(case, degree=4, free=("t1", "t2", "t3")), budget=600, catalog=others
    )
    (point,) = found.special
    assert point.same_as == () and len(point.new) == 1
    assert "(new)" in statement(found)


def test_a_generated_familys_special_set_is_the_catalog_case_it_was_made_from():
    case = family("kovalevskaya-transformed")
    found = discover(case, search_options(case, degree=4, free=("c",)), catalog=catalog_index())
    (point,) = found.special
    assert point.when == ("c = 1",)
    same = {s.case: s for s in point.same_as}
    assert "K" in same["kovalevskaya-1889-heavy-top"].claims
    moved = dict(same["kovalevskaya-1889-heavy-top"].transformation)
    assert moved["M1"].lstrip("-") == "M3"  # the axes 1 and 3 exchanged, as generated


def test_an_entry_of_wolfs_list_is_rediscovered_and_identified():
    """Wolf and Efimovskaya's set S4 (a Hamiltonian with M3 gamma1 cross terms) at b = 1,
    n3 = 1, m2 = 0, with its condition m1 = b n3 left free: the search finds the set
    m1 = 1, identifies it with the list's entry, and names its quartic K: the claim is
    carried through the entry's normal form at its values (its shift holds b and n3)."""
    case = family("wolf-s4-m1")
    found = discover(
        case,
        search_options(case, degree=4, weights={"M": 1, "gamma": 1}, free=("m1",)),
        catalog=catalog_index(),
    )
    assert found.complete and found.generic.extra == 0
    (point,) = found.special
    assert point.when == ("m1 = 1",)
    (status,) = point.status
    assert status.status == "rediscovered"
    assert status.equals == ("wolf-2003-e3-sokolov-linear:K",)
    same = {s.case: s for s in point.same_as}
    assert dict(same["wolf-2003-e3-sokolov-linear"].values) == {"b": "1", "m2": "0", "n3": "1"}
    assert same["wolf-2003-e3-sokolov-linear"].claims == ("K",)


def test_a_failed_identification_is_in_the_coverage_and_the_search_is_not_complete(
    monkeypatch,
):
    from registry.discovery.identification import identify as module

    def failing(*args, **options):
        raise ArithmeticError("planted")

    monkeypatch.setattr(module, "match", failing)
    case = family("kovalevskaya-diagonal-torque")
    only = CatalogIndex.of(c for c in catalog_cases() if c.id == "kovalevskaya-1889-heavy-top")
    found = discover(
        case, search_options(case, degree=4, free=("t1", "t2", "t3")), budget=600, catalog=only
    )
    (point,) = found.special
    assert point.same_as == ()
    assert not found.complete
    assert any(
        "could not compare 1 catalog cases: kovalevskaya-1889-heavy-top" in line
        for line in found.coverage
    )


def test_a_budget_spent_identifying_keeps_the_sets_found_and_says_where_it_ran_out(monkeypatch):
    import time

    from registry.discovery.identification import identify as module

    def slow(*args, **options):
        time.sleep(120)

    monkeypatch.setattr(module, "match", slow)
    case = family("kovalevskaya-diagonal-torque")
    only = CatalogIndex.of(c for c in catalog_cases() if c.id == "kovalevskaya-1889-heavy-top")
    found = discover(
        case, search_options(case, degree=4, free=("t1", "t2", "t3")), budget=20, catalog=only
    )
    (point,) = found.special
    assert point.when == ("t1 = 0", "t2 = 0", "t3 = 0") and point.same_as == ()
    assert not found.complete
    assert "while identifying the sets found with the catalog" in found.coverage[0]


def test_a_level_set_that_holds_the_free_parameters_is_read_at_each_sets_values():
    # The Casimir of a gyrostat is s + k.gamma: the integral of Sretenskii's gyrostat lives
    # on its zero level. The integral found where k1 = k2 = 0 must be proven on that level
    # set at k1 = k2 = 0 (it was checked with k1, k2 left without values, and failed).
    found = search(
        "goryachev-chaplygin-gyrostat",
        degree=3,
        free=("k1", "k2", "k3"),
        weights={"M": 1, "gamma": 2},
        on=("M1*gamma1 + M2*gamma2 + M3*gamma3 + k1*gamma1 + k2*gamma2 + k3*gamma3 = 0",),
    )
    assert found.complete, found.undecided
    (integral,) = where(found)[("k1 = 0", "k2 = 0")]
    sretenskii = "(M3 - k3)*(M1**2 + M2**2) - 4*M1*gamma3"
    assert sp.expand(sp.sympify(integral) - sp.sympify(sretenskii)) == 0
    assert set(where(found)) == {("k1 = 0", "k2 = 0")}


def test_a_set_whose_integral_is_a_product_with_cancelling_leading_parts_is_not_special():
    # Within the axially symmetric set, where the cubic terms vanish, the Casimir drops to
    # degree 4 and a degree-3 integral appears that is a polynomial in the set's integral
    # and the known ones (leading parts cancel): counted degree by degree it looked new.
    found = search(
        "lagrange-axial-torque",
        degree=4,
        free=("p11", "p22", "p33", "k3", "c113", "c223"),
        weights={"M": 1, "gamma": 2},
    )
    assert found.complete, found.undecided
    (symmetric,) = where(found).items()
    assert symmetric[0] == ("p11 = p22", "c113 = c223")
    (integral,) = symmetric[1]
    assert sp.expand(sp.sympify(integral) - sp.sympify("M3 - c223*gamma3**2 - p22*gamma3")) == 0


def test_a_family_given_by_its_equations_is_searched_at_its_special_values():
    """Lorenz's system with sigma, r, b free, degree 2: at sigma = 0, dx/dt = 0 and x is
    an integral. The set is searched with sigma put into the equations (before, the field
    kept sigma, and the set was left "not searched", the search incomplete); no other
    values carry an integral of degree <= 2."""
    found = search("lorenz", degree=2, free=("sigma", "r", "b"))
    assert found.complete and not any("not searched" in c for c in found.coverage)
    assert where(found) == {("sigma = 0",): ("x",)}
    assert found.generic.extra == 0
