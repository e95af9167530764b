"""The search runs in the ring the system lives in: inverses of the denominator factors of
its equations of motion and square roots, with their relations.

Literature: Goryachev (1916), the cubic integral of A = B = 4C with the potential
a gamma1 + b/gamma3^2 on s = 0, which has b M3/gamma3^2; its gyrostat (Borisov and
Mamaev 2002) on s + k gamma3 = 0; Yehia's (2003) case b, with sqrt(gamma1^2 + gamma2^2).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import sympy as sp

from registry.discovery.ring import NotInRingError, SystemRing
from registry.discovery.search import discover, search_options
from registry.discovery.survey import searched, stated_options
from registry.language.casefile import load_case
from registry.language.parser import Namespace, parse_expression
from registry.mathematics import mechanics as mech

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "data" / "cases"
FAMILIES = ROOT / "tests" / "data" / "families"


@pytest.mark.parametrize(
    ("path", "on"),
    [
        ("heavy-top/goryachev-1916-heavy-top.toml", "s = 0"),
        ("gyrostat/borisov-2002-goryachev-chaplygin-gyrostat.toml", "s + k*gamma3 = 0"),
    ],
)
def test_goryachevs_rational_integral_is_found_and_named_as_the_printed_one(path, on):
    case = load_case(CASES / path)
    search = discover(case, search_options(case, degree=3, on=[on]))
    assert search.complete
    (integral,) = search.generic.integrals
    assert "/gamma3**2" in integral
    (status,) = search.generic.status
    assert (status.status, status.equals) == ("rediscovered", ("K",))


def test_a_planted_rational_integral_is_found_exactly_where_it_is():
    """A = B = 1, C = 1/lam with a gamma1 + b/gamma3^2: Goryachev's condition A = B = 4C
    is lam = 4, the only special value on s = 0, with its rational integral."""
    case = load_case(FAMILIES / "goryachev-1916-lam.toml")
    search = discover(case, search_options(case, degree=3, on=["s = 0"], free=["lam"]))
    assert search.complete and search.generic.extra == 0
    (special,) = search.special
    assert special.when == ("lam = 4",)
    (integral,) = special.integrals
    expected = mech.M3 * (mech.M1**2 + mech.M2**2) - mech.M1 * mech.gamma3
    b = case.parameters["b"]
    found = parse_expression(integral, Namespace(case.parameters, case.functions))
    assert sp.expand(found - expected - 2 * b * mech.M3 / mech.gamma3**2) == 0


@pytest.mark.parametrize(
    "name",
    ["yehia-2003-kovalevskaya-b", "bcc-yehia-b-corrected-torque", "bcc-yehia-b-corrected-casimir"],
)
def test_the_radical_cases_are_searched_and_decided(name):
    case = load_case(CASES / f"{name}.toml")
    for search in searched([(case, o) for o in stated_options(case)], budget=120):
        assert search.decided and search.complete, search.coverage


def test_the_radical_is_a_variable_with_its_relation():
    rho = sp.sqrt(mech.gamma1**2 + mech.gamma2**2)
    ring = SystemRing([1 / rho, mech.M1 / rho**3], (1, 1, 1, 2, 2, 2), bound_from=[1 / rho])
    kinds = [a.kind for a in ring.adjoined]
    assert kinds == ["root", "root_inverse"]
    root, inverse = ring.adjoined
    assert ring.lift(rho**3) == sp.expand(root.symbol**3)
    assert ring.lower(ring.lift(mech.M1 / rho**3)) == mech.M1 / rho**3
    assert root.symbol**2 - (mech.gamma1**2 + mech.gamma2**2) in ring.relations()


def test_an_arbitrary_function_family_is_refused_with_the_reason():
    case = load_case(CASES / "bcc-family-axis.toml")
    (search,) = searched([(case, stated_options(case)[0])], budget=60)
    assert not search.decided
    assert "arbitrary function(s) U" in search.coverage[0]
    with pytest.raises(NotInRingError, match="transcendental function cos"):
        SystemRing([sp.cos(mech.gamma3)], (1, 1, 1, 2, 2, 2))


def test_hess_level_set_whose_basis_divides_by_a_parameter_is_searched():
    """Hess's relation x0 M1 + z0 M3 = 0: its basis divides by x0, which the case
    declares nonzero; the level set is searched (and is invariant under Hess's
    condition), where it was refused before."""
    case = load_case(CASES / "heavy-top" / "hess-1890-heavy-top.toml")
    search = discover(case, search_options(case, degree=2, on=["x0*M1 + z0*M3 = 0"]))
    assert search.decided and search.complete


def test_a_level_set_dividing_by_a_parameter_is_split_into_both_cases():
    """a*M3 = 0 with a real: a != 0 is M3 = 0 (Lagrange's top there: nothing beyond the
    known integrals), a = 0 the free symmetric top, searched as a case of its own on the
    whole phase space, where M3 is extra (|M|^2 = 2 H + (1 - 1/c3) M3^2 is not)."""
    case = load_case(FAMILIES / "lagrange-a-real.toml")
    search = discover(case, search_options(case, degree=2, on=["a*M3 = 0"]))
    assert search.complete and search.generic.extra == 0
    (free_top,) = search.special
    assert free_top.when == ("a = 0",) and free_top.integrals == ("M3",)


def test_a_search_never_draws_sympys_randomised_factoring(monkeypatch):
    """Gaire's Chaplygin ball: sympy's multivariate factoring (Wang's method) draws
    random evaluation points, and on this field's denominator it took 0.03 s in one
    process and minutes in another, so a search's budget held in one run and not the
    next. The ring and the ansatz factor by FLINT: sympy's is never reached."""
    import sympy.polys.factortools as factortools

    def refuse(*args, **kwargs):
        raise AssertionError("sympy's randomised multivariate factoring was called")

    monkeypatch.setattr(factortools, "dmp_zz_wang", refuse)
    case = load_case(CASES / "nonholonomic" / "gaire-2025-chaplygin-ball-code.toml")
    search = discover(case, search_options(case, degree=2))
    assert search.decided
    assert any("M1*gamma1 + M2*gamma2 + M3*gamma3" in i for i in search.generic.integrals)
