"""An extra integral is printed in its simplest form modulo the trivial ones."""

from __future__ import annotations

import random

import sympy as sp
from sympy import QQ
from sympy.polys.matrices import DomainMatrix

from registry.discovery.simplest_form import _best, _coefficients, _combined, _dense, simplest


def test_the_representative_with_fewest_variables_then_terms_is_kept():
    # columns: x (uses variable 0), y (variable 1), z (variable 2)
    columns = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    trivial = [[QQ(0), QQ(1), QQ(1)]]  # y + z is trivial
    assert simplest([QQ(1), QQ(1), QQ(1)], trivial, columns, QQ) == [QQ(1), QQ(0), QQ(0)]
    # x + z and x - y use two variables each: the first (canonical) one is kept
    assert simplest([QQ(1), QQ(0), QQ(1)], trivial, columns, QQ) == [QQ(1), QQ(0), QQ(1)]


def test_without_a_trivial_vector_that_meets_it_the_vector_is_kept():
    columns = [(1, 0, 0), (0, 1, 0)]
    assert simplest([QQ(1), QQ(0)], [[QQ(0), QQ(1)]], columns, QQ) == [QQ(1), QQ(0)]


def test_over_rational_functions_the_winner_is_computed_exactly():
    # columns x, y, z; a*y + z/b is trivial: x + a*y + z/b reduces to x, exactly in Q(a, b)
    a, b = sp.symbols("a b")
    field = QQ.frac_field(a, b)
    one, zero = field.one, field.zero
    trivial = [[zero, field.from_sympy(a), field.from_sympy(1 / b)]]
    vector = [one, field.from_sympy(a), field.from_sympy(1 / b)]
    assert simplest(vector, trivial, [(1, 0, 0), (0, 1, 0), (0, 0, 1)], field) == [one, zero, zero]
    # x + 2*a*y + z/b: x - z/b (y cancelled) and x + a*y (z cancelled) are as simple,
    # and the first one tried is kept
    vector = [one, field.from_sympy(2 * a), field.from_sympy(1 / b)]
    assert simplest(vector, trivial, [(1, 0, 0), (0, 1, 0), (0, 0, 1)], field) == [
        one,
        zero,
        field.from_sympy(-1 / b),
    ]


def test_the_tries_modulo_a_prime_choose_what_exact_tries_choose():
    # random sparse vectors over Q(a): the representative found by trying at a point
    # modulo a prime is the one trying every system in Q(a) finds, and it is the vector
    # plus a combination of the trivial ones
    a = sp.Symbol("a")
    field = QQ.frac_field(a)
    rnd = random.Random(7)
    values = [0, 0, 0, 1, -1, 2, a, a + 1, 1 / (a - 2), a**2]
    columns = [tuple(int(i == k % 3) for i in range(3)) for k in range(7)]
    for _ in range(12):
        trivial = [
            [field.from_sympy(rnd.choice(values)) for _ in columns]
            for _ in range(rnd.randint(1, 3))
        ]
        vector = [field.from_sympy(rnd.choice(values)) for _ in columns]
        vec = {j: c for j, c in enumerate(vector) if c}
        relevant = [{j: c for j, c in enumerate(t) if c} for t in trivial if any(t[j] for j in vec)]
        variables = [frozenset(i for i, e in enumerate(c) if e) for c in columns]
        found = simplest(vector, trivial, columns, field)
        exact = _best(vec, relevant, variables, field) if relevant else None
        if exact is None:
            assert found == vector
            continue
        zeros, chosen = exact
        coeffs = _coefficients(vec, relevant, zeros, chosen, field)
        assert found == _dense(_combined(vec, relevant, chosen, coeffs, field), 7, field)
        rows = [[f - v for f, v in zip(found, vector, strict=True)], *trivial]
        with_difference = DomainMatrix(rows, (len(rows), 7), field).rank()
        assert with_difference == DomainMatrix(trivial, (len(trivial), 7), field).rank()


def test_a_domain_without_a_modular_image_is_tried_exactly():
    field = QQ.algebraic_field(sp.sqrt(2))
    r2 = field.from_sympy(sp.sqrt(2))
    trivial = [[field.zero, r2, field.one]]
    vector = [field.one, 2 * r2, 2 * field.one]
    columns = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    assert simplest(vector, trivial, columns, field) == [field.one, field.zero, field.zero]


def test_a_coefficient_without_a_modular_image_sends_the_tries_back_to_the_domain():
    # 1/PRIME has no image modulo PRIME: the tries are made in QQ, with the same answer
    from registry.discovery.linear import PRIME

    columns = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    tiny = QQ(1, PRIME)
    trivial = [[QQ(0), tiny, QQ(1)]]
    assert simplest([QQ(1), 2 * tiny, QQ(2)], trivial, columns, QQ) == [QQ(1), QQ(0), QQ(0)]
