"""What a search knows of a system (``registry/discovery/known.py``): H and the bracket's
Casimirs, each proven before it counts, and the case's claims that the audit proves."""

from __future__ import annotations

from registry.discovery.known import known_integrals, verified_claims
from registry.discovery.search import _system, search_options
from registry.language.casefile import load_case, parse_case_text
from registry.mathematics.case_mechanics import CaseMechanics
from tests.helpers.samples import CASES

WRONG = """id = "wrong-claim"
title = "Lagrange's top with one true and one false claim"
[source]
citation = "test"
[parameters]
z0 = "real"
[system]
inertia = ["1", "1", "2"]
potential = "z0*gamma3"
[[claims]]
label = "M3"
kind = "integral"
expression = "M3"
[[claims]]
label = "M1"
kind = "integral"
expression = "M1"
"""


def test_the_known_integrals_are_h_and_the_casimirs_that_hold():
    m = CaseMechanics(load_case(CASES / "zhukovsky-gyrostat.toml"))
    names = [name for name, _ in known_integrals(m)]
    assert names[0] == "H" and "gamma1**2 + gamma2**2 + gamma3**2" in names
    assert len(names) == 3  # and the gyrostat's Casimir (M + k).gamma


def test_only_the_claims_the_audit_proves_are_known():
    case = parse_case_text(WRONG)
    m = CaseMechanics(case)
    system = _system(search_options(case, degree=2), m, [])[0]
    assert [k.name for k in verified_claims(case, system)] == ["M3"]


def test_a_bracket_of_its_own_has_its_quadratic_casimirs_known():
    """Ryabov's two-field Kowalevski top on (M, alpha, beta): |alpha|^2, alpha.beta and
    |beta|^2 are Casimirs of its bracket, known to the search like |gamma|^2 on e(3), so
    the one extra integral of degree 4 is the Kowalevski-type quartic alone."""
    case = load_case(CASES / "two-fields" / "ryabov-2014-two-field-kowalevski-top.toml")
    names = [name for name, _ in known_integrals(CaseMechanics(case))]
    assert names == [
        "H",
        "alpha1**2 + alpha2**2 + alpha3**2",
        "alpha1*beta1 + alpha2*beta2 + alpha3*beta3",
        "beta1**2 + beta2**2 + beta3**2",
    ]
    from registry.discovery.search import discover

    found = discover(case, search_options(case, degree=4))
    assert found.complete and found.generic.extra == 1
    assert all(s.new for s in found.generic.status)
