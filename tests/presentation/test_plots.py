"""Drift plots: I(t) - I(0) next to H(t) - H(0) along one trajectory, as a PNG."""

from __future__ import annotations

import pytest

import registry
from registry.presentation.plots import drift_plot
from tests.helpers.samples import CASES, YEHIA_B

PNG = b"\x89PNG"


@pytest.fixture(scope="module")
def reg(tmp_path_factory):
    with registry.open(tmp_path_factory.mktemp("plots") / "r.sqlite") as opened:
        opened.add(CASES / f"{YEHIA_B}.toml")
        yield opened


def test_drift_plot_writes_a_png(reg, tmp_path):
    path = drift_plot(reg.case(YEHIA_B), "I2", tmp_path / "plots" / "i2.png")
    assert path == tmp_path / "plots" / "i2.png"
    assert path.read_bytes().startswith(PNG)
    with pytest.raises(KeyError):
        drift_plot(reg.case(YEHIA_B), "no-such-claim", tmp_path / "x.png")


def test_a_claim_that_cannot_be_integrated_is_a_value_error(reg, tmp_path):
    case = reg.case(YEHIA_B)
    claim = case.claims[0]
    from dataclasses import replace

    from registry.mathematics.mechanics import gamma1
    from registry.model import Equation

    impossible = replace(claim, on=(Equation("gamma1**2 = -1", gamma1**2, -1),))
    with pytest.raises(ValueError, match="no trajectory could be integrated"):
        drift_plot(replace(case, claims=(impossible,)), claim.label, tmp_path / "x.png")
