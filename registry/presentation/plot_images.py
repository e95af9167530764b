"""The drift images a report shows, drawn once per curve and kept in the cache folder.

An image is keyed by a hash of what it draws (the case, the claim and the curve's
numbers) and of how it is drawn (``DRAWING``, matplotlib's version), so a second report
of the same run reads its images instead of drawing them; matplotlib is imported only
when an image has to be drawn. Deleting the folder loses nothing but time.
"""

from __future__ import annotations

import hashlib
import json
import os
from functools import cache
from importlib.metadata import version
from pathlib import Path
from typing import TYPE_CHECKING

from ..model import DriftCurve
from ..settings import cache_folder

if TYPE_CHECKING:
    from .plots import DriftCanvas

#: Bump when how a drift plot is drawn changes (``plots.DriftCanvas``): older images are
#: not used.
DRAWING = "1"


@cache
def _matplotlib() -> str:
    """The version of matplotlib installed (read without importing it)."""
    return version("matplotlib")


def key(curve: DriftCurve) -> str:
    """The hash of what an image of ``curve`` shows and of how it is drawn."""
    what = [DRAWING, _matplotlib(), curve.case, curve.claim, curve.t, curve.di, curve.dh]
    return hashlib.sha256(json.dumps(what).encode()).hexdigest()


def _path(curve: DriftCurve) -> Path:
    return cache_folder() / "drift-plots" / DRAWING / f"{key(curve)}.png"


class DriftImages:
    """The report images of drift curves: read from the cache folder, else drawn (on one
    ``plots.DriftCanvas`` for all of them) and kept there."""

    def __init__(self) -> None:
        self._canvas: DriftCanvas | None = None
        #: how many images were drawn rather than read (what a second report saves)
        self.drawn = 0

    def png(self, curve: DriftCurve) -> bytes:
        """The PNG of the curve's drift plot (``DriftCanvas.palette_png``)."""
        path = _path(curve)
        try:
            return path.read_bytes()
        except OSError:
            pass
        if self._canvas is None:
            from .plots import DriftCanvas  # matplotlib: only when an image is drawn

            self._canvas = DriftCanvas()
        png = self._canvas.palette_png(curve)
        self.drawn += 1
        _keep(path, png)
        return png


def _keep(path: Path, png: bytes) -> None:
    """Keep an image in the cache folder (written aside, renamed into place); a folder
    that cannot be written only costs the time to draw it again."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        aside = path.with_suffix(f".{os.getpid()}.tmp")
        aside.write_bytes(png)
        aside.replace(path)
    except OSError:
        return
