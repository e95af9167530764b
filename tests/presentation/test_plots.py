"""Drift plots: I(t) - I(0) next to H(t) - H(0) along one trajectory, as a PNG, drawn from
the curve the audit computed (``audit.numeric_evidence.drift_curve``); one canvas drawing
curve after curve gives the pixels a new canvas gives each."""

from __future__ import annotations

import io
from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

import registry
from registry.audit.numeric_evidence import drift_curve, drift_curves
from registry.mathematics.mechanics import gamma1
from registry.model import DriftCurve, Equation
from registry.presentation.plots import PALETTE_COLOURS, DriftCanvas, drift_plot
from tests.helpers.samples import CASES, YEHIA_B

PNG = b"\x89PNG"


@pytest.fixture(scope="module")
def reg(tmp_path_factory):
    with registry.open(tmp_path_factory.mktemp("plots") / "r.sqlite") as opened:
        opened.add(CASES / f"{YEHIA_B}.toml")
        yield opened


def test_drift_plot_writes_a_png_of_the_curve(reg, tmp_path):
    curve = drift_curve(reg.case(YEHIA_B), "I2")
    assert len(curve.t) == len(curve.di) == len(curve.dh) > 100 and curve.t[0] == 0.0
    assert max(abs(x) for x in curve.di) > 1e3 * max(abs(x) for x in curve.dh)  # I2 drifts
    path = drift_plot(curve, tmp_path / "plots" / "i2.png")
    assert path == tmp_path / "plots" / "i2.png"
    assert path.read_bytes().startswith(PNG)


def test_a_curve_without_h_is_drawn_alone(tmp_path):
    curve = DriftCurve("c", "I", (0.0, 1.0, 2.0), (0.0, 0.5, 1.0))
    assert drift_plot(curve, tmp_path / "x.png").read_bytes().startswith(PNG)


def _pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def test_a_reused_canvas_draws_each_curve_as_a_new_one_does(reg):
    """Lines, labels, limits and legend are all replaced: a curve with H after one
    without, and one without after one with, look as they do drawn alone."""
    with_h = drift_curve(reg.case(YEHIA_B), "I2")
    alone = DriftCurve("c", "I", (0.0, 1.0, 2.0), (0.0, -3e-4, 7e-4))
    canvas = DriftCanvas()
    for curve in (with_h, alone, with_h, alone):
        assert np.array_equal(_pixels(canvas.png(curve)), _pixels(DriftCanvas().png(curve)))
        legend = [t.get_text() for t in canvas.axes.get_legend().get_texts()]
        assert len(legend) == (2 if curve.dh else 1)
        assert legend[0].startswith("$I(t) - I(0)$")


def test_the_report_image_is_the_plot_in_a_few_colours(reg):
    """Red I and blue H stay apart in the palette image, at the plot's size."""
    curve = drift_curve(reg.case(YEHIA_B), "I2")
    canvas = DriftCanvas()
    full, small = _pixels(canvas.png(curve)), canvas.palette_png(curve)
    image = Image.open(io.BytesIO(small))
    assert image.mode == "P" and image.size == (full.shape[1], full.shape[0])
    assert len(image.getcolors()) <= PALETTE_COLOURS
    assert np.abs(_pixels(small).astype(int) - full).mean() < 3  # grey levels of 255
    colours = {c for _, c in image.convert("RGB").getcolors()}
    # hues, not exact shades: the dashed blue line is anti-aliased to a lighter blue
    # (about (114, 169, 207) in the full image with matplotlib 3.11)
    reddish = any(r > 150 and g < 100 and b < 100 for r, g, b in colours)
    bluish = any(b > 120 and b - r > 60 and b > g for r, g, b in colours)
    assert reddish and bluish


def test_the_facade_writes_a_claims_plot_and_names_a_claim_it_does_not_make(reg, tmp_path):
    assert reg.plot(YEHIA_B, "I2", tmp_path / "i2.png").read_bytes().startswith(PNG)
    with pytest.raises(registry.errors.UnknownClaimError):
        reg.plot(YEHIA_B, "no-such-claim", tmp_path / "x.png")


def test_a_claim_that_cannot_be_integrated_says_why(reg):
    case = reg.case(YEHIA_B)
    claim = case.claims[0]
    impossible = replace(claim, on=(Equation("gamma1**2 = -1", gamma1**2, -1),))
    case = replace(case, claims=(impossible,))
    with pytest.raises(ValueError, match="no trajectory could be integrated"):
        drift_curve(case, claim.label)
    assert (
        "no trajectory could be integrated"
        in drift_curves([(case, claim.label)])[case.id, claim.label]
    )
