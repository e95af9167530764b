"""Reports of an audit run (Markdown, HTML, LaTeX), drift plots and ``registry report``.

One database with three seed cases is audited once (with numeric evidence) and
shared by the module; the run-diff tests use a second, one-case database.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner
from samples import CASES, SEED, YEHIA_B, ZHUKOVSKY

import registry
from registry.cli import main
from registry.errors import UnknownRunError
from registry.language.parser import Namespace, parse_expression
from registry.model import VerdictChange
from registry.presentation.plots import drift_plot
from registry.presentation.report_writers import _Tex, build_report

PNG = b"\x89PNG"


@pytest.fixture(scope="module")
def db(tmp_path_factory) -> Path:
    """A database file with the three seed cases, audited once with numeric evidence."""
    path = tmp_path_factory.mktemp("reports") / "registry.sqlite"
    with registry.open(path) as reg:
        reg.add(*(CASES / f"{c}.toml" for c in SEED))
        reg.audit(jobs=0, numeric=True)
    return path


@pytest.fixture(scope="module")
def reg(db):
    with registry.open(db) as opened:
        yield opened


@pytest.fixture(scope="module")
def markdown(reg, tmp_path_factory) -> tuple[str, Path]:
    out = tmp_path_factory.mktemp("md")
    return build_report(reg, fmt="md", out_dir=out), out


@pytest.fixture(scope="module")
def html_report(reg) -> str:
    return build_report(reg, fmt="html")


@pytest.fixture(scope="module")
def tex(db, tmp_path_factory) -> tuple[object, Path]:
    """``registry report --format tex -o DIR/report.tex``: the CLI result and the file."""
    out = tmp_path_factory.mktemp("tex") / "report.tex"
    args = ["--db", str(db), "report", "--format", "tex", "-o", str(out)]
    return CliRunner().invoke(main, args), out


def _correction(reg, case_id: str, kind: str):
    """The first correction of ``kind`` in the newest run's audit of ``case_id``."""
    run = int(reg.runs()["run"].max())
    (audit,) = [a for c, a in reg.store.run_results(run) if c == case_id]
    return next(c for c in audit.corrections if c.kind == kind)


# ------------------------------------------------------------------- markdown


def _summary_rows(text: str) -> list[str]:
    """The rows of the Markdown report's summary table, header and rule excluded."""
    lines = text.split("## Summary\n", 1)[1].lstrip("\n").splitlines()
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
        rows.append(f"| {c.case} | {c.label} | {c.kind} | {integral} | {casimir} | {overall} |")
    return rows


def test_markdown_summary_keeps_the_integral_and_casimir_columns_apart(tmp_path):
    """The Hamiltonian is an integral but no Casimir: its row tells the columns apart
    (every seed claim has equal integral and casimir verdicts)."""
    text = (CASES / f"{ZHUKOVSKY}.toml").read_text(encoding="utf-8")
    text += (
        '\n[[claims]]\nlabel = "H"\nkind = "integral"\nexpression = '
        '"M1**2/(2*A) + M2**2/(2*B) + M3**2/(2*C) + xi1*gamma1 + xi2*gamma2 + xi3*gamma3"\n'
    )
    path = tmp_path / f"{ZHUKOVSKY}.toml"
    path.write_text(text, encoding="utf-8")
    with registry.open(tmp_path / "registry.sqlite") as reg:
        reg.add(path)
        reg.audit(jobs=0)
        report = build_report(reg, fmt="md", plots=False)
        expected = _expected_rows(reg)
    assert f"| {ZHUKOVSKY} | H | integral | verified | refuted | verified |" in expected
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
    assert f"| {YEHIA_B} | I2 | casimir | refuted | refuted | refuted |" in expected
    assert f"| {ZHUKOVSKY} | area | casimir | verified | verified | verified |" in expected


def test_markdown_shows_the_torque_in_math(reg, markdown):
    text, _ = markdown
    mu3 = reg.case(YEHIA_B).system.torque_exprs[2]
    assert f"$$\n\\mu_{{3}} = {sp.latex(mu3)}\n$$" in text


def test_markdown_shows_the_repairs_of_yehia_b(reg, markdown):
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
    text = build_report(reg, fmt="md", out_dir=tmp_path, plots=False)
    assert ".png" not in text
    assert not list(tmp_path.iterdir())


def test_unknown_run_is_refused(reg):
    with pytest.raises(UnknownRunError):
        build_report(reg, run=999, plots=False)


def test_drift_plot_writes_a_png(reg, tmp_path):
    path = drift_plot(reg.case(YEHIA_B), "I2", tmp_path / "plots" / "i2.png")
    assert path == tmp_path / "plots" / "i2.png"
    assert path.read_bytes().startswith(PNG)
    with pytest.raises(KeyError):
        drift_plot(reg.case(YEHIA_B), "no-such-claim", tmp_path / "x.png")


# ----------------------------------------------------------------------- html


class _Balanced(HTMLParser):
    """Records tags that are closed out of order or never closed."""

    VOID = {"meta", "img", "br", "hr", "link", "input", "source"}

    def __init__(self) -> None:
        super().__init__()
        self.open: list[str] = []
        self.errors: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag not in self.VOID:
            self.open.append(tag)

    def handle_endtag(self, tag):
        if not self.open or self.open.pop() != tag:
            self.errors.append(f"</{tag}> at {self.getpos()}")


