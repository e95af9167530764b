"""The ARS test: Laurent series solved order by order, compatibility conditions at the
resonances, free coefficients kept symbolic, a Jordan block seen as a missing
coefficient; both sides of planted failures, and a printed failure reproduced."""

from __future__ import annotations

import sympy as sp

from registry.mathematics import painleve
from registry.mathematics.balances import balances
from registry.mathematics.exponent_analysis import exponents
from registry.mathematics.kovalevskaya import kovalevskaya_matrix
from registry.mathematics.painleve import laurent_series
from registry.mathematics.weighted import split_field

x, y, z, t = sp.symbols("x y z t")
a, b, c, eps = sp.symbols("a b c epsilon")


def planted(coupling):
    """x' = -x^2 (x = 1/t), z' = 2 x z (z = f4 t^2, resonance 4), y' = 5 x y + coupling
    z^2 (resonance 8): y/t^5 has derivative coupling f4^2 / t, a logarithm unless the
    coupling vanishes. Weights x: 1, y: 3, z: 2."""
    return [x, y, z], [-(x**2), 5 * x * y + coupling * z**2, 2 * x * z], [1, 3, 2]


def test_a_planted_logarithm_is_found_unless_the_coupling_vanishes():
    failing = exponents(*planted(a))
    (balance,) = failing.balances
    assert balance.exponents.values == (-1, 4, 8)
    step8 = balance.painleve.resonances[-1]
    f4 = balance.painleve.resonances[0].free[0]
    assert step8.order == 8 and sp.expand(step8.conditions[0] + a * f4**2) == 0
    assert balance.painleve.obstructions == (
        f"compatibility condition at resonance 8 fails: -a*{f4}**2",
    )
    assert not failing.painleve_passes and failing.all_integer
    assert failing.conditions == (
        f"balance 1: compatibility condition at resonance 8 fails: -a*{f4}**2",
    )
    passing = exponents(*planted(0))
    assert passing.painleve_passes and passing.conditions == ()
    assert not exponents(*planted(3)).painleve_passes


def test_the_series_solves_the_equations_to_its_last_order():
    variables, field, weights = planted(0)
    split = split_field(variables, field, weights)
    (balance,) = balances(split)
    series = laurent_series(split, balance.component, kovalevskaya_matrix(split), {4: 1, 8: 1})
    laurent = {
        v: sp.Add(*(t ** (k - w) * series.coefficients[k][i] for k in range(9)))
        for i, (v, w) in enumerate(zip(variables, weights, strict=True))
    }
    for v, f, w in zip(variables, field, weights, strict=True):
        residual = sp.expand((sp.diff(laurent[v], t) - f.xreplace(laurent)) * t ** (w + 1))
        low = [residual.coeff(t, k) for k in range(9)]  # orders 0..8 relative to t^-(w+1)
        assert all(sp.expand(r) == 0 for r in low)
    free = [s for step in series.resonances for s in step.free]
    assert [str(f) for f in free] == ["f4", "f8"]
    assert series.coefficients[4][2] == free[0]  # z = f4 t^2


def test_a_jordan_block_at_a_resonance_means_a_missing_coefficient():
    """y' = 3 x y + a z, z' = 2 x z: exponent 4 twice, but K - 4 has rank 2 when a != 0."""
    field = [-(x**2), 3 * x * y + a * z, 2 * x * z]
    (balance,) = exponents([x, y, z], field, [1, 1, 2]).balances
    (step,) = balance.painleve.resonances
    assert (step.order, step.multiplicity, len(step.free), step.missing) == (4, 2, 1, 1)
    assert "not diagonalizable" in balance.painleve.obstructions[0]
    (diagonal,) = exponents([x, y, z], [-(x**2), 3 * x * y, 2 * x * z], [1, 1, 2]).balances
    assert diagonal.painleve.compatible and len(diagonal.painleve.resonances[0].free) == 2


def test_a_lower_order_term_forces_a_logarithm_in_a_field_that_is_not_homogeneous():
    """x' = -x^2, y' = x y + a x^2 + epsilon: y = -a/(2t) + epsilon t log t + C t."""
    result = exponents([x, y], [-(x**2), x * y + a * x**2 + eps], [1, 1])
    assert not result.homogeneous
    (balance,) = result.balances
    assert balance.balance.point == {x: 1, y: -a / 2}
    assert balance.painleve.obstructions == (
        "compatibility condition at resonance 2 fails: -epsilon",
    )
    assert exponents([x, y], [-(x**2), x * y + a * x**2], [1, 1]).painleve_passes


