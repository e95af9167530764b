"""The registry's classification of the reference paper's torque class (scripts/classify.py,
docs/classifications.md): the Kovalevskaya body with mu = grad phi, every one of phi's 19
coefficients free, has exactly two special sets at degree 4, Yehia's Kovalevskaya gyrostat
and the set of the discovered case data/cases/discovered/, whose integral is the one the
search found there."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest
import sympy as sp

from registry.discovery.search import discover, search_options
from registry.language.casefile import load_case
from registry.presentation.search_output import search_document
from tests.helpers.catalog import catalog_index

ROOT = Path(__file__).resolve().parents[1]
FAMILY = ROOT / "data" / "families" / "kovalevskaya-gradient-torque.toml"
DISCOVERED = (
    ROOT / "data" / "cases" / "discovered" / "registry-2026-symmetric-body-affine-torque.toml"
)


def _script():
    spec = importlib.util.spec_from_file_location("classify", ROOT / "scripts" / "classify.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow  # about a minute of computing (19 free parameters)
def test_the_kovalevskaya_body_with_a_gradient_torque_has_two_special_sets():
    case = load_case(FAMILY)
    free = list(case.parameters)
    assert len(free) == 19
    options = search_options(case, degree=4, weights={"M": 1, "gamma": 2}, free=free)
    found = discover(case, options, catalog=catalog_index())
    assert found.complete, found.coverage
    assert not found.generic.integrals
    gyrostat, quadratic = sorted(found.special, key=lambda s: "k1 = 0" not in s.when)
    zero = {f"{p} = 0" for p in free}
    assert set(gyrostat.when) == zero - {"k3 = 0"}  # k = k3 e3, the rest 0
    assert any(
        s.case == "yehia-1986-kovalevskaya-gyrostat" and s.claims == ("K",)
        for s in gyrostat.same_as
    )
    assert not any(st.new for st in gyrostat.status)
    assert set(quadratic.when) == zero - {"k1 = 0", "p33 = 0"} | {"p33 = 1/k1"}
    assert "pleshakov-2007-generalized-grioli" in {s.case for s in quadratic.same_as}
    # of the catalog's cases, only the one written from this search claims its integral
    claimed = {s.case: s.claims for s in quadratic.same_as if s.claims}
    assert claimed == {DISCOVERED.stem: ("F",)}
    assert not any(st.new for st in quadratic.status)
    (integral,) = quadratic.integrals
    # the discovered case at the Kovalevskaya body's values holds the same integral
    k1 = case.parameters["k1"]
    written = load_case(DISCOVERED)
    p = written.parameters
    (claim,) = [c for c in written.claims if c.label == "F"]
    at = claim.expression.expr.xreplace({p["A"]: 2, p["C"]: 1, p["a"]: 1, p["lam"]: 1 / k1})
    names = {str(s): s for s in at.free_symbols}
    ratio = sp.cancel(at / sp.sympify(integral, locals=names))
    assert ratio.is_number and ratio != 0
    # the script's table names both sets and the identification
    text = _script().table("kovalevskaya", search_document(found))
    assert "yehia-1986-kovalevskaya-gyrostat" in text and "p33 = 1/k1" in text
    assert "complete: yes" in text


@pytest.mark.slow  # about 15 s of computing (8 free parameters)
def test_wolf_and_efimovskayas_family_at_the_kovalevskaya_ratio_is_classified_completely():
    # Wolf, Efimovskaya, Regular and Chaotic Dynamics 8 (2003) 155-162: at A = diag(1, 1, 2)
    # the quartic cases are the Kovalevskaya gyrostat and Sokolov's case; the locus has
    # quadric components (c22**2 n3**2 - c22 m2 n3 - c22 + m2**2/4 + 1/4 = 0 in a slice)
    # that only a parametrisation through the discriminant makes rational
    case = load_case(ROOT / "data" / "families" / "wolf-e3-kovalevskaya-ratio.toml")
    free = list(case.parameters)
    options = search_options(case, degree=4, weights={"M": 1, "gamma": 1}, free=free)
    found = discover(case, options, catalog=catalog_index())
    assert found.complete, found.coverage
    sets = {frozenset(s.when): s for s in found.special}
    gyrostat = sets[frozenset({"b31 = 0", "b32 = 0", "c11 = 0", "c12 = 0", "c22 = 0"})]
    assert "wolf-2003-e3-kovalevskaya-gyrostat" in {s.case for s in gyrostat.same_as}
    # Sokolov's case in every rotation about the axis, one set
    (sokolov,) = [s for s in found.special if "c22 = b31**2/4 + b32**2/4" in s.when]
    assert {"c12 = 0", "c11 = b31**2/4 + b32**2/4"} <= set(sokolov.when)
    assert "wolf-2003-e3-sokolov-linear" in {s.case for s in sokolov.same_as}
    assert not any(st.new for st in sokolov.status)
    assert not any("parametrisation" in c for c in found.coverage)


@pytest.mark.slow  # about 10 s of computing (8 free parameters)
def test_wolfs_family_at_the_goryachev_chaplygin_ratio_on_s_zero_finds_its_cubic_case():
    # at A = diag(1, 1, 4) the list's integrals are cubic on s = 0: Goryachev-Chaplygin's
    # case, with its gyrostat n3, any linear potential and M3-gamma terms balanced by
    # c11 = c22 = (b31**2 + b32**2)/16
    case = load_case(ROOT / "data" / "families" / "wolf-e3-goryachev-chaplygin-ratio.toml")
    free = list(case.parameters)
    options = search_options(case, degree=3, weights={"M": 1, "gamma": 1}, free=free, on=["s = 0"])
    found = discover(case, options, catalog=catalog_index())
    assert found.complete, found.coverage
    (chaplygin,) = [s for s in found.special if "c12 = 0" in s.when and "m1 = 0" not in s.when]
    assert set(chaplygin.when) == {
        "c11 = b31**2/16 + b32**2/16",
        "c12 = 0",
        "c22 = b31**2/16 + b32**2/16",
    }
    assert "wolf-2003-e3-goryachev-chaplygin-all-s" in {s.case for s in chaplygin.same_as}
    assert not any(st.new for st in chaplygin.status)
    # the only other set: the body symmetric about its axis, with M3
    (symmetric,) = [s for s in found.special if s is not chaplygin]
    assert symmetric.integrals == ("M3",)
