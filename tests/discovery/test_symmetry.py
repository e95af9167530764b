"""Symmetries of the field split the ansatz, and the search's answer stays the same.

Each symmetry found is checked again here, independently of the ring arithmetic that
found it: X(G x) = +-G X(x) with sympy expressions of the equations of motion. A family
whose symmetry one term breaks must not be split: what it finds with the split and
without it must be the same (integrals, special sets, counts, completeness).
"""

from __future__ import annotations

import pytest
import sympy as sp

from registry.discovery.integrals import KernelCache
from registry.discovery.linear import GF_PRIME, Field, Span
from registry.discovery.search import _system, discover, search_options
from registry.discovery.symmetry import (
    Decomposition,
    SignedPermutation,
    _characters,
    rotations,
    signed_permutations,
)
from registry.language.casefile import parse_case_text
from registry.language.forms import with_values as substituted
from registry.mathematics import mechanics as mech
from registry.mathematics.case_mechanics import CaseMechanics
from tests.helpers.samples import family


def system_of(case, **options):
    opts = search_options(case, **options)
    free = [case.parameters[f] for f in opts.free]
    return _system(opts, CaseMechanics(case), free)[0]


def holds(case, g: SignedPermutation) -> bool:
    """X(G x) == eps G X(x) for the case's own equations of motion, in sympy."""
    field = [sp.sympify(x).subs(mech.s, mech.S_VALUE) for x in CaseMechanics(case).field]
    state = list(mech.STATE)
    image = {x: s * state[j] for x, (j, s) in zip(state, g.images, strict=True)}
    eps = -1 if g.reversing else 1
    return all(
        sp.simplify(field[i].xreplace(image) - eps * s * field[j]) == 0
        for i, (j, s) in enumerate(g.images)
    )


LAGRANGE = """
id = "lagrange-test"
title = "A = B = 1, C = 1/2, centre of mass on the axis{extra_title}"
[source]
citation = "test"
[parameters]
z = "nonzero"
{extra_param}
[system]
inertia = ["1", "1", "1/2"]
potential = "z*gamma3{extra}"
"""


def lagrange(extra: str = "", param: str = ""):
    text = LAGRANGE.format(
        extra=extra,
        extra_title=f" plus {extra}" if extra else "",
        extra_param=f'{param} = "real"' if param else "",
    )
    return parse_case_text(text, "lagrange-test.toml")


def same_search(a, b) -> bool:
    return (a.generic, a.special, a.complete, a.dimensions, a.known) == (
        b.generic,
        b.special,
        b.complete,
        b.dimensions,
        b.known,
    )


def test_lagrange_top_turns_about_its_axis_and_reflects():
    system = system_of(lagrange(), degree=8)
    assert [r.axis for r in rotations(system.field)] == [2]
    found = signed_permutations(system.field)
    swaps = [g for g in found if not g.diagonal]
    assert swaps and all(g.images[0][0] == 1 and g.images[3] in ((4, 1), (4, -1)) for g in swaps)
    assert all(holds(lagrange(), g) for g in found)
    assert system.decomposition is not None
    assert "split into" in system.symmetry_note and "rotation about axis 3" in system.symmetry_note


def test_heavy_top_with_centre_in_the_xz_plane_has_the_reflection_of_the_brief():
    case = family("heavy-top-b-c-z0")
    system = system_of(case, degree=4, free=["b", "c", "z0"])
    found = signed_permutations(system.field)
    texts = {g.text() for g in found}
    assert "M1 -> -M1, M3 -> -M3, gamma2 -> -gamma2" in texts
    assert all(g.diagonal for g in found)  # b, c free: no axis may be swapped
    assert rotations(system.field) == []
    assert all(holds(case, g) for g in found)
    # sign changes only: the blocks of the sparsity are their eigenspaces already
    assert system.decomposition is None


def test_every_class_vector_is_an_eigenvector_and_the_classes_span_the_ansatz():
    system = system_of(lagrange(), degree=6)
    split = system.decomposition
    assert sum(len(c) for c in split.classes) == len(system.columns)
    pad = (0,) * (len(system.ring.gens) - system.n)
    for combos in split.classes:
        for combo in combos:
            poly = system.ring({(*system.columns[j][0], *pad): c for j, c in combo.items()})
            for g in split.group:
                assert g.act(poly) in (poly, -poly)


@pytest.mark.parametrize(
    "name, options",
    [
        ("heavy-top-lam", dict(degree=4, free=["lam"])),
        ("heavy-top-lam", dict(degree=3, free=["lam"], on=["s = 0"])),
        ("lagrange-lam", dict(degree=4, free=["lam"])),
        ("lagrange-lam", dict(degree=4, free=["lam"], on=["s = 0"])),
        ("heavy-top-b-c-z0", dict(degree=4, free=["b", "c", "z0"])),
        ("kirchhoff-diagonal", dict(degree=2, weights=(1, 1), free=["B", "C", "b1", "b2", "b3"])),
        ("euler-top", dict(degree=4)),
        ("clebsch-b3", dict(degree=2, weights=(1, 1), free=["b3"])),
        ("lagrange-lam", dict(degree=8)),
        ("lagrange-lam", dict(degree=6, free=["lam"])),
    ],
)
def test_the_search_is_the_same_with_and_without_symmetries(name, options):
    case = family(name)
    opts = search_options(case, **options)
    split = discover(case, opts, budget=300)
    whole = discover(case, opts, budget=300, symmetries=False)
    assert split.complete and same_search(split, whole)
    assert "symmetries: not used" in whole.method
    assert "symmetries: " in split.method


