"""The content of a run's report: every case, claim and verdict, the torque in math, the
corrections of a refuted claim, drift plots, and ``registry report`` choosing the run.

One database with three seed cases is audited once (with numeric evidence) and
shared by the module.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.errors import UnknownRunError
from registry.language.parser import Namespace, parse_expression
from registry.presentation.report_writers import anchor
from tests.helpers.samples import CASES, SEED, YEHIA_B, ZHUKOVSKY

PNG = b"\x89PNG"


@pytest.fixture(scope="module")
def db(module_databases) -> str:
    """A database with the three seed cases, audited once with numeric evidence (on
    SQLite, then on PostgreSQL: fixture ``backend``)."""
    path = module_databases.new("reports")
    with registry.open(path) as reg:
        reg.add(*(CASES / f"{c}.toml" for c in SEED))
        reg.audit(jobs=1, numeric=True)
    return path


@pytest.fixture(scope="module")
def reg(db):
    with registry.open(db) as opened:
        yield opened


@pytest.fixture(scope="module")
def markdown(reg, tmp_path_factory) -> tuple[str, Path]:
    out = tmp_path_factory.mktemp("md")
    return reg.report(fmt="md", out_dir=out), out


def _correction(reg, case_id: str, kind: str):
    """The first correction of ``kind`` in the newest run's audit of ``case_id``."""
    run = int(reg.runs()["run"].max())
    (audit,) = [a for c, a in reg.store.run_results(run) if c == case_id]
    return next(c for c in audit.corrections if c.kind == kind)


