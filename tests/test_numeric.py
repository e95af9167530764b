"""Numerical evidence agrees with the symbolic verdicts, and disagreements are reported."""

from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

import registry
from registry import Verdict, load_case
from registry import mechanics as mech
from registry import numeric as numeric_module
from registry.checks import Mechanics
from registry.cli import main
from registry.numeric import Drift, claim_drift

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"


def test_yehia_b_I2_drifts_orders_of_magnitude_above_h():
    case = load_case(CASES / "yehia-2003-kovalevskaya-b.toml")
    d = claim_drift(Mechanics(case), case.claim("I2"))
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
    d = claim_drift(Mechanics(case), case.claims[0])
    assert d.runs >= 2
    assert d.drift < 1e-7
    assert not d.contradicts(Verdict.VERIFIED)


def test_a_planted_disagreement_is_reported_and_fails_strict(tmp_path, monkeypatch):
    def lying(m, claim, seed=0, runs=3):  # a "verified" claim that drifts
        return Drift(claim.label, 1.0, 1e-12, runs)

    monkeypatch.setattr(numeric_module, "claim_drift", lying)
    db = tmp_path / "r.sqlite"
    with registry.open(db) as reg:
        reg.add(CASES / "zhukovsky-gyrostat.toml")
    runner = CliRunner()
    result = runner.invoke(main, ["--db", str(db), "audit", "--strict", "--jobs", "0"])
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
        first = reg.audit(jobs=0, numeric=True)
        second = reg.audit(jobs=0, numeric=True)
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
    from registry.numeric import _only_numeric

    g1, m1 = mech.AXIS[0], mech.MOMENTUM[0]
    _only_numeric([sp.sin(m1) + sp.sqrt(g1) * sp.atan(g1) / 3 + sp.Abs(m1)])
    with pytest.raises(ValueError, match="unexpected symbols"):
        _only_numeric([g1 + sp.Symbol("os")])
    with pytest.raises(ValueError, match="unexpected function"):
        _only_numeric([sp.Function("system")(g1)])
