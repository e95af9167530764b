"""A corrected case written back as a case file loads again, and its claim re-checks."""

from registry import Verdict, audit_case, load_case, parse_case_text
from tests.helpers.clocks import PATIENT
from tests.helpers.samples import case_file


def load(case_id):
    return load_case(case_file(case_id))


def test_exported_corrected_case_loads_and_is_verified(tmp_path):
    from registry.language.case_writer import corrected_case_text

    case, audit = load("yehia-2003-kovalevskaya-b"), None
    audit = audit_case(case, budget=PATIENT)  # a busy machine must not cut the proof off
    (fix,) = [c for c in audit.corrections if c.kind == "torque"]
    text = corrected_case_text(case, fix, run=1)
    fixed = parse_case_text(text, "exported.toml")
    assert fixed.id == "yehia-2003-kovalevskaya-b-corrected-torque"
    result = audit_case(fixed, checks=["jacobi", "casimir"], budget=PATIENT)
    assert result.result("jacobi").verdict is Verdict.VERIFIED
    assert result.result("casimir", "I2").verdict is Verdict.VERIFIED
