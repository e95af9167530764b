"""Every case of the seed catalog loads and the audit says what the reference paper says."""

from functools import cache
from pathlib import Path

import pytest

from registry import Verdict, audit_case, load_case
from tests.helpers.samples import SEED_FILES

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"

#: The reference paper's statements (Sec. 4), and classical results: case id ->
#: (jacobi, {claim label: (integral, casimir)}). energy, c1 and hamiltonian hold everywhere.
V, R = Verdict.VERIFIED, Verdict.REFUTED
EXPECTED = {
    "zhukovsky-gyrostat": (V, {"area": (V, V)}),
    "grioli-1957-charged-body": (V, {"area": (V, V)}),
    "pleshakov-2007-generalized-grioli": (V, {"area": (V, V)}),
    "affine-nonsymmetric": (R, {"area": (R, R)}),
    "yehia-2003-cyclic": (V, {"cyclic": (V, V)}),
    "yehia-2003-kovalevskaya-a": (V, {"I2": (V, V)}),
    "yehia-2003-kovalevskaya-b": (V, {"I2": (R, R)}),
    "bcc-yehia-b-corrected-casimir": (V, {"C": (V, V)}),
    "bcc-yehia-b-corrected-torque": (V, {"I2": (V, V)}),
    "a-s-family": (V, {"C": (V, V)}),
    "axis-torque": (V, {"C": (V, V)}),
    "borisov-mamaev-1997": (V, {"C": (V, V)}),
    # the paper's general statements, for arbitrary functions
    "bcc-family-psi-grad-phi": (V, {"C": (V, V)}),
    "bcc-family-a-s": (V, {"C": (V, V)}),
    "bcc-family-axis": (V, {"C": (V, V)}),
    # classical: the cubic integral holds on s = 0 only, and is no Casimir
    "goryachev-chaplygin-1900": (V, {"K": (V, R)}),
}


def case_files():
    """Every case file of the seed catalog (the literature catalog in the sub-folders has
    its own test, ``test_literature``)."""
    return SEED_FILES


def test_every_expected_case_has_a_file_and_every_file_is_expected():
    stems = [p.stem for p in case_files()]
    assert len(stems) == len(set(stems))
    assert set(EXPECTED) == set(stems)


@cache
def audited(path: Path):
    case = load_case(path)
    return case, audit_case(case)


@pytest.mark.parametrize("path", case_files(), ids=lambda p: p.stem)
def test_case_loads_and_audits(path):
    case, audit = audited(path)
    assert case.id == path.stem
    assert case.source.citation
    for name in ("energy", "c1", "hamiltonian"):
        assert audit.result(name).verdict is Verdict.VERIFIED, name
    assert all(r.verdict is not Verdict.ERROR for r in audit.results), [
        r.reason for r in audit.results if r.verdict is Verdict.ERROR
    ]
    assert case.id in EXPECTED, f"{case.id}: state its expected verdicts in EXPECTED"
    jacobi, claims = EXPECTED[case.id]
    assert audit.result("jacobi").verdict is jacobi
    assert {c.label for c in case.claims} == set(claims)
    for label, (integral, casimir) in claims.items():
        assert audit.result("integral", label).verdict is integral, label
        assert audit.result("casimir", label).verdict is casimir, label


@pytest.mark.parametrize("path", case_files(), ids=lambda p: p.stem)
def test_refutations_carry_a_witness_and_the_residual(path):
    _, audit = audited(path)
    for r in audit.results:
        if r.verdict is Verdict.REFUTED:
            assert r.witness is not None and r.witness.point, r
            assert r.residual, r
            assert r.witness.approx not in ("0", "0.0")
