"""Notebook display: cases and audits as escaped HTML tables and LaTeX arrays (the
Jupyter reprs installed by ``registry.presentation.notebook``)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from types import SimpleNamespace

import pytest

import registry
from registry.presentation import notebook

ROOT = Path(registry.__file__).resolve().parent.parent
CASES = ROOT / "data" / "cases"
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"


@pytest.fixture(scope="module")
def audited(tmp_path_factory):
    """A database with two seed cases, audited in this process."""
    db = tmp_path_factory.mktemp("sharing") / "registry.sqlite"
    reg = registry.open(db)
    reg.add(CASES / f"{YEHIA_B}.toml", CASES / f"{ZHUKOVSKY}.toml")
    report = reg.audit(jobs=1)
    yield SimpleNamespace(reg=reg, db=db, report=report)
    reg.close()


def _balanced(text: str) -> bool:
    depth = 0
    for char in text:
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0


def test_case_reprs():
    case = registry.load_case(CASES / f"{YEHIA_B}.toml")
    html = case._repr_html_()
    assert YEHIA_B in html and "<table" in html
    assert "I2 (casimir)" in html and "Yehia" in html
    latex = case._repr_latex_()
    assert latex.startswith(("$", "\\begin"))
    assert r"\gamma_{1}" in latex and _balanced(latex)
    assert notebook.case_html(case) == html


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
