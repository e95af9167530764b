"""Zero testing: probes refute with checked witnesses, proofs are complete for their class."""

import sympy as sp

from registry.mathematics import zero_test
from registry.mathematics.certified_evaluation import evaluate
from registry.mathematics.domain import Domain
from registry.mathematics.mechanics import AXIS, M1, M2, S_VALUE, gamma1, gamma2, gamma3, s
from registry.mathematics.zero_test import decide
from registry.model import Verdict

k = sp.Symbol("k", positive=True)
DOMAIN = Domain(parameters=(k,))
SPHERE = gamma1**2 + gamma2**2 + gamma3**2 - 1


def test_identical_zero_is_verified_without_work():
    result = decide({"r": sp.Integer(0)}, DOMAIN)
    assert result.verdict is Verdict.VERIFIED
    assert result.method == "identically zero"


def test_equal_radicals_written_differently_are_not_refuted():
    x, y = gamma1, gamma2
    r = sp.sqrt((x + y) ** 2 + 1) - sp.sqrt(x**2 + 2 * x * y + y**2 + 1)
    result = decide({"r": r}, DOMAIN)
    assert result.verdict is Verdict.VERIFIED


def test_s_is_the_product_m_gamma():
    assert decide({"r": s - S_VALUE}, DOMAIN).verdict is Verdict.VERIFIED


def test_a_nonzero_residual_is_refuted_with_a_checked_witness():
    r = k * gamma1 * sp.sqrt(gamma1**2 + gamma2**2) - gamma3
    result = decide({"r": r}, DOMAIN)
    assert result.verdict is Verdict.REFUTED
    w = result.witness
    point = {sp.Symbol(n, real=True): sp.sympify(v) for n, v in w.point.items() if n != "k"}
    point[k] = sp.sympify(w.point["k"])
    # re-evaluate independently with sympy at 30 digits
    assert abs(sp.N(r.xreplace(point), 30)) > 0
    assert evaluate(r, point).text() == w.value


def test_parameters_respect_their_assumptions():
    # k is positive: sqrt(k**2) - k is zero on the domain, though not for real k
    assert decide({"r": sp.sqrt(k**2) - k}, DOMAIN).verdict is Verdict.VERIFIED
    n = sp.Symbol("n", integer=True, nonzero=True)
    result = decide({"r": k * n - gamma1}, Domain(parameters=(k, n)))
    assert result.verdict is Verdict.REFUTED
    assert sp.Rational(result.witness.point["k"]) > 0
    assert sp.Rational(result.witness.point["n"]).q == 1 and result.witness.point["n"] != "0"


def test_level_sets_restrict_the_question():
    residual = gamma1**2 + gamma2**2 + gamma3**2 - 1
    assert decide({"r": residual}, DOMAIN).verdict is Verdict.REFUTED
    on_sphere = decide({"r": residual}, DOMAIN.restricted([SPHERE]))
    assert on_sphere.verdict is Verdict.VERIFIED and on_sphere.method == "level-set reduction"
    off = decide({"r": gamma3**2 - 1 + gamma1**2}, DOMAIN.restricted([SPHERE]))
    assert off.verdict is Verdict.REFUTED


def test_witnesses_on_level_sets_lie_on_the_set():
    on = [SPHERE, s]
    result = decide({"r": gamma1 * s + gamma2}, DOMAIN.restricted(on))
    assert result.verdict is Verdict.REFUTED
    point = {sp.Symbol(n, real=True): sp.sympify(v) for n, v in result.witness.point.items()}
    assert sp.simplify(SPHERE.xreplace(point)) == 0
    assert sp.simplify(S_VALUE.xreplace(point)) == 0


def test_transcendental_identities_with_branch_cuts_are_decided_correctly():
    # atan(x) + atan(1/x) = pi/2 only for x > 0: refuted, with an interval witness
    r = sp.atan(gamma1) + sp.atan(1 / gamma1) - sp.pi / 2
    result = decide({"r": r}, DOMAIN)
    assert result.verdict is Verdict.REFUTED and result.method == "interval probe"


