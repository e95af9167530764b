"""A short run of the coverage-guided fuzzer of the case-file reader and the expression
language (``scripts/fuzz_parser.py``, issue 34): a few thousand inputs made by libFuzzer
from the catalog and the hostile files, each loaded or refused with a clean message,
none past its time or memory bound, and the store never imported. The documented run
(100,000 inputs and more) is the script's own; this one keeps it working.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.clocks import HANG

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "fuzz_parser.py"
RUNS = 3000


@pytest.fixture(scope="module")
def atheris_installed() -> None:
    try:
        import atheris  # noqa: F401
    except ImportError as err:
        if os.environ.get("REGISTRY_CI"):
            pytest.fail(f"REGISTRY_CI is set, but atheris is not installed: {err}")
        pytest.skip(f"atheris is not installed ({err}); pip install -e '.[test]'")


def test_a_short_fuzz_run_finds_nothing(atheris_installed, tmp_path):
    out = tmp_path / "fuzz"
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--runs", str(RUNS), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=5 * HANG,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].endswith(f"; {RUNS} runs")
    inputs = int(lines[1].split()[0])
    assert inputs >= RUNS
    assert lines[-1] == "found: nothing (every input loaded or was refused with a clean message)"
    stats = json.loads((out / "stats.json").read_text())
    assert stats["store_modules"] == []  # nothing stored: the store was never imported
    assert not (out / "findings.jsonl").exists()


def test_the_fuzzer_reports_what_it_finds(atheris_installed, tmp_path, monkeypatch):
    """A reader that crashes on some input is found, named and its input kept."""
    out = tmp_path / "fuzz"
    broken = tmp_path / "sitecustomize.py"  # loaded by the fuzzing child at its start
    broken.write_text(
        "import sys\n"
        "if '--child' in sys.argv:\n"
        "    import registry.language.parser as p\n"
        "    real = p.parse_expression\n"
        "    def crashing(text, *args, **kwargs):\n"
        "        if '**9**9' in text:  # a seed (a hostile piece of tests/test_hostile.py)\n"
        "            raise KeyError('a bug')\n"
        "        return real(text, *args, **kwargs)\n"
        "    p.parse_expression = crashing\n",
        encoding="utf-8",
    )
    monkeypatch.setenv("PYTHONPATH", f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--runs", "600", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=5 * HANG,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    found = [line for line in done.stdout.splitlines() if line.startswith("found ")]
    assert found and all(": KeyError at " in line for line in found), found
    kept = list((out / "findings").iterdir())
    assert kept and all(b"**9**9" in path.read_bytes() for path in kept)
