"""Where a family with several free parameters can pass the Painlevé test: the parameter
space stratified by the necessary conditions of its balances (``painleve_strata``).

The passing sets are checked against what is known of each family independently of the
method: a planted field whose one compatibility condition is written into it, and the
heavy top, where Kovalevskaya (Acta Math. 12 (1889) 177) found that the general
solution is single-valued only for Euler's top (centre of mass at the fixed point),
Lagrange's (two equal moments, the centre on the symmetry axis) and her own (moments
(2, 2, 1) up to scale, the centre in the plane of the equal ones), the spherical top
(all moments equal) being Lagrange's about any axis. With moments (1, b, c) each of
Lagrange's and Kovalevskaya's cases appears once per choice of the equal pair.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

from registry.discovery.exponents import analyse_case, case_field, exponent_options
from registry.discovery.painleve_strata import (
    _admissible,
    _ratio,
    half_integer_strata,
    painleve_strata,
)
from registry.errors import WeightedFieldError
from registry.language.casefile import load_case
from registry.mathematics.exponent_analysis import exponents
from registry.mathematics.exponent_families import kind_of
from tests.helpers.samples import FAMILIES, TEST_DATA

EXPONENTS = TEST_DATA / "exponents"


def strata_of(path, free, stratify=painleve_strata):
    case = load_case(path)
    found = case_field(case, exponent_options(case, free=free))
    return stratify(found.variables, found.field, found.weights, found.free)


def sets(strata) -> set[frozenset]:
    """The passing sets as sets of equations 'p = value' (order-free)."""
    return {frozenset(sets_of(s)) for s in strata.passing}


def sets_of(s) -> set[str]:
    return {f"{p} = {sp.sstr(v)}" for p, v in s.values.items()}


def members_pass(strata, path, free) -> None:
    """Two members of each passing set, at small rational values of its free parameters,
    analysed on their own (the plain analysis of a field with numbers): each passes."""
    case = load_case(path)
    found = case_field(case, exponent_options(case, free=free))
    rng = random.Random(7)
    for s in strata.passing:
        for _ in range(2):
            pick = {p: sp.Rational(rng.randint(1, 9), rng.randint(1, 5)) for p in s.free}
            values = {k: sp.sympify(v).xreplace(pick) for k, v in s.values.items()}
            values |= {p: v for p, v in pick.items() if p in set(found.free)}
            field = [sp.sympify(e).xreplace(values) for e in found.field]
            analysis = exponents(found.variables, field, found.weights)
            assert analysis.painleve_passes, (s.text(), values, analysis.conditions)


# ------------------------------------------------------------------ real points


def test_a_positive_parameter_set_to_a_value_that_cannot_be_positive_is_not_admissible():
    p, q = sp.symbols("p q", positive=True)
    w = sp.Symbol("w", real=True)
    assert not _admissible({q: -2 * p * (p + 1) / (2 * p + 1)})
    assert _admissible({q: p / (2 * p + 1)})
    assert _admissible({q: -w / (2 * p + 1)})  # of either sign as w varies
    assert _admissible({sp.Symbol("q", real=True): -2 * p})


# ------------------------------------------------------------------ families


def test_a_planted_condition_gives_exactly_its_parabola():
    """y' = 5xy + (a - b^2) z^2: the condition at resonance 8 is -(a - b^2) f4^2 = 0, so
    the test passes on a = b^2 and nowhere else, and the list is complete."""
    found = strata_of(EXPONENTS / "planted-family.toml", ["a", "b"])
    assert sets(found) == {frozenset({"a = b**2"})}
    (parabola,) = found.passing
    assert [str(p) for p in parabola.free] == ["b"]
    assert parabola.analysis is not None and parabola.analysis.painleve_passes
    assert found.complete and not found.undecided
    members_pass(found, EXPONENTS / "planted-family.toml", ["a", "b"])


def test_a_mutated_condition_moves_the_passing_set(tmp_path):
    """The same field with the coupling a - b^2 - 1: the set moves to a = b^2 + 1."""
    text = (EXPONENTS / "planted-family.toml").read_text()
    path = tmp_path / "mutated.toml"
    path.write_text(text.replace("(a - b**2)*z**2", "(a - b**2 - 1)*z**2"))
    found = strata_of(path, ["a", "b"])
    assert sets(found) == {frozenset({"a = b**2 + 1"})}
    assert found.complete


def test_the_symmetric_top_with_its_centre_off_the_plane_keeps_lagrange_and_the_sphere():
    """Moments (1, 1, c), centre (x0, 0, 1): Lagrange's top x0 = 0 and the spherical top
    c = 1 pass; Kovalevskaya's c = 1/2 does not (its centre must lie in the equatorial
    plane); complete."""
    found = strata_of(FAMILIES / "heavy-top-c-x0.toml", ["c", "x0"])
    assert sets(found) == {frozenset({"x0 = 0"}), frozenset({"c = 1"})}
    assert found.complete
    by_set = {frozenset(map(str, s.values)): s for s in found.passing}
    lagrange = by_set[frozenset({"x0"})].analysis
    assert lagrange is not None and lagrange.painleve_passes
    members_pass(found, FAMILIES / "heavy-top-c-x0.toml", ["c", "x0"])
    # and a value outside both sets fails, as the completed list says
    case = load_case(FAMILIES / "heavy-top-c-x0.toml")
    field = case_field(case, exponent_options(case, free=["c", "x0"]))
    c, x0 = field.free
    outside = [sp.sympify(e).xreplace({c: 3, x0: 2}) for e in field.field]
    assert not exponents(field.variables, outside, field.weights).painleve_passes


def test_kovalevskayas_moments_pass_only_with_the_centre_in_the_plane_of_the_equal_ones():
    """Moments (1, 1, 1/2), centre (x0, y0, z0): the exponents of the balances with
    gamma != 0 vary with the centre. The two balances of a component are complex
    conjugate, so integer exponents need the part of their characteristic polynomial in
    gamma3 to vanish: z0 = 0, Kovalevskaya's case. With Lagrange's x0 = y0 = 0 the list is
    complete."""
    path = FAMILIES / "kovalevskaya-moments-centre.toml"
    found = strata_of(path, ["x0", "y0", "z0"])
    assert sets(found) == {frozenset({"z0 = 0"}), frozenset({"x0 = 0", "y0 = 0"})}
    assert found.complete
    members_pass(found, path, ["x0", "y0", "z0"])


@pytest.mark.parametrize("moment", ["1/3", "1/4", "2"])
def test_other_moments_with_a_general_centre_keep_only_lagrange(tmp_path, moment):
    """The same with moments (1, 1, c) for c = 1/3, 1/4 (Goryachev-Chaplygin's ratio,
    whose exponents are not all integers) and 2: only Lagrange's top passes."""
    text = (FAMILIES / "kovalevskaya-moments-centre.toml").read_text()
    path = tmp_path / "mutated.toml"
    path.write_text(text.replace('"1", "1", "1/2"', f'"1", "1", "{moment}"'))
    found = strata_of(path, ["x0", "y0", "z0"])
    assert sets(found) == {frozenset({"x0 = 0", "y0 = 0"})}
    assert found.complete


