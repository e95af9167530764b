"""The polynomial Casimirs of low degree of a bracket given entry by entry
(``registry/mathematics/bracket_casimirs.py``), against brackets whose Casimirs are
known: e(3) (M.gamma and |gamma|^2), so(4) (two quadrics), a bracket with none."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.bracket_casimirs import polynomial_casimirs

M = sp.symbols("M1:4")
G = sp.symbols("g1:4")


def lie_poisson(structure) -> sp.Matrix:
    """Pi_ij = sum_k c_ij^k x_k for the structure constants given as a function."""
    return sp.Matrix(6, 6, structure)


def e3(i: int, j: int) -> sp.Expr:
    x = (*M, *G)
    eps = sp.LeviCivita
    if i < 3 and j < 3:
        return sum(eps(i, j, k) * M[k] for k in range(3))
    if i < 3 <= j:
        return sum(eps(i, j - 3, k) * G[k] for k in range(3))
    if j < 3 <= i:
        return sum(eps(i - 3, j, k) * G[k] for k in range(3))
    return sp.Integer(0) * x[0]


def test_the_casimirs_of_e3_are_m_dot_gamma_and_gamma_squared():
    found = polynomial_casimirs(lie_poisson(e3), (*M, *G))
    span = {sp.expand(c) for c in found}
    assert len(found) == 2
    assert sp.expand(sum(g**2 for g in G)) in span
    assert sp.expand(sum(m * g for m, g in zip(M, G, strict=True))) in span


def test_the_casimirs_of_so4_with_a_parameter_are_found_over_its_field():
    kappa = sp.Symbol("kappa")

    def so4(i: int, j: int) -> sp.Expr:
        if i >= 3 and j >= 3:  # {gamma_i, gamma_j} = kappa eps_ijk M_k
            return kappa * sum(sp.LeviCivita(i - 3, j - 3, k) * M[k] for k in range(3))
        return e3(i, j)

    found = polynomial_casimirs(lie_poisson(so4), (*M, *G))
    assert len(found) == 2
    for c in found:  # each is one indeed
        gradient = sp.Matrix([sp.diff(c, x) for x in (*M, *G)])
        assert (lie_poisson(so4) * gradient).expand() == sp.zeros(6, 1)
    quadric = sp.expand(kappa * sum(m**2 for m in M) + sum(g**2 for g in G))
    combos = [sp.expand(c) for c in found]
    a, b = sp.symbols("a b")
    solved = sp.solve(
        sp.Poly(a * combos[0] + b * combos[1] - quadric, *M, *G).coeffs(), [a, b], dict=True
    )
    assert solved  # kappa |M|^2 + |gamma|^2 lies in their span


def test_a_symplectic_bracket_has_no_casimir_and_a_bracket_not_polynomial_is_left():
    q, p = sp.symbols("q p")
    assert polynomial_casimirs(sp.Matrix([[0, 1], [-1, 0]]), (q, p)) == []
    assert polynomial_casimirs(sp.Matrix([[0, 1 / q], [-1 / q, 0]]), (q, p)) == []
