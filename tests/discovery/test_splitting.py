"""Case splitting on the pivots: units are what the assumptions keep nonzero, every
branch's rank holds at every one of its points, and a parameter that may vanish is
split on, each point of parameter space in exactly one branch."""

from __future__ import annotations

import random

import sympy as sp

from registry.discovery.splitting import Branch, Region, _Splitter, drop_sets

REGION = Region(("b", "c", "z", "q"), 3, frozenset({0, 1}), frozenset({0, 1}))
CTX = REGION.context
B, C, Z, Q = CTX.gens()
b, c, z = sp.symbols("b c z")


def splitter() -> _Splitter:
    return _Splitter(REGION, random.Random(0))


def test_units_are_what_the_assumptions_and_the_branch_keep_nonzero():
    s, branch = splitter(), Branch([], 1)
    assert s.unit_entry(3 * B**2 * C, branch)  # monomial in positive parameters
    assert s.unit_entry(B + 2 * C + 1, branch)  # one sign where b, c > 0
    assert s.unit_entry(Z**2 + B, branch)  # z real: z**2 >= 0, b > 0
    assert s.unit_entry(Q**2 - 5, branch)  # symbolic parameter: generic
    assert not s.unit_entry(Z, branch)  # z may vanish
    assert not s.unit_entry(B - C, branch)
    assert not s.unit_entry(Z * B + 1, branch)
    branch.units[str(Z)] = Z
    assert s.unit_entry(Z * B, branch)


def test_a_parameter_that_may_vanish_is_split_on():
    # [z, b - c]: rank 1 unless z = 0 and b = c
    split = drop_sets([{0: Z, 1: B - C}], 1, REGION, random.Random(1))
    assert split.sets == [{z: 0, b: c}] and not split.undecided


def test_the_sets_are_exactly_where_the_determinant_vanishes():
    rows = [{0: B, 1: C, 2: Z}, {0: C, 1: B, 2: Z + B - C}, {0: B * Z, 1: 2 * C, 2: Z**2 + B}]
    split = drop_sets(rows, 3, REGION, random.Random(2))
    matrix = sp.Matrix(
        [[sp.sympify(str(r.get(k, 0)).replace("^", "**")) for k in range(3)] for r in rows]
    )
    det = sp.factor(matrix.det())
    assert det != 0 and not split.undecided
    for values in split.sets:  # the rank falls on every set ...
        assert sp.simplify(det.xreplace(values)) == 0
    rnd = random.Random(3)
    for _ in range(20):  # ... and every point where it falls lies in one
        point = {b: sp.Rational(rnd.randint(1, 9), rnd.randint(1, 9)), z: rnd.randint(-5, 5)}
        for cv in sp.solve(det.subs(point), c):
            if cv.is_rational and cv > 0:
                at = {**point, c: cv}
                assert any(
                    all(sp.simplify((s_ - e).xreplace(at)) == 0 for s_, e in values.items())
                    for values in split.sets
                )


def test_pivots_keep_the_rank_at_every_point_of_the_branch():
    s = splitter()
    branch = Branch([{0: B, 1: Z}, {0: C, 1: B + Z}], 2)
    s.normalise(branch)
    i, k = s.unit_pivot(branch)
    s.eliminate(branch, i, k)
    (rest,) = branch.rows
    (entry,) = rest.values()
    # b (b + z) - c z or the same from the other pivot: the 2 x 2 determinant
    det = B * (B + Z) - C * Z
    assert entry == det or entry == -det
    assert branch.need == 1


def test_several_nonlinear_equations_are_kept_together_as_an_algebraic_set():
    region = Region(("b", "c", "z"), 3)
    ctx = region.context
    b_, c_, z_ = ctx.gens()
    rows = [{0: b_**2 + c_**2 - z_**2 - 1}, {0: b_**2 - c_**2 - z_**3}]
    split = drop_sets(rows, 1, region, random.Random(4))
    assert not split.sets and not split.undecided
    (found,) = split.algebraic
    assert len(found.equations) == 2 and found.text().endswith("= 0")


