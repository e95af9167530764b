"""Which terms a field can have, to rule out a match without solving for it.

A transformation of ``transformations`` maps each term of one field to terms of the
other: a signed permutation of the axes maps a monomial to one monomial (scalings and
signs change only its coefficient), a rotation about an axis mixes the two axes it
turns, and a residual shift L -> L + (h0 + h.gamma) A^-1 gamma replaces a factor L_i by
L_i, gamma_i or gamma_i gamma_j (A diagonal), and adds the terms of its Jacobian. The
case's *reachable support* (its terms at generic parameter values, closed under the
shift) contains every term the case can show in any coordinates of that kind, so a
system with a term outside it, in every order of the axes, is no member of the case.
The test is one-sided: passing it proves nothing, failing it proves no match.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence

Term = tuple[int, tuple[int, ...]]


def _unit(i: int) -> tuple[int, ...]:
    return tuple(int(k == i) for k in range(6))


def _add(a: Sequence[int], b: Sequence[int]) -> tuple[int, ...]:
    return tuple(x + y for x, y in zip(a, b, strict=True))


def reachable(support: Iterable[Term], shifted: bool, diagonal: bool) -> frozenset[Term]:
    """The support closed under residual shifts (module docstring); the support itself
    where the form has no shift. A non-diagonal inverse inertia mixes the axes: every
    gamma may then replace an L."""
    support = frozenset(support)
    if not shifted:
        return support
    out: set[Term] = set()

    def replacements(i: int) -> list[tuple[int, ...]]:
        axes = [i] if diagonal else [0, 1, 2]
        found = [_unit(i)]
        for a in axes:
            found.append(_unit(3 + a))
            found.extend(_add(_unit(3 + a), _unit(3 + j)) for j in range(3))
        return found

    for component, monomial in support:
        factors = [i for i in range(3) for _ in range(monomial[i])]
        rest = (0, 0, 0, *monomial[3:])
        for choice in itertools.product(*(replacements(i) for i in factors)):
            total = rest
            for part in choice:
                total = _add(total, part)
            out.add((component, total))
    # the Jacobian of the shift times dgamma/dt: any gamma monomial of degree <= 1 more
    gamma_terms = {(c, m) for c, m in out if c >= 3}
    for c in range(3):
        for _, m in gamma_terms:
            out.add((c, m))
            for j in range(3):
                out.add((c, _add(m, _unit(3 + j))))
    return frozenset(out)


def permuted(term: Term, order: Sequence[int]) -> Term:
    """A term with axis i sent to axis order[i]."""
    component, monomial = term
    new = [0] * 6
    for i in range(3):
        new[order[i]] = monomial[i]
        new[3 + order[i]] = monomial[3 + i]
    target = order[component] if component < 3 else 3 + order[component - 3]
    return target, tuple(new)


def collapsed(term: Term, pair: Sequence[int]) -> tuple:
    """A term with the two axes of ``pair`` made one (a rotation mixes them)."""
    component, monomial = term
    i, j = pair
    k = 3 - i - j
    kind = ("L" if component < 3 else "g", "axis" if component % 3 == k else "pair")
    return (
        kind,
        monomial[k],
        monomial[i] + monomial[j],
        monomial[3 + k],
        monomial[3 + i] + monomial[3 + j],
    )


def orders_allowed(
    mine: Iterable[Term],
    theirs: frozenset[Term],
    orders: Iterable[Sequence[int]],
    axis: int | None = None,
) -> list[tuple[int, ...]]:
    """The orders of the axes under which every term of ``mine`` can be one of
    ``theirs`` (a reachable support); with a rotation about ``axis`` of ``mine``, up to
    mixing the two axes it turns."""
    mine = list(mine)
    kept = []
    for order in orders:
        if axis is None:
            ok = all(permuted(t, order) in theirs for t in mine)
        else:
            pair = [i for i in range(3) if i != axis]
            image_pair = [order[i] for i in pair]
            targets = {collapsed(t, image_pair) for t in theirs}
            ok = all(collapsed(permuted(t, order), image_pair) in targets for t in mine)
        if ok:
            kept.append(tuple(order))
    return kept


def rigid_top(form_field: Sequence, state: Sequence, assumptions: dict[str, str]) -> frozenset:
    """The terms of dL/dt of highest degree in L (when it is 2 or more) whose coefficient
    cannot vanish at any allowed parameter value (a number, times powers of positive or
    nonzero parameters). A residual shift changes only terms of lower degree in L, so a
    system that matches the case has each of them, in some order of the axes."""
    import sympy as sp  # noqa: PLC0415 - keeps this module's import light

    out = set()
    for i, f in enumerate(form_field[:3]):
        poly = sp.Poly(f, *state)
        terms = poly.terms()
        if not terms:
            continue
        top = max(sum(m[:3]) for m, _ in terms)
        if top < 2:
            continue
        for monomial, coefficient in terms:
            if sum(monomial[:3]) == top and _rigid(coefficient, assumptions):
                out.add((i, monomial))
    return frozenset(out)


def _rigid(coefficient, assumptions: dict[str, str]) -> bool:
    import sympy as sp  # noqa: PLC0415

    for factor in sp.Mul.make_args(sp.factor(coefficient)):
        base = factor.base if factor.is_Pow else factor
        if base.is_number:
            if base == 0:
                return False
            continue
        if not (base.is_Symbol and assumptions.get(str(base)) in ("positive", "nonzero")):
            return False
    return True


def rigid_allowed(
    mine: Iterable[Term], rigid: frozenset, order: Sequence[int], axis: int | None = None
) -> bool:
    """Whether each rigid term of the case is a term of ``mine`` in this order of the axes
    (with a rotation about ``axis`` of ``mine``: up to mixing the two axes it turns)."""
    images = [permuted(t, order) for t in mine]
    if axis is None:
        return rigid <= set(images)
    pair = [order[i] for i in range(3) if i != axis]
    return {collapsed(t, pair) for t in rigid} <= {collapsed(t, pair) for t in images}