def test_the_symmetric_top_with_its_centre_anywhere_is_kovalevskayas_selection():
    """Moments (1, 1, c), centre (x0, y0, z0), four free parameters: the spherical top,
    Lagrange's and Kovalevskaya's, and the list is complete (Kovalevskaya 1889, for the
    tops with two equal moments)."""
    path = FAMILIES / "symmetric-top-centre.toml"
    found = strata_of(path, ["c", "x0", "y0", "z0"])
    assert sets(found) == {
        frozenset({"c = 1"}),
        frozenset({"x0 = 0", "y0 = 0"}),
        frozenset({"c = 1/2", "z0 = 0"}),
    }
    assert found.complete
    members_pass(found, path, ["c", "x0", "y0", "z0"])


# ------------------------------------------------------------------ exponents in (1/2)Z


def test_goryachev_chaplygins_ratio_is_the_one_set_of_half_integer_exponents():
    """Moments (1, 1, c), centre anywhere: every exponent is in (1/2)Z on the three sets
    where the test passes and on one more, c = 1/4 with the centre in the equatorial
    plane: Goryachev-Chaplygin's top (A = B = 4C), whose balances along the third axis
    have lambda^2 - lambda + sigma, sigma = 2 (2c - 1)(b - c) / b = -3/4, among their
    exponents: -1/2 and 3/2 (derived by hand in tests/discovery/test_exponents.py).
    Complete; a member analysed on its own has half-integer exponents, and a member
    with its centre off the plane has some exponent outside (1/2)Z."""
    path = FAMILIES / "symmetric-top-centre.toml"
    found = strata_of(path, ["c", "x0", "y0", "z0"], half_integer_strata)
    assert sets(found) == {
        frozenset({"c = 1"}),
        frozenset({"x0 = 0", "y0 = 0"}),
        frozenset({"c = 1/2", "z0 = 0"}),
        frozenset({"c = 1/4", "z0 = 0"}),
    }
    assert found.complete
    kinds = {frozenset(sets_of(s)): kind_of(s.analysis) for s in found.passing}
    assert kinds[frozenset({"c = 1/2", "z0 = 0"})] == "integer"  # Kovalevskaya's
    (gc,) = [s for s in found.passing if sets_of(s) == {"c = 1/4", "z0 = 0"}]
    assert kind_of(gc.analysis) == "half-integer"
    assert sp.Rational(-1, 2) in [v for b in gc.analysis.balances for v in b.exponents.values]
    case = load_case(path)
    field = case_field(case, exponent_options(case, free=["c", "x0", "y0", "z0"]))
    c, x0, y0, z0 = field.free
    at = {c: sp.Rational(1, 4), x0: 3, y0: -2, z0: 0}
    member = exponents(field.variables, [e.xreplace(at) for e in field.field], field.weights)
    assert kind_of(member) == "half-integer" and not member.painleve_passes
    outside = {**at, z0: 1}  # the centre off the plane
    member = exponents(field.variables, [e.xreplace(outside) for e in field.field], field.weights)
    assert kind_of(member) not in ("integer", "half-integer")


