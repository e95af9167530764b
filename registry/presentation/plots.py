"""Plots of numerical evidence: how a claimed integral drifts next to the energy.

The plots draw data the audit computed (``model.DriftCurve``); nothing is integrated
here. Rendered headless (matplotlib's Agg canvas, no display and no global pyplot
state), so reports can be built in scripts, workers and CI.
"""

from __future__ import annotations

import os
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..model import DriftCurve


def _largest(values) -> float:
    """The largest absolute value of a sequence (0 for an empty one)."""
    return max((abs(v) for v in values), default=0.0)


def drift_plot(curve: DriftCurve, path: str | os.PathLike) -> Path:
    """Write a PNG of I(t) - I(0) and H(t) - H(0) along the curve's trajectory; its path."""
    # fixed margins and a fixed legend place: a layout engine, or matplotlib's search for
    # the best legend place, would take most of the time a plot takes
    fig = Figure(figsize=(6.4, 3.8), dpi=100)
    fig.subplots_adjust(left=0.13, right=0.97, bottom=0.28, top=0.92)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    label_i = f"$I(t) - I(0)$   (largest |change| {_largest(curve.di):.2e})"
    ax.plot(curve.t, curve.di, color="tab:red", lw=1.6, label=label_i)
    if curve.dh:
        label_h = f"$H(t) - H(0)$   (largest |change| {_largest(curve.dh):.2e})"
        ax.plot(curve.t, curve.dh, color="tab:blue", lw=1.2, ls="--", label=label_h)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("time $t$")
    ax.set_ylabel("change along the trajectory")
    ax.set_title(f"{curve.case} / {curve.claim}", fontsize=10, parse_math=False)
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), fontsize=8, frameon=False)
    ax.grid(True, alpha=0.3)
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, format="png")
    return out
