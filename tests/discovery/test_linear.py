"""Linear algebra of a search over Q, Q(p) and modulo a prime: kernels, ranks and
spans agree with sympy's own, and modular ranks only bound the rational ones."""

from __future__ import annotations

import random

import sympy as sp
from sympy import QQ
from sympy.polys.matrices import DomainMatrix

from registry.discovery.linear import GF_PRIME, Field, Span, nullspace, rank

LAM = sp.Symbol("lam")


def test_rational_kernel_and_rank_match_sympy():
    rnd = random.Random(3)
    fld = Field(QQ, (), {})
    for _ in range(20):
        rows, cols = rnd.randint(1, 5), rnd.randint(1, 5)
        dense = [[sp.Rational(rnd.randint(-2, 2)) for _ in range(cols)] for _ in range(rows)]
        entries = [
            (i, j, QQ.from_sympy(v)) for i, row in enumerate(dense) for j, v in enumerate(row)
        ]
        matrix = sp.Matrix(dense)
        assert rank(rows, cols, entries, fld) == matrix.rank()
        basis = nullspace(rows, cols, entries, fld)
        assert len(basis) == cols - matrix.rank()
        for v in basis:
            assert matrix * sp.Matrix([QQ.to_sympy(x) for x in v]) == sp.zeros(rows, 1)


def test_parameters_evaluate_at_points_and_stay_symbols_elsewhere():
    poly = {(2,): 1, (0,): -1}  # lam**2 - 1
    assert Field(QQ, (LAM,), {0: 3}).evaluate(poly) == 8
    symbolic = Field(QQ.frac_field(LAM), (LAM,), {})
    assert symbolic.domain.to_sympy(symbolic.evaluate(poly)) == LAM**2 - 1
    modular = Field(GF_PRIME, (LAM,), {0: 3})
    assert int(modular.evaluate(poly)) == 8


def test_a_rank_modulo_the_prime_is_at_most_the_rank_over_q():
    fld = Field(QQ, (), {})
    mod = Field(GF_PRIME, (), {})
    entries = [(0, 0, 1), (0, 1, 2), (1, 0, 2), (1, 1, 4 + GF_PRIME.mod)]  # singular mod p only
    assert rank(2, 2, [(r, c, fld.number(v)) for r, c, v in entries], fld) == 2
    assert rank(2, 2, [(r, c, mod.number(v)) for r, c, v in entries], mod) == 1


def test_span_reduces_to_canonical_residues():
    fld = Field(QQ, (), {})
    span = Span(fld)
    assert span.add([QQ(1), QQ(1), QQ(0)])
    assert not span.add([QQ(2), QQ(2), QQ(0)])
    assert span.add([QQ(0), QQ(1), QQ(1)])
    assert span.dim == 2
    assert span.reduce([QQ(1), QQ(2), QQ(1)]) == [0, 0, 0]


def test_kernels_over_q_of_p_are_the_reduced_echelon_basis_of_sympy():
    a, b = sp.symbols("a b")
    fld = Field(QQ.frac_field(a, b), (a, b), {})
    rnd = random.Random(5)
    pool = [sp.Integer(0), sp.Integer(1), a, b - 1, a * b / 2, (a + 1) / (b + 2), a**2 - b]
    for _ in range(15):
        rows, cols = rnd.randint(1, 5), rnd.randint(1, 6)
        dense = [[rnd.choice(pool) for _ in range(cols)] for _ in range(rows)]
        entries = [
            (i, j, fld.domain.from_sympy(v))
            for i, row in enumerate(dense)
            for j, v in enumerate(row)
        ]
        basis = nullspace(rows, cols, entries, fld)
        # sympy's over the field itself, each vector scaled to 1 at its free column
        matrix = DomainMatrix(
            [[fld.domain.from_sympy(v) for v in row] for row in dense], (rows, cols), fld.domain
        )
        expected = [
            [x / next(y for y in reversed(v) if y) for x in v] for v in matrix.nullspace().to_list()
        ]
        assert basis == expected


def test_a_parameter_standing_for_an_inverse_evaluates_to_it_over_q_of_p():
    """iota = 1/(a + 1): a parameter polynomial with iota is a fraction of Q(a); summed in
    Q[a] first and then divided, it equals the same sum taken term by term in Q(a)."""
    a, b, iota = sp.symbols("a b iota")
    domain = QQ.frac_field(a, b, iota)
    fld = Field(domain, [a, b, iota], {}, {2: a + 1})
    poly = sp.Poly(3 * a**2 * iota**2 - b * iota + a * b + 7, a, b, iota).as_dict()
    expected = sp.cancel(3 * a**2 / (a + 1) ** 2 - b / (a + 1) + a * b + 7)
    assert domain.to_sympy(fld.evaluate(poly)) == expected
    # a value for b: the rest stays symbolic
    at = Field(domain, [a, b, iota], {1: 2}, {2: a + 1})
    assert domain.to_sympy(at.evaluate(poly)) == sp.cancel(expected.subs(b, 2))
