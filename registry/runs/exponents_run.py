"""A Kovalevskaya analysis run: analyses that are recorded, and reused when recorded
before.

The policy of ``Registry.analyse_exponents``: a stored case version already analysed with
the same options by this code version reuses that analysis unless the run is fresh;
with ``record`` the analysis is stored with the case version (a new row each time, the
earlier ones kept). The analysis itself runs in this process, its family's candidate
values in local processes or on a Dask cluster (``discovery.exponents``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ..discovery.exponents import analyse_case, exponent_options
from ..errors import UnknownCaseError
from ..execution.executor import Executor
from ..language.casefile import load_case
from ..model import Case, ExponentOptions, ExponentResult, Weights
from ..presentation.exponents_output import exponents_text
from ..settings import DEFAULT_EXPONENT_SECONDS
from ..store.database import Store, StoredCase
from ..version import code_version


@dataclass(frozen=True)
class ExponentReport:
    """One Kovalevskaya analysis: its result, its number in the registry (None when it
    was not recorded), whether a stored analysis was reused, and what happened on the
    Dask cluster that ran a family's candidates (one line each)."""

    result: ExponentResult
    number: int | None = None
    reused: bool = False
    events: tuple[str, ...] = ()

    def document(self) -> dict[str, Any]:
        """The JSON document of docs/json-output.md (Kovalevskaya exponents)."""
        document = dict(self.result.document)
        if self.number is not None:
            document["analysis"] = self.number
            document["reused"] = self.reused
        if self.events:
            document["events"] = list(self.events)
        return document

    def text(self) -> str:
        """The analysis in plain text, as ``registry exponents`` prints it."""
        return exponents_text(self.result)

    @property
    def statement(self) -> str:
        return self.result.statement


@dataclass(frozen=True)
class ExponentRequest:
    """What an analysis is asked: the weights by vector (None: the case's own), the free
    parameters, the seconds it may take; whether to store it (``record``) or analyse
    again instead of reusing a stored analysis (``fresh``)."""

    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None
    free: tuple[str, ...] = ()
    budget: float | None = DEFAULT_EXPONENT_SECONDS
    record: bool = False
    fresh: bool = False

    def options(self, case: Case) -> ExponentOptions:
        return exponent_options(case, self.weights, self.free)


def exponents_run(
    store: Store | None,
    target: str | os.PathLike | Case,
    request: ExponentRequest,
    executor: Executor,
) -> ExponentReport:
    """``Registry.analyse_exponents``: analyse a case file, a stored case or a ``Case``;
    reuse an analysis recorded before, record this one if asked. Without a store (a case
    file or a ``Case`` analysed on its own), nothing is reused or recorded."""
    if request.record and store is not None:
        store.require_writer("record an exponent analysis")
    if store is None:
        case, stored = (target if isinstance(target, Case) else load_case(target)), None
    else:
        case, stored = _target(store, target)
    options = request.options(case)
    if store is not None and stored is not None and not request.fresh:
        found = store.stored_exponents(stored.pk, options, code_version())
        if found is not None:
            return ExponentReport(found[1], found[0], reused=True)
    result = analyse_case(case, options, budget=request.budget, executor=executor)
    events = tuple(executor.events)
    if not request.record or store is None:
        return ExponentReport(result, events=events)
    if stored is None:
        store.add_case(case)
        (stored,) = store.case_versions([case.id])
    number = store.record_exponents(stored.pk, result, code_version())
    return replace(ExponentReport(result, number), events=events)


def _target(store: Store, target: str | os.PathLike | Case) -> tuple[Case, StoredCase | None]:
    """The case to analyse and its stored version (None when not stored)."""
    if isinstance(target, Case):
        case = target
    elif Path(target).is_file():
        case = load_case(target)
    else:
        (stored,) = store.case_versions([str(target)])
        return stored.parse(), stored
    try:
        versions = store.case_versions([case.id], latest_only=False)
    except UnknownCaseError:
        return case, None
    same = [s for s in versions if s.content_hash == case.content_hash]
    return case, (same[-1] if same else None)
