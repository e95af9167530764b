"""The searches the registry records for every case of its catalog: at the degree its
claims reach, with weights suited to its potential, on the whole phase space and on each
level set its claims are stated on; a system the method cannot search gets a record
that says why, so that the catalog states, case by case, what is and is not known."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import sympy as sp

from ..errors import DiscoveryError
from ..execution.local import local_mapper
from ..execution.mapping import MAPPER_GRACE, Mapper, in_order
from ..mathematics import mechanics as mech
from ..mathematics.case_mechanics import CaseMechanics
from ..model import Case, Claim, IntegralSet, Provenance, Search, SearchOptions
from .grading import homogeneous_weights
from .search import discover

#: The smallest degree searched: below it no integral beyond H and |gamma|^2 can show.
LEAST_DEGREE = 2


def stated_options(case: Case) -> list[SearchOptions]:
    """The searches recorded for ``case``, whole phase space first.

    Weights M: 1, gamma: 1 where the potential has terms of degree >= 2 in gamma (which
    make H homogeneous there), else M: 1, gamma: 2; for a case that gives H or a deformed
    bracket, the weights that make its vector field homogeneous (``grading``), else
    M: 1, gamma: 1. The degree is the largest weighted degree of its polynomial claims
    (the literature's, where it has any), at least 2.
    """
    weights = _weights(case)
    claims = [c for c in case.claims if c.provenance is Provenance.LITERATURE] or list(case.claims)
    degree = max([LEAST_DEGREE, *(d for c in claims if (d := _degree(c, weights)) is not None)])
    level_sets = list(dict.fromkeys(c.on for c in claims if c.on))
    return [SearchOptions(degree, weights, on) for on in [(), *level_sets]]


def _weights(case: Case) -> tuple[int, int]:
    """The grading of the recorded searches of ``case`` (see ``stated_options``)."""
    system = case.system
    if not system.hamiltonian_form and system.kappa_expr == 0:
        return (1, 1) if _gamma_degree(system.potential.expr) >= 2 else (1, 2)
    return homogeneous_weights(CaseMechanics(case).field) or (1, 1)


def not_searched(case: Case, options: SearchOptions, reason: str) -> Search:
    """The record of a search the method refuses (a non-polynomial system, a level set
    it cannot reduce by): nothing established, and why."""
    return Search(
        case=case.id,
        content_hash=case.content_hash,
        options=options,
        known=(),
        generic=IntegralSet((), 0),
        special=(),
        complete=False,
        coverage=(f"not searched: {reason}",),
    )


def searched(
    work: Sequence[tuple[Case, SearchOptions]],
    *,
    budget: float | None,
    jobs: int = 1,
    mapper: Mapper | None = None,
) -> Iterator[Search]:
    """The search of each (case, options), in order, in this process, in ``jobs``
    worker processes (which die with this one), or through ``mapper`` (a Dask cluster);
    a search the method refuses, or that came back with no result, is recorded as
    ``not_searched`` with the reason."""
    if mapper is not None:
        yield from _mapped(work, budget, mapper)
        return
    if jobs <= 1 or len(work) <= 1:
        yield from (_searched(item, budget) for item in work)
        return
    yield from _mapped(work, budget, local_mapper(jobs))


def _mapped(
    work: Sequence[tuple[Case, SearchOptions]], budget: float | None, mapper: Mapper
) -> Iterator[Search]:
    """``searched`` through a mapper, in the work's order."""
    seconds = None if budget is None else budget + MAPPER_GRACE
    calls = mapper(_searched_apart, [(item, budget) for item in work], seconds)
    for index, outcome in in_order(calls, len(work)):
        if isinstance(outcome, BaseException):  # the cluster gave no result for it
            case, options = work[index]
            outcome = not_searched(case, options, f"no result came back: {outcome}")
        yield outcome


def _searched(item: tuple[Case, SearchOptions], budget: float | None) -> Search:
    case, options = item
    try:
        return discover(case, options, budget=budget)
    except DiscoveryError as err:
        return not_searched(case, options, str(err))


def _searched_apart(work) -> Search:
    return _searched(*work)


def _degree(claim: Claim, weights: tuple[int, int]) -> int | None:
    """The weighted degree of a claim in the system's ring (``ring_degree``)."""
    return ring_degree(claim.expression.expr, weights)


def ring_degree(expr: sp.Expr, weights: tuple[int, int]) -> int | None:
    """The weighted degree of an expression in a system's ring (``ring``): of its terms'
    polynomial parts in (M, gamma), inverses weighing nothing and sqrt(b) half of b;
    None for an expression outside such a ring. ``s`` counts as a constant (it is a
    known integral wherever it is one)."""
    expr = sp.expand(sp.sympify(expr))
    w = dict(zip(mech.STATE, (weights[0],) * 3 + (weights[1],) * 3, strict=True))

    def weight(e: sp.Expr) -> int | None:
        if e in w:
            return w[e]
        if e.is_number or not (e.free_symbols & set(mech.STATE)):
            return 0
        if isinstance(e, sp.Mul):
            parts = [weight(f) for f in e.args]
            return None if None in parts else sum(parts)  # type: ignore[arg-type]
        if isinstance(e, sp.Pow) and e.exp.is_Rational:
            if e.exp < 0:
                return 0
            inner = [weight(t) for t in sp.Add.make_args(sp.expand(e.base))]
            return None if None in inner else int(max(inner) * e.exp)  # type: ignore[type-var]
        return None

    degrees = [weight(t) for t in sp.Add.make_args(expr)]
    return None if None in degrees else max(degrees, default=0)  # type: ignore[type-var]


def _gamma_degree(potential: sp.Expr) -> int:
    """The degree of a potential in gamma, in its ring (0 where it is in none)."""
    return ring_degree(potential, (0, 1)) or 0
