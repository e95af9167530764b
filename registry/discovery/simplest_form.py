"""The simplest representative of an extra integral modulo the trivial ones.

An extra integral is determined up to adding trivial integrals (products of known
ones). Of the representatives that cancel up to t of its monomials (t the dimension
of the trivial span it meets), the one with the fewest variables, then the fewest
terms, is kept: for the Kovalevskaya top this is her own form, free of M3.

The vectors are handled sparsely (coordinate -> nonzero coefficient) and each small
square system is solved by exact elimination over the domain's elements, without a
matrix object per try: at degree 6 there are thousands of tries (a sextic integral on
so(4) has 23 trivial integrals beside it), and that bookkeeping was most of a search.
"""

from __future__ import annotations

from itertools import combinations

#: Most combinations of monomials tried (beyond it the canonical form is kept).
MAX_TRIES = 3000


def simplest(vector: list, trivial: list[list], columns, domain) -> list:
    """The representative of ``vector`` + span(``trivial``) with fewest variables, then
    fewest terms; ``columns`` gives each coordinate's exponents (which variables)."""
    vec = {j: c for j, c in enumerate(vector) if c}
    relevant = [{j: c for j, c in enumerate(t) if c} for t in trivial if any(t[j] for j in vec)]
    if not relevant:
        return vector
    t = len(relevant)
    cand_cols = sorted(set(vec).union(*relevant))
    variables = [frozenset(i for i, e in enumerate(columns[j]) if e) for j in range(len(vector))]
    best, best_cost = vec, _cost(vec, variables)
    tries = 0
    for size in range(1, t + 1):
        for zeros in combinations(cand_cols, size):
            tries += 1
            if tries > MAX_TRIES:
                return _dense(best, len(vector), domain)
            # choose coefficients (for `size` of the trivial vectors) that cancel `zeros`
            for chosen in combinations(range(t), size):
                rows = [[relevant[i].get(z, domain.zero) for i in chosen] for z in zeros]
                coeffs = _solve(rows, [-vec.get(z, domain.zero) for z in zeros], domain)
                if coeffs is None:
                    continue
                cand = dict(vec)
                for c, i in zip(coeffs, chosen, strict=True):
                    if c:
                        for j, b in relevant[i].items():
                            value = cand.get(j, domain.zero) + c * b
                            if value:
                                cand[j] = value
                            else:
                                cand.pop(j, None)
                cost = _cost(cand, variables)
                if cost < best_cost:
                    best, best_cost = cand, cost
                break
    return _dense(best, len(vector), domain)


def _solve(rows: list[list], rhs: list, domain) -> list | None:
    """The solution x of the square system rows x = rhs over ``domain``, or None where
    the matrix is singular (exact Gauss-Jordan elimination with the first nonzero pivot)."""
    n = len(rows)
    a = [[*row, b] for row, b in zip(rows, rhs, strict=True)]
    for col in range(n):
        pivot = next((r for r in range(col, n) if a[r][col]), None)
        if pivot is None:
            return None
        a[col], a[pivot] = a[pivot], a[col]
        inverse = domain.one / a[col][col]
        a[col] = [x * inverse for x in a[col]]
        for r in range(n):
            if r != col and a[r][col]:
                factor = a[r][col]
                a[r] = [x - factor * y for x, y in zip(a[r], a[col], strict=True)]
    return [a[r][n] for r in range(n)]


def _dense(vec: dict, n: int, domain) -> list:
    return [vec.get(j, domain.zero) for j in range(n)]


def _cost(vec: dict, variables: list[frozenset]) -> tuple[int, int]:
    used: set[int] = set()
    for j in vec:
        used |= variables[j]
    return (len(used), len(vec))
