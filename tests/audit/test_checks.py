"""The checks: each registered with its cost and a one-line statement, each returning a
CheckResult (never a bare bool), runnable alone on one case."""

from __future__ import annotations

from registry import Verdict, load_case
from registry.audit import checks
from registry.audit.checks import CHECKS
from registry.language.parser import Namespace, parse_expression
from registry.mathematics.case_mechanics import CaseMechanics
from registry.mathematics.mechanics import M1, M2, M3, gamma1, gamma2, gamma3, s
from registry.model import CheckResult
from tests.helpers.samples import AFFINE, YEHIA_B, ZHUKOVSKY, case_file


def test_every_check_is_registered_with_a_statement_and_a_cost():
    assert list(CHECKS) == [
        "jacobi",
        "energy",
        "c1",
        "hamiltonian",
        "invariant",
        "integral",
        "casimir",
        "measure",
        "relation",
    ]
    for spec in CHECKS.values():
        assert spec.statement and "\n" not in spec.statement
        assert spec.cost in ("cheap", "expensive")
    assert [n for n, spec in CHECKS.items() if spec.per_claim] == [
        "invariant",
        "integral",
        "casimir",
        "measure",
        "relation",
    ]


def test_a_check_runs_alone_on_one_case_and_returns_a_result():
    m = CaseMechanics(load_case(case_file(ZHUKOVSKY)))
    result = checks.energy(m)
    assert isinstance(result, CheckResult)
    assert (result.check, result.verdict, result.claim) == ("energy", Verdict.VERIFIED, None)
    assert result.method and result.seconds >= 0
    claim = m.case.claims[0]
    assert checks.casimir(m, claim).claim == claim.label


def test_a_refutation_carries_a_readable_residual_and_its_witness():
    case = load_case(case_file(YEHIA_B))
    m = CaseMechanics(case)
    result = checks.casimir(m, case.claim("I2"))
    assert result.verdict is Verdict.REFUTED
    assert result.witness is not None and result.witness.component.startswith("Pi grad[")
    # the residual is written in the case-file language, so it can be pasted into a case
    ns = Namespace(case.parameters, case.functions)
    assert parse_expression(result.residual, ns) != 0


def test_a_broken_jacobi_identity_is_refuted():
    m = CaseMechanics(load_case(case_file(AFFINE)))
    assert checks.jacobi(m).verdict is Verdict.REFUTED


def test_the_invariance_of_a_level_set_applies_only_to_claims_on_one():
    case = load_case(case_file("goryachev-chaplygin-1900"))
    spec = CHECKS["invariant"]
    assert [c.label for c in case.claims if spec.applies(c)] == [
        c.label for c in case.claims if c.on
    ]
    m = CaseMechanics(case)
    on_set = next(c for c in case.claims if c.on)
    assert checks.invariant(m, on_set) is checks.invariant(m, on_set)  # computed once


def test_residuals_are_shown_with_s_expanded_and_factored():
    assert checks.readable(s * gamma1 - M1 * gamma1**2) == gamma1 * (M2 * gamma2 + M3 * gamma3)


def test_a_remembered_residual_is_shown_for_its_own_shorthands_only():
    """``readable`` remembers its results by expression and shorthands: the same residual
    under another case's shorthands (s standing for another expression) is shown anew."""
    residual = s * gamma1
    paper = checks.readable(residual)
    assert checks.readable(residual) is paper  # remembered
    other = checks.readable(residual, {s: M1})
    assert other == M1 * gamma1
    assert paper == checks.readable(residual, {s: M1 * gamma1 + M2 * gamma2 + M3 * gamma3})
    assert paper != other