def _summary_rows(text: str) -> list[str]:
    """The rows of the Markdown report's summary table, header and rule excluded."""
    lines = text.split('## <a id="summary"></a>Summary\n', 1)[1].lstrip("\n").splitlines()
    table = []
    for line in lines:
        if not line.startswith("|"):
            break
        table.append(line)
    assert table[:2] == [
        "| case | claim | kind | integral | casimir | verdict |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    return table[2:]


def _expected_rows(reg) -> list[str]:
    """One summary row per audited claim, with the audit's own verdicts; the overall
    verdict is that of the property the claim's kind names."""
    verdicts = reg.verdicts()
    per_claim = verdicts[verdicts["claim"].notna()]
    verdict = {(r.case, r.claim, r.check): r.verdict for r in per_claim.itertuples()}
    rows = []
    for c in reg.claims().itertuples():
        integral, casimir = (
            verdict[c.case, c.label, "integral"],
            verdict[c.case, c.label, "casimir"],
        )
        overall = integral if c.kind == "integral" else casimir
        case = f"[{c.case}](#{anchor('case', c.case)})"  # linked to the case's section
        rows.append(f"| {case} | {c.label} | {c.kind} | {integral} | {casimir} | {overall} |")
    return rows


def test_markdown_summary_keeps_the_integral_and_casimir_columns_apart(tmp_path, db_target):
    """The Hamiltonian is an integral but no Casimir: its row tells the columns apart
    (every seed claim has equal integral and casimir verdicts)."""
    text = (CASES / f"{ZHUKOVSKY}.toml").read_text(encoding="utf-8")
    text += (
        '\n[[claims]]\nlabel = "H"\nkind = "integral"\nexpression = '
        '"M1**2/(2*A) + M2**2/(2*B) + M3**2/(2*C) + xi1*gamma1 + xi2*gamma2 + xi3*gamma3"\n'
    )
    path = tmp_path / f"{ZHUKOVSKY}.toml"
    path.write_text(text, encoding="utf-8")
    with registry.open(db_target) as reg:
        reg.add(path)
        reg.audit(jobs=1)
        report = reg.report(fmt="md", plots=False)
        expected = _expected_rows(reg)
    linked = f"[{ZHUKOVSKY}](#case-{ZHUKOVSKY})"
    assert f"| {linked} | H | integral | verified | refuted | verified |" in expected
    assert sorted(_summary_rows(report)) == sorted(expected)


def test_markdown_names_every_case_and_verdict(reg, markdown):
    text, _ = markdown
    for case_id in SEED:
        assert case_id in text
    assert "refuted" in text and "verified" in text
    assert "| case | claim | kind | integral | casimir | verdict |" in text
    expected = _expected_rows(reg)
    assert len(expected) == 3
    assert sorted(_summary_rows(text)) == sorted(expected)
    # the paper's refuted claim and a classical true one
    yehia, zhukovsky = (f"[{c}](#case-{c})" for c in (YEHIA_B, ZHUKOVSKY))
    assert f"| {yehia} | I2 | casimir | refuted | refuted | refuted |" in expected
    assert f"| {zhukovsky} | area | casimir | verified | verified | verified |" in expected


def test_the_report_groups_cases_by_topic_with_contents_and_links(reg, markdown):
    text, _ = markdown
    contents = text.split('<a id="contents"></a>Contents', 1)[1].split("## ", 1)[0]
    topics = {c.topic or "other" for c in map(reg.case, SEED)}
    for name in topics:
        assert f"[{name}](#topic-{name.replace(' ', '-')})" in contents
        assert f'## <a id="topic-{name.replace(" ", "-")}"></a>' in text
    for case_id in SEED:
        assert f'### <a id="case-{case_id}"></a>{case_id}: ' in text
        assert f"[{case_id}](#case-{case_id})" in contents
    # each case sits under its topic's heading
    for case_id in SEED:
        name = (reg.case(case_id).topic or "other").replace(" ", "-")
        before = text.split(f'<a id="case-{case_id}"></a>', 1)[0]
        assert (
            before.rfind(f'<a id="topic-{name}"></a>')
            > max(
                before.rfind(f'<a id="topic-{other.replace(" ", "-")}"></a>')
                for other in topics - {reg.case(case_id).topic or "other"}
            )
            or len(topics) == 1
        )


def test_markdown_shows_the_torque_in_math(reg, markdown):
    text, _ = markdown
    mu3 = reg.case(YEHIA_B).system.torque_exprs[2]
    assert f"$$\n\\mu_{{3}} = {sp.latex(mu3)}\n$$" in text


def test_markdown_shows_the_corrections_of_yehia_b(reg, markdown):
    text, _ = markdown
    case = reg.case(YEHIA_B)
    fix = _correction(reg, YEHIA_B, "torque")
    ns = Namespace(case.parameters, case.functions)
    mu3 = parse_expression(fix.torque[2], ns)
    assert f"\\mu_{{3}}' = {sp.latex(mu3)}" in text
    assert "Corrected torque" in text and "Corrected Casimir" in text
    assert "$N = 0$" in text


def test_markdown_links_drift_plots_that_exist(markdown):
    text, out = markdown
    links = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text)
    assert links, "no plot linked"
    for link in links:
        assert (out / link).is_file()
    yehia = [link for link in links if YEHIA_B in link and "I2" in link]
    assert len(yehia) == 1
    assert (out / yehia[0]).read_bytes().startswith(PNG)
    assert not any(ZHUKOVSKY in link for link in links)  # verified: no plot


def test_report_without_plots_writes_no_png(reg, tmp_path):
    text = reg.report(fmt="md", out_dir=tmp_path, plots=False)
    assert ".png" not in text
    assert not list(tmp_path.iterdir())


def test_unknown_run_is_refused(reg):
    with pytest.raises(UnknownRunError):
        reg.report(run=999, plots=False)


def test_cli_default_output_in_current_directory(db, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["--db", str(db), "report", "--no-plots"])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == "report.md"
    text = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert YEHIA_B in text and ".png" not in text


def test_cli_unknown_run_is_an_error(db):
    result = CliRunner().invoke(main, ["--db", str(db), "report", "--run", "999"])
    assert result.exit_code == 1
    assert "Error: no audit run number 999" in result.output


def test_cli_help_has_an_example():
    result = CliRunner().invoke(main, ["report", "--help"])
    assert result.exit_code == 0
    assert "Example:" in result.output
