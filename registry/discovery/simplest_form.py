"""The simplest representative of an extra integral modulo the trivial ones.

An extra integral is determined up to adding trivial integrals (products of known
ones). Of the representatives that cancel up to t of its monomials (t the dimension
of the trivial span it meets), the one with the fewest variables, then the fewest
terms, is kept: for the Kovalevskaya top this is her own form, free of M3.

Thousands of small square systems are tried (a sextic integral on so(4) has 23
trivial integrals beside it). Over Q(p) each try cost gcds of rational functions, and
that was most of a search (a quartic on Wolf's e(3) families: 30 s of 33). The tries
are therefore made with the coefficients' images at a random point modulo a prime
(which monomials cancel, which systems are singular: the same as over Q(p), except
with probability about degree/2^61 per try), and only the winner is computed over the
domain itself. An unlucky point can only make a representative other than the
simplest one kept; every vector returned is ``vector`` plus a combination of the
trivial ones, computed exactly.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from itertools import combinations
from typing import Any

from .linear import GF_PRIME, PRIME

#: Most combinations of monomials tried (beyond it the best found so far is kept).
MAX_TRIES = 3000

#: The seed of the random point (fixed: the same search prints the same form anywhere).
SEED = 20250611


def simplest(vector: list, trivial: list[list], columns, domain) -> list:
    """The representative of ``vector`` + span(``trivial``) with fewest variables, then
    fewest terms; ``columns`` gives each coordinate's exponents (which variables)."""
    vec = {j: c for j, c in enumerate(vector) if c}
    relevant = [{j: c for j, c in enumerate(t) if c} for t in trivial if any(t[j] for j in vec)]
    if not relevant:
        return vector
    variables = [frozenset(i for i, e in enumerate(columns[j]) if e) for j in range(len(vector))]
    image = _image(domain)
    try:
        if image is None:
            raise _Pole
        images = (
            {j: image(c) for j, c in vec.items()},
            [{j: image(c) for j, c in t.items()} for t in relevant],
        )
    except _Pole:  # no modular image (another domain, or a pole): the tries made exactly
        best = _best(vec, relevant, variables, domain)
    else:
        best = _best(*images, variables, GF_PRIME)
    if best is None:
        return vector
    zeros, chosen = best
    coeffs = _coefficients(vec, relevant, zeros, chosen, domain)
    if coeffs is None:  # singular over the domain after all (an unlucky point)
        return vector
    return _dense(_combined(vec, relevant, chosen, coeffs, domain), len(vector), domain)


def _best(vec: dict, relevant: list[dict], variables: list[frozenset], domain):
    """(the cancelled columns, the trivial vectors used) of the representative with
    the lowest cost, tried in ``domain``; None where ``vec`` itself is the best."""
    t = len(relevant)
    cand_cols = sorted(set(vec).union(*relevant))
    best, best_cost = None, _cost(vec, variables)
    tries = 0
    for size in range(1, t + 1):
        for zeros in combinations(cand_cols, size):
            tries += 1
            if tries > MAX_TRIES:
                return best
            # choose coefficients (for `size` of the trivial vectors) that cancel `zeros`
            for chosen in combinations(range(t), size):
                coeffs = _coefficients(vec, relevant, zeros, chosen, domain)
                if coeffs is None:
                    continue
                cost = _cost(_combined(vec, relevant, chosen, coeffs, domain), variables)
                if cost < best_cost:
                    best, best_cost = (zeros, chosen), cost
                break
    return best


def _coefficients(vec: dict, relevant: list[dict], zeros, chosen, domain) -> list | None:
    """The coefficients of the ``chosen`` trivial vectors that cancel ``vec`` at the
    columns ``zeros``, or None where they are not determined."""
    rows = [[relevant[i].get(z, domain.zero) for i in chosen] for z in zeros]
    return _solve(rows, [-vec.get(z, domain.zero) for z in zeros], domain)


def _combined(vec: dict, relevant: list[dict], chosen, coeffs: list, domain) -> dict:
    """``vec`` plus sum coeffs[k] * relevant[chosen[k]], sparse."""
    cand = dict(vec)
    for c, i in zip(coeffs, chosen, strict=True):
        if c:
            for j, b in relevant[i].items():
                value = cand.get(j, domain.zero) + c * b
                if value:
                    cand[j] = value
                else:
                    cand.pop(j, None)
    return cand


def _image(domain) -> Callable[[object], object] | None:
    """The map from ``domain`` (QQ, or a field of rational functions over QQ) to the
    integers modulo PRIME at a random point (_Pole where the point is a pole of the
    element), or None for another domain."""
    if domain.is_QQ or domain.is_ZZ:
        return _rational
    if not (domain.is_FractionField and (domain.domain.is_QQ or domain.domain.is_ZZ)):
        return None
    rnd = random.Random(SEED)
    point = [GF_PRIME(rnd.randrange(1, PRIME)) for _ in domain.symbols]
    cache: dict = {}

    def poly(p) -> Any:
        total = GF_PRIME.zero
        for exps, coeff in p.items():
            term = _rational(coeff)
            for x, e in zip(point, exps, strict=True):
                if e:
                    term *= x**e
            total += term
        return total

    def image(c) -> Any:
        hit = cache.get(c)
        if hit is None:
            denom = poly(c.denom)
            if not denom:
                raise _Pole
            hit = cache[c] = poly(c.numer) / denom
        return hit

    return image


def _rational(q) -> Any:
    """A rational number modulo PRIME (_Pole where its denominator is a multiple of it)."""
    denominator = GF_PRIME(int(q.denominator))
    if not denominator:
        raise _Pole
    return GF_PRIME(int(q.numerator)) / denominator


class _Pole(ArithmeticError):
    """A coefficient has no image: the random point is one of its poles, or a
    denominator is a multiple of the prime."""


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
