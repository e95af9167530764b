"""Golden outputs: the verdict table and the JSON of a fresh audit of the seed catalog are
pinned, so that a refactoring (or any change) cannot alter what users see unnoticed.

Timings and run numbers are left out of the comparison; the table is read at 80
columns, what a terminal of normal width (and a pipe) gets. When an output changes on
purpose, regenerate the files with ``python -m tests.test_golden`` and review the diff.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from registry.cli import main
from tests.helpers.samples import CASES

GOLDEN = Path(__file__).parent / "data" / "golden"
#: The reference paper's seed catalog: the case files at the top of data/cases.
SEED_FILES = sorted(CASES.glob("*.toml"))
#: The terminal width the verdict table is pinned at.
WIDTH = 80


def without_timings(value):
    """A JSON value with every ``seconds`` key dropped and the run number blanked."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k != "seconds"}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def audit_outputs(db: Path) -> tuple[dict, str]:
    """(JSON document, verdict table) of a fresh audit of the seed catalog."""
    runner = CliRunner(env={"COLUMNS": str(WIDTH)})
    added = runner.invoke(main, ["--db", str(db), "add", *map(str, SEED_FILES)])
    assert added.exit_code == 0, added.output
    as_json = runner.invoke(main, ["--db", str(db), "audit", "--fresh", "--json", "--jobs", "1"])
    assert as_json.exit_code == 0, as_json.output
    table = runner.invoke(main, ["--db", str(db), "audit", "--fresh", "--jobs", "1"])
    assert table.exit_code == 0, table.output
    document = without_timings(json.loads(as_json.stdout))
    document["run"] = None
    return document, re.sub(r"^run \d+: ", "run N: ", table.stdout, flags=re.M)


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    return audit_outputs(tmp_path_factory.mktemp("golden") / "r.sqlite")


def test_the_seed_catalog_is_sixteen_files():
    assert len(SEED_FILES) == 16


def test_audit_json_is_what_it_was(outputs):
    expected = json.loads((GOLDEN / "seed-audit.json").read_text(encoding="utf-8"))
    assert outputs[0] == expected


def test_verdict_table_is_what_it_was(outputs):
    assert outputs[1] == (GOLDEN / "seed-table.txt").read_text(encoding="utf-8")


if __name__ == "__main__":  # regenerate the golden files
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        document, table = audit_outputs(Path(tmp) / "r.sqlite")
    GOLDEN.mkdir(parents=True, exist_ok=True)
    (GOLDEN / "seed-audit.json").write_text(
        json.dumps(document, indent=2, ensure_ascii=False) + "\n", encoding="utf-8"
    )
    (GOLDEN / "seed-table.txt").write_text(table, encoding="utf-8")
    sys.exit(0)
