"""Numerical evidence agrees with the symbolic verdicts, and disagreements are reported."""

import json
from dataclasses import replace

import pytest
import sympy as sp
from click.testing import CliRunner

import registry
from registry import Verdict, load_case
from registry.audit import numeric_evidence
from registry.audit.numeric_evidence import (
    DEPARTURE_TOL,
    DISAGREE_FACTOR,
    RUNS,
    Drift,
    claim_drift,
)
from registry.cli import main
from registry.execution.time_budget import TimeBudget
from registry.mathematics import mechanics as mech
from registry.mathematics.case_mechanics import CaseMechanics
from registry.mathematics.sampling import sample_points
from tests.helpers.samples import CASES, CLASSICAL, LEVEL_SETS


def test_yehia_b_I2_drifts_orders_of_magnitude_above_h():
    case = load_case(CASES / "yehia-2003-kovalevskaya-b.toml")
    d = claim_drift(CaseMechanics(case), case.claim("I2"))
    assert d.runs >= 2
    assert d.drift > 1e3 * d.floor
    assert d.drift > 1e-2
    assert not d.contradicts(Verdict.REFUTED)
    assert d.contradicts(Verdict.VERIFIED)


@pytest.mark.parametrize(
    "case_id",
    [
        "zhukovsky-gyrostat",
        "yehia-2003-kovalevskaya-a",
        "borisov-mamaev-1997",
        "goryachev-chaplygin-1900",
    ],
)
def test_true_claims_stay_at_the_noise_floor(case_id):
    case = load_case(CASES / f"{case_id}.toml")
    d = claim_drift(CaseMechanics(case), case.claims[0])
    assert d.runs >= 2
    assert d.drift < 1e-7
    assert not d.contradicts(Verdict.VERIFIED)


def test_a_planted_disagreement_is_reported_and_fails_strict(tmp_path, monkeypatch):
    def lying(m, claim, seed=0, runs=3, **_):  # a "verified" claim that drifts
        return Drift(claim.label, 1.0, 1e-12, runs)

    monkeypatch.setattr(numeric_evidence, "claim_drift", lying)
    db = tmp_path / "r.sqlite"
    with registry.open(db) as reg:
        reg.add(CASES / "zhukovsky-gyrostat.toml")
    runner = CliRunner()
    result = runner.invoke(main, ["--db", str(db), "audit", "--strict", "--jobs", "1"])
    assert result.exit_code == 1
    assert "DISAGREEMENT zhukovsky-gyrostat/area" in result.stdout
    assert "Error: numerical evidence contradicts the verdict of zhukovsky-gyrostat/area" in (
        result.stderr
    )
    with registry.open(db) as reg:
        (audit,) = [a for _, a in reg.store.run_results(1)]
        assert audit.evidence[0].contradicts


def test_evidence_is_stored_and_reused(tmp_path):
    with registry.open(tmp_path / "r.sqlite") as reg:
        reg.add(CASES / "borisov-mamaev-1997.toml")
        first = reg.audit(jobs=1, numeric=True)
        second = reg.audit(jobs=1, numeric=True)
        assert first.audits[0].evidence == second.audits[0].evidence
        assert reg.runs().set_index("run").loc[second.run, "n_reused"] > 0


@pytest.mark.parametrize("path", sorted(CASES.glob("*.toml")), ids=lambda p: p.stem)
def test_numbers_and_symbolic_verdicts_agree_on_every_seed_case(path):
    audit = registry.audit_case(load_case(path), numeric=True)
    assert audit.evidence
    for e in audit.evidence:
        assert e.runs >= 1, e
        assert not e.contradicts, e


def test_plot_command_writes_a_png_and_refuses_unknown_claims(tmp_path):
    db = tmp_path / "r.sqlite"
    with registry.open(db) as reg:
        reg.add(CASES / "borisov-mamaev-1997.toml")
    runner = CliRunner()
    out = tmp_path / "c.png"
    ok = runner.invoke(main, ["--db", str(db), "plot", "borisov-mamaev-1997", "C", "-o", str(out)])
    assert ok.exit_code == 0 and out.read_bytes().startswith(b"\x89PNG")
    bad = runner.invoke(main, ["--db", str(db), "plot", "borisov-mamaev-1997", "K"])
    assert bad.exit_code == 1
    assert "Error: case 'borisov-mamaev-1997' has no claim 'K'" in bad.stderr


