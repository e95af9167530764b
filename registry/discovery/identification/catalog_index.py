"""The catalog as identification reads it: each case's normal form and what can be
decided without solving anything, computed once per case version.

An entry keeps the case's ``FieldForm`` (``field_form``), the assumptions on its
parameters, and the ratios of its inverse inertia that do not depend on its parameters
(2C : 2C : C is 2 : 2 : 1 whatever C is), so that most cases are ruled out for a given
system by comparing numbers. Entries are kept by content hash in this process: a
catalog read again costs nothing for the cases it already held.
"""

from __future__ import annotations

import itertools
import os
import pickle
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import sympy as sp

from ...mathematics import mechanics as mech
from ...model import Case
from ...settings import cache_folder
from .field_form import STATE, FieldForm, field_form
from .matching import Prepared, prepare, remember
from .supports import reachable, rigid_top

_CACHE: dict[str, Entry] = {}


@dataclass(frozen=True)
class Entry:
    """One case of the catalog: its id, the case, its normal form (None where its field
    has none: not polynomial, another phase space), its parameters' assumptions by
    name, and its kinetic ratios (``ratios``)."""

    id: str
    case: Case
    form: FieldForm | None
    assumptions: dict[str, str]
    ratios: tuple[sp.Expr | None, ...] | None
    #: every term the case's field can show in coordinates of the kind matched
    reachable: frozenset = frozenset()
    #: the terms of dL/dt every system that matches it must show (``supports.rigid_top``)
    rigid: frozenset = frozenset()
    #: what every match with it needs (``matching.Prepared``)
    prepared: Prepared | None = None
    #: why the case has no normal form and is never compared ("" where it has one)
    reason: str = ""

    @property
    def size(self) -> int:
        """How many parameters the case has: fewer is more specific."""
        return len(self.case.parameters)


#: Bump when what an entry holds, or how it is computed, changes: older files are ignored.
FORM_VERSION = "3"


def _cached(case: Case) -> Path:
    return cache_folder() / "forms" / FORM_VERSION / f"{case.id}-{case.content_hash[:24]}.pickle"


def entry(case: Case) -> Entry:
    """The index entry of one case version: computed once per content hash, kept in this
    process and in the cache folder (``settings.cache_folder``)."""
    key = f"{case.id}:{case.content_hash}"
    found = _CACHE.get(key)
    path = _cached(case) if case.content_hash else None
    if found is None and path is not None and path.is_file():
        try:
            stored = pickle.loads(path.read_bytes())  # noqa: S301 - our own cache file
            found = replace(stored, case=case)
            prepare_from(found)
        except Exception:  # noqa: BLE001 - a stale or broken cache file is recomputed
            found = None
    if found is None:
        form, reason = _form(case)
        assumptions = {name: str(kind) for name, kind in case.assumptions.items()}
        terms = (
            reachable(form.support(), form.shifted, form.kinetic.is_diagonal())
            if form is not None and form.kinetic is not None
            else form.support()
            if form is not None
            else frozenset()
        )
        rigid = rigid_top(form.field, STATE, assumptions) if form is not None else frozenset()
        ready = prepare(form) if form is not None else None
        found = Entry(case.id, case, form, assumptions, ratios(form), terms, rigid, ready, reason)
        if path is not None:
            _store(path, found)
    _CACHE[key] = found
    return found


def _form(case: Case) -> tuple[FieldForm | None, str]:
    """The case's normal form, or None with the reason it has none: a system on another
    state than (M, gamma) (a nonholonomic system in its own variables, two fields, an
    (omega, gamma) form), a field that is not polynomial in the state, or one whose
    form could not be computed."""
    dynamics = case.dynamics
    variables = tuple(dynamics.variables)
    if variables != mech.STATE:
        names = ", ".join(str(v) for v in variables)
        return None, f"its state ({names}) is not (M, gamma): not compared"
    try:
        form = field_form(dynamics)
    except Exception as error:  # noqa: BLE001 - one case never stops the index
        return None, f"its normal form could not be computed ({type(error).__name__})"
    if form is None:
        return None, "its field is not polynomial in (M, gamma), or A is singular: not compared"
    return form, ""


def prepare_from(found: Entry) -> None:
    """Hand a cached entry's prepared matching data to ``matching``."""
    if found.form is not None and found.prepared is not None:
        remember(found.form, found.prepared)


def _store(path: Path, found: Entry) -> None:
    """Keep an entry in the cache folder (written aside, renamed into place); a folder
    that cannot be written only costs the time to compute it again."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        aside = path.with_suffix(f".{os.getpid()}.tmp")
        aside.write_bytes(pickle.dumps(replace(found, case=None)))  # type: ignore[arg-type]
        aside.replace(path)
    except OSError:
        return


def ratios(form: FieldForm | None) -> tuple[sp.Expr | None, ...] | None:
    """d_i / d_j for the pairs (0, 1), (0, 2), (1, 2) of a diagonal inverse inertia,
    each a number where the parameters cancel and None where they do not; None for a
    form with no diagonal inverse inertia."""
    if form is None or form.kinetic is None or not form.kinetic.is_diagonal():
        return None
    d = [form.kinetic[i, i] for i in range(3)]
    out: list[sp.Expr | None] = []
    for i, j in ((0, 1), (0, 2), (1, 2)):
        r = sp.cancel(d[i] / d[j])
        out.append(r if r.is_number else None)
    return tuple(out)


def compatible(mine: tuple | None, theirs: tuple | None) -> bool:
    """Whether some order of the axes can make two inverse inertias proportional, from
    their numeric ratios alone (True where either is unknown)."""
    return bool(ratio_orders(mine, theirs))


def ratio_orders(mine: tuple | None, theirs: tuple | None) -> list[tuple[int, ...]]:
    """The orders of the axes (i -> order[i]) under which the numeric ratios of two
    inverse inertias agree (every order where either is unknown)."""
    orders = list(itertools.permutations(range(3)))
    if mine is None or theirs is None:
        return orders
    pairs = {(0, 1): 0, (0, 2): 1, (1, 2): 2}

    def ratio(r, i, j):
        if i == j:
            return sp.Integer(1)
        if (i, j) in pairs:
            return r[pairs[(i, j)]]
        value = r[pairs[(j, i)]]
        return None if value is None else 1 / value

    kept = []
    for order in orders:
        if all(
            (a := ratio(mine, i, j)) is None
            or (b := ratio(theirs, order[i], order[j])) is None
            or a == b
            for i, j in pairs
        ):
            kept.append(order)
    return kept


@dataclass(frozen=True)
class CatalogIndex:
    """The index of a catalog: one entry per case (``entry``)."""

    entries: tuple[Entry, ...]

    @classmethod
    def of(cls, cases: Iterable[Case]) -> CatalogIndex:
        return cls(tuple(entry(c) for c in cases))

    def ids(self) -> Sequence[str]:
        return [e.id for e in self.entries]

    def unindexed(self) -> dict[str, str]:
        """The cases never compared, each with the reason (``Entry.reason``)."""
        return {e.id: e.reason for e in self.entries if e.form is None}
