"""Which claims of the catalog cases a system is the same as its integrals equal.

A claim K of a matched case is carried into the system's own variables through the match
(``Transformation.pullback``: into the case's normal form at its parameter values,
through the change of variables, out of the system's normal form). An integral F found
on the system is the claim again where F = sum c_j P_j + const, with P_j products of the
system's known integrals and of such claims: decided by ``novelty`` exactly as for the
searched case's own claims (linear algebra over Q or Q(p), then the identity checked in
the system's ring). A claim with level sets (``on``), or that is not a polynomial of
the system's state once carried over (a rotation's square roots left in it), is not
used. A claim need not be proven for this: the identity with F, an integral proven by
the audit, is what is checked.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import sympy as sp

from .catalog_index import CatalogIndex
from .field_form import FieldForm
from .identify import SameAs


def carried_claims(
    same: Sequence[SameAs], mine: FieldForm, index: CatalogIndex
) -> list[tuple[str, str, sp.Expr]]:
    """(case id, claim label, the claim in the system's M, gamma and parameters) for every
    claim of every matched case that can be carried over (module docstring)."""
    entries = {e.id: e for e in index.entries}
    out = []
    for match in same:
        entry = entries.get(match.case)
        if entry is None or entry.form is None:
            continue
        values = match.found.values
        # the case's normal form at those values: its shift f(gamma) may hold parameters
        at_values = replace(
            entry.form, shift=tuple(sp.sympify(e).xreplace(values) for e in entry.form.shift)
        )
        for claim in entry.case.claims:
            if claim.on or not claim.kind.conserved:
                continue
            expr = entry.case.dynamics.expanded(claim.expression.expr)
            if expr.atoms(sp.Function) or not expr.free_symbols:
                continue
            try:
                at = sp.sympify(expr).xreplace(values)
                carried = match.found.transformation.pullback(at, at_values, mine)
            except (TypeError, ValueError, ZeroDivisionError):
                continue
            if any(not a.exp.is_Integer for a in carried.atoms(sp.Pow)):
                carried = sp.expand(sp.radsimp(carried))  # a rotation's radicals cancel
            out.append((match.case, claim.label, carried))
    return out
