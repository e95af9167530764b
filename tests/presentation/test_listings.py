"""The listings the command line prints, through the facade's ``*_text`` functions: they
fit the width asked for (80 and 100 columns), are plain text, keep every identifier
whole, and hold what the frames hold; ``registry searches`` gives one row per search
with its result in short, ``--long`` the sentence, ``--json`` the search documents."""

from __future__ import annotations

import dataclasses

import pytest

import registry
from registry.api import checks, checks_text
from registry.model import IntegralSet, IntegralStatus
from registry.presentation.listings import NONE, searches_listing
from registry.presentation.search_output import ansatz_text, search_document, short_result
from tests.helpers.samples import FAMILIES, SEED, YEHIA_B, case_file

WIDTHS = (80, 100)


@pytest.fixture(scope="module")
def reg(tmp_path_factory):
    """Three seed cases and a family, audited once, with the family's search recorded
    (a special set: a derived case)."""
    path = tmp_path_factory.mktemp("listings") / "r.sqlite"
    with registry.open(path) as reg:
        reg.add(*(case_file(c) for c in SEED), FAMILIES / "heavy-top-lam.toml")
        reg.discover(FAMILIES / "heavy-top-lam.toml", degree=3, free=["lam"], record=True)
        reg.audit(jobs=1)
        yield reg


def listings(reg, width: int) -> dict[str, str]:
    return {
        "cases": reg.cases_text(width=width),
        "verdicts": reg.verdicts_text(width=width),
        "corrections": reg.corrections_text(width=width),
        "runs": reg.runs_text(width=width),
        "searches": reg.searches_text(width=width),
        "searches --long": reg.searches_text(long=True, width=width),
        "list-checks": checks_text(width),
    }


@pytest.mark.parametrize("width", WIDTHS)
def test_every_listing_fits_the_width_in_plain_text(reg, width):
    for name, text in listings(reg, width).items():
        lines = text.splitlines()
        assert lines, name
        assert max(map(len, lines)) <= width, name
        assert "\x1b" not in text, name  # no ANSI codes
        assert all(line == line.rstrip() for line in lines), name


def test_without_a_width_the_listings_use_the_terminals(reg, monkeypatch):
    monkeypatch.setenv("COLUMNS", "100")
    assert reg.cases_text() == reg.cases_text(width=100)
    monkeypatch.setenv("COLUMNS", "60")
    assert max(map(len, reg.cases_text().splitlines())) <= 60


def test_the_cases_are_headed_by_their_whole_id_version_and_title(reg):
    text = reg.cases_text(width=80)
    frame = reg.cases()
    for case, version in zip(frame["case"], frame["version"], strict=True):
        (heading,) = [line for line in text.splitlines() if line.startswith(f"{case} (")]
        assert heading.startswith(f"{case} (version {version}): ")
    assert reg.cases_text(author="Nobody") == NONE


def test_the_verdicts_hold_every_check_of_the_frame(reg):
    frame = reg.verdicts()
    rows = set()
    case = None
    for line in reg.verdicts_text(width=80).splitlines()[3:]:
        if not line.startswith(" "):
            case = line.split()[0]
        else:
            claim, check, verdict, *_ = line.split()
            rows.add((case, claim, check, verdict))
    expected = {
        (c, "-" if not isinstance(k, str) else k, check, v)
        for c, k, check, v in zip(
            frame["case"], frame["claim"], frame["check"], frame["verdict"], strict=True
        )
    }
    assert rows == expected


def test_the_corrections_name_their_run_and_each_case(reg):
    text = reg.corrections_text(width=80)
    run = int(reg.runs()["run"].max())
    assert text.splitlines()[0] == f"run {run}"
    assert any(line.startswith(f"{YEHIA_B} (version 1)") for line in text.splitlines())
    assert "  I2  " in text


def test_the_runs_say_when_how_long_and_what_each_found(reg):
    lines = reg.runs_text(width=80).splitlines()
    assert lines[0].split()[:4] == ["run", "started", "took", "status"]
    (row,) = [line for line in lines[2:] if not line.startswith(" ")]
    assert row.split()[0] == "1" and "complete" in row and "verified" in row


def test_the_checks_are_listed_in_the_order_they_run():
    text = checks_text(80)
    names = [line.split()[0] for line in text.splitlines()[2:] if not line.startswith(" ")]
    assert names == [c.name for c in checks()]


def test_one_row_per_search_under_its_case_with_the_result_in_short(reg):
    frame = reg.searches()
    lines = reg.searches_text(width=80).splitlines()
    assert lines[1].split() == ["search", "ansatz", "complete", "result"]
    numbers = [int(line.split()[0]) for line in lines[3:] if line[:3].strip().isdigit()]
    assert numbers == list(frame["search"])
    (row,) = [line for line in lines if line.startswith("  1 ")]
    assert row.split()[1:5] == ["degree", "3;", "M=1,gamma=2;", "free"]


def test_the_long_listing_and_the_documents_state_each_search_in_full(reg):
    frame = reg.searches()
    long = reg.searches_text(long=True, width=80)
    words = " ".join(long.split())
    for statement in frame["statement"]:
        assert " ".join(statement.split()) in words
    documents = reg.search_documents()
    assert [d["search"] for d in documents] == list(frame["search"])
    assert [d["statement"] for d in documents] == list(frame["statement"])
    assert all(d["version"] == 1 for d in documents)
    assert reg.search_documents(YEHIA_B) == []
    assert reg.searches_text(YEHIA_B) == NONE


def test_a_recorded_search_reads_back_as_the_document_discover_printed(reg):
    again = reg.discover(FAMILIES / "heavy-top-lam.toml", degree=3, free=["lam"])
    assert again.reused
    (listed,) = reg.search_documents("family-heavy-top-lam")
    printed = search_document(again.search)
    assert {k: v for k, v in listed.items() if k not in ("search", "version")} == printed


def test_the_result_in_short():
    statuses = (IntegralStatus("new"), IntegralStatus("rediscovered", ("M3",), ("H",), "M3"))
    generic = IntegralSet((), 2, ("F", "M3"), (), statuses)
    search = dataclasses.replace(_search(), generic=generic)
    assert short_result(search) == "2 extra (1 new, 1 rediscovered)"
    one = IntegralSet((), 1, ("F",), (), statuses[:1])
    special = (IntegralSet(("lam = 1",), 1), IntegralSet(("lam = 0",), 2))
    assert short_result(dataclasses.replace(search, generic=one)) == "1 extra (new)"
    both = dataclasses.replace(search, generic=IntegralSet((), 0), special=special)
    assert short_result(both) == "no extra integral; 2 special sets"
    assert short_result(dataclasses.replace(search, dimensions=())) == "not decided"
    assert ansatz_text(search.options) == "degree 2; M=1,gamma=2; free lam"


def test_no_searches_is_none():
    assert searches_listing([]) == NONE


def _search():
    from registry.model import Search, SearchOptions

    return Search(
        case="c",
        content_hash="h",
        options=SearchOptions(degree=2, free=("lam",)),
        known=("H",),
        generic=IntegralSet((), 0),
        special=(),
        complete=True,
        dimensions=((1, 0, 0, 0),),
    )