def test_html_is_one_self_contained_file(html_report):
    text = html_report
    assert text.startswith("<!DOCTYPE html>")
    assert re.search(r'<img class="plot"[^>]* src="data:image/png;base64,[A-Za-z0-9+/=]+"', text)
    assert "<script" not in text and "<link" not in text
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", text)
    for case_id in SEED:
        assert case_id in text


def test_html_parses_with_balanced_tags(html_report):
    parser = _Balanced()
    parser.feed(html_report)
    parser.close()
    assert parser.errors == []
    assert parser.open == []


# ------------------------------------------------------------------------ tex


def _unbalanced_braces(text: str) -> int:
    """How far the braces of a TeX text are from balanced (escaped ones excluded)."""
    depth = 0
    for ch in re.sub(r"\\[{}\\]", "", text):
        depth += {"{": 1, "}": -1}.get(ch, 0)
        if depth < 0:
            return depth
    return depth


def test_cli_writes_the_tex_report(tex):
    result, out = tex
    assert result.exit_code == 0, result.output
    assert result.output.strip() == str(out)
    assert out.is_file()


def test_tex_fragment_is_well_formed(tex):
    _, out = tex
    text = out.read_text(encoding="utf-8")
    assert "\\documentclass" not in text and "\\begin{document}" not in text
    assert _unbalanced_braces(text) == 0
    stack = []
    for kind, env in re.findall(r"\\(begin|end)\{([^}]*)\}", text):
        if kind == "begin":
            stack.append(env)
        else:
            assert stack and stack.pop() == env
    assert stack == []
    assert text.count("\\[") == text.count("\\]") > 0
    assert "\\section*{" in text and "\\begin{tabular}" in text
    for image in re.findall(r"\\includegraphics\[[^]]*\]\{([^}]+)\}", text):
        assert (out.parent / image).read_bytes().startswith(PNG)


def test_tex_fragment_compiles(tex, tmp_path):
    if shutil.which("pdflatex") is None:
        if os.environ.get("REGISTRY_CI"):
            pytest.fail("pdflatex is required in CI")
        pytest.skip("no pdflatex")
    _, out = tex
    (out.parent / "wrapper.tex").write_text(
        "\\documentclass{article}\n\\usepackage{amsmath,graphicx}\n"
        "\\begin{document}\n\\input{report}\n\\end{document}\n"
    )
    run = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "wrapper.tex"],
        cwd=out.parent,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout[-3000:]


def test_tex_escapes_special_characters():
    assert _Tex().escape("a_b & 50% #1 {x} $y$ ~^\\") == (
        r"a\_b \& 50\% \#1 \{x\} \$y\$ \textasciitilde{}\textasciicircum{}\textbackslash{}"
    )


# ------------------------------------------------------------------- the CLI


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


# ----------------------------------------------------------------------- diff


CHANGED_TITLE = 'title = "Zhukovsky & Co.: k_i at 100% #1"'


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory) -> Path:
    """A one-case database audited twice: the original claim, then a sign flipped in it."""
    folder = tmp_path_factory.mktemp("diff")
    original = (CASES / f"{ZHUKOVSKY}.toml").read_text(encoding="utf-8")
    original = re.sub(r"^title = .*$", CHANGED_TITLE, original, count=1, flags=re.M)
    changed = original.replace('expression = "(M1 + k1)*gamma1', 'expression = "(M1 - k1)*gamma1')
    assert changed != original
    with registry.open(folder / "registry.sqlite") as reg:
        for text in (original, changed):
            path = folder / f"{ZHUKOVSKY}.toml"
            path.write_text(text, encoding="utf-8")
            reg.add(path)
            reg.audit(jobs=0)
    return folder / "registry.sqlite"


def test_diff_of_a_run_with_itself_is_empty(db):
    with registry.open(db) as reg:
        assert reg.diff(1, 1) == []
    result = CliRunner().invoke(main, ["--db", str(db), "report", "--diff", "1", "1"])
    assert result.exit_code == 0, result.output
    assert "no changes" in result.output


def test_diff_lists_the_changed_verdicts(two_runs):
    with registry.open(two_runs) as reg:
        changes = reg.diff(1, 2)
    expected = {"case": ZHUKOVSKY, "claim": "area", "before": "verified", "after": "refuted"}
    assert VerdictChange(**expected, check="casimir") in changes
    assert all(c.case == ZHUKOVSKY and c.claim == "area" for c in changes)
    result = CliRunner().invoke(main, ["--db", str(two_runs), "report", "--diff", "1", "2"])
    assert result.exit_code == 0, result.output
    assert "no changes" not in result.output
    row = next(line for line in result.output.splitlines() if "casimir" in line)
    assert row.split() == [ZHUKOVSKY, "area", "casimir", "verified", "refuted"]


def test_diff_of_an_unknown_run_is_an_error(two_runs):
    result = CliRunner().invoke(main, ["--db", str(two_runs), "report", "--diff", "1", "7"])
    assert result.exit_code == 1
    assert "Error:" in result.output


def test_tex_escapes_the_title_of_a_case(two_runs):
    with registry.open(two_runs) as reg:
        text = build_report(reg, fmt="tex", plots=False)
    assert r"Zhukovsky \& Co.: k\_i at 100\% \#1" in text
    assert _unbalanced_braces(text) == 0
