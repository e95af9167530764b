"""The examples of the README and of docs/ run as shown.

A shell or Python block marked ``<!-- runs -->`` on the line before it is run, page by
page in the order a reader meets them, in a temporary folder that holds the catalog
(``data/cases``), the test families (``tests/data``) and a database of its own; it must
exit with status 0 (``<!-- runs: exit N -->``: with status N). A block marked
``<!-- file: NAME -->`` is written to NAME in that folder first (a case file the
commands after it load), and a text block marked ``<!-- output -->`` must appear in
the output of the example run just before it. Every shell and Python block says
whether it runs: ``<!-- runs -->``, or ``<!-- not run: REASON -->`` (a cluster, a
server, the whole catalog), so that no example goes untested by oversight.
"""

from __future__ import annotations

import re
import sys

import pytest

from tests.helpers.docs import Block, blocks, page_id, pages, prepare, run

CODE = {"sh", "bash", "shell", "console", "python", "py"}
RUNS = re.compile(r"runs(?:: exit (?P<status>\d+))?")
FILE = re.compile(r"file: (?P<name>[\w.-]+)")


def unmarked(page_blocks: list[Block]) -> list[str]:
    """The code blocks of a page that neither run nor say why not."""
    return [
        b.where
        for b in page_blocks
        if b.lang in CODE and not (RUNS.fullmatch(b.marker) or b.marker.startswith("not run: "))
    ]


def runnable(path) -> bool:
    return any(RUNS.fullmatch(b.marker) or FILE.fullmatch(b.marker) for b in blocks(path))


PAGES = pages()
RUNNABLE = [p for p in PAGES if runnable(p)]


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_example_says_whether_it_runs(page):
    found = blocks(page)
    assert unmarked(found) == [], "mark each: <!-- runs --> or <!-- not run: REASON -->"
    for b in found:
        if RUNS.fullmatch(b.marker):
            assert b.lang in CODE, f"{b.where}: only shell and Python examples run"
        if b.marker == "output":
            assert b.lang == "text", f"{b.where}: an output is a text block"


def test_the_docs_have_examples_that_run():
    ids = {page_id(p) for p in RUNNABLE}
    assert {"README.md", "docs/adding-a-case.md", "docs/getting-started.md"} <= ids
    marks = [b.marker for p in RUNNABLE for b in blocks(p)]
    assert "runs: exit 1" in marks and "output" in marks  # the refusal, and what it says


def test_an_unmarked_example_is_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- runs -->\n```sh\ntrue\n```\n\n```python\nprint(1)\n```\n"
        "<!-- not run: a server -->\n```sh\nserve\n```\n",
        encoding="utf-8",
    )
    found = blocks(page)
    assert [b.marker for b in found] == ["runs", "", "not run: a server"]
    assert [b.line for b in found] == [2, 6, 10]
    assert unmarked(found) == [f"{page}:6"]


def command(block: Block) -> list[str]:
    if block.lang in ("python", "py"):
        return [sys.executable, "-c", block.text]
    return ["bash", "-euo", "pipefail", "-c", block.text]


@pytest.mark.slow  # each page's commands in turn: about 10 to 30 s of processor time each
@pytest.mark.parametrize("page", RUNNABLE, ids=page_id)
def test_the_examples_run(page, tmp_path):
    env = prepare(tmp_path)
    output = None
    for block in blocks(page):
        if named := FILE.fullmatch(block.marker):
            (tmp_path / named["name"]).write_text(block.text, encoding="utf-8")
        elif marked := RUNS.fullmatch(block.marker):
            done = run(command(block), tmp_path, env)
            output = done.stdout
            wanted = int(marked["status"] or 0)
            assert done.returncode == wanted, f"{block.where} exited {done.returncode}:\n{output}"
        elif block.marker == "output":
            assert output is not None, f"{block.where}: an output with no example before it"
            shown = "\n".join(line.rstrip() for line in block.text.strip().splitlines())
            printed = "\n".join(line.rstrip() for line in output.splitlines())
            assert shown in printed, f"{block.where}: not in the output:\n{output}"
