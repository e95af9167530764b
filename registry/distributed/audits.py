"""Audits on a Dask cluster: the local worker pool's work, through ``tasks.run_calls``.

Each case is audited by ``audit_case`` in a child process of a Dask worker, under the
same ``TimeBudget`` as in the local pool: every check is interrupted by SIGALRM in the
child when its time is up, and the whole case is killed at
``TimeBudget.case_deadline(count_checks(case))``. Cases sharing a torque go to one
task, largest first, as in the local pool (``audit.parallel.batches``); small groups
share a task, so that Dask's cost per task and a child's start stay small beside
the work, and the tasks shrink as the run goes (``tasks.guided``), so that its end
leaves few workers idle. A killed case, or one whose child crashed, gets exactly the result the
local pool gives it (``case_audit.as_audit``): the verdicts
do not depend on where a case was audited.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from functools import partial
from typing import TYPE_CHECKING

from ..audit.case_audit import as_audit, audit_case, count_checks
from ..audit.parallel import batches
from ..execution.time_budget import TimeBudget
from ..model import Case, CaseAudit
from .scheduler import threads
from .tasks import Event, guided, run_calls

if TYPE_CHECKING:
    from distributed import Client

#: A task takes at most 1/(SHARES_PER_THREAD x worker threads) of the cases still to
#: plan: large tasks first (each task's cost is small beside its work), single cases
#: at the end (the last to finish leave little idle time).
SHARES_PER_THREAD = 2
#: Cases per task at most: what a worker lost takes with it, and must do again.
MAX_BATCH = 25


def plan(cases: Sequence[Case], n_threads: int, max_batch: int = MAX_BATCH) -> list[list[int]]:
    """The cases' indices cut into tasks: torque groups kept together where they fit
    (largest first), tasks shrinking as the cases left do (``tasks.guided``), none
    larger than ``max_batch``."""
    groups = [[i for i, _ in group] for group in batches(cases)]
    return guided(groups, SHARES_PER_THREAD * max(1, n_threads), max_batch)


def audit_on_cluster(
    client: Client,
    cases: Sequence[Case],
    budget: TimeBudget,
    numeric: bool = False,
    done: Callable[[Case], None] | None = None,
    on_event: Callable[[Event], None] | None = None,
) -> Iterator[tuple[int, CaseAudit]]:
    """Audit ``cases`` on the cluster of ``client``; yield (index, audit) as each arrives.

    The counterpart of ``audit.parallel.audit_in_workers``, with the same results case by
    case; ``done`` is called with each case as its audit arrives, ``on_event`` with what
    happened on the cluster (a worker lost, its cases done elsewhere).
    """
    audit = partial(audit_case, budget=budget, numeric=numeric)
    calls = run_calls(
        client,
        audit,
        cases,
        deadline=lambda case: budget.case_deadline(count_checks(case)),
        batches=plan(cases, threads(client)),
        label=lambda case: case.id,
        on_event=on_event,
        name="registry-audit",
    )
    try:
        for index, outcome in calls:
            case = cases[index]
            if done is not None:
                done(case)
            yield index, as_audit(case, outcome)
    finally:
        calls.close()
