"""The writers of a run's report: one self-contained HTML file with balanced tags, a
LaTeX fragment that is well formed (and compiles, where pdflatex is installed), and
LaTeX's special characters escaped.

One database with three seed cases is audited once (with numeric evidence) and
shared by the module; the title test uses a second, one-case database.
"""

from __future__ import annotations

import html
import os
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.presentation import report_content
from registry.presentation.plots import DriftCanvas
from registry.presentation.report_writers import TexWriter, anchor
from tests.helpers.samples import CASES, SEED, YEHIA_B, ZHUKOVSKY

PNG = b"\x89PNG"


@pytest.fixture(scope="module")
def db(tmp_path_factory) -> Path:
    """A database file with the three seed cases, audited once with numeric evidence."""
    path = tmp_path_factory.mktemp("reports") / "registry.sqlite"
    with registry.open(path) as reg:
        reg.add(*(CASES / f"{c}.toml" for c in SEED))
        reg.audit(jobs=1, numeric=True)
    return path


@pytest.fixture(scope="module")
def reg(db):
    with registry.open(db) as opened:
        yield opened


@pytest.fixture(scope="module")
def html_report(reg) -> str:
    return reg.report(fmt="html")


@pytest.fixture(scope="module")
def tex(db, tmp_path_factory) -> tuple[object, Path]:
    """``registry report --format tex -o DIR/report.tex``: the CLI result and the file."""
    out = tmp_path_factory.mktemp("tex") / "report.tex"
    args = ["--db", str(db), "report", "--format", "tex", "-o", str(out)]
    return CliRunner().invoke(main, args), out


# ------------------------------------------------------------------- markdown


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


def test_html_embeds_one_plot_per_refuted_claim_drawn_from_its_stored_curve(reg, html_report):
    outcomes = reg.run_report(int(reg.runs()["run"].max())).outcomes()
    refuted = report_content.plotted(outcomes)
    stored = {(c.case, c.claim) for o in outcomes for c in o.curves}
    assert refuted and {(case.id, label) for case, label in refuted} <= stored
    assert html_report.count('<img class="plot"') == len(refuted)
    for case, label in refuted:
        section = html_report.split(f'id="{anchor("case", case.id)}"', 1)[1]
        section = section.split('id="case-', 1)[0]  # up to the next case
        claim = section.split(f"Claim {label} (", 1)[1].split("<h4", 1)[0]
        assert claim.count('<img class="plot"') == 1


def test_a_second_html_report_reads_its_plots_from_the_cache(reg, html_report, monkeypatch):
    """The same file, with no plot drawn: drawing one fails here."""

    def refuse(self, curve):
        raise AssertionError("a cached drift plot was drawn again")

    monkeypatch.setattr(DriftCanvas, "palette_png", refuse)
    assert reg.report(fmt="html") == html_report


def test_html_formulas_are_mathml_with_their_text_not_images(reg, html_report):
    """Formulas are MathML the browser renders as text (no image of a formula), each
    displayed one followed by its case-file text to copy; only the drift plots are PNG."""
    text = html_report
    assert text.count("<math") > 20
    assert len(re.findall(r"<img ", text)) == len(re.findall(r'<img class="plot"', text))
    case = reg.case(YEHIA_B)
    torque = case.system.torque[2].text
    assert f'<code class="source">mu3 = {html.escape(torque)}</code>' in text
    # the MathML of mu3 as the printer writes it, gamma3 as a subscripted gamma
    assert "<msub><mi>γ</mi><mi>3</mi></msub>" in text
    assert "&InvisibleTimes;" not in text and "&#947;" not in text  # characters as such


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
    assert TexWriter().escape("a_b & 50% #1 {x} $y$ ~^\\") == (
        r"a\_b \& 50\% \#1 \{x\} \$y\$ \textasciitilde{}\textasciicircum{}\textbackslash{}"
    )


# ------------------------------------------------------------------- the CLI


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
            reg.audit(jobs=1)
    return folder / "registry.sqlite"


def test_tex_escapes_the_title_of_a_case(two_runs):
    with registry.open(two_runs) as reg:
        text = reg.report(fmt="tex", plots=False)
    assert r"Zhukovsky \& Co.: k\_i at 100\% \#1" in text
    assert _unbalanced_braces(text) == 0
