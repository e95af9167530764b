"""Systems on any phase space, end to end: the audit agrees with an independent script on
the catalog's cases in the new forms, a top written as equations gets the same verdicts
as in the reference paper's form, and each new check is proven and refuted on a case
built for it (a bracket that is not Poisson, a density with its sign flipped, an integral
claimed without the relation it needs)."""

import json
import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from registry import Verdict, audit_case, load_case
from registry.language.casefile import parse_case_text
from registry.language.printer import to_text

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "data" / "cases"
DATA = Path(__file__).resolve().parent / "data" / "any-form"
V, R = Verdict.VERIFIED, Verdict.REFUTED


def any_form_files() -> list[Path]:
    found = []
    for path in sorted(CASES.rglob("*.toml")):
        text = path.read_text(encoding="utf-8")
        if "[system.equations]" in text or "[system.bracket]" in text:
            found.append(path)
    return found


def test_the_catalog_has_cases_in_the_new_forms_from_eight_sources():
    cases = [load_case(p) for p in any_form_files()]
    assert len(cases) >= 15
    assert len({c.source.citation for c in cases}) >= 8


def test_the_audit_agrees_with_an_independent_script():
    files = any_form_files()
    run = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "check_any_form.py"), *map(str, files)],
        capture_output=True,
        text=True,
        check=True,
        timeout=900,
    )
    independent = {
        (line["case"], line["claim"]): line["holds"]
        for line in map(json.loads, run.stdout.split("\n")[:-1])
    }
    compared = 0
    for path in files:
        case = load_case(path)
        audit = audit_case(case, corrections=False)
        for claim in case.claims:
            ours = audit.result(str(claim.kind), claim.label).verdict
            theirs = independent[case.id, claim.label]
            if ours in (V, R) and theirs is not None:
                assert (ours is V) == theirs, (case.id, claim.label, ours, theirs)
                compared += 1
    assert compared >= 30


def equations_form(case_path: Path, mutate: str | None = None) -> tuple[str, str]:
    """A paper-form case rewritten as a system given by its equations (its field printed
    in the case language, s = M.gamma a definition), with its claims; with ``mutate``, the
    signs of the claim with the most terms are flipped in both forms. Returns both texts."""
    case = load_case(case_path)
    paper = case_path.read_text(encoding="utf-8")
    claims = list(case.claims)
    if mutate:
        k = max(range(len(claims)), key=lambda i: _signs(claims[i].expression.text))
        text = claims[k].expression.text
        flipped = text.replace("+", "#").replace("-", "+").replace("#", "-")
        assert flipped != text
        paper = paper.replace(f'expression = "{text}"', f'expression = "{flipped}"')
        claims[k] = replace(claims[k], expression=replace(claims[k].expression, text=flipped))
    state = [str(v) for v in case.dynamics.variables]
    lines = [
        f'id = "{case.id}-equations"',
        f'title = "{case.id} written as equations"',
        "[source]",
        'citation = "a test"',
        "[parameters]",
        *(f'{p} = "{kind}"' for p, kind in _parameter_kinds(paper).items()),
        "[system]",
        f"variables = {json.dumps(state)}",
        "[system.definitions]",
        's = "M1*gamma1 + M2*gamma2 + M3*gamma3"',
        "[system.equations]",
        *(
            f'{v} = "{to_text(case.dynamics.expanded(f))}"'
            for v, f in zip(state, case.dynamics.field, strict=True)
        ),
    ]
    for claim in claims:
        kind = "integral"  # a Casimir needs a bracket: these claims are compared as integrals
        lines += ["[[claims]]", f'label = "{claim.label}"', f'kind = "{kind}"']
        lines.append(f'expression = "{claim.expression.text}"')
        if claim.on:
            lines.append(f"on = {json.dumps([eq.text for eq in claim.on])}")
    return paper, "\n".join(lines) + "\n"


def _signs(text: str) -> int:
    return text.count("+") + text.count("-")


def _parameter_kinds(text: str) -> dict[str, str]:
    section = text.split("[parameters]", 1)[1].split("\n[", 1)[0]
    out = {}
    for line in section.strip().splitlines():
        if "=" in line:
            name, kind = (part.strip() for part in line.split("=", 1))
            out[name] = kind.strip('"')
    return out


TOPS = ["lagrange-1788-heavy-top", "kovalevskaya-1889-heavy-top", "hess-1890-heavy-top"]


@pytest.mark.parametrize("mutate", [None, "sign"])
@pytest.mark.parametrize("top", TOPS)
def test_a_top_written_as_equations_gets_the_paper_forms_verdicts(top, mutate):
    paper, equations = equations_form(CASES / "heavy-top" / f"{top}.toml", mutate)
    a = audit_case(parse_case_text(paper, f"{top}.toml"), corrections=False)
    b = audit_case(parse_case_text(equations, f"{top}-equations.toml"), corrections=False)
    labels = [r.claim for r in a.results if r.check == "integral"]
    assert labels
    for label in labels:
        assert b.result("integral", label).verdict is a.result("integral", label).verdict, label
    if mutate:
        assert R in {a.result("integral", label).verdict for label in labels}


def test_kowalevskis_own_variables_give_the_same_verdicts_as_the_paper_form():
    omega = audit_case(
        load_case(CASES / "heavy-top" / "kovalevskaya-1889-heavy-top-omega-equations.toml")
    )
    paper = audit_case(load_case(CASES / "heavy-top" / "kovalevskaya-1889-heavy-top.toml"))
    assert omega.result("integral", "K").verdict is paper.result("integral", "K").verdict is V
    assert omega.result("integral", "energy").verdict is paper.result("integral", "H").verdict
    wrong = audit_case(
        load_case(CASES / "heavy-top" / "kovalevskaya-1889-heavy-top-omega-wrong-sign.toml")
    )
    assert wrong.result("integral", "K-wrong").verdict is R