def test_moments_left_free_are_classified_by_their_ratio():
    """Moments (A, A, C) both free, the centre in the equatorial plane: the exponents
    that vary depend on A/C only (scaling the moments is a symmetry), so the values of
    the ratio are sought as for one parameter. The test passes on the spherical top
    A = C and Kovalevskaya's A = 2C (and where the centre is the fixed point); every
    exponent is in (1/2)Z on those and on Goryachev and Chaplygin's A = 4C. Both lists
    complete (before, no set was decided: the exponents vary with two parameters)."""
    path = FAMILIES / "symmetric-top-moments-free.toml"
    free = ["A", "C", "x0", "y0"]
    found = strata_of(path, free)
    assert sets(found) == {
        frozenset({"A = C"}),
        frozenset({"A = 2*C"}),
        frozenset({"x0 = 0", "y0 = 0"}),
    }
    assert found.complete, found.undecided
    members_pass(found, path, free)
    half = strata_of(path, free, half_integer_strata)
    assert sets(half) == sets(found) | {frozenset({"A = 4*C"})}
    assert half.complete, half.undecided
    (gc,) = [s for s in half.passing if sets_of(s) == {"A = 4*C"}]
    assert kind_of(gc.analysis) == "half-integer"


def test_a_planted_ratio_gives_its_family_and_the_values_without_a_leading_part_are_named():
    """dx/dt = a x², dy/dt = b x y: exponents -1 and 1 - b/a. Every exponent is in
    (1/2)Z exactly on b = a (n1/2 + 1), n1 an integer, and on a = 0 (x constant, y an
    exponential). For the ARS test those resonances move with n1, which the series
    cannot follow: said so. Where a = b = 0 the field vanishes: named, not a crash."""
    path = EXPONENTS / "planted-ratio.toml"
    half = strata_of(path, ["a", "b"], half_integer_strata)
    assert sets(half) == {frozenset({"b = a*(n1/2 + 1)"}), frozenset({"a = 0"})}
    (indexed,) = [s for s in half.passing if "b" in map(str, s.values)]
    n1 = next(p for p in indexed.free if str(p) == "n1")
    a, b = sp.symbols("a b", real=True)
    for k in (-3, 0, 5):  # members: the exponent 1 - b/a is -k/2
        ratio = sp.sympify(indexed.values[b]).xreplace({n1: k}) / a
        assert sp.simplify(1 - ratio) == sp.Rational(-k, 2)
    assert [u for u in half.undecided if "no leading part" in u]
    found = strata_of(path, ["a", "b"])
    assert sets(found) == {frozenset({"a = 0"})}
    assert any("move with n1" in u for u in found.undecided)
    assert not found.complete


