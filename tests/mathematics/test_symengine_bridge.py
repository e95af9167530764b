"""The optional symengine path and the pure-sympy fallback give the same results."""

from dataclasses import dataclass

import pytest
import sympy as sp

from registry import Verdict, audit_case, load_case
from registry.mathematics import mechanics as mech
from registry.mathematics import symengine_bridge
from tests.helpers.samples import CASES

C = sp.Symbol("C", positive=True)
g1, g2, g3 = mech.AXIS


@dataclass
class Backend:
    """The backend a test runs on, and how many symengine results came back to sympy."""

    symengine: bool
    calls: int = 0

    def assert_used(self) -> None:
        """symengine did the work under the symengine backend, and never under sympy
        (symengine_bridge.py falls back to sympy silently, so a result alone cannot tell)."""
        if self.symengine:
            assert self.calls > 0, "symengine was never used"
        else:
            assert self.calls == 0, "symengine was used with ENABLED = False"


@pytest.fixture(params=[True, False], ids=["symengine", "sympy"])
def backend(request, monkeypatch):
    if request.param and symengine_bridge.se is None:
        pytest.skip("symengine is not installed")
    monkeypatch.setattr(symengine_bridge, "ENABLED", request.param)
    state = Backend(request.param)
    original = symengine_bridge._back

    def counting_back(result, expr):
        state.calls += 1
        return original(result, expr)

    monkeypatch.setattr(symengine_bridge, "_back", counting_back)
    return state


@pytest.mark.parametrize(
    "expr",
    [
        C * g1 * sp.sqrt(g1**2 + g2**2) + sp.atan(g3 / g1),
        C * (g1 + g2) ** 3 / (g1**2 + g2**2) ** sp.Rational(3, 2) + sp.exp(C * g3),
        mech.s**2 * g3 + sp.log(1 + mech.s**2),
    ],
)
def test_derivatives_and_expansions_agree_with_sympy(backend, expr):
    for v in (g1, g3, mech.s):
        assert sp.simplify(symengine_bridge.diff(expr, v) - sp.diff(expr, v)) == 0
    assert sp.simplify(symengine_bridge.expand(expr) - sp.expand(expr)) == 0
    backend.assert_used()


def test_symbols_keep_their_assumptions(backend):
    d = symengine_bridge.diff(C * g1**2, g1)
    assert d.free_symbols == {C, g1}
    assert next(iter(d.free_symbols - {g1})).is_positive
    backend.assert_used()


def test_families_of_arbitrary_functions_stay_with_sympy(backend):
    phi = sp.Function("phi", real=True)(*mech.AXIS)
    assert symengine_bridge.diff(phi, g1) == sp.Derivative(phi, g1)
    assert backend.calls == 0  # not even under symengine


@pytest.mark.parametrize(
    "case_id", ["yehia-2003-kovalevskaya-b", "affine-nonsymmetric", "bcc-family-a-s"]
)
def test_verdicts_do_not_depend_on_the_backend(backend, case_id):
    case = load_case(CASES / f"{case_id}.toml")
    audit = audit_case(case, corrections=False)
    expected = {
        "yehia-2003-kovalevskaya-b": Verdict.REFUTED,
        "affine-nonsymmetric": Verdict.REFUTED,
        "bcc-family-a-s": Verdict.VERIFIED,
    }[case_id]
    claim = case.claims[0].label
    assert audit.result("casimir", claim).verdict is expected
    assert audit.result("energy").verdict is Verdict.VERIFIED
    backend.assert_used()


def test_partials_are_diff_one_variable_at_a_time(backend):
    """One conversion for every variable gives exactly what ``diff`` gives for each."""
    expr = C * g1 * sp.sqrt(g1**2 + g2**2) * mech.s + sp.atan(g3 / g1)
    variables = (g1, g2, g3, mech.s, C)
    assert symengine_bridge.partials(expr, variables) == tuple(
        symengine_bridge.diff(expr, v) for v in variables
    )
    backend.assert_used()
