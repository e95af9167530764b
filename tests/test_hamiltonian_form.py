"""Issue 20: any Hamiltonian, and the brackets of so(4) and so(3,1).

A case may give H itself (``system.hamiltonian``) and the bracket's parameter
``system.kappa``; the equations are dx/dt = Pi grad H with
Pi = [[hat(M + mu), hat(gamma)], [hat(gamma), kappa hat(M)]] (docs/case-format.md).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass

import pytest
import sympy as sp
import tomli_w

import registry
from registry.audit.case_audit import audit_case
from registry.audit.checks import not_applicable
from registry.audit.outcome import case_outcome
from registry.discovery.search import discover, search_options
from registry.errors import CaseFormatError
from registry.language.case_writer import corrected_case_text, derived_case_text
from registry.language.casefile import load_case, parse_case_text
from registry.language.printer import to_text
from registry.mathematics import mechanics as mech
from registry.mathematics.case_mechanics import CaseMechanics
from registry.mathematics.zero_test import decide
from registry.model import Case, IntegralSet, SearchOptions, Verdict
from registry.presentation.audit_json import case_document
from registry.presentation.notebook import case_html, case_latex
from tests.helpers.samples import CASES, CLASSICAL, HAMILTONIAN, SEED, case_file

M1, M2, M3 = mech.MOMENTUM
g1, g2, g3 = mech.AXIS
kappa = sp.Symbol("kappa", real=True)
c = sp.Symbol("c", real=True)

HEAD = """\
id = "kovalevskaya-so4-test"
title = "Kovalevskaya's top on so(4) and so(3,1)"
[source]
citation = "test fixture: Komarov's Kovalevskaya analogue, derived in this file"
[parameters]
c = "real"
kappa = "real"
"""

#: Komarov's integral of the Kovalevskaya top on so(4)/so(3,1), in the convention of
#: docs/case-format.md (Pi is -1 times Sokolov's bracket); derived in ``test_komarov_integral``.
K_DEFORMED = "(M1**2 - M2**2 - 2*c*gamma1 + kappa*c**2)**2 + (2*M1*M2 - 2*c*gamma2)**2"
#: The same without its kappa-dependent term: Kovalevskaya's e(3) integral.
K_UNDEFORMED = "(M1**2 - M2**2 - 2*c*gamma1)**2 + (2*M1*M2 - 2*c*gamma2)**2"

KOVALEVSKAYA_SO4 = (
    HEAD
    + f"""\
[system]
hamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"
kappa = "kappa"

[[claims]]
label = "K"
kind = "integral"
expression = "{K_DEFORMED}"