def test_the_split_sets_are_named_in_the_method():
    """At degree 6 the heavy top's ansatz has blocks large enough to split: the spherical
    top (lam = 1, centre of mass on axis 1) is split, the generic values are not (sign
    changes only), and the small blocks of degree 4 are not even looked at."""
    case = family("heavy-top-lam")
    found = discover(case, search_options(case, degree=6, free=["lam"]), budget=300)
    parts = [p for p in found.method.split("; ") if p.startswith("symmetries")]
    assert parts[0].startswith("symmetries: none used (found: ") and "sign changes" in parts[0]
    (spherical,) = [p for p in parts if p.startswith("symmetries where lam = 1: the group")]
    assert "rotation about axis 1" in spherical
    small = discover(case, search_options(case, degree=4, free=["lam"]), budget=300)
    assert "symmetries: not sought (the sparsity's largest block has" in small.method


@pytest.mark.parametrize(
    "extra", ["", " + gamma1**2/10", " + gamma1*gamma2", " + gamma1", " + gamma2**3"]
)
def test_one_term_that_breaks_the_symmetry_is_noticed(extra):
    case = lagrange(extra)
    system = system_of(case, degree=3)
    found = signed_permutations(system.field)
    assert all(holds(case, g) for g in found)
    axial = [r.axis for r in rotations(system.field)]
    swaps = [g for g in found if not g.diagonal]
    if extra:
        assert axial == []
    else:
        assert axial == [2] and swaps
    if extra in (" + gamma1**2/10", " + gamma1"):
        assert swaps == []  # gamma1 and gamma2 no longer play the same part
    opts = search_options(case, degree=3)
    assert same_search(discover(case, opts), discover(case, opts, symmetries=False))


def test_a_family_whose_symmetry_one_parameter_breaks_is_split_only_where_it_vanishes():
    case = lagrange(" + e*gamma1**2", "e")
    opts = search_options(case, degree=2, free=["e"])
    split = discover(case, opts)
    whole = discover(case, opts, symmetries=False)
    assert same_search(split, whole)
    assert [s.when for s in split.special] == [("e = 0",)]
    assert "M3" in split.special[0].integrals
    generic = [p for p in split.method.split("; ") if p.startswith("symmetries: ")]
    assert generic and "split into" not in generic[0]
    at_zero = substituted(case, {case.parameters["e"]: sp.Integer(0)})
    assert system_of(at_zero, degree=6).decomposition is not None
    assert system_of(case, degree=6).decomposition is None


def test_on_s0_a_swap_that_moves_the_leading_term_is_not_used():
    """Normal forms modulo s = 0 (leading term M1 gamma1) commute only with maps that
    keep the leading terms: the swap of axes 1 and 2 does not, that of 2 and 3 does."""
    lag = system_of(lagrange(), degree=8, on=["s = 0"])
    assert lag.decomposition is None and "none used" in lag.symmetry_note
    kirchhoff = family("kirchhoff-diagonal")
    values = {kirchhoff.parameters["C"]: kirchhoff.parameters["B"]}
    values[kirchhoff.parameters["b3"]] = kirchhoff.parameters["b2"]
    axial = substituted(kirchhoff, values)
    system = system_of(axial, degree=5, weights=(1, 1), on=["s = 0"])
    assert system.decomposition is not None
    for g in system.decomposition.group:
        assert holds(axial, g)
        assert {j for j, _ in g.images[:3]} == {0, 1, 2} and g.images[0][0] == 0


def test_a_split_along_a_map_that_is_no_symmetry_would_change_the_answer():
    """The check has teeth: forced on the field it does not keep, a split claims
    integrals that do not exist (what ``signed_permutations`` refuses to let happen)."""
    unbroken = system_of(lagrange(), degree=6)
    broken_case = lagrange(" + gamma1**2/10")
    broken = system_of(broken_case, degree=4)
    assert broken.decomposition is None
    wrong = unbroken.decomposition
    assert not any(holds(broken_case, g) for g in wrong.group if not g.diagonal)
    forced = Decomposition(_characters(broken, list(wrong.group)), wrong.group, "forced")
    point = {i: 7 + 3 * i for i in range(len(broken.params))}
    fld = Field(GF_PRIME, broken.params, point)

    def integrals(blocks) -> list:
        broken.blocks = blocks
        return KernelCache(broken, fld).kernel(4)

    honest = integrals(broken._blocks())
    claimed = integrals(broken._blocks([forced]))
    both = Span(fld)
    for v in [*honest, *claimed]:
        both.add(v)
    assert both.dim > len(honest)  # the forced split "finds" what is no integral
