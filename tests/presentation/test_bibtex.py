"""The sources of the stored cases as BibTeX (``registry export --bibtex``) and the
software's own citation (CITATION.cff).

One database with two seed cases is audited once per module (fixture ``audited``).
"""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main

ROOT = Path(registry.__file__).resolve().parent.parent
CASES = ROOT / "data" / "cases"
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"


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


def _balanced(text: str) -> bool:
    depth = 0
    for char in text:
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0


def test_bibtex_has_one_entry_per_source_with_unique_keys(audited):
    text = audited.reg.bibtex()
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
    text = reg.bibtex()
    keys = re.findall(r"^@\w+\{([^,]+),", text, flags=re.M)
    assert sorted(keys) == ["demo-c", "smith1999a", "smith1999b"]
    assert _balanced(text)
    assert r"\textbraceleft{}braces\textbraceright{} \& 100\% of \$x\_1\$" in text


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
    assert to_stdout.stdout == target.read_text(encoding="utf-8") == audited.reg.bibtex()


def test_citation_cff_parses():
    import yaml  # PyYAML, in the project's ``test`` extra

    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    data = yaml.safe_load(text)
    assert isinstance(data, dict)
    # the keys CFF 1.2.0 requires of a citation, and of each of its references
    for key in ("cff-version", "message", "title", "authors"):
        assert data.get(key), key
    assert data["cff-version"] == "1.2.0"
    assert data["title"] == "The registry of rigid-body integrability claims"
    assert data["version"] == "0.1.0"
    assert data["license"] == "MIT"
    assert re.fullmatch(r"\d{4}-\d{2}-\d{2}", str(data["date-released"]))
    assert data["authors"] == [{"name": "The registry developers"}]
    (paper,) = data["references"]
    for key in ("type", "title", "authors"):
        assert paper.get(key), key
    assert paper["title"].startswith("Hamilton-Poisson formulation")
    assert [a["family-names"] for a in paper["authors"]] == ["Birtea", "Căşu", "Comănescu"]
    assert [a["given-names"] for a in paper["authors"]] == ["Petre", "Ioan", "Dan"]


def test_citation_version_is_the_package_version():
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    project = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    version = re.search(r'^version = "([^"]+)"', project, flags=re.M).group(1)
    assert f'version: "{version}"' in text


def test_the_whole_catalog_round_trips_through_a_bibtex_parser():
    """Every source of data/cases is one entry that a BibTeX parser reads back with its
    authors, year and title from the case files' structured citations."""
    import bibtexparser

    from registry.language.casefile import load_case
    from tests.helpers.samples import CASES

    reg = registry.open(":memory:")
    reg.add(CASES)
    database = bibtexparser.loads(reg.bibtex())
    sources = {}
    for path in sorted(CASES.rglob("*.toml")):
        case = load_case(path)
        sources.setdefault((case.source.citation, case.source.doi), []).append(case)
    assert len(database.entries) == len(sources)
    keys = [e["ID"] for e in database.entries]
    assert len(set(keys)) == len(keys)
    # the note is LaTeX: the characters TeX reserves come escaped (technion\_second\_brain)
    by_note = {
        re.sub(r"\\([_&%#$])", r"\1", e["note"]).split(". Registry cases: ")[0]: e
        for e in database.entries
    }
    for (citation, doi), cases in sources.items():
        entry = by_note[citation]
        source = cases[0].source
        assert entry["year"] == str(source.year)
        assert entry["author"] == " and ".join(source.authors)
        if source.title:
            assert entry["title"] == source.title
        if doi:
            assert entry["doi"] == doi
        named = entry["note"].split(". Registry cases: ")[1].split(", ")
        assert sorted(named) == sorted(c.id for c in cases)