def test_the_printed_fitzhugh_nagumo_conditions_are_reproduced():
    """W. Hereman's Painlevé-test program, output p_fhn.out (GitHub willyhereman/mytest,
    painleve/macsyma/single), for sqrt(2) f'' + c f' - 2 sqrt(2) f^3 + (2a + 2) f^2
    - sqrt(2) a f = 0, prints the failing compatibility conditions at resonance 4:
    -c (c - 2a + 1)(c + a - 2)(c + a + 1) / (27 sqrt 2) for U0 = 1 and
    c (c - a - 1)(c - a + 2)(c + 2a - 1) / (27 sqrt 2) for U0 = -1. With u = sqrt(2) f and
    tau = t / sqrt(2) (rational coefficients): u'' = -c u' + 2u^3 - 2(a + 1)u^2 + 2a u."""
    u, p = sp.symbols("u p")
    field = [p, -c * p + 2 * u**3 - 2 * (a + 1) * u**2 + 2 * a * u]
    result = exponents([u, p], field, [1, 2])
    printed = {
        1: -c * (c - 2 * a + 1) * (c + a - 2) * (c + a + 1),
        -1: c * (c - a - 1) * (c - a + 2) * (c + 2 * a - 1),
    }
    for b in result.balances:
        assert b.exponents.values == (-1, 4)
        (step,) = b.painleve.resonances
        (condition,) = step.conditions
        ratio = sp.cancel(condition / printed[b.balance.point[u]])
        assert ratio.is_number and ratio != 0
    assert not exponents([u, p], [p, -p + 2 * u**3 - 2 * u**2], [1, 2]).painleve_passes  # c=1, a=0
    assert exponents([u, p], [p, 2 * u**3 - 2 * (a + 1) * u**2 + 2 * a * u], [1, 2]).painleve_passes


def algebraic_balances(coupling):
    """x' = x^2 + a y^2, y' = 2 x y, z' = -2 x z + b y^2 + coupling x y: balances with
    y^2 = 1/(4a), a field of degree 2 over Q(a, b, ...), exponents -1, 1, 2; the condition
    at 2 is b f1^2 up to a unit (z' gets b y^2 from the free coefficient of order 1)."""
    return [x, y, z], [x**2 + a * y**2, 2 * x * y, -2 * x * z + b * y**2 + coupling * x * y]


def test_over_parameters_the_kernel_projection_agrees_with_elimination(monkeypatch):
    """Balances of degree 2 over Q(a, b): the resonance steps by the projection onto the
    kernel (no pivot inverted) and, forced, by elimination find the same free
    coefficients and the same failing conditions; with b = 0 the test passes."""
    monkeypatch.setattr(painleve, "PROJECT_ABOVE_DEGREE", 1)  # degree 2 projects too
    calls = []
    project = painleve._Recursion._project

    def counted(self, r, rhs):
        found = project(self, r, rhs)
        calls.append(found is not None)
        return found

    monkeypatch.setattr(painleve._Recursion, "_project", counted)
    projected = {e: exponents(*algebraic_balances(e), [1, 1, 1]) for e in (0, c)}
    assert calls and all(calls)  # elimination met a pivot outside k: the projection ran
    monkeypatch.setattr(painleve._Recursion, "_project", lambda self, r, rhs: None)
    eliminated = {e: exponents(*algebraic_balances(e), [1, 1, 1]) for e in (0, c)}
    for e in (0, c):
        pairs = zip(projected[e].balances, eliminated[e].balances, strict=True)
        seen = 0
        for one, other in pairs:
            assert one.exponents.values == other.exponents.values
            steps = one.painleve.resonances, other.painleve.resonances
            for s, t_ in zip(*steps, strict=True):
                assert (s.order, len(s.free), s.missing) == (t_.order, len(t_.free), t_.missing)
                assert len(s.conditions) == len(t_.conditions)
                for p, q in zip(s.conditions, t_.conditions, strict=True):
                    seen += 1  # neither vanishes where b is not 0 (there a pivot would)
                    assert all(sp.cancel(v.subs(b, value)) != 0 for v in (p, q) for value in (1, 2))
        assert seen == 2  # one condition at 2 on each of the two algebraic balances
    with_b_zero = [x**2 + a * y**2, 2 * x * y, -2 * x * z + c * x * y]
    assert exponents([x, y, z], with_b_zero, [1, 1, 1]).painleve_passes


def test_the_projected_series_solves_the_equations_modulo_the_balances_field():
    variables, field = algebraic_balances(0)
    field = [f.subs(b, 0) for f in field]
    split = split_field(variables, field, [1, 1, 1])
    component = next(bl.component for bl in balances(split) if bl.component.degree == 2)
    assert component.domain != sp.QQ and component.minimal.degree() == 2
    series = laurent_series(split, component, kovalevskaya_matrix(split), {1: 1, 2: 1})
    assert series.compatible and [len(s.free) for s in series.resonances] == [1, 1]
    u = component.symbol
    laurent = {
        v: sp.Add(*(t ** (k - 1) * series.coefficients[k][i] for k in range(3)))
        for i, v in enumerate(variables)
    }
    for v, f in zip(variables, field, strict=True):
        residual = sp.expand((sp.diff(laurent[v], t) - f.xreplace(laurent)) * t**2)
        for k in range(3):
            low = sp.together(residual.coeff(t, k))
            assert sp.rem(sp.numer(low), component.minimal.as_expr(), u) == 0