def test_code_is_generated_only_for_state_numbers_and_language_functions():
    from registry.audit.numeric_evidence import _only_numeric

    g1, m1 = mech.AXIS[0], mech.MOMENTUM[0]
    _only_numeric([sp.sin(m1) + sp.sqrt(g1) * sp.atan(g1) / 3 + sp.Abs(m1)], mech.STATE)
    with pytest.raises(ValueError, match="unexpected symbols"):
        _only_numeric([g1 + sp.Symbol("os")], mech.STATE)
    with pytest.raises(ValueError, match="unexpected function"):
        _only_numeric([sp.Function("system")(g1)], mech.STATE)


# --- the comparison rules (issue "evidence that never cries wolf") ---------------------


def classical(name: str) -> registry.Case:
    return load_case(CLASSICAL / f"{name}.toml")


V, R = Verdict.VERIFIED, Verdict.REFUTED
#: The classical test catalog as the literature decides it: file -> {claim: (integral, casimir)}.
#: Mis-stated claims are there on purpose: a true integral claimed as a Casimir, an integral
#: without the level set it needs, a sign or a term wrong, unit-sphere forms off the sphere.
CLASSICAL_EXPECTED = {
    "free-top": {
        "H": (V, R), "M2-as-casimir": (V, R), "M2": (V, R), "area": (V, V), "M1-false": (R, R)
    },
    "lagrange-top": {"M3": (V, R), "M3-as-casimir": (V, R), "M1-false": (R, R)},
    "kovalevskaya-top": {"K": (V, R), "K-as-casimir": (V, R), "K-sign": (R, R)},
    "goryachev-chaplygin-top": {"K": (V, R), "K-as-casimir": (V, R), "K-everywhere": (R, R)},
    "chaplygin-kirchhoff": {
        "K": (V, R), "K-sphere-form": (R, R), "K-sphere-form-on-sphere": (V, R)
    },
    "clebsch": {"F": (V, R), "F-as-casimir": (V, R), "F-sign": (R, R)},
    "zhukovsky-volterra-gyrostat": {
        "M-plus-k": (V, R), "area": (V, V), "M-false": (R, R), "area-no-k": (R, R)
    },
}  # fmt: skip


def true_integrals() -> list[tuple[str, str]]:
    """(file, claim) of every true integral of the classical test catalog that is no Casimir,
    stated without a level set."""
    return [
        (name, label)
        for name, claims in CLASSICAL_EXPECTED.items()
        for label, verdicts in claims.items()
        if verdicts == (V, R) and not classical(name).claim(label).on
    ]


def audited_claim(case, claim):
    audit = registry.audit_case(replace(case, claims=(claim,)), numeric=True)
    (evidence,) = audit.evidence
    return audit.result("integral", claim.label), audit.result("casimir", claim.label), evidence


@pytest.mark.parametrize("name,label", true_integrals())
def test_a_true_integral_stated_as_a_casimir_is_refuted_as_casimir_and_the_numbers_agree(
    name, label
):
    case = classical(name)
    claim = replace(case.claim(label), kind=registry.ClaimKind.CASIMIR)
    integral, casimir, evidence = audited_claim(case, claim)
    assert integral.verdict is Verdict.VERIFIED
    assert casimir.verdict is Verdict.REFUTED
    assert evidence.compared_with == "integral"
    assert evidence.runs >= 2 and not evidence.contradicts, evidence
    assert evidence.drift < 1e-7  # conserved: flat, which no Casimir refutation can explain


@pytest.mark.parametrize("name,label", true_integrals())
def test_a_perturbed_true_integral_is_refuted_and_the_numbers_agree(name, label):
    """One term of the integral gets a factor 1 + gamma1/3 (a mutation that is never a mere
    rescaling, also for one-term integrals such as M3)."""
    case = classical(name)
    claim = case.claim(label)
    expr = claim.expression.expr
    state = {*mech.STATE, mech.s}
    term = [t for t in sp.Add.make_args(sp.expand(expr)) if t.free_symbols & state][-1]
    changed = expr + term * mech.AXIS[0] / 3
    mutated = replace(claim, expression=registry.model.Expression(str(changed), changed))
    integral, _, evidence = audited_claim(case, mutated)
    assert integral.verdict is Verdict.REFUTED
    assert evidence.runs >= 2
    assert evidence.drift > DISAGREE_FACTOR * evidence.floor
    assert not evidence.contradicts


