"""Plots of numerical evidence: how a claimed integral drifts next to the energy.

The plots draw data the audit computed (``model.DriftCurve``); nothing is integrated
here. Rendered headless (matplotlib's Agg canvas, no display and no global pyplot
state), so reports can be built in scripts, workers and CI. A report draws all its
plots on one ``DriftCanvas``: one figure whose lines, labels and limits are set again
for each curve, which draws the same pixels as a new figure in a fraction of the time.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image  # matplotlib's own dependency

from ..model import DriftCurve

#: Colours of a report's plot: an adaptive palette (fast octree) keeps the red and the
#: blue line apart and makes the PNG a fifth of its full-colour size.
PALETTE_COLOURS = 32


def _largest(values) -> float:
    """The largest absolute value of a sequence (0 for an empty one)."""
    return max((abs(v) for v in values), default=0.0)


class DriftCanvas:
    """One figure on which drift plots are drawn in turn, I(t) - I(0) and H(t) - H(0)."""

    def __init__(self) -> None:
        # fixed margins and a fixed legend place: a layout engine, or matplotlib's search
        # for the best legend place, would take most of the time a plot takes
        fig = Figure(figsize=(6.4, 3.8), dpi=100)
        fig.subplots_adjust(left=0.13, right=0.97, bottom=0.28, top=0.92)
        self.canvas = FigureCanvasAgg(fig)
        ax = self.axes = fig.add_subplot()
        (self.line_i,) = ax.plot([], [], color="tab:red", lw=1.6)
        (self.line_h,) = ax.plot([], [], color="tab:blue", lw=1.2, ls="--")
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel("time $t$")
        ax.set_ylabel("change along the trajectory")
        self.title = ax.set_title("", fontsize=10, parse_math=False, y=1.0)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        ax.grid(True, alpha=0.3)

    def draw(self, curve: DriftCurve) -> None:
        """Draw ``curve`` on the canvas (the previous curve's lines and labels replaced)."""
        ax = self.axes
        self.line_i.set_data(curve.t, curve.di)
        self.line_i.set_label(f"$I(t) - I(0)$   (largest |change| {_largest(curve.di):.2e})")
        self.line_h.set_data(curve.t if curve.dh else (), curve.dh)
        self.line_h.set_visible(bool(curve.dh))
        # a label starting with "_" keeps a curve without H's line out of the legend
        label_h = f"$H(t) - H(0)$   (largest |change| {_largest(curve.dh):.2e})"
        self.line_h.set_label(label_h if curve.dh else "_no H")
        self.title.set_text(f"{curve.case} / {curve.claim}")
        ax.relim(visible_only=True)
        ax.autoscale_view()
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), fontsize=8, frameon=False)
        self.canvas.draw()

    def png(self, curve: DriftCurve) -> bytes:
        """The curve's plot as a full-colour PNG."""
        self.draw(curve)
        out = io.BytesIO()
        self.canvas.print_png(out)
        return out.getvalue()

    def palette_png(self, curve: DriftCurve) -> bytes:
        """The curve's plot as a PNG of ``PALETTE_COLOURS`` colours, taken from the canvas's
        pixels without a full-colour PNG in between: what a report embeds or links."""
        self.draw(curve)
        width, height = self.canvas.get_width_height()
        rgba = Image.frombuffer("RGBA", (width, height), self.canvas.buffer_rgba())
        image = rgba.convert("RGB").quantize(PALETTE_COLOURS, method=Image.Quantize.FASTOCTREE)
        out = io.BytesIO()
        image.save(out, format="PNG")
        return out.getvalue()


def drift_plot(curve: DriftCurve, path: str | os.PathLike) -> Path:
    """Write a PNG of I(t) - I(0) and H(t) - H(0) along the curve's trajectory; its path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(DriftCanvas().png(curve))
    return out