def test_the_projection_declines_a_jordan_block_and_elimination_counts_it():
    """x' = x^2 + a w^2, w' = 2 x w (w^2 = 1/(4a)), y' = -2 x y + coupling z, z' = 0
    (weights 1, 1, 1, 2): exponent 2 twice (y and z); with the coupling K - 2 is a Jordan
    block there, so the kernel projection does not apply and one coefficient is missing."""
    w_, zz = sp.symbols("w zz")
    variables = [x, w_, y, zz]

    def recursion(coupling):
        field = [x**2 + a * w_**2, 2 * x * w_, -2 * x * y + coupling * zz, sp.Integer(0)]
        split = split_field(variables, field, [1, 1, 1, 2])
        (component,) = [bl.component for bl in balances(split) if bl.component.degree == 2][:1]
        matrix = kovalevskaya_matrix(split)
        return painleve._Recursion(split, component, matrix, {1: 1, 2: 2})

    jordan = recursion(c)
    assert jordan._project(2, [jordan.algebra.zero] * 4) is None
    plain = recursion(0)
    solution, conditions, free = plain._project(2, [plain.algebra.zero] * 4)
    assert len(free) == 2 and all(v.is_zero for v in conditions)
    assert free == plain.free[2][:2] and len(solution) == 4
    field = [x**2 + a * w_**2, 2 * x * w_, -2 * x * y + c * zz, sp.Integer(0)]
    result = exponents(variables, field, [1, 1, 1, 2])
    algebraic = [bl for bl in result.balances if bl.balance.component.degree == 2]
    assert algebraic and all(
        step.missing == 1 for bl in algebraic for step in bl.painleve.resonances if step.order == 2
    )


def divided(coupling, lower=0):
    """x' = x^2 + lower (x = -1/t for lower 0), y' = a y^3 / x + coupling x under weights
    (1, 1): for coupling and lower 0, y = (a t^2 + K)^(-1/2) exactly, so
    y t = f1 t - (a/2) f1^3 t^3 + ... at the balance (-1, 0) (exponents -1, 1); the
    coupling adds -coupling/t to y', a logarithm. The balances y = +-1/(sqrt(a) t) have
    exponents -2, -1."""
    return [x, y], [x**2 + lower, a * y**3 / x + coupling * x], [1, 1]


def test_a_field_divided_by_a_state_variable_has_its_exponents_and_logarithm():
    failing = exponents(*divided(eps))
    found = {tuple(b.balance.point.values()): b for b in failing.balances}
    root = sp.sqrt(1 / a)
    assert set(found) == {(-1, 0), (-1, root), (-1, -root)}
    assert found[(-1, 0)].exponents.values == (-1, 1)
    assert found[(-1, root)].exponents.values == found[(-1, -root)].exponents.values == (-2, -1)
    (step,) = found[(-1, 0)].painleve.resonances
    # by hand: at order 1 the rest is the coupling times X_0 = -1, in y's equation, which
    # K - 1 = diag(-2, 0) does not reach
    assert step.order == 1 and step.conditions[0] in (eps, -eps) and len(step.conditions) == 1
    assert not failing.painleve_passes
    assert exponents(*divided(0)).painleve_passes
    assert exponents(*divided(0, b)).painleve_passes


def test_the_series_of_a_divided_field_solves_its_equations():
    """With lower = 0 the series is the exact solution's; with lower = b, 1/x has a
    series of its own (x = -sqrt(b) cot(sqrt(b) t)), and the series still solves the
    equations order by order."""
    for lower in (0, b):
        variables, field, weights = divided(0, lower)
        split = split_field(variables, field, weights)
        assert split.denominators == ((x, 1),) and split.leading == (x**2, a * y**3 / x)
        (balance,) = [r for r in balances(split) if r.point[y] == 0]
        matrix = kovalevskaya_matrix(split)
        series = laurent_series(split, balance.component, matrix, {1: 1}, order=5)
        (f1,) = series.resonances[0].free
        if lower == 0:
            assert [series.coefficients[k][1] for k in range(4)] == [0, f1, 0, -a * f1**3 / 2]
        else:
            assert [series.coefficients[k][0] for k in range(3)] == [-1, 0, b / 3]
        laurent = {
            v: sp.Add(*(t ** (k - w) * series.coefficients[k][i] for k in range(6)))
            for i, (v, w) in enumerate(zip(variables, weights, strict=True))
        }
        for v, f, w in zip(variables, field, weights, strict=True):
            residual = (sp.diff(laurent[v], t) - f.xreplace(laurent)) * t ** (w + 1)
            expansion = sp.series(sp.together(residual), t, 0, 6).removeO()
            assert all(sp.simplify(expansion.coeff(t, k)) == 0 for k in range(6)), (v, lower)
