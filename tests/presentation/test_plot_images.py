"""The drift images of a report: drawn once per curve and read back from the cache folder
by a later report; a changed curve is drawn again, and a cache that cannot be written
only means drawing again."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from dataclasses import astuple

import pytest
from PIL import Image

from registry.model import DriftCurve
from registry.presentation import plot_images
from registry.presentation.plot_images import DriftImages, key
from registry.presentation.plots import DriftCanvas

CURVE = DriftCurve("c", "I", (0.0, 1.0, 2.0), (0.0, 0.5, 1.0), (0.0, 1e-9, -2e-9))


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("REGISTRY_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_an_image_is_drawn_once_and_read_back_by_a_later_report(cache, monkeypatch):
    first = DriftImages()
    png = first.png(CURVE)
    assert first.drawn == 1
    assert png == DriftCanvas().palette_png(CURVE)  # the picture the canvas draws
    assert list(cache.rglob("*.png")) == [
        cache / "drift-plots" / plot_images.DRAWING / f"{key(CURVE)}.png"
    ]

    def refuse(self, curve):
        raise AssertionError("an image in the cache was drawn again")

    monkeypatch.setattr(DriftCanvas, "palette_png", refuse)
    again = DriftImages()
    assert again.png(CURVE) == png
    assert again.drawn == 0


def test_a_changed_curve_or_claim_is_drawn_again(cache):
    images = DriftImages()
    images.png(CURVE)
    moved = DriftCurve("c", "I", (0.0, 1.0, 2.0), (0.0, 0.5, 1.5), CURVE.dh)
    renamed = DriftCurve("c", "J", CURVE.t, CURVE.di, CURVE.dh)
    assert len({key(CURVE), key(moved), key(renamed)}) == 3
    images.png(moved)
    images.png(renamed)
    assert images.drawn == 3
    assert len(list(cache.rglob("*.png"))) == 3


def test_a_cache_that_cannot_be_written_only_costs_drawing_again(tmp_path, monkeypatch):
    blocked = tmp_path / "a-file"
    blocked.write_text("not a folder", encoding="utf-8")
    monkeypatch.setenv("REGISTRY_CACHE", str(blocked))
    images = DriftImages()
    png = images.png(CURVE)
    assert images.png(CURVE) == png and images.drawn == 2
    assert Image.open(io.BytesIO(png)).format == "PNG"


def test_a_report_imports_matplotlib_only_to_draw(cache):
    """Building a report and reading cached images need no matplotlib (its import is
    a good part of drawing the first plot)."""
    png = DriftImages().png(CURVE)
    probe = (
        "import sys\nfrom registry.presentation import report_content\n"
        "from registry.presentation.plot_images import DriftImages\n"
        "from registry.model import DriftCurve\n"
        f"png = DriftImages().png(DriftCurve{astuple(CURVE)!r})\n"
        "print(len(png), 'matplotlib' in sys.modules)"
    )
    env = {**os.environ, "REGISTRY_CACHE": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, env=env
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [str(len(png)), "False"]
