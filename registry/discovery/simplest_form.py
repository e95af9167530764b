"""The simplest representative of an extra integral modulo the trivial ones.

An extra integral is determined up to adding trivial integrals (products of known
ones). Of the representatives that cancel up to t of its monomials (t the dimension
of the trivial span it meets), the one with the fewest variables, then the fewest
terms, is kept: for the Kovalevskaya top this is her own form, free of M3.
"""

from __future__ import annotations

from itertools import combinations

from sympy.polys.matrices import DomainMatrix

#: Most combinations of monomials tried (beyond it the canonical form is kept).
MAX_TRIES = 3000


def simplest(vector: list, trivial: list[list], columns, domain) -> list:
    """The representative of ``vector`` + span(``trivial``) with fewest variables, then
    fewest terms; ``columns`` gives each coordinate's exponents (which variables)."""
    support = {j for j, c in enumerate(vector) if c}
    relevant = [t for t in trivial if any(t[j] for j in support)]
    if not relevant:
        return vector
    t = len(relevant)
    cand_cols = sorted(support | {j for tv in relevant for j, c in enumerate(tv) if c})
    best, best_cost = vector, _cost(vector, columns)
    tries = 0
    for size in range(1, t + 1):
        for zeros in combinations(cand_cols, size):
            tries += 1
            if tries > MAX_TRIES:
                return best
            # choose coefficients (for `size` of the trivial vectors) that cancel `zeros`
            for chosen in combinations(range(t), size):
                m = DomainMatrix(
                    [[relevant[i][z] for i in chosen] for z in zeros], (size, size), domain
                )
                try:
                    rhs = DomainMatrix([[-vector[z]] for z in zeros], (size, 1), domain)
                    coeffs = m.lu_solve(rhs).to_list()
                except Exception:
                    continue
                cand = list(vector)
                for (c,), i in zip(coeffs, chosen, strict=True):
                    if c:
                        cand = [a + c * b for a, b in zip(cand, relevant[i], strict=True)]
                cost = _cost(cand, columns)
                if cost < best_cost:
                    best, best_cost = cand, cost
                break
    return best


def _cost(vector, columns) -> tuple[int, int]:
    used: set[int] = set()
    terms = 0
    for j, c in enumerate(vector):
        if c:
            terms += 1
            used.update(i for i, e in enumerate(columns[j]) if e)
    return (len(used), terms)
