"""A matched case's claims carried into the system's own variables."""

from __future__ import annotations

import sympy as sp

from registry.discovery.identification.claim_match import carried_claims
from registry.discovery.identification.identify import identify
from tests.helpers.catalog import catalog_case, catalog_index


def test_kovalevskayas_integral_is_carried_into_the_normalised_case():
    mine = catalog_case("kovalevskaya-1889-heavy-top-normalised")
    found = identify(mine.dynamics, catalog_index(), exclude=(mine.id,))
    general = [s for s in found.same if s.case == "kovalevskaya-1889-heavy-top"]
    carried = dict(
        ((c, label), e) for c, label, e in carried_claims(general, found.form, catalog_index())
    )
    k = carried[("kovalevskaya-1889-heavy-top", "K")]
    own = next(c for c in mine.claims if c.label == "K").expression.expr
    assert sp.expand(k - own) == 0
