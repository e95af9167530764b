"""The domain of residuals (``registry/mathematics/domain.py``): restricting it to a
level set or requiring more to be defined keeps everything else."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.domain import Domain
from registry.mathematics.mechanics import AXIS, s
from registry.mathematics.zero_test import decide
from registry.model import Verdict

a = sp.Symbol("a", positive=True)


def test_restricted_replaces_the_level_set_and_keeps_the_rest():
    domain = Domain(parameters=(a,), nonzero=(a,), on=(s,), defined=(a,))
    on = (AXIS[0],)
    restricted = domain.restricted(on)
    assert restricted.on == on
    assert (restricted.parameters, restricted.nonzero, restricted.defined) == ((a,), (a,), (a,))
    assert domain.on == (s,)  # frozen: the original is unchanged


def test_requiring_adds_to_what_must_be_defined():
    domain = Domain(defined=(a,)).requiring([1 / AXIS[2]])
    assert domain.defined == (a, 1 / AXIS[2])


def test_the_level_set_decides_what_vanishes():
    """s*gamma1 is not zero in general, but is on s = 0 (the zero test uses the domain)."""
    residual = {"r": s * AXIS[0]}
    assert decide(residual, Domain()).verdict is Verdict.REFUTED
    assert decide(residual, Domain().restricted([s])).verdict is Verdict.VERIFIED
