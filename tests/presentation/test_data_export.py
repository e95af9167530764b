"""Publishing the registry's tables (``registry export --format``): CSV, JSON and Parquet
files that round-trip and hold what the registry holds.

One database with two seed cases is audited once per module (fixture ``audited``).
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.presentation import data_export

ROOT = Path(registry.__file__).resolve().parent.parent
CASES = ROOT / "data" / "cases"
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"
READERS = {
    "csv": data_export.read_table,  # plain read_csv would read a volume "8" as a number
    # pandas' own JSON reader, told which columns are text ("8" is a volume, "0" a kappa)
    "json": lambda p: pd.read_json(
        p,
        orient="records",
        precise_float=True,
        dtype={c: "string" for c in data_export.TEXT_COLUMNS},
    ),
    "parquet": pd.read_parquet,
}
KEYS = {
    "cases": ["case", "version", "citation"],
    "claims": ["case", "label", "kind", "expression"],
    "verdicts": ["case", "claim", "check", "verdict", "method"],
    "all_results": ["case", "claim", "check", "verdict", "run"],
    "corrections": ["case", "claim", "kind", "verdict"],
    "runs": ["run", "status", "n_results"],
}


@pytest.fixture(scope="module")
def audited(module_databases):
    """A database with two seed cases, audited in this process (on SQLite, then on
    PostgreSQL: fixture ``backend``)."""
    db = module_databases.new("sharing")
    reg = registry.open(db)
    reg.add(CASES / f"{YEHIA_B}.toml", CASES / f"{ZHUKOVSKY}.toml")
    report = reg.audit(jobs=1)
    yield SimpleNamespace(reg=reg, db=db, report=report)
    reg.close()


# ------------------------------------------------------------------ tables


def _canonical(value, column: str):
    """One cell in a form every format reads back alike (dtypes normalised)."""
    if isinstance(value, dict | list):
        return value
    if value is None or (not isinstance(value, str) and pd.isna(value)) or value == "":
        return None
    if column in data_export.JSON_COLUMNS:
        return json.loads(value)
    if column.endswith("_at"):
        return pd.Timestamp(value).tz_convert("UTC").isoformat()
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    if isinstance(value, int | float) or hasattr(value, "dtype"):
        return float(f"{float(value):.12g}")
    return str(value)


def _rows(frame: pd.DataFrame) -> list[dict]:
    return [
        {c: _canonical(v, c) for c, v in row.items()}
        for row in frame.astype(object).to_dict("records")
    ]


@pytest.mark.parametrize("fmt", data_export.FORMATS)
def test_each_format_writes_six_tables_that_round_trip(audited, fmt, tmp_path):
    paths = audited.reg.export(tmp_path / fmt, fmt)
    assert [p.name for p in paths] == [f"{name}.{fmt}" for name in data_export.TABLES]
    originals = audited.reg.tables()
    for path in paths:
        name = path.stem
        original, back = originals[name], READERS[fmt](path)
        assert back.shape == original.shape, name
        assert list(back.columns) == list(original.columns), name
        assert _rows(back) == _rows(original), name
        for key in KEYS[name]:
            assert [_canonical(v, key) for v in back[key]] == [
                _canonical(v, key) for v in original[key]
            ], (name, key)


def _verdict_map(frame: pd.DataFrame) -> dict:
    """(case, claim, check) -> verdict of a verdicts table (claim None for case checks)."""
    return {
        (r.case, None if pd.isna(r.claim) else r.claim, r.check): str(r.verdict)
        for r in frame.itertuples()
    }


def test_the_tables_hold_what_the_registry_holds(audited, tmp_path):
    t = audited.reg.tables()
    assert set(t["cases"]["case"]) == {YEHIA_B, ZHUKOVSKY}
    assert len(t["all_results"]) == sum(t["runs"]["n_results"])
    assert set(t["verdicts"]["verdict"]) <= {"verified", "refuted", "inconclusive"}
    table = _verdict_map(t["verdicts"])
    assert len(table) == len(t["verdicts"])  # one row per (case, claim, check)
    assert table == _verdict_map(audited.reg.verdicts())
    # and what the audit itself found
    found = {
        (a.case, r.claim, r.check): str(r.verdict) for a in audited.report.audits for r in a.results
    }
    assert table == found
    assert table[YEHIA_B, "I2", "casimir"] == "refuted"
    assert table[ZHUKOVSKY, "area", "casimir"] == "verified"
    # the exported files say the same
    for fmt in data_export.FORMATS:
        audited.reg.export(tmp_path / fmt, fmt)
        exported = data_export.read_table(tmp_path / fmt / f"verdicts.{fmt}")
        assert _verdict_map(exported) == table, fmt
    assert len(t["corrections"]) > 0


@pytest.mark.parametrize("fmt", data_export.FORMATS)
def test_json_columns_come_back_as_json(audited, fmt, tmp_path):
    audited.reg.export(tmp_path, fmt)
    verdicts = data_export.read_table(tmp_path / f"verdicts.{fmt}")
    witness = verdicts.query("check == 'casimir' and case == @YEHIA_B")["witness"].iloc[0]
    original = audited.reg.verdicts().query("check == 'casimir' and case == @YEHIA_B")
    assert witness == original["witness"].iloc[0]
    assert isinstance(witness["point"], dict)
    runs = data_export.read_table(tmp_path / f"runs.{fmt}")
    assert runs["options"].iloc[0]["jobs"] == 1
    assert str(runs["started_at"].dtype).startswith("datetime64")
    payloads = data_export.read_table(tmp_path / f"corrections.{fmt}")["payload"]
    assert all(isinstance(p, dict) for p in payloads)


def test_an_unknown_format_is_refused(audited, tmp_path):
    with pytest.raises(ValueError, match="unknown format"):
        audited.reg.export(tmp_path, "xlsx")


# ------------------------------------------------------------------ CLI


def test_cli_export_writes_tables(audited, tmp_path):
    out = tmp_path / "tables"
    result = CliRunner().invoke(
        main, ["--db", str(audited.db), "export", "--format", "csv", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.split() == [str(out / f"{name}.csv") for name in data_export.TABLES]
    assert all((out / f"{name}.csv").stat().st_size > 0 for name in data_export.TABLES)


@pytest.mark.parametrize("args", [[], ["--format", "csv", "--bibtex"]])
def test_cli_export_needs_exactly_one_kind(audited, args):
    result = CliRunner().invoke(main, ["--db", str(audited.db), "export", *args])
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        "Error: give exactly one of --format and --bibtex (see: registry export --help)"
    ]


def test_cli_export_help_has_an_example():
    result = CliRunner().invoke(main, ["export", "--help"])
    assert result.exit_code == 0
    assert "Example: registry export" in result.stdout