[[claims]]
label = "K-e3"
kind = "integral"
expression = "{K_UNDEFORMED}"
"""
)


def verdicts(audit) -> dict[tuple[str, str | None], Verdict]:
    return {(r.check, r.claim): r.verdict for r in audit.results}


# ------------------------------------------------------------------ the language


def test_the_hamiltonian_form_loads():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    system = case.system
    assert system.hamiltonian_form
    assert system.hamiltonian.text == "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"
    assert system.hamiltonian.expr == M1**2 + M2**2 + 2 * M3**2 + 2 * c * g1
    assert system.kappa.text == "kappa" and system.kappa_expr == kappa
    assert system.inertia == () and system.potential.expr == 0
    assert system.torque_exprs == (0, 0, 0)


@pytest.mark.parametrize(
    ("value", "expected"),
    [("1", sp.Integer(1)), ("-0.25", sp.Rational(-1, 4)), ('"-1/4"', sp.Rational(-1, 4))],
)
def test_kappa_is_a_number_or_an_expression(value, expected):
    text = HEAD + f'[system]\nhamiltonian = "M1**2 + gamma1"\nkappa = {value}\n'
    assert parse_case_text(text).system.kappa_expr == expected


def test_kappa_with_the_inertia_form_and_its_default():
    text = HEAD + '[system]\ninertia = ["1", "1", "2"]\npotential = "c*gamma1"\n'
    assert parse_case_text(text).system.kappa_expr == 0
    assert not parse_case_text(text).system.hamiltonian_form
    deformed = parse_case_text(text + 'kappa = "kappa"\n')
    assert deformed.system.kappa_expr == kappa


def test_hamiltonian_with_inertia_is_an_error_that_says_so():
    text = HEAD + '[system]\nhamiltonian = "M1**2"\ninertia = ["1", "1", "2"]\n'
    with pytest.raises(CaseFormatError) as info:
        parse_case_text(text, "so4.toml")
    assert str(info.value) == (
        "so4.toml: system.hamiltonian: give either the Hamiltonian or system.inertia, not "
        "both: with system.hamiltonian, H is the whole energy (inertia and potential are "
        "part of it)"
    )


def test_hamiltonian_may_use_s_radicals_and_declared_functions():
    text = (
        HEAD
        + '[functions]\nf = ["s"]\n[system]\n'
        + 'hamiltonian = "M1**2 + M2**2 + M3**2 + sqrt(gamma1**2 + 1) + f(s)"\n'
    )
    case = parse_case_text(text)
    assert case.system.hamiltonian.expr.has(mech.s)
    assert audit_case(case, ["energy"]).results[0].verdict is Verdict.VERIFIED


#: Hashes of seed cases as computed before the Hamiltonian form existed: a case file
#: that does not use the new fields keeps its hash (every stored result stays valid).
PINNED_HASHES = {
    "yehia-2003-kovalevskaya-b": "26f9cc30a1caf478f4ab37a9869ffd40122bb447d9c8554bc1f34f357934ecc1",
    "zhukovsky-gyrostat": "e193e494c42f75e3a27e42a1ea4f9156a3133ed2a915f6ce087044cb7f1bf963",
    "affine-nonsymmetric": "509a37570aabb3240d8b5e72a35511026660742fc76b54e1c732c45173dca56b",
}


@pytest.mark.parametrize("case_id", SEED)
def test_content_hash_of_old_case_files_is_unchanged(case_id):
    assert load_case(case_file(case_id)).content_hash == PINNED_HASHES[case_id]


def test_content_hash_sees_the_new_fields():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    other = parse_case_text(KOVALEVSKAYA_SO4.replace('kappa = "kappa"', 'kappa = "0"'))
    same_as_default = parse_case_text(KOVALEVSKAYA_SO4.replace('kappa = "kappa"\n', ""))
    assert len({case.content_hash, other.content_hash, same_as_default.content_hash}) == 3


def test_printed_forms_carry_h_and_kappa():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    html = case_html(case)
    assert "Hamiltonian H" in html and "κ" in html and "inertia" not in html
    assert r"\kappa" in case_latex(case)


def test_derived_case_keeps_the_hamiltonian_form():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    found = IntegralSet(when=("kappa = 1",), extra=1, integrals=("M3",))
    derived = parse_case_text(derived_case_text(case, found, SearchOptions()))
    assert derived.system.hamiltonian.expr == case.system.hamiltonian.expr
    assert derived.system.kappa_expr == 1
    assert "kappa" not in derived.parameters


# ------------------------------------------------------------------ the mechanics


def test_komarov_integral():
    """Among (M1^2 - M2^2 + a c gamma1 + b kappa c^2)^2 + (2 M1 M2 + a' c gamma2)^2, the
    integral of H = M1^2 + M2^2 + 2 M3^2 + 2 c gamma1 on the bracket kappa is the one
    with a = a' = -2, b = 1 (derived here, not taken from memory)."""
    h = M1**2 + M2**2 + 2 * M3**2 + 2 * c * g1
    field = mech.equations_of_motion((0, 0, 0), kappa, h=h)
    b = sp.Symbol("b")
    found = []
    for a in (2, -2):
        for a2 in (2, -2):
            k = (M1**2 - M2**2 + a * c * g1 + b * kappa * c**2) ** 2 + (
                2 * M1 * M2 + a2 * c * g2
            ) ** 2
            residual = sp.Poly(sp.expand(mech.time_derivative(k, field)), *mech.STATE)
            found += [(a, a2, s[b]) for s in sp.solve(residual.coeffs(), b, dict=True)]
    assert found == [(-2, -2, 1)]


def test_kappa_deformed_integral_holds_and_the_undeformed_one_is_refuted():
    audit = audit_case(parse_case_text(KOVALEVSKAYA_SO4))
    found = verdicts(audit)
    assert found["jacobi", None] is Verdict.VERIFIED
    assert found["energy", None] is Verdict.VERIFIED
    assert found["c1", None] is Verdict.VERIFIED
    assert ("hamiltonian", None) not in found
    assert found["integral", "K"] is Verdict.VERIFIED
    assert found["integral", "K-e3"] is Verdict.REFUTED
    witness = audit.result("integral", "K-e3").witness
    assert witness is not None and witness.point["kappa"] != "0"
    # on e(3) (kappa = 0) both are Kovalevskaya's integral
    e3 = audit_case(parse_case_text(KOVALEVSKAYA_SO4.replace('kappa = "kappa"', 'kappa = "0"')))
    assert verdicts(e3)["integral", "K-e3"] is Verdict.VERIFIED
    # there the parameter kappa of K is only a shift of M1^2 - M2^2 - 2 c gamma1
    assert verdicts(e3)["integral", "K"] is Verdict.REFUTED


def test_the_bracket_casimirs():
    """M.gamma and kappa|M|^2 + |gamma|^2 are Casimirs of Pi (mu = 0), |gamma|^2 alone is
    not where kappa != 0."""
    m = CaseMechanics(parse_case_text(KOVALEVSKAYA_SO4))
    for expr, expected in (
        (mech.S_VALUE, Verdict.VERIFIED),
        (2 * mech.casimir_c1(kappa), Verdict.VERIFIED),
        (2 * mech.C1, Verdict.REFUTED),
    ):
        assert decide(m.casimir_residual(expr), m.domain).verdict is expected


@pytest.mark.parametrize("k", [0, 1, -1, kappa])
@pytest.mark.parametrize(
    ("torque", "poisson_when_deformed"),
    [
        ((0, 0, 0), True),
        ((0, 0, sp.Symbol("lam", positive=True)), False),  # a gyrostat: constant torque
        ((0, 0, sp.Symbol("lam", positive=True) * g3), False),
    ],
)
def test_jacobi_for_every_kappa_with_and_without_torque(k, torque, poisson_when_deformed):
    """Pi is Poisson for mu = 0 on e(3), so(4) and so(3,1); a constant torque (or
    lam gamma3 e3) keeps it Poisson on e(3) only: kappa != 0 breaks it."""
    pi = mech.poisson_tensor(torque, k)
    nonzero = [v for v in mech.jacobiator(pi).values() if sp.expand(v) != 0]
    assert (not nonzero) is (k == 0 or poisson_when_deformed)


def test_kappa_with_torque_breaks_jacobi_in_the_audit():
    text = (
        HEAD
        + 'lam = "positive"\n[system]\nhamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"\n'
        + 'kappa = "kappa"\ntorque = ["0", "0", "lam"]\n'
    )
    audit = audit_case(parse_case_text(text))
    assert verdicts(audit)["jacobi", None] is Verdict.REFUTED
    conditions = {cond.target: cond for cond in audit.conditions}
    assert ("kappa = 0",) in conditions["jacobi"].branches


def test_hamiltonian_check_does_not_apply_to_the_hamiltonian_form():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    assert "defined as Pi grad H" in not_applicable(case)["hamiltonian"]
    audit = audit_case(case)
    document = case_document(case_outcome(audit, case))
    assert "hamiltonian" not in document["checks"]
    assert document["not_applicable"] == not_applicable(case)
    assert not not_applicable(load_case(case_file(SEED[0])))


# ------------------------------------------- both forms of every catalog case


def as_hamiltonian_form(case: Case) -> Case:
    """The same case written with ``system.hamiltonian`` (H = M.I^-1 M/2 + U)."""
    data = tomllib.loads(case.text)
    system = data["system"]
    system.pop("inertia")
    system.pop("potential", None)
    system["hamiltonian"] = to_text(CaseMechanics(case).hamiltonian)
    return parse_case_text(tomli_w.dumps(data), f"{case.id} as Hamiltonian form")


CATALOG = sorted(CASES.rglob("*.toml")) + sorted(CLASSICAL.glob("*.toml"))
INERTIA_FORM = [p for p in CATALOG if load_case(p).system.form == "inertia"]


@pytest.mark.parametrize("path", INERTIA_FORM, ids=lambda p: p.stem)
def test_inertia_form_gives_exactly_the_equations_pi_grad_h(path):
    """For every catalog case, today's equations (2.2) equal Pi grad H of the Hamiltonian
    form, component by component (proven by the zero test)."""
    case = load_case(path)
    explicit = CaseMechanics(case)
    general = CaseMechanics(as_hamiltonian_form(case))
    difference = {
        str(v): a - b for v, a, b in zip(mech.STATE, explicit.field, general.field, strict=True)
    }
    assert decide(difference, explicit.domain).verdict is Verdict.VERIFIED


@pytest.mark.slow
@pytest.mark.parametrize("path", INERTIA_FORM, ids=lambda p: p.stem)
def test_both_forms_give_the_same_verdicts(path):
    case = load_case(path)
    twin = as_hamiltonian_form(case)
    first = verdicts(audit_case(case, corrections=False))
    second = verdicts(audit_case(twin, corrections=False))
    assert first.pop(("hamiltonian", None)) is Verdict.VERIFIED
    assert first == second


HAMILTONIAN_FORM = [p for p in CATALOG if load_case(p).system.form == "hamiltonian"]


@dataclass(frozen=True)
class Coordinates:
    """A change of coordinates: the old ones in terms of the new (``old``), how many places
    the torque's components move, and the factor kappa is divided by."""

    old: dict
    torque_shift: int = 0
    kappa_over: int = 1


#: A cyclic permutation of the axes (a rotation: the bracket is kept, the torque, a
#: vector, is permuted too), and gamma = 2 gamma' (which turns kappa into kappa/4).
ROTATED = Coordinates({M1: M3, M2: M1, M3: M2, g1: g3, g2: g1, g3: g2}, torque_shift=1)
SCALED = Coordinates({g1: 2 * g1, g2: 2 * g2, g3: 2 * g3, mech.s: 2 * mech.s}, kappa_over=4)


def rewritten(case: Case, change: Coordinates) -> Case:
    """``case`` in the new coordinates of ``change``: H, the torque, kappa and every claim
    and level set rewritten, as a physicist would type them."""
    data = tomllib.loads(case.text)
    system, new = data["system"], lambda e: to_text(e.xreplace(change.old))
    system["hamiltonian"] = new(case.system.hamiltonian.expr)
    torque = [new(t.expr) for t in case.system.torque]
    shift = change.torque_shift
    system["torque"] = torque[shift:] + torque[:shift]
    system["kappa"] = to_text(case.system.kappa.expr / change.kappa_over)
    for claim, written in zip(case.claims, data.get("claims", []), strict=True):
        written["expression"] = new(claim.expression.expr)
        if claim.on:
            written["on"] = [f"{new(eq.lhs)} = {new(eq.rhs)}" for eq in claim.on]
    return parse_case_text(tomli_w.dumps(data), f"{case.id} in other coordinates")


@pytest.mark.slow
@pytest.mark.parametrize("path", HAMILTONIAN_FORM, ids=lambda p: p.stem)
def test_a_rotation_of_the_axes_or_a_rescaled_gamma_changes_no_verdict(path):
    """The audit decides what a case means, not how its coordinates were chosen: every
    Hamiltonian-form case of the catalog, with its axes permuted cyclically or with
    gamma = 2 gamma' and kappa/4, gets the same verdict for every check and claim."""
    case = load_case(path)
    first = verdicts(audit_case(case, corrections=False))
    for change in (ROTATED, SCALED):
        assert verdicts(audit_case(rewritten(case, change), corrections=False)) == first


# ------------------------------------------------------------------ discovery

SEARCHED = """\
id = "search-family"
title = "A family to search"
[source]
citation = "test fixture"
"""


def test_discovery_finds_kovalevskaya_on_so4_in_a_family():
    """H = M1^2 + M2^2 + a M3^2 + 2 gamma1 on so(4) (kappa = 1), a free: a = 2 is
    Kovalevskaya's analogue (a quartic integral), a = 1 Lagrange's (M1); nothing else."""
    case = parse_case_text(
        SEARCHED
        + '[parameters]\na = "real"\n[system]\n'
        + 'hamiltonian = "M1**2 + M2**2 + a*M3**2 + 2*gamma1"\nkappa = "1"\n'
    )
    found = discover(case, search_options(case, degree=4, weights=(1, 1), free=["a"]))
    assert found.complete and found.generic.extra == 0
    assert found.known == (
        "H",
        "M1**2 + M2**2 + M3**2 + gamma1**2 + gamma2**2 + gamma3**2",
        "M1*gamma1 + M2*gamma2 + M3*gamma3",
    )
    special = {s.when: s for s in found.special}
    assert set(special) == {("a = 1",), ("a = 2",)}
    assert special["a = 1",].integrals == ("M1",)
    (quartic,) = special["a = 2",].integrals
    # it is Komarov's integral at c = kappa = 1, up to the Casimirs and H
    at = {c: 1, kappa: 1}
    komarov = sp.sympify(K_DEFORMED, locals={"c": c, "kappa": kappa}).xreplace(at)
    assert "not weighted-homogeneous" in found.method
    twin = parse_case_text(
        SEARCHED
        + '[system]\nhamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*gamma1"\nkappa = "1"\n'
        + f'[[claims]]\nlabel = "F"\nkind = "integral"\nexpression = "{quartic}"\n'
        + f'[[claims]]\nlabel = "K"\nkind = "integral"\nexpression = "{komarov}"\n'
    )
    assert verdicts(audit_case(twin, corrections=False))["integral", "F"] is Verdict.VERIFIED
    assert verdicts(audit_case(twin, corrections=False))["integral", "K"] is Verdict.VERIFIED


def test_discovery_finds_clebschs_condition_from_one_free_coefficient():
    """Kirchhoff's H = (M1^2 + 2 M2^2 + 3 M3^2)/2 + (gamma1^2 + 2 gamma2^2 + b gamma3^2)/2
    is Clebsch's case exactly where (b1 - b2)/a3 + (b2 - b3)/a1 + (b3 - b1)/a2 = 0 with
    a = (1, 2, 3) (the coefficients of M_i^2, as dH/dM = a M), b = (1, 2, b): b = 7/3."""
    case = parse_case_text(
        SEARCHED
        + '[parameters]\nb = "real"\n[system]\n'
        + 'hamiltonian = "M1**2/2 + M2**2 + 3*M3**2/2 + gamma1**2/2 + gamma2**2 + b*gamma3**2/2"\n'
    )
    found = discover(case, search_options(case, degree=2, weights=(1, 1), free=["b"]))
    assert found.complete and found.generic.extra == 0
    assert [s.when for s in found.special] == [("b = 7/3",)]
    assert found.special[0].extra == 1
    a1, a2, a3, b1, b2 = 1, 2, 3, 1, 2
    b3 = sp.Symbol("b3")
    assert sp.solve((b1 - b2) / sp.S(a3) + (b2 - b3) / sp.S(a1) + (b3 - b1) / sp.S(a2), b3) == [
        sp.Rational(7, 3)
    ]


def test_kappa_may_be_free():
    """Kovalevskaya's top with kappa free: Komarov's integral exists for every kappa, so
    the generic values have the quartic integral, and no kappa is special."""
    case = parse_case_text(
        SEARCHED
        + '[parameters]\nkappa = "real"\n[system]\n'
        + 'hamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*gamma1"\nkappa = "kappa"\n'
    )
    found = discover(case, search_options(case, degree=4, weights=(1, 1), free=["kappa"]))
    assert found.complete and found.generic.extra == 1 and found.special == ()
    assert "M1**2*kappa" in found.known[1]


def test_the_papers_corrections_say_they_do_not_apply_on_so4():
    audit = audit_case(parse_case_text(KOVALEVSKAYA_SO4))
    assert audit.family.name == "none"
    assert audit.family.reason.startswith("not applicable: ")
    assert "kappa = kappa" in audit.family.reason
    assert not [c for c in audit.corrections if c.kind in ("casimir", "torque")]
    # parameter conditions are still sought: K-e3 holds where kappa c^2 vanishes
    (conditions,) = [c for c in audit.conditions if c.target == "K-e3"]
    assert {b for b in conditions.branches} == {("c = 0",), ("kappa = 0",)}


# ------------------------------------------- stored and distributed runs


def local_verdicts() -> dict[tuple[str, str, str | None], str]:
    """(case, check, claim) -> verdict of every fixture case, audited in this process."""
    found = {}
    for path in sorted(HAMILTONIAN.glob("*.toml")):
        case = load_case(path)
        for r in audit_case(case).results:
            found[case.id, r.check, r.claim] = str(r.verdict)
    return found


def stored_verdicts(reg, run: int) -> dict[tuple[str, str, str | None], str]:
    frame = reg.verdicts()
    frame = frame[frame.run == run]
    return {
        (row.case, row.check, row.claim if isinstance(row.claim, str) and row.claim else None): (
            row.verdict
        )
        for row in frame.itertuples()
    }


def test_the_fixtures_verdicts():
    found = local_verdicts()
    assert found["test-kovalevskaya-so4", "integral", "K"] == "verified"
    assert found["test-kovalevskaya-so4", "integral", "K-e3"] == "refuted"
    assert found["test-kovalevskaya-so4", "casimir", "C"] == "verified"
    assert found["test-kovalevskaya-so4", "casimir", "C-e3"] == "refuted"
    assert found["test-kovalevskaya-so31", "integral", "K"] == "verified"
    assert found["test-kovalevskaya-so31", "integral", "K-e3"] == "refuted"
    assert found["test-clebsch-kirchhoff", "integral", "F"] == "verified"
    assert found["test-clebsch-kirchhoff", "integral", "F-sign"] == "refuted"
    assert found["test-gyrostat-so4", "jacobi", None] == "refuted"
    assert found["test-gyrostat-so4", "integral", "M3"] == "verified"
    assert not any(check == "hamiltonian" for _, check, _ in found)
    assert "inconclusive" not in found.values() and "error" not in found.values()


def test_a_database_of_either_backend_stores_the_local_verdicts(db_target):
    with registry.open(db_target) as reg:
        reg.add(HAMILTONIAN)
        report = reg.audit(jobs=1)
        assert stored_verdicts(reg, report.run) == local_verdicts()
        stored = reg.case("test-kovalevskaya-so4")
        assert stored.system.hamiltonian.text == "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"
        assert stored.system.kappa.text == "kappa"
        assert reg.verify_db().ok


def test_the_audit_json_carries_h_and_kappa():
    case = parse_case_text(KOVALEVSKAYA_SO4)
    document = case_document(case_outcome(audit_case(case, corrections=False), case))
    assert document["system"] == {
        "hamiltonian": "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1",
        "kappa": "kappa",
    }
    old = load_case(case_file(SEED[0]))
    assert "system" not in case_document(case_outcome(audit_case(old, ["c1"]), old))


def test_the_survey_searches_new_form_cases(tmp_path):
    with registry.open(tmp_path / "r.sqlite") as reg:
        reg.add(HAMILTONIAN)
        reports = {r.search.case: r.search for r in reg.survey(jobs=1)}
    so4 = reports["test-kovalevskaya-so4"]
    assert (
        dict(so4.options.weights) == {"M": 1, "gamma": 1} and so4.options.degree == 4
    )  # no grading fits
    assert so4.decided and so4.generic.extra == 1  # Komarov's K, rediscovered
    assert "not weighted-homogeneous" in so4.method
    clebsch = reports["test-clebsch-kirchhoff"]
    assert dict(clebsch.options.weights) == {"M": 1, "gamma": 1} and clebsch.options.degree == 2
    assert clebsch.generic.extra == 1 and "not weighted-homogeneous" not in clebsch.method


def test_numeric_evidence_integrates_pi_grad_h():
    """The drift of Komarov's K along trajectories of so(3,1) is at H's noise floor; that
    of Kovalevskaya's e(3) integral is not: the integrator runs the general equations."""
    audit = audit_case(load_case(HAMILTONIAN / "kovalevskaya-so31.toml"), numeric=True)
    evidence = {e.claim: e for e in audit.evidence}
    assert evidence["K"].runs >= 2 and not evidence["K"].contradicts
    assert evidence["K"].drift < 1e-6
    assert evidence["K-e3"].drift > 1e-3 and not evidence["K-e3"].contradicts


def test_a_corrected_torque_is_written_back_in_the_hamiltonian_form(tmp_path):
    """The paper's corrections apply to any H on e(3): Yehia's case b) written with its
    Hamiltonian gets the paper's corrected torque, and the exported case keeps H."""
    case = as_hamiltonian_form(load_case(case_file(SEED[0])))
    audit = audit_case(case)
    torque = [c for c in audit.corrections if c.kind == "torque"]
    assert torque
    text = corrected_case_text(case, torque[0])
    written = parse_case_text(text)
    assert written.system.hamiltonian.expr == case.system.hamiltonian.expr
    assert written.system.inertia == ()
    assert [e.text for e in written.system.torque] == list(torque[0].torque)
    assert verdicts(audit_case(written, corrections=False))["casimir", torque[0].claim] is (
        Verdict.VERIFIED
    )


def test_the_inertia_form_on_so4_is_the_same_system():
    """Moments (1/2, 1/2, 1/4) and U = 2 c gamma1 with kappa give Kovalevskaya's so(4) H:
    the same verdicts, and there the hamiltonian check applies and holds (the paper's
    equations with kappa M x grad U added to dgamma/dt are Pi grad H)."""
    inertia_form = KOVALEVSKAYA_SO4.replace(
        'hamiltonian = "M1**2 + M2**2 + 2*M3**2 + 2*c*gamma1"',
        'inertia = ["1/2", "1/2", "1/4"]\npotential = "2*c*gamma1"',
    )
    first = verdicts(audit_case(parse_case_text(inertia_form), corrections=False))
    second = verdicts(audit_case(parse_case_text(KOVALEVSKAYA_SO4), corrections=False))
    assert first.pop(("hamiltonian", None)) is Verdict.VERIFIED
    assert first == second
