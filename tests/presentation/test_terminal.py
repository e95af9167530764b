"""The width the command line prints to: $COLUMNS, else the terminal's, else 80."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from registry.presentation.terminal import terminal_width


@pytest.mark.parametrize(("columns", "width"), [("120", 120), ("80", 80), ("12", 40)])
def test_columns_sets_the_width_and_none_is_narrower_than_forty(monkeypatch, columns, width):
    monkeypatch.setenv("COLUMNS", columns)
    assert terminal_width() == width


def test_a_pipe_without_columns_gets_eighty():
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    code = "from registry.presentation.terminal import terminal_width; print(terminal_width())"
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "80\n"