def test_a_bracket_that_fails_jacobi_is_refuted_with_a_witness():
    audit = audit_case(load_case(DATA / "bracket-not-poisson.toml"))
    jacobi = audit.result("jacobi")
    assert jacobi.verdict is R
    assert jacobi.witness is not None and set(jacobi.witness.point) == {"x", "y", "z"}
    x, z = (float(eval_rational(jacobi.witness.point[k])) for k in "xz")
    assert jacobi.residual in ("2*x*z", "-2*x*z")
    assert x * z != 0
    # the Hamiltonian is still conserved: the flow is Pi grad H for any antisymmetric Pi
    assert audit.result("integral", "H").verdict is V


def eval_rational(text: str):
    from fractions import Fraction

    return Fraction(text)


def test_chaplygins_ball_density_is_proven_and_its_flipped_sign_refuted():
    derived = audit_case(load_case(DATA / "chaplygin-ball-derived-claims.toml"))
    assert {r.claim: r.verdict for r in derived.results} == {
        "density": V,
        "energy": V,
        "momentum-squared": V,
        "area": V,
    }
    flipped = audit_case(load_case(DATA / "chaplygin-ball-density-flipped.toml"), corrections=False)
    result = flipped.result("measure", "density-flipped")
    assert result.verdict is R and result.witness is not None


def test_suslovs_problem_keeps_its_energy_and_not_lebesgues_measure():
    """Suslov's problem (omega3 = 0): the energy is conserved, a flipped sign in it is not;
    Lebesgue's measure is not invariant (the divergence -I13 w2/I11 + I23 w1/I22), and
    both wrong claims hold exactly where I13 = I23 = 0, the body without the coupling."""
    audit = audit_case(load_case(DATA / "suslov-problem.toml"))
    assert {r.claim: r.verdict for r in audit.results if r.check != "casimir"} == {
        "energy": V,
        "lebesgue": R,
        "energy-sign": R,
    }
    assert audit.result("measure", "lebesgue").witness is not None
    conditions = {c.target: c.branches for c in audit.conditions}
    assert conditions["lebesgue"] == (("I13 = 0", "I23 = 0"),)
    assert conditions["energy-sign"] == (("I13 = 0", "I23 = 0"),)


def test_todas_traces_are_proven_and_a_changed_coefficient_refuted():
    """Flaschka's traces of L, L**2 and L**3 are integrals of Toda's lattice; tr L**3 with
    one coefficient changed (3 -> 2) is refuted at a point where dI/dt is not zero."""
    audit = audit_case(load_case(DATA / "toda-flaschka.toml"))
    assert {r.claim: r.verdict for r in audit.results} == {
        "trace": V,
        "trace-2": V,
        "trace-3": V,
        "trace-3-mutated": R,
    }
    assert audit.result("integral", "trace-3-mutated").witness is not None


def test_an_integral_claimed_without_its_relation_is_refuted_and_holds_with_it():
    path = CASES / "nonholonomic" / "verdier-2016-chaplygin-sleigh-odelab.toml"
    text = path.read_text(encoding="utf-8")
    on = 'on = ["-sin(theta)*vx + cos(theta)*vy - a*vtheta = 0"]\n'
    assert on in text
    with_it = audit_case(parse_case_text(text, path.name), corrections=False)
    without = audit_case(parse_case_text(text.replace(on, ""), path.name), corrections=False)
    assert with_it.result("integral", "energy").verdict is V
    assert with_it.result("invariant", "energy").verdict is V
    refuted = without.result("integral", "energy")
    assert refuted.verdict is R and refuted.witness is not None


@pytest.mark.parametrize(
    ("path", "label", "check"),
    [
        (
            "nonholonomic/bloch-2015-chaplygin-sleigh-lebesgue-measure-wrong.toml",
            "lebesgue",
            "measure",
        ),
        (
            "nonholonomic/bloch-2015-chaplygin-sleigh-relation-wrong.toml",
            "no-translation",
            "relation",
        ),
        ("nonholonomic/tenenbaum-2025-chaplygin-sleigh.toml", "equilibria-line", "relation"),
    ],
)
def test_numeric_evidence_watches_densities_and_relations_and_agrees(path, label, check):
    audit = audit_case(load_case(CASES / path), numeric=True)
    (evidence,) = [e for e in audit.evidence if e.claim == label]
    assert evidence.compared_with == check
    assert evidence.runs >= 2 and not evidence.contradicts
    verdict = audit.result(check, label).verdict
    if verdict is R:
        assert evidence.drift > 1e3 * max(evidence.floor, 1e-13)
    else:
        assert evidence.drift < 1e-8
    assert math.isfinite(evidence.floor)


def test_a_true_density_keeps_ln_rho_plus_the_integral_of_div_v_constant():
    audit = audit_case(load_case(DATA / "chaplygin-ball-derived-claims.toml"), numeric=True)
    (evidence,) = [e for e in audit.evidence if e.claim == "density"]
    assert evidence.compared_with == "measure" and evidence.runs >= 2
    assert evidence.drift < 1e-8 and not evidence.contradicts


def test_a_refuted_claim_of_any_form_gets_a_drift_curve_without_h():
    audit = audit_case(
        load_case(CASES / "nonholonomic" / "bloch-2015-chaplygin-sleigh-relation-wrong.toml")
    )
    (curve,) = audit.curves
    assert curve.claim == "no-translation" and curve.dh == ()
    assert len(curve.t) == len(curve.di) > 10 and max(abs(x) for x in curve.di) > 1e-3