def test_real_roots_where_the_assumptions_allow_them():
    from registry.discovery.splitting import _real_roots_allowed

    ctx = Region(("x", "y"), 2).context
    X, _ = ctx.gens()
    # (irreducible polynomial, real roots, positive roots, nonzero roots)
    cases = [
        (X**2 - 2, 2, 1, 2),
        (X**2 + 1, 0, 0, 0),
        (X**3 - 2, 1, 1, 1),
        (X**3 + 2, 1, 0, 1),
        (X**5 - 4 * X + 2, 3, 2, 3),  # Eisenstein at 2; roots near -1.5, 0.5, 1.2
        (2 * X + 3, 1, 0, 1),
        (X, 1, 0, 0),
        (2 * 10**41 * X**2 - 1, 2, 1, 2),  # roots +-2.2e-21: balls near 0
        (X**2 - 10**41 * X - 1, 2, 1, 2),  # roots 1e41 and -1e-41
    ]
    for poly, real, positive, nonzero in cases:
        assert _real_roots_allowed(poly, 0, False, False) == real, poly
        assert _real_roots_allowed(poly, 0, True, True) == positive, poly
        assert _real_roots_allowed(poly, 0, False, True) == nonzero, poly


def test_a_unit_under_one_region_is_not_one_under_another():
    # The nowhere-zero memo is shared by the blocks of a search: it must keep the
    # regions (their assumptions) apart. b**2 - 2 vanishes at b = sqrt(2) > 0 but
    # b + 1 has no positive root: a unit for b > 0, not for b real.
    positive = Region(("b",), 1, frozenset({0}), frozenset({0}))
    real = Region(("b",), 1)
    (Bp,) = positive.context.gens()
    assert _Splitter(positive, random.Random(0)).unit_entry(Bp + 1, Branch([], 1))
    assert not _Splitter(real, random.Random(0)).unit_entry(Bp + 1, Branch([], 1))
    assert _Splitter(positive, random.Random(0)).unit_entry(Bp + 1, Branch([], 1))
    assert not _Splitter(positive, random.Random(0)).unit_entry(Bp**2 - 2, Branch([], 1))


def test_entries_with_huge_coefficients_are_split_on():
    # python-flint 0.9's factor() overflowed on such entries and the search crashed
    big = 10**30
    split = drop_sets([{0: (Z - big) * (Z + big) * (B - C)}], 1, REGION, random.Random(4))
    assert not split.undecided
    assert sorted(split.sets, key=str) == sorted(
        [{z: sp.Integer(big)}, {z: sp.Integer(-big)}, {b: c}], key=str
    )


def test_branches_explored_elsewhere_give_the_same_sets_in_the_same_order(monkeypatch):
    # a spread that runs each call here, through the packing that crosses processes,
    # and one that fails: the sets are those of one process, in its order
    from registry.discovery import splitting

    rows = [
        {0: B, 1: C, 2: Z, 3: Q},
        {0: C, 1: B, 2: Z + B - C, 3: Z * Q},
        {0: B * Z, 1: 2 * C, 2: Z**2 + B, 3: C - B},
        {0: Z - 1, 1: Z * B - C, 2: B, 3: Z**3},
    ]
    alone = drop_sets(rows, 4, REGION, random.Random(3))
    assert alone.branches > 4 and alone.sets
    monkeypatch.setattr(splitting, "SPREAD_AFTER", 1)
    monkeypatch.setattr(splitting, "SPREAD", 4)
    calls: list[int] = []

    def here(fn, items):
        calls.append(len(items))
        return [fn(item) for item in items]

    spread = drop_sets(rows, 4, REGION, random.Random(3), here)
    assert calls and calls[0] > 1  # the branches did go through the spread
    assert spread.sets == alone.sets and spread.algebraic == alone.algebraic
    assert spread.branches == alone.branches and not spread.undecided

    failed = drop_sets(rows, 4, REGION, random.Random(3), lambda fn, items: ["lost"] * len(items))
    assert any("lost" in u for u in failed.undecided)  # never a silent gap
