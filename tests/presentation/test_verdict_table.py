"""The verdict table, from the audit's outcome objects (the seed catalog's whole table is
pinned by tests/test_golden.py), wrapped to a width, and the table of the verdicts two
runs disagree on."""

from __future__ import annotations

import dataclasses

import pytest

from registry import audit_case, load_case
from registry.audit.case_audit import failed_case
from registry.audit.outcome import outcomes
from registry.model import Evidence, Verdict, VerdictChange
from registry.presentation.verdict_table import diff_table, disagreements, verdict_table
from tests.helpers.samples import YEHIA_B, ZHUKOVSKY, case_file

HEADER = ["claim", "kind", "integral", "casimir", "verdict"]


@pytest.fixture(scope="module")
def audited():
    cases = [load_case(case_file(c)) for c in (YEHIA_B, ZHUKOVSKY)]
    return [audit_case(c) for c in cases], {c.id: c for c in cases}


def test_each_case_heads_its_claims_then_the_summary_and_the_corrections(audited):
    audits, cases = audited
    table = verdict_table(outcomes(audits, cases), run=4).splitlines()
    assert table[0] == "case (torque family; Poisson)"
    assert table[1].split() == HEADER
    heading = table.index(f"{YEHIA_B} (family psi-gamma-grad-phi; Poisson verified)")
    assert table[heading + 1].split() == ["I2", "casimir", "refuted", "refuted", "refuted"]
    assert table[heading + 1].startswith("  I2 ")
    assert any(line.startswith("run 4: 2 cases, ") for line in table)
    corrections = table[table.index("Corrections (each re-checked):") + 1 :]
    assert f"  {YEHIA_B}/I2: holds when N = 0" in corrections
    assert any(line.startswith(f"  {YEHIA_B}/I2: corrected torque: mu3 = ") for line in corrections)


@pytest.mark.parametrize("width", [60, 80, 100])
def test_the_table_fits_the_width_and_wraps_under_a_hanging_indent(audited, width):
    audits, cases = audited
    table = verdict_table(outcomes(audits, cases), run=4, width=width).splitlines()
    assert max(map(len, table)) <= width
    corrections = table[table.index("Corrections (each re-checked):") + 1 :]
    assert all(line.startswith(("  " + YEHIA_B, "    ")) for line in corrections)
    unwrapped = verdict_table(outcomes(audits, cases), run=4)
    assert max(map(len, unwrapped.splitlines())) > 100  # the Casimir, on one line


def test_a_case_that_could_not_be_loaded_is_a_heading_and_a_note():
    table = verdict_table(outcomes([failed_case("broken", "h", ValueError("no"))], {}))
    lines = table.splitlines()
    assert lines[3:5] == ["broken (Poisson error)", "  -"]
    assert "1 cases, 0 claims (none)" in lines
    assert "  note: broken: energy error (ValueError: no)" in lines


def test_a_contradiction_of_the_numbers_leads_the_notes(audited):
    audits, cases = audited
    zhukovsky = audits[1]
    label = cases[ZHUKOVSKY].claims[0].label
    lying = Evidence(label, 1e-2, 1e-14, 3, contradicts=True)
    found = outcomes([dataclasses.replace(zhukovsky, evidence=(lying,))], cases)
    assert disagreements(found) == [f"{ZHUKOVSKY}/{label}"]
    notes = [line for line in verdict_table(found).splitlines() if "note:" in line]
    assert notes[0] == (
        f"  note: DISAGREEMENT {ZHUKOVSKY}/{label}: integral verified but the drift of I is "
        "1.00e-02 against 1.00e-14 for H"
    )
    assert "numeric evidence: 0 of 1 claims agree with their integral verdicts" in (
        verdict_table(found).splitlines()
    )


def test_the_verdicts_two_runs_disagree_on():
    changes = [
        VerdictChange("c", None, "jacobi", Verdict.VERIFIED, Verdict.REFUTED),
        VerdictChange("c", "I", "casimir", None, Verdict.VERIFIED),
        VerdictChange("d", "K", "integral", Verdict.REFUTED, Verdict.VERIFIED),
    ]
    assert diff_table(changes, 1, 2).splitlines() == [
        "case",
        "  claim  check     run 1     run 2",
        "  -----  --------  --------  --------",
        "c",
        "  -      jacobi    verified  refuted",
        "  I      casimir   -         verified",
        "d",
        "  K      integral  refuted   verified",
    ]
    assert diff_table([], 1, 2) == "no changes between run 1 and run 2"