def test_a_claim_in_unit_sphere_form_on_s_zero_is_refuted_there_and_the_numbers_agree():
    case = classical("chaplygin-kirchhoff")
    claim = case.claim("K-sphere-form")
    assert [eq.text for eq in claim.on] == ["s = 0"]
    integral, _, evidence = audited_claim(case, claim)
    assert integral.verdict is Verdict.REFUTED
    assert not evidence.contradicts
    assert evidence.drift > DISAGREE_FACTOR * evidence.floor  # |gamma| is not 1 off the sphere
    # on the smaller set s = 0, |gamma| = 1 the same expression is conserved: had the numbers
    # been taken there (the old default), a flat drift would have contradicted "refuted"
    on_sphere = case.claim("K-sphere-form-on-sphere")
    assert sp.simplify(on_sphere.expression.expr - claim.expression.expr) == 0
    flat = claim_drift(CaseMechanics(case), on_sphere)
    assert flat.drift < 1e-7 and flat.contradicts(Verdict.REFUTED)


def test_numbers_on_one_instance_of_a_family_cannot_contradict_a_refutation():
    case = load_case(CASES / "bcc-family-psi-grad-phi.toml")
    d = claim_drift(CaseMechanics(case), case.claims[0])
    assert "one instance of the family's arbitrary functions" in d.narrowed
    assert d.drift < 1e-7  # the family's Casimir is conserved for this instance
    assert not d.contradicts(Verdict.REFUTED)  # refuted elsewhere is still possible
    assert replace(d, narrowed="").contradicts(Verdict.REFUTED)
    assert not d.contradicts(Verdict.VERIFIED)


@pytest.mark.slow  # integrates trajectories for every claim of the catalog: over a minute loaded
def test_strict_audit_of_the_classical_catalog_passes_with_every_claim_decided(tmp_path):
    db = tmp_path / "r.sqlite"
    with registry.open(db) as reg:
        reg.add(CLASSICAL)
    result = CliRunner().invoke(main, ["--db", str(db), "audit", "--strict", "--json"])
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    claims = [c for case in document["cases"] for c in case["claims"]]
    assert len(claims) == sum(map(len, CLASSICAL_EXPECTED.values()))
    decided = {
        (case["case"].removeprefix("test-"), c["label"]): (c["integral"], c["casimir"])
        for case in document["cases"]
        for c in case["claims"]
    }
    expected = {
        (name, label): (str(i), str(c))
        for name, claims in CLASSICAL_EXPECTED.items()
        for label, (i, c) in claims.items()
    }
    assert decided == expected
    for c in claims:
        assert c["numeric"]["agrees"] and c["numeric"]["compared_with"] == "integral", c
        assert c["numeric"]["runs"] >= 2, c


# --- on a level set: departure, projection, scale (issue "numbers that respect invariant
# relations") ----------------------------------------------------------------------------


def level_set_case(name: str) -> registry.Case:
    return load_case(LEVEL_SETS / f"{name}.toml")


def test_a_repelling_invariant_set_is_integrated_on_the_set_and_true_claims_stay_flat():
    case = level_set_case("repelling-s0")
    audit = registry.audit_case(case, numeric=True, budget=None)
    for label in ("s", "H"):
        for check in ("integral", "invariant"):
            assert audit.result(check, label).verdict is V, (check, label)
    assert audit.result("casimir", "s").verdict is V
    found = {e.claim: e for e in audit.evidence}
    for label in ("s", "H"):
        e = found[label]
        assert e.projected and e.runs == RUNS and not e.reason, e
        assert e.departure < 1e-13, e  # back on the set after each step
        assert e.drift < 1e-9 and not e.contradicts, e
    # the same trajectories left alone leave the set: their drift of s is the departure
    # itself, far above the floor, and is not compared with the verdict
    left = claim_drift(CaseMechanics(case), case.claim("s"))
    assert not left.projected and left.departure > DEPARTURE_TOL
    assert left.drift > DISAGREE_FACTOR * left.floor
    assert left.reason.startswith("every trajectory left the claim's set")
    assert not left.contradicts(V)


