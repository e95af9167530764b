"""The searches the registry records for every case of its catalog: at the degree its
claims reach, with weights suited to its potential, on the whole phase space and on each
level set its claims are stated on; a system the method cannot search gets a record
that says why, so that the catalog states, case by case, what is and is not known."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from ..dynamics import Dynamics
from ..errors import DiscoveryError
from ..execution.executor import Executor, InProcess, in_order, timed
from ..execution.serving import Failure
from ..mathematics.grading import ring_degree, weights_by_symbol
from ..model import Case, Claim, IntegralSet, Provenance, Search, SearchOptions, Weights
from .search import discover

#: The smallest degree searched: below it no integral beyond H and |gamma|^2 can show.
LEAST_DEGREE = 2


def stated_options(case: Case) -> list[SearchOptions]:
    """The searches recorded for ``case``, whole phase space first.

    The weights are the system's grading (``Dynamics.grading``: for the reference paper's
    form M: 1, gamma: 1 where the potential has terms of degree >= 2 in gamma, which make
    H homogeneous there, else M: 1, gamma: 2; for the other forms the weights that make
    the vector field homogeneous, where some do). The degree is the largest weighted
    degree of its polynomial integral claims (the literature's, where it has any; a density or
    an invariant relation is no integral), at least 2.
    """
    weights = case.dynamics.grading
    integrals = [c for c in case.claims if c.kind.conserved]
    claims = [c for c in integrals if c.provenance is Provenance.LITERATURE] or integrals
    degree = max(
        [
            LEAST_DEGREE,
            *(d for c in claims if (d := _degree(c, weights, case.dynamics)) is not None),
        ]
    )
    level_sets = list(dict.fromkeys(c.on for c in claims if c.on))
    return [SearchOptions(degree, weights, on) for on in [(), *level_sets]]


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
    executor: Executor | None = None,
) -> Iterator[Search]:
    """The search of each (case, options), in order, by ``executor`` (default: in this
    process), one call each; a search the method refuses, or that came back with no
    result, is recorded as ``not_searched`` with the reason."""
    executor = executor or InProcess()
    calls = executor.map(
        _searched_apart,
        [(item, budget) for item in work],
        deadline=timed(budget),
        label=lambda w: w[0][0].id,
        name="registry-search",
    )
    for index, outcome in in_order(calls, len(work)):
        if isinstance(outcome, Failure):  # the call gave no result
            case, options = work[index]
            outcome = not_searched(case, options, f"no result came back: {outcome.reason}")
        yield outcome


def _searched(item: tuple[Case, SearchOptions], budget: float | None) -> Search:
    case, options = item
    try:
        return discover(case, options, budget=budget)
    except DiscoveryError as err:
        return not_searched(case, options, str(err))


def _searched_apart(work) -> Search:
    return _searched(*work)


def _degree(claim: Claim, weights: Weights, dynamics: Dynamics) -> int | None:
    """The weighted degree of a claim in the system's ring (``grading.ring_degree``)."""
    return ring_degree(claim.expression.expr, weights_by_symbol(weights, dynamics.vectors))
