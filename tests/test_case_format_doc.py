"""docs/case-format.md, the reference of the case-file format, stays true: every TOML
example in it is a complete case file that loads (or, marked ``<!-- refused -->``, is
refused with exactly the message shown after it), the claims of the examples that load
are verified by the audit, and the limits it states are the loader's."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from registry.audit.case_audit import audit_case, claim_verdict
from registry.errors import CaseFormatError
from registry.language import casefile, limits, toml_input
from registry.language.casefile import parse_case_text
from registry.model import Verdict

DOC = Path(__file__).resolve().parent.parent / "docs" / "case-format.md"
TEXT = DOC.read_text(encoding="utf-8")

#: A fenced TOML block, the marker comment on the line before it (if any), and the
#: fenced text block that follows it (if any: the message of a refused example).
BLOCK = re.compile(
    r"(?:<!-- (?P<mark>[^>]*?) -->\n)?```toml\n(?P<toml>.*?)```\n"
    r"(?:\n[^`]*?```text\n(?P<said>.*?)```)?",
    re.S,
)


def examples() -> list[tuple[str, str | None, str, str | None]]:
    """(id, marker, TOML text, message) of every TOML example, in the doc's order."""
    found = []
    for m in BLOCK.finditer(TEXT):
        case_id = re.search(r'^id = "([^"]+)"', m["toml"], re.M)
        assert case_id, f"a TOML example without an id:\n{m['toml']}"
        found.append((case_id.group(1), m["mark"], m["toml"], m["said"]))
    return found


EXAMPLES = examples()
IDS = [e[0] for e in EXAMPLES]


def test_the_doc_has_its_examples():
    assert len(EXAMPLES) >= 6
    assert len(set(IDS)) == len(IDS), "two examples share an id"
    marks = {mark for _, mark, _, _ in EXAMPLES}
    assert marks <= {None, "refused"}, marks
    assert any("hamiltonian = " in toml for _, _, toml, _ in EXAMPLES)
    assert any("kappa = " in toml for _, _, toml, _ in EXAMPLES)
    assert any("[system.equations]" in toml for _, _, toml, _ in EXAMPLES)
    assert any("[system.bracket]" in toml for _, _, toml, _ in EXAMPLES)
    assert any('kind = "measure"' in toml for _, _, toml, _ in EXAMPLES)


@pytest.mark.parametrize(("case_id", "mark", "toml", "said"), EXAMPLES, ids=IDS)
def test_every_example_loads_or_is_refused_as_shown(case_id, mark, toml, said):
    if mark == "refused":
        with pytest.raises(CaseFormatError) as caught:
            parse_case_text(toml, f"{case_id}.toml")
        assert said is not None, "a refused example must show its message"
        assert str(caught.value) == said.strip()
        return
    case = parse_case_text(toml, f"{case_id}.toml")
    assert case.id == case_id
    assert case.claims, "every example that loads claims something"


@pytest.mark.parametrize(
    ("case_id", "toml"),
    [(i, t) for i, m, t, _ in EXAMPLES if m != "refused"],
    ids=[i for i, m, _, _ in EXAMPLES if m != "refused"],
)
def test_the_claims_of_the_examples_are_verified(case_id, toml):
    case = parse_case_text(toml, f"{case_id}.toml")
    audit = audit_case(case, corrections=False)
    for claim in case.claims:
        verdicts = {r.check: r.verdict for r in audit.results if r.claim == claim.label}
        verdict = claim_verdict(claim.kind, verdicts)
        assert verdict is Verdict.VERIFIED, (claim.label, audit.results)


@pytest.mark.parametrize(
    ("case_id", "old", "new", "check", "label"),
    [
        ("example-gyrostat", "(M3 + k3)*gamma3", "M3*gamma3", "casimir", "area"),
        ("example-kappa-axisymmetric", "kappa*(M1**2", "(M1**2", "casimir", "deformed"),
        ("example-lagrange-hamiltonian", "(M1**2 + M2**2)/(2*A)", "M1**2/A", "integral", "M3"),
        ("example-sleigh", '"1/omega"', '"omega"', "measure", "density"),
        ("example-sleigh", '"omega"\n', '"v"\n', "relation", "no-turning"),
        (
            "example-two-fields",
            "alpha2**2 + alpha3**2",
            "alpha2**2 + beta3**2",
            "casimir",
            "alpha-squared",
        ),
    ],
)
def test_a_changed_example_is_not_verified(case_id, old, new, check, label):
    """The audit above can fail: a term dropped from a claim or from H."""
    (toml,) = [t for i, _, t, _ in EXAMPLES if i == case_id]
    mutated = toml.replace(old, new)
    assert mutated != toml
    audit = audit_case(parse_case_text(mutated, "mutated.toml"), corrections=False)
    assert audit.result(check, label).verdict is Verdict.REFUTED


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("at\nmost 1 MB", toml_input.MAX_FILE_BYTES // 1_000_000),
        ("at most 200 claims", casefile.MAX_CLAIMS),
        ("100 parameters", casefile.MAX_PARAMETERS),
        ("20 level-set equations", casefile.MAX_EQUATIONS),
        ("20 aliases", casefile.MAX_ALIASES),
        ("20,000 characters", limits.MAX_LENGTH),
        ("5,000 syntax nodes", limits.MAX_NODES),
        ("100 digits", limits.MAX_DIGITS),
        ("exponents at most 1000", limits.MAX_EXPONENT),
    ],
)
def test_the_limits_the_doc_states_are_the_loaders(text, value):
    assert text in TEXT
    number = int(re.search(r"[\d,]+", text.replace("\n", " ")).group().replace(",", ""))
    assert number == value