def test_exponents_of_one_coefficient_cut_the_set_before_those_of_two():
    """Two quartic oscillators, x^4/4 + a x^2 y^2/2 + b y^4/4: the balances on the axis
    y = 0 have exponents in a alone, the others in a and b. Their candidates for a cut
    the plane first, and the rest is examined on each line. Found: Ramani, Dorizzi and
    Grammaticos's 1 : 2 : 1 (a = b = 1) and 1 : 6 : 1 (a = 3, b = 1), and two points of
    the separable a = 0; not complete, the family a = 1 - n1/2 with b free named as
    undecided. Before, nothing was decided (the exponents vary with two parameters)."""
    path = FAMILIES / "quartic-oscillators.toml"
    found = strata_of(path, ["a", "b"])
    assert sets(found) == {
        frozenset({"a = 1", "b = 1"}),
        frozenset({"a = 3", "b = 1"}),
        frozenset({"a = 0", "b = 1"}),
        frozenset({"a = 0", "b = 0"}),
    }
    assert not found.complete
    assert any(u.startswith("a = 1 - n1/2 (n1 integer)") for u in found.undecided)
    members_pass(found, path, ["a", "b"])


def test_roots_that_depend_on_a_ratio_only_are_recognised():
    lam = sp.Symbol("lambda")
    a, c = sp.symbols("A C", positive=True)
    x = sp.Symbol("x", real=True)
    homogeneous = [lam**2 - lam + (2 * a - c) * (a - c) / a**2, a * lam - 3 * c]
    assert _ratio(homogeneous, {a, c}) == (a, c)  # the first positive one scales
    assert _ratio([lam - x / a], {a, x}) == (a, x)
    assert _ratio([lam**2 - lam + (2 * a - c) * (a - 1) / a**2], {a, c}) is None
    assert _ratio([lam**2 - a * lam + c], {a, c}) is None  # degrees 1 and 1 differ from 0
    assert _ratio([lam - a / c], {a, c, x}) is None  # three parameters


@pytest.mark.parametrize(("moment", "expected"), [("1/4", {"z0 = 0"}), ("1/3", set())])
def test_the_half_integer_sets_move_with_the_moments(tmp_path, moment, expected):
    """Moments (1, 1, 1/4) keep the equatorial plane z0 = 0 beside Lagrange's axis;
    (1, 1, 1/3) keep only the axis."""
    text = (FAMILIES / "kovalevskaya-moments-centre.toml").read_text()
    path = tmp_path / "mutated.toml"
    path.write_text(text.replace('"1", "1", "1/2"', f'"1", "1", "{moment}"'))
    found = strata_of(path, ["x0", "y0", "z0"], half_integer_strata)
    assert sets(found) == {frozenset({"x0 = 0", "y0 = 0"})} | (
        {frozenset(expected)} if expected else set()
    )
    assert found.complete


@pytest.mark.slow
def test_a_curve_without_a_solvable_parameter_is_parametrised_and_passes():
    """Moments (1 + a^2 c^2, c + 3/4, 1), centre on the third axis: Lagrange's top on the
    quartic a^2 c^2 = c - 1/4, reached through a new parameter w1; the spherical top
    (a = 0, c = 1/4) and Kovalevskaya's (1, 1/2, 1) at a = 0, c = -1/4."""
    path = FAMILIES / "quadric-moments.toml"
    found = strata_of(path, ["a", "c"])
    assert sets(found) == {
        frozenset({"c = w1**2/4 + 1/4", "a = 2*w1/(w1**2 + 1)"}),
        frozenset({"a = 0", "c = 1/4"}),
        frozenset({"a = 0", "c = -1/4"}),
    }
    members_pass(found, path, ["a", "c"])


def test_the_family_document_carries_the_passing_sets_and_says_what_they_prove():
    case = load_case(FAMILIES / "heavy-top-c-x0.toml")
    result = analyse_case(case, exponent_options(case, free=["c", "x0"]), budget=120)
    found = result.document["painleve_sets"]
    assert sorted(s["when"] for s in found["passing"]) == [["c = 1"], ["x0 = 0"]]
    assert found["complete"] and found["undecided"] == [] and found["strata"] >= 3
    assert all(s["painleve"]["passes"] for s in found["passing"])
    statement = result.document["statement"]
    assert "passes for the generic members of: " in statement
    assert "at every admissible real value outside these sets it fails" in statement


def test_the_strata_of_one_depth_are_examined_through_the_mapper_given():
    """Each depth's strata go to the mapper in one call (a worker pool's map), and the
    outcome is the one found in process."""
    case = load_case(FAMILIES / "heavy-top-c-x0.toml")
    found = case_field(case, exponent_options(case, free=["c", "x0"]))
    calls: list[int] = []

    def mapper(fn, items):
        calls.append(len(items))
        return [fn(item) for item in items]

    args = (found.variables, found.field, found.weights, found.free)
    mapped, here = painleve_strata(*args, mapper=mapper), painleve_strata(*args)
    assert calls[0] == 1 and len(calls) >= 2 and sum(calls) == mapped.visited
    assert sets(mapped) == sets(here) and mapped.undecided == here.undecided


