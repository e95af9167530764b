"""Publishing (``registry.sharing``), notebook display (``registry.display``), CITATION.cff
and the progress bar of ``registry audit``.

One database with two seed cases is audited once per module (fixture ``audited``).
"""

from __future__ import annotations

import dataclasses
import io
import json
import re
import sys
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest
from click.testing import CliRunner

import registry
from registry import display, sharing
from registry.cli import main

ROOT = Path(registry.__file__).resolve().parent.parent
CASES = ROOT / "data" / "cases"
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"
READERS = {
    "csv": pd.read_csv,
    "json": lambda p: pd.read_json(p, orient="records", precise_float=True),
    "parquet": pd.read_parquet,
}
KEYS = {
    "cases": ["case", "version", "citation"],
    "claims": ["case", "label", "kind", "expression"],
    "verdicts": ["case", "claim", "check", "verdict", "method"],
    "all_results": ["case", "claim", "check", "verdict", "run"],
    "repairs": ["case", "claim", "kind", "verdict"],
    "runs": ["run", "status", "n_results"],
}


@pytest.fixture(scope="module")
def audited(tmp_path_factory):
    """A database with two seed cases, audited in this process."""
    db = tmp_path_factory.mktemp("sharing") / "registry.sqlite"
    reg = registry.open(db)
    reg.add(CASES / f"{YEHIA_B}.toml", CASES / f"{ZHUKOVSKY}.toml")
    report = reg.audit(jobs=0)
    yield SimpleNamespace(reg=reg, db=db, report=report)
    reg.close()


# ------------------------------------------------------------------ tables


def _canonical(value, column: str):
    """One cell in a form every format reads back alike (dtypes normalised)."""
    if isinstance(value, dict | list):
        return value
    if value is None or (not isinstance(value, str) and pd.isna(value)) or value == "":
        return None
    if column in sharing.JSON_COLUMNS:
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


@pytest.mark.parametrize("fmt", sharing.FORMATS)
def test_each_format_writes_six_tables_that_round_trip(audited, fmt, tmp_path):
    paths = sharing.export_tables(audited.reg, tmp_path / fmt, fmt)
    assert [p.name for p in paths] == [f"{name}.{fmt}" for name in sharing.TABLES]
    originals = sharing.tables(audited.reg)
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
    t = sharing.tables(audited.reg)
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
    for fmt in sharing.FORMATS:
        sharing.export_tables(audited.reg, tmp_path / fmt, fmt)
        exported = sharing.read_table(tmp_path / fmt / f"verdicts.{fmt}")
        assert _verdict_map(exported) == table, fmt
    assert len(t["repairs"]) > 0


@pytest.mark.parametrize("fmt", sharing.FORMATS)
def test_json_columns_come_back_as_json(audited, fmt, tmp_path):
    sharing.export_tables(audited.reg, tmp_path, fmt)
    verdicts = sharing.read_table(tmp_path / f"verdicts.{fmt}")
    witness = verdicts.query("check == 'casimir' and case == @YEHIA_B")["witness"].iloc[0]
    original = audited.reg.verdicts().query("check == 'casimir' and case == @YEHIA_B")
    assert witness == original["witness"].iloc[0]
    assert isinstance(witness["point"], dict)
    runs = sharing.read_table(tmp_path / f"runs.{fmt}")
    assert runs["options"].iloc[0]["jobs"] == 0
    assert str(runs["started_at"].dtype).startswith("datetime64")
    payloads = sharing.read_table(tmp_path / f"repairs.{fmt}")["payload"]
    assert all(isinstance(p, dict) for p in payloads)


def test_an_unknown_format_is_refused(audited, tmp_path):
    with pytest.raises(ValueError, match="unknown format"):
        sharing.export_tables(audited.reg, tmp_path, "xlsx")


# ------------------------------------------------------------------ BibTeX


def _balanced(text: str) -> bool:
    depth = 0
    for char in text:
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0


def test_bibtex_has_one_entry_per_source_with_unique_keys(audited):
    text = sharing.bibtex(audited.reg)
    keys = re.findall(r"^@(\w+)\{([^,]+),", text, flags=re.M)
    assert len(keys) == audited.reg.cases()["citation"].nunique() == 2
    assert len({k for _, k in keys}) == len(keys)
    assert _balanced(text)
    assert "Yehia" in text and "2003" in text
    assert ("article", "yehia2003") in keys
    assert ("book", "moiseyev1968") in keys
    assert f"Registry cases: {YEHIA_B}" in text


def test_bibtex_keys_are_unique_and_fall_back_to_the_case_id(case_factory):
    reg = registry.open(":memory:")
    citations = {
        "demo-a": "A.B. Smith, J. Fun. 1 (1999) 1-2",
        "demo-b": "A.B. Smith, J. Fun. 2 (1999) 3-4",
        "demo-c": "Anonymous report on {braces} & 100% of $x_1$",
    }
    for i, (case_id, citation) in enumerate(citations.items()):
        reg.add_case(case_factory(case_id, f'id = "{case_id}" # {i}\n', citation=citation))
    text = sharing.bibtex(reg)
    keys = re.findall(r"^@\w+\{([^,]+),", text, flags=re.M)
    assert sorted(keys) == ["demo-c", "smith1999a", "smith1999b"]
    assert _balanced(text)
    assert r"\textbraceleft{}braces\textbraceright{} \& 100\% of \$x\_1\$" in text


def test_latex_escape_leaves_no_bare_special():
    escaped = sharing.latex_escape(r"a_b & c% {d} #e ~f ^g \h $i")
    assert re.search(r"(?<!\\)[&%#$_]", escaped) is None
    assert _balanced(escaped)