def test_sine_and_cosine_of_one_argument_are_related_in_the_normal_form():
    r = sp.sin(gamma1) ** 2 + sp.cos(gamma1) ** 2 - 1
    assert decide({"r": r}, DOMAIN).method == "algebraic normal form"
    r = sp.tan(gamma1) * sp.cos(gamma1) ** 3 + sp.sin(gamma1) ** 3 - sp.sin(gamma1)
    assert decide({"r": r}, DOMAIN).verdict is Verdict.VERIFIED
    r = sp.cosh(gamma1) ** 2 - sp.sinh(gamma1) ** 2 - 1
    assert decide({"r": r}, DOMAIN).verdict is Verdict.VERIFIED
    r = sp.cosh(gamma1) ** 2 + sp.sinh(gamma1) ** 2 - 1  # not an identity
    assert decide({"r": r}, DOMAIN).verdict is Verdict.REFUTED


def test_a_trigonometric_level_set_is_reduced_with_its_relation():
    # on sin(g1) M1 = cos(g1) M2, M1 sin(g1)**2 - M2 sin(g1) cos(g1) vanishes; the proof needs
    # the level set, and the level set needs sin**2 + cos**2 = 1 for the second residual
    on = DOMAIN.restricted([sp.sin(gamma1) * M1 - sp.cos(gamma1) * M2])
    r = M1 * sp.sin(gamma1) ** 2 - M2 * sp.sin(gamma1) * sp.cos(gamma1)
    assert decide({"r": r}, on).verdict is Verdict.VERIFIED
    r2 = M1 - M1 * sp.cos(gamma1) ** 2 - M2 * sp.sin(gamma1) * sp.cos(gamma1)
    assert decide({"r": r2}, on).method == "level-set reduction"


def test_identities_outside_the_normal_forms_fall_back_to_simplify():
    r = sp.sin(2 * gamma1) - 2 * sp.sin(gamma1) * sp.cos(gamma1)  # two arguments
    result = decide({"r": r}, DOMAIN)
    assert result.verdict is Verdict.VERIFIED and result.method == "simplify"


def test_a_residual_that_only_probes_say_is_zero_is_inconclusive(monkeypatch):
    monkeypatch.setattr(zero_test, "SIMPLIFY_LIMIT", 0)  # no last resort
    r = sp.sin(2 * gamma1) - 2 * sp.sin(gamma1) * sp.cos(gamma1)
    result = decide({"r": r}, DOMAIN)
    assert result.verdict is Verdict.INCONCLUSIVE
    assert result.reason == "vanishes at 4 random points; no symbolic proof"


def test_families_are_refuted_with_concrete_functions():
    phi = sp.Function("phi")
    domain = Domain(functions={"phi": (phi, AXIS)})
    r = sp.diff(phi(*AXIS), gamma1) - sp.diff(phi(*AXIS), gamma2)
    result = decide({"r": r}, domain)
    assert result.verdict is Verdict.REFUTED
    assert "phi(gamma1, gamma2, gamma3)" in result.witness.functions
    # and a true family identity (mixed partials commute) is proven
    ok = sp.diff(phi(*AXIS), gamma1, gamma2) - sp.diff(phi(*AXIS), gamma2, gamma1)
    assert decide({"r": ok}, domain).verdict is Verdict.VERIFIED


def test_a_remembered_proof_holds_only_on_its_own_level_set():
    """Proofs are remembered by residual, level set, shorthands and state: a residual
    proven zero on the sphere is not taken as proven off it (nor with s another name)."""
    zero_test._proven.cache_clear()
    r = (gamma1**2 + gamma2**2 + gamma3**2) * M1 - M1
    on_sphere = decide({"r": r}, DOMAIN.restricted([SPHERE]))
    assert on_sphere.verdict is Verdict.VERIFIED
    assert on_sphere.method == "level-set reduction"
    assert decide({"r": r}, DOMAIN).verdict is Verdict.REFUTED
    again = decide({"r": r}, DOMAIN.restricted([SPHERE]), seed=7)
    assert (again.verdict, again.method) == (Verdict.VERIFIED, "level-set reduction")
    assert zero_test._proven.cache_info().hits >= 1  # the second proof was remembered
    # asked directly (the probes above refute before any proof is sought off the sphere)
    shorthands, state = tuple(DOMAIN.shorthands.items()), DOMAIN.state
    assert zero_test._proven(r, (SPHERE,), shorthands, state) == "level-set reduction"
    assert zero_test._proven(r, (), shorthands, state) is None
    # the same residual in s: proven with s = M . gamma, not with s standing for M1
    t = s - S_VALUE
    assert decide({"t": t}, DOMAIN).verdict is Verdict.VERIFIED
    other = Domain(parameters=(k,), shorthands={s: M1})
    assert decide({"t": t}, other).verdict is Verdict.REFUTED