def test_past_its_budget_the_stratification_says_what_it_did_not_examine():
    case = load_case(FAMILIES / "heavy-top-five.toml")
    found = case_field(case, exponent_options(case, free=["b", "c", "x0", "y0", "z0"]))
    strata = painleve_strata(found.variables, found.field, found.weights, found.free, budget=5)
    assert not strata.complete
    assert any(u.startswith("the time (5 s) ran out after") for u in strata.undecided)
    assert strata.seconds < 30


@pytest.mark.slow
def test_with_three_distinct_moments_only_eulers_top_passes_and_the_list_is_complete():
    """Moments (1, 1 + p, 1 + p + q), p, q > 0, centre anywhere: every heavy top with
    distinct moments up to the order of the axes and the scale of time. The test passes
    only where the centre is the fixed point, and the list is complete: the hypersurfaces
    the five-parameter family leaves undecided have, at these signs, real points only on
    rational sets (a quadric whose terms are all >= 0, quartics in x0^2 whose
    discriminant is never positive, a conic through a rational point). With the family
    of two equal moments (complete above), this is Kovalevskaya's 1889 selection."""
    path = FAMILIES / "heavy-top-distinct-moments.toml"
    free = ["p", "q", "x0", "y0", "z0"]
    found = strata_of(path, free)
    assert sets(found) == {frozenset({"x0 = 0", "y0 = 0", "z0 = 0"})}
    assert found.complete, found.undecided
    members_pass(found, path, free)


@pytest.mark.slow
def test_the_heavy_top_with_all_its_parameters_selects_euler_lagrange_and_kovalevskaya():
    """Moments (1, b, c), centre (x0, y0, z0): the passing sets are Euler's, the spherical
    top, and Lagrange's and Kovalevskaya's once for each pair of equal moments; the sets
    left undecided are only those without a rational parametrisation (irrational values,
    non-rational hypersurfaces), named one by one: the list is not called complete."""
    found = strata_of(FAMILIES / "heavy-top-five.toml", ["b", "c", "x0", "y0", "z0"])
    assert sets(found) == {
        frozenset({"x0 = 0", "y0 = 0", "z0 = 0"}),  # Euler
        frozenset({"b = 1", "c = 1"}),  # the spherical top
        frozenset({"b = 1", "x0 = 0", "y0 = 0"}),  # Lagrange, moments (1, 1, c)
        frozenset({"c = 1", "x0 = 0", "z0 = 0"}),  # Lagrange, moments (1, b, 1)
        frozenset({"b = c", "y0 = 0", "z0 = 0"}),  # Lagrange, moments (1, c, c)
        frozenset({"b = 1", "c = 1/2", "z0 = 0"}),  # Kovalevskaya (2, 2, 1)
        frozenset({"b = 1/2", "c = 1", "y0 = 0"}),  # Kovalevskaya (2, 1, 2)
        frozenset({"b = 2", "c = 2", "x0 = 0"}),  # Kovalevskaya (1, 2, 2)
    }
    members_pass(found, FAMILIES / "heavy-top-five.toml", ["b", "c", "x0", "y0", "z0"])
    # b**2 = 1/2, quartics in the centre's coordinates
    assert all("no rational parametrisation" in u for u in found.undecided), found.undecided


@pytest.mark.slow
def test_the_heavy_top_with_no_moment_normalised_selects_the_same_eight_sets():
    """Moments (A, B, C) and centre (x0, y0, z0), all six free: the sets of the family
    with moments (1, b, c) above, homogeneous now, and again only sets without a
    rational parametrisation left. The symmetric tops with the centre in their
    equatorial plane (A = B, z0 = 0 and its permutations), whose exponents vary with
    two moments, are decided by their ratio (before, each was left undecided)."""
    path = FAMILIES / "heavy-top-six.toml"
    free = ["A", "B", "C", "x0", "y0", "z0"]
    found = strata_of(path, free)
    assert sets(found) == {
        frozenset({"x0 = 0", "y0 = 0", "z0 = 0"}),  # Euler
        frozenset({"A = C", "B = C"}),  # the spherical top
        frozenset({"A = B", "x0 = 0", "y0 = 0"}),  # Lagrange, about each axis
        frozenset({"A = C", "x0 = 0", "z0 = 0"}),
        frozenset({"B = C", "y0 = 0", "z0 = 0"}),
        frozenset({"A = 2*C", "B = 2*C", "z0 = 0"}),  # Kovalevskaya, (2, 2, 1) and so on
        frozenset({"A = C", "B = C/2", "y0 = 0"}),
        frozenset({"A = C/2", "B = C", "x0 = 0"}),
    }
    assert found.undecided
    assert all("no rational parametrisation" in u for u in found.undecided), found.undecided
    members_pass(found, path, free)


