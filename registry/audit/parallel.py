"""Auditing many cases at once, wherever the executor runs its calls.

The audit decides only what is particular to cases: which cases go to one worker in a
row (those sharing a torque, largest first: the worker recognises the torque's family
once, with sympy's caches warm), each case's deadline (its checks' budget), and what a
call without a result becomes (``case_audit.as_audit``). Where the calls run (this
process, local workers, a Dask cluster) is the executor's business
(``execution.executor``): the verdicts do not depend on it.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Sequence
from functools import partial

import sympy as sp

from ..execution.executor import Executor
from ..execution.time_budget import TimeBudget
from ..model import Case, CaseAudit
from .case_audit import as_audit, audit_case, count_checks


def estimated_cost(case: Case) -> int:
    """A rough size of the work a case needs: its expressions' operation counts, with
    families of arbitrary functions weighted up. Used to start the largest cases first."""
    exprs = [*(g.expr for g in case.dynamics.given), *(c.expression.expr for c in case.claims)]
    return sum(sp.count_ops(e) for e in exprs) + 100 * len(case.functions)


def _torque(case: Case) -> tuple:
    """What cases sharing a torque share: its components and the parameters' assumptions."""
    torque = case.dynamics.torque or ()
    return tuple(e.text for e in torque), tuple(sorted(case.assumptions.items()))


def batches(cases: Sequence[Case]) -> list[list[tuple[int, Case]]]:
    """The cases as (index, case), grouped by torque, largest group first, largest case
    first within a group: one worker audits a group, recognising its torque's family
    once and with sympy's caches warm (a correction after the case it corrects costs a
    fraction of the first); largest first, so no long group starts last."""
    cost = [estimated_cost(c) for c in cases]
    groups: dict[tuple, list[tuple[int, Case]]] = {}
    for i in sorted(range(len(cases)), key=lambda i: -cost[i]):
        groups.setdefault(_torque(cases[i]), []).append((i, cases[i]))
    return sorted(groups.values(), key=lambda g: -sum(cost[i] for i, _ in g))


def audit_cases(
    cases: Sequence[Case],
    executor: Executor,
    budget: TimeBudget,
    numeric: bool = False,
    on_event: Callable | None = None,
) -> Generator[tuple[int, CaseAudit], None, None]:
    """Audit ``cases`` with ``executor``; yield (index, audit) as each finishes.

    A case whose call overran its deadline (its worker killed), crashed or was lost on a
    cluster gets the record ``case_audit.as_audit`` makes of it; the others go on.
    """
    calls = executor.map(
        partial(audit_case, budget=budget, numeric=numeric),
        cases,
        deadline=lambda case: budget.case_deadline(count_checks(case)),
        groups=[[i for i, _ in group] for group in batches(cases)],
        label=lambda case: case.id,
        on_event=on_event,
        name="registry-audit",
    )
    try:
        for index, outcome in calls:
            yield index, as_audit(cases[index], outcome)
    finally:
        calls.close()
