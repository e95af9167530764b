"""Which catalog cases a system is: every case of the index whose vector field, at some
values of its parameters and after one of the equivalences of ``transformations``, is
the system's own (``matching``), each with its values and transformation.

Cases are first ruled out without solving: one with no normal form (or the system has
none), one whose inverse inertia's numeric ratios match the system's in no order of the
axes (``catalog_index.compatible``). The others are matched, the most specific first
(fewest parameters). A case is listed once, with the first transformation found (the
simplest tried first). Implemented equivalences: parameter values; scalings of time,
of M and of gamma; permutations and sign changes of the axes; rotations about an axis
of symmetry; adding Casimirs to H (nothing to do on fields); shifts M -> M + f(gamma)
that keep dgamma/dt = gamma x A M (``field_form``). Not implemented: general rotations
(a body with three different moments has only the signed permutations), time
reparametrisations by a function of the state, and changes of the bracket (so(4) to
e(3) limits).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import sympy as sp

from ...dynamics import Dynamics
from ...language.printer import to_text
from .catalog_index import CatalogIndex, Entry, compatible, ratio_orders, ratios
from .field_form import FieldForm, field_form
from .matching import Match, _symmetry_axis, match
from .supports import orders_allowed, rigid_allowed


def _orders(mine: FieldForm, entry: Entry) -> tuple[list, list]:
    """The orders of the axes a match may use (plain, and with a rotation about the
    system's axis of symmetry), those the reachable supports rule out left out."""
    theirs = entry.form
    assert theirs is not None
    if not mine.shifted or mine.kinetic is None or theirs.kinetic is None:
        return ([(0, 1, 2)] if _support(mine) <= entry.reachable else []), []
    if not (mine.kinetic.is_diagonal() and theirs.kinetic.is_diagonal()):
        return [(0, 1, 2)], []
    terms = _support(mine)
    candidates = ratio_orders(ratios(mine), entry.ratios)
    plain = [
        o
        for o in orders_allowed(terms, entry.reachable, candidates)
        if rigid_allowed(terms, entry.rigid, o)
    ]
    axis = _symmetry_axis(mine.kinetic)
    if axis is None:
        return plain, []
    rotated, seen = [], set()
    for order in orders_allowed(terms, entry.reachable, candidates, axis):
        i, j = [order[k] for k in range(3) if k != axis]
        if sp.cancel(theirs.kinetic[i, i] - theirs.kinetic[j, j]) != 0:
            continue  # the case's moments there are not equal for all its values
        if not rigid_allowed(terms, entry.rigid, order, axis):
            continue
        key = (order[axis], frozenset(order[i] for i in range(3) if i != axis))
        if key not in seen:
            seen.add(key)
            rotated.append(order)
    return plain, rotated


@functools.lru_cache(maxsize=64)
def _support(form: FieldForm) -> frozenset:
    return form.support()


@dataclass(frozen=True)
class SameAs:
    """A catalog case the system is: its id, the case's parameter values (text, in the
    system's parameters), the transformation (the case's M, gamma and t as expressions
    of the system's), whether it is the identity, and the match itself (for the claims,
    ``claim_match``)."""

    case: str
    values: dict[str, str]
    transformation: dict[str, str]
    identity: bool
    found: Match

    def as_dict(self) -> dict:
        return {
            "case": self.case,
            "values": dict(self.values),
            "transformation": dict(self.transformation),
        }


@dataclass(frozen=True)
class Identification:
    """What identifying one system found: the cases it is (``same``), the ids of the cases
    compared (all others were ruled out or did not match), and the seconds it took."""

    same: tuple[SameAs, ...]
    compared: tuple[str, ...]
    seconds: float
    form: FieldForm | None = None
    #: the cases not compared because the time ran out (none: the catalog was covered)
    skipped: tuple[str, ...] = ()
    #: the cases whose comparison failed, each with the error (never said to differ)
    failed: tuple[tuple[str, str], ...] = ()


#: Seconds one identification may take (a system with free parameters costs more).
BUDGET = 60.0


def identify(
    dynamics: Dynamics,
    index: CatalogIndex,
    *,
    exclude: tuple[str, ...] = (),
    budget: float | None = BUDGET,
) -> Identification:
    """The catalog cases that are the system (module docstring); ``exclude`` names cases
    not to compare with (the system's own). Past ``budget`` seconds the cases left are
    named in ``skipped``, never said to be other systems; a case whose comparison raises
    is named in ``failed`` with the error, and the others are still compared."""
    started = time.perf_counter()
    mine = field_form(dynamics)
    if mine is None:
        return Identification((), (), time.perf_counter() - started)
    key = ratios(mine)
    found: list[SameAs] = []
    compared: list[str] = []
    skipped: list[str] = []
    failed: list[tuple[str, str]] = []
    for entry in sorted(index.entries, key=lambda e: (e.size, e.id)):
        if entry.id in exclude or entry.form is None:
            continue
        if budget is not None and time.perf_counter() - started > budget:
            skipped.append(entry.id)
            continue
        if entry.form.shifted != mine.shifted or not compatible(key, entry.ratios):
            continue
        try:
            orders, rotated = _orders(mine, entry)
            if not orders and not rotated:
                continue
            compared.append(entry.id)
            result = match(
                mine, entry.form, assumptions=entry.assumptions, orders=orders, rotated=rotated
            )
            if result is None:
                continue
            values = {str(p): to_text(sp.sympify(v)) for p, v in result.values.items()}
            transformation = result.transformation.description(mine, entry.form, result.values)
        except Exception as error:  # noqa: BLE001 - one case never stops identification
            failed.append((entry.id, f"{type(error).__name__}: {error}"[:200]))
            continue
        found.append(
            SameAs(entry.id, values, transformation, result.transformation.is_identity(), result)
        )
    seconds = time.perf_counter() - started
    return Identification(
        tuple(found), tuple(compared), seconds, mine, tuple(skipped), tuple(failed)
    )