# ------------------------------------------------------------------ CLI


def test_cli_export_writes_tables(audited, tmp_path):
    out = tmp_path / "tables"
    result = CliRunner().invoke(
        main, ["--db", str(audited.db), "export", "--format", "csv", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.split() == [str(out / f"{name}.csv") for name in sharing.TABLES]
    assert all((out / f"{name}.csv").stat().st_size > 0 for name in sharing.TABLES)


def test_cli_export_bibtex_to_a_file_and_to_stdout(audited, tmp_path):
    runner = CliRunner()
    target = tmp_path / "sources.bib"
    to_file = runner.invoke(
        main, ["--db", str(audited.db), "export", "--bibtex", "-o", str(target)]
    )
    assert to_file.exit_code == 0, to_file.output
    assert to_file.stdout.strip() == str(target)
    to_stdout = runner.invoke(main, ["--db", str(audited.db), "export", "--bibtex"])
    assert to_stdout.exit_code == 0, to_stdout.output
    assert to_stdout.stdout == target.read_text(encoding="utf-8") == sharing.bibtex(audited.reg)


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


# ------------------------------------------------------------------ CITATION.cff


def test_citation_cff_parses():
    import yaml  # PyYAML, in the project's ``test`` extra

    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    data = yaml.safe_load(text)
    assert isinstance(data, dict)
    # the keys CFF 1.2.0 requires of a citation, and of each of its references
    for key in ("cff-version", "message", "title", "authors"):
        assert data.get(key), key
    assert data["cff-version"] == "1.2.0"
    assert data["title"] == "Registry of rigid-body integrability claims"
    assert data["version"] == "0.1.0"
    assert data["authors"] == [{"name": "Registry maintainers"}]
    (paper,) = data["references"]
    for key in ("type", "title", "authors"):
        assert paper.get(key), key
    assert paper["title"].startswith("Hamilton-Poisson formulation")
    assert [a["family-names"] for a in paper["authors"]] == ["Birtea", "Casu", "Comanescu"]


def test_citation_version_is_the_package_version():
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    project = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    version = re.search(r'^version = "([^"]+)"', project, flags=re.M).group(1)
    assert f'version: "{version}"' in text


# ------------------------------------------------------------------ display


def test_case_reprs():
    case = registry.load_case(CASES / f"{YEHIA_B}.toml")
    html = case._repr_html_()
    assert YEHIA_B in html and "<table" in html
    assert "I2 (casimir)" in html and "Yehia" in html
    latex = case._repr_latex_()
    assert latex.startswith(("$", "\\begin"))
    assert r"\gamma_{1}" in latex and _balanced(latex)
    assert display.case_html(case) == html


def test_case_html_and_latex_are_escaped():
    case = registry.load_case(CASES / f"{ZHUKOVSKY}.toml")
    odd = dataclasses.replace(case, title="<script>alert(1)</script> & 50% of x_1")
    assert "<script>" not in odd._repr_html_()
    assert "&lt;script&gt;" in odd._repr_html_()
    assert r"50\% of x\_1" in odd._repr_latex_()


def test_audit_repr_shows_the_witness_of_refuted_checks(audited):
    audit = next(a for a in audited.report.audits if a.case == YEHIA_B)
    html = audit._repr_html_()
    assert "<table" in html and YEHIA_B in html
    for row in ("jacobi", "casimir", "refuted", "exact probe"):
        assert row in html
    witness = audit.result("casimir", "I2").witness
    assert witness.approx in html
    assert html.count("<tr>") == len(audit.results) + 1


# ------------------------------------------------------------------ progress bar


class _RecordingBar:
    """Stands in for tqdm: records how it was made and what it was told."""

    made: list[_RecordingBar] = []

    def __init__(self, **kwargs):
        self.kwargs, self.postfixes, self.updates, self.closed = kwargs, [], 0, False
        _RecordingBar.made.append(self)

    def set_postfix_str(self, text, refresh=True):
        self.postfixes.append(text)

    def update(self, n=1):
        self.updates += n

    def close(self):
        self.closed = True


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.fixture
def recording_bar(monkeypatch):
    import tqdm

    _RecordingBar.made = []
    monkeypatch.setattr(tqdm, "tqdm", _RecordingBar)
    return _RecordingBar.made


def test_audit_json_is_quiet_and_parsable(audited, recording_bar):
    result = CliRunner().invoke(main, ["--db", str(audited.db), "audit", "--json", "--jobs", "0"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["cases"]
    (bar,) = recording_bar
    assert bar.kwargs["disable"] is True and bar.closed


def test_audit_json_with_the_real_bar_prints_only_json(audited):
    result = CliRunner().invoke(main, ["--db", str(audited.db), "audit", "--json", "--jobs", "0"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["run"] > 0
    assert result.stderr == ""


def test_audit_on_a_terminal_shows_each_case(tmp_path, monkeypatch, recording_bar):
    db = str(tmp_path / "registry.sqlite")
    runner = CliRunner()
    assert runner.invoke(main, ["--db", db, "add", str(CASES / f"{ZHUKOVSKY}.toml")]).exit_code == 0
    monkeypatch.setattr("registry.cli.sys", SimpleNamespace(stderr=_Tty(), exit=sys.exit))
    result = runner.invoke(main, ["--db", db, "audit", "--fresh", "--jobs", "0"])
    assert result.exit_code == 0, result.output
    (bar,) = recording_bar
    assert bar.kwargs["disable"] is False and bar.kwargs["total"] == 1
    assert bar.postfixes == [ZHUKOVSKY] and bar.updates == 1 and bar.closed
    assert ZHUKOVSKY in result.stdout
