"""Plots of numerical evidence: how a claimed integral drifts next to the energy.

Rendered headless (matplotlib's Agg canvas, no display and no global pyplot state),
so reports can be built in scripts, workers and CI.
"""

from __future__ import annotations

import os
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..audit.numeric_evidence import trajectory
from ..mathematics.case_mechanics import CaseMechanics
from ..model import Case


def _largest(values) -> float:
    """The largest absolute value of an array (0 for an empty one)."""
    return float(abs(values).max()) if len(values) else 0.0


def drift_plot(case: Case, claim_label: str, path: str | os.PathLike, seed: int = 0) -> Path:
    """Write a PNG of I(t) - I(0) and H(t) - H(0) along one trajectory; return its path.

    The trajectory is the first one the numeric evidence integrates (same seed).
    Raises KeyError for an unknown claim, ValueError when nothing could be integrated.
    """
    claim = case.claim(claim_label)
    run = trajectory(CaseMechanics(case), claim, seed)
    fig = Figure(figsize=(6.4, 3.6), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    label_i = f"$I(t) - I(0)$   (largest |change| {_largest(run.di):.2e})"
    label_h = f"$H(t) - H(0)$   (largest |change| {_largest(run.dh):.2e})"
    ax.plot(run.t, run.di, color="tab:red", lw=1.6, label=label_i)
    ax.plot(run.t, run.dh, color="tab:blue", lw=1.2, ls="--", label=label_h)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("time $t$")
    ax.set_ylabel("change along the trajectory")
    ax.set_title(f"{case.id} / {claim.label}", fontsize=10, parse_math=False)
    ax.legend(loc="best", fontsize=8)
    ax.grid(True, alpha=0.3)
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, format="png")
    return out
