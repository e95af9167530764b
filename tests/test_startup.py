"""Start-up pays only for what it uses: ``import registry`` imports none of the heavy
libraries, ``registry --help`` none of those the commands need only when they run
(scripts/bench_startup.py measures the times; here, what is imported)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import registry
from registry.cli import VERDICTS
from registry.model import Verdict

HEAVY = ("sympy", "sqlalchemy", "alembic", "pandas", "numpy", "scipy", "matplotlib", "dask")


def imported_after(code: str) -> dict[str, bool]:
    """Which of the heavy libraries a fresh interpreter has imported after ``code``."""
    probe = (
        f"{code}\nimport json, sys\nprint(json.dumps({{m: m in sys.modules for m in {HEAVY!r}}}))"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_import_registry_imports_no_heavy_library():
    assert imported_after("import registry") == dict.fromkeys(HEAVY, False)


@pytest.mark.parametrize("args", [["--help"], ["audit", "--help"], ["--version"]])
def test_the_help_and_the_version_import_no_heavy_library(args):
    code = (
        "import sys\nfrom registry.cli import main\n"
        f"sys.argv = ['registry', *{args!r}]\n"
        "try:\n    main()\nexcept SystemExit:\n    pass"
    )
    assert imported_after(code) == dict.fromkeys(HEAVY, False)


def test_a_public_name_is_imported_when_first_used():
    found = imported_after("import registry\nregistry.Case")
    assert found["sympy"] and not found["pandas"] and not found["sqlalchemy"]
    assert registry.open is registry.api.open_registry
    assert set(registry.__all__) <= set(dir(registry))
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        registry.no_such_name  # noqa: B018


def test_the_verdicts_the_cli_offers_are_the_models():
    assert VERDICTS == tuple(str(v) for v in Verdict)
