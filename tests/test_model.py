"""The domain model: verdicts combined, read-only mappings that pickle, and the two
conversions the model owns (torque component numbers, numbers that do not exist)."""

from __future__ import annotations

import math
import pickle

import pytest

from registry.mathematics.mechanics import STATE, s
from registry.model import (
    VARIABLE_NAMES,
    CaseAudit,
    CheckResult,
    Correction,
    Evidence,
    FrozenDict,
    Verdict,
    component_index,
    component_number,
    nan_to_none,
    none_to_nan,
)

V, R, U, E = Verdict.VERIFIED, Verdict.REFUTED, Verdict.INCONCLUSIVE, Verdict.ERROR


@pytest.mark.parametrize(
    ("verdicts", "combined"),
    [([V, V], V), ([V, R, E], R), ([V, E, U], E), ([V, U], U), ([], U)],
)
def test_verdicts_combine_as_documented(verdicts, combined):
    assert Verdict.combined(verdicts) is combined


def test_frozen_mappings_refuse_changes_and_survive_pickling():
    frozen = FrozenDict({"a": 1})
    with pytest.raises(TypeError):
        frozen["b"] = 2
    with pytest.raises(TypeError):
        frozen.update(b=2)
    assert pickle.loads(pickle.dumps(frozen)) == {"a": 1}
    assert hash(frozen) == hash(FrozenDict({"a": 1}))


def test_torque_components_are_numbered_from_one_where_people_read_them():
    assert [component_number(k) for k in range(3)] == [1, 2, 3]
    assert [component_index(component_number(k)) for k in range(3)] == [0, 1, 2]
    fix = Correction("torque", "I2", torque=("a", "b", "c"), changed=(2,), checks={"jacobi": V})
    assert fix.changed_components == ((3, "c"),)
    assert fix.kept_components == (1, 2)
    assert fix.as_dict()["changed"] == [3]
    assert fix.as_dict()["checks"] == {"jacobi": "verified"}


def test_a_number_that_does_not_exist_is_none_outside_and_nan_inside():
    assert nan_to_none(math.nan) is None and nan_to_none(2.5) == 2.5
    assert math.isnan(none_to_nan(None)) and none_to_nan(2.5) == 2.5
    found = Evidence("I", math.nan, math.nan, 0, note="no start point")
    assert found.as_dict()["drift"] is None and found.as_dict()["floor"] is None


def test_results_are_found_by_check_and_claim():
    audit = CaseAudit("c", "h", (CheckResult("integral", V, "m", claim="I"),))
    assert audit.result("integral", "I").verdict is V
    with pytest.raises(KeyError):
        audit.result("integral")


def test_variable_names_are_those_of_the_mechanics():
    assert VARIABLE_NAMES == tuple(str(v) for v in (*STATE, s))


def test_only_integrals_and_casimirs_are_conserved_kinds():
    from registry.model import ClaimKind

    assert {k for k in ClaimKind if k.conserved} == {ClaimKind.INTEGRAL, ClaimKind.CASIMIR}