def test_a_false_claim_on_a_repelling_set_is_refuted_and_drifts_on_the_set():
    case = level_set_case("repelling-s0")
    audit = registry.audit_case(case, numeric=True, budget=None)
    assert audit.result("integral", "M3-false").verdict is R
    assert audit.result("invariant", "M3-false").verdict is V
    (e,) = [e for e in audit.evidence if e.claim == "M3-false"]
    assert e.projected and e.departure < 1e-13 and not e.reason
    assert e.drift > DISAGREE_FACTOR * e.floor and not e.contradicts, e


def test_an_attracting_invariant_set_keeps_its_trajectories_as_it_is():
    case = level_set_case("attracting-s0")
    m = CaseMechanics(case)
    for label in ("s", "H"):
        d = claim_drift(m, case.claim(label))  # not projected: nothing leaves
        assert not d.projected and d.runs == RUNS and not d.reason
        assert d.departure < DEPARTURE_TOL and d.drift < 1e-9
        assert not d.contradicts(V)
    d = claim_drift(m, case.claim("M3-false"))
    assert d.drift > DISAGREE_FACTOR * d.floor and not d.contradicts(R)


def test_strict_passes_on_repelling_and_attracting_sets_with_the_reason_in_the_json(tmp_path):
    db = tmp_path / "r.sqlite"
    with registry.open(db) as reg:  # audited without a clock (a busy machine), then reused
        reg.add(LEVEL_SETS)
        reg.audit(jobs=1, numeric=True, budget=TimeBudget(check=600.0, corrections=600.0))
    result = CliRunner().invoke(main, ["--db", str(db), "audit", "--strict", "--json"])
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    numbers = {
        (case["case"], c["label"]): c["numeric"]
        for case in document["cases"]
        for c in case["claims"]
    }
    assert all(n["agrees"] for n in numbers.values()), numbers
    assert numbers["repelling-s0", "s"]["projected"] is True
    assert numbers["repelling-s0", "s"]["departure"] < 1e-13
    with registry.open(db) as reg:  # stored: the same evidence comes back from the database
        (audit,) = [a for _, a in reg.store.run_results(1) if a.case == "repelling-s0"]
    stored = {e.claim: e for e in audit.evidence}
    assert stored["s"].projected and stored["s"].departure < 1e-13 and not stored["s"].reason


def _large_momenta(m, claim, factor, count=3):
    """Exact points of the claim's set (homogeneous in M) with the momenta scaled up."""
    points = []
    for p in sample_points(m.claim_domain(claim), count, seed=1):
        q = {**p, **{v: p[v] * factor for v in mech.MOMENTUM}}
        q[mech.s] = sp.expand(mech.S_VALUE.xreplace(q))
        points.append(q)
    return points


def test_hess_relation_sampled_at_large_momenta_is_judged_by_the_size_of_its_terms():
    case = load_case(CASES / "heavy-top" / "hess-1890-heavy-top.toml")
    m = CaseMechanics(case)
    claim = case.claim("hess")
    starts = _large_momenta(m, claim, 150)
    assert max(abs(p[v]) for p in starts for v in mech.MOMENTUM) > 100
    d = claim_drift(m, claim, invariant=V, starts=starts)
    assert d.projected and d.runs == 3 and d.departure < 1e-13
    assert d.drift < 1e-12 and not d.contradicts(V), d  # x0 M1 + z0 M3 vanishes: 0 / 0 terms
    # without Hess's condition on the centre of mass the set is not kept and the relation
    # is refuted: the trajectories are never projected, and the numbers agree
    loose = load_case(CASES / "heavy-top" / "hess-1890-heavy-top-unrestricted.toml")
    audit = registry.audit_case(loose, numeric=True, budget=None)
    assert audit.result("integral", "hess").verdict is R
    assert audit.result("invariant", "hess").verdict is R
    (e,) = audit.evidence
    assert not e.projected and not e.contradicts, e  # the set is not kept: never projected
    assert e.reason.startswith("every trajectory left the claim's set"), e  # so not compared
    assert e.as_dict()["reason"] == e.reason and e.as_dict()["departure"] > DEPARTURE_TOL