def test_henon_heiles_passes_where_chang_tabor_and_weiss_found_it():
    """H = (px² + py²)/2 + (A x² + B y²)/2 + x²y + e y³/3 (C/D = -e in Chang, Tabor and
    Weiss, J. Math. Phys. 23 (1982) 531), weights (2, 2, 3, 3): the test passes exactly
    at e = 6 (any A, B) and at e = 1 with A = B, their two Painlevé cases, and the list
    is complete. Every exponent is in (1/2)Z exactly at e = 1, 2, 6 and 16: their weak
    Painlevé case C/D = -16 (3/2 and 7/2), and e = 2, where the balances with x != 0
    meet the one with x = 0, whose exponent 0 then fails the test at every A, B."""
    path = FAMILIES / "henon-heiles.toml"
    case = load_case(path)
    weights = {"x": 2, "y": 2, "px": 3, "py": 3}
    found = case_field(case, exponent_options(case, weights, free=["e", "A", "B"]))
    system = (found.variables, found.field, found.weights, found.free)
    passing = painleve_strata(*system)
    assert sets(passing) == {frozenset({"e = 6"}), frozenset({"e = 1", "A = B"})}
    assert passing.complete
    half = half_integer_strata(*system)
    assert sets(half) == {frozenset({f"e = {v}"}) for v in (1, 2, 6, 16)}
    assert half.complete
    kinds = {frozenset(sets_of(s)): kind_of(s.analysis) for s in half.passing}
    assert kinds[frozenset({"e = 16"})] == "half-integer"
    e, a, b = found.free

    def member(values):
        field = [sp.sympify(v).xreplace(values) for v in found.field]
        return exponents(found.variables, field, found.weights)

    assert member({e: 6, a: sp.Rational(1, 2), b: 3}).painleve_passes
    assert member({e: 1, a: 2, b: 2}).painleve_passes
    assert not member({e: 1, a: 1, b: 2}).painleve_passes  # A = B matters
    assert not member({e: 2, a: 1, b: 3}).painleve_passes  # the exponent 0


def test_lorenz_passes_exactly_where_tabor_and_weiss_found_it():
    """dx/dt = sigma (y - x), dy/dt = r x - y - x z, dz/dt = x y - b z, with the default
    weights (x: 1, y, z: 2, which keep every component in the leading part): the test
    passes exactly at (sigma, b, r) = (1/2, 1, 0), (1, 2, 1/9) and (1/3, 0, r), Tabor
    and Weiss's list (Phys. Rev. A 24 (1981) 2157), and at sigma = 0, where x is a
    constant and the system linear; the list is complete. Every exponent is an integer
    (-1, 2, 4) for every value, so the half-integer list is the whole space."""
    path = FAMILIES / "lorenz.toml"
    found = strata_of(path, ["sigma", "r", "b"])
    assert sets(found) == {
        frozenset({"sigma = 0"}),
        frozenset({"sigma = 1/3", "b = 0"}),
        frozenset({"sigma = 1", "r = 1/9", "b = 2"}),
        frozenset({"sigma = 1/2", "r = 0", "b = 1"}),
    }
    assert found.complete
    members_pass(found, path, ["sigma", "r", "b"])
    half = strata_of(path, ["sigma", "r", "b"], half_integer_strata)
    assert sets(half) == {frozenset()} and half.complete
    case = load_case(path)
    system = case_field(case, exponent_options(case, free=["sigma", "r", "b"]))
    sigma, r, b = system.free
    field = [sp.sympify(v).xreplace({sigma: 1, r: sp.Rational(1, 8), b: 2}) for v in system.field]
    assert not exponents(system.variables, field, system.weights).painleve_passes  # r moved


@pytest.mark.parametrize("stratify", [painleve_strata, half_integer_strata])
def test_the_strata_of_a_divided_field_are_refused_not_misread(stratify):
    x, y, a, b = sp.symbols("x y a b")
    with pytest.raises(WeightedFieldError, match="polynomial fields only"):
        stratify([x, y], [x**2 + b * x, a * y**3 / x], [1, 1], [a, b])
