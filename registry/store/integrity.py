"""Verifying a registry database: what ``registry check`` reports.

The database engine's own checks and the table relations come from ``storage``
(no algebra there); here every stored case version is parsed again from its
text, its content hash recomputed, its columns compared with the parse, and
every stored expression (claims, derived Casimirs and torques, parameter
conditions) parsed again in its case's names. A clean report means that every
stored result still refers to exactly the case text it was computed from.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ..errors import CaseFormatError, ExpressionError
from ..language.casefile import parse_case_text
from ..language.parser import Namespace, parse_equation, parse_expression
from ..model import Case
from . import migrate
from .database import SCHEMA_VERSION, Store, StoredText


@dataclass(frozen=True)
class Verification:
    """The outcome of ``verify``: the schema, what was looked at, what is wrong."""

    revision: str | None
    counts: Mapping[str, int] = field(default_factory=dict)
    problems: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return not self.problems


def verify(store: Store) -> Verification:
    """Check a registry database end to end (see the module docstring)."""
    revision, version = store.schema_revision()
    problems = []
    if revision != migrate.head():
        problems.append(f"schema revision {revision}, expected {migrate.head()}")
    if version != str(SCHEMA_VERSION):
        problems.append(f"meta.schema_version is {version!r}, expected '{SCHEMA_VERSION}'")
    problems += store.database_problems()

    cases: dict[int, Case] = {}
    names: dict[int, str] = {}
    for stored in store.case_versions(latest_only=False):
        name = names[stored.pk] = f"case {stored.case_id} version {stored.version}"
        try:
            case = parse_case_text(stored.text, name)
        except CaseFormatError as err:
            problems += [f"{name}: the stored text no longer parses: {p}" for p in err.problems]
            continue
        if case.content_hash != stored.content_hash:
            problems.append(f"{name}: the stored hash does not match the stored text")
        if case.id != stored.case_id:
            problems.append(f"{name}: the stored text has id {case.id!r}")
        cases[stored.pk] = case

    texts = store.stored_expressions()
    for pk, case in cases.items():
        mine = [t for t in texts if t.case_pk == pk]
        problems += [f"{names[pk]}: {p}" for p in _columns_agree(case, mine)]
    for t in texts:
        case = cases.get(t.case_pk)
        if case is None:
            continue  # its text did not parse: already reported
        problem = _reparse(t, Namespace(case.parameters, case.functions))
        if problem:
            problems.append(f"{names[t.case_pk]}: {t.place}: {problem}")

    notes = tuple(
        f"run {run} is still running (process {pid} on {host})"
        for run, host, pid in store.running_runs()
    )
    return Verification(revision, store.counts(), tuple(problems), notes)


def _reparse(stored: StoredText, ns: Namespace) -> str | None:
    """Why a stored expression or equation does not parse, or None."""
    try:
        (parse_equation if stored.equation else parse_expression)(stored.text, ns)
    except ExpressionError as err:
        return f"{stored.text!r} does not parse: {err}"
    return None


def _columns_agree(case: Case, stored: list[StoredText]) -> list[str]:
    """Differences between a case version's columns and the parse of its text."""
    expected = {"potential": case.system.potential.text}
    for i in range(3):
        expected[f"torque[{i}]"] = case.system.torque[i].text
        expected[f"inertia[{i}]"] = case.system.inertia[i].text
    for claim in case.claims:
        where = f"claim {claim.label!r}"
        expected[f"{where} expression"] = claim.expression.text
        expected.update({f"{where} on[{i}]": e.text for i, e in enumerate(claim.on)})
    found = {t.place: t.text for t in stored if not t.place.startswith("run ")}
    problems = [
        f"{place}: stored as {found.get(place)!r}, but the case text says {text!r}"
        for place, text in expected.items()
        if found.get(place) != text
    ]
    problems += [f"{place}: stored, but not in the case text" for place in found.keys() - expected]
    return problems
