"""Every internal link of the documentation leads somewhere: in the README, the pages of
docs/, the changelog and the catalog's README, each relative link names a file or folder
that exists and, with an ``#anchor``, a heading of that Markdown file (GitHub's anchors,
which the Sphinx build uses too: ``myst_heading_anchors`` in docs/conf.py). A pointer to
a file that is not in the repository (as ``CASE_FORMAT.md`` once was) fails here.
External addresses (http, https, mailto) are not fetched."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

import pytest

from tests.helpers.docs import ROOT, page_id, pages

PAGES = [*pages(), ROOT / "CHANGELOG.md", ROOT / "data" / "cases" / "README.md"]

FENCED = re.compile(r"^(\s*)(`{3,}).*?^\1\2[ \t]*$", re.S | re.M)
CODE_SPAN = re.compile(r"(`+).+?\1", re.S)
#: [text](target) and ![alt](target), the target up to a space or the closing parenthesis
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
#: [label]: target, a reference definition
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)", re.M)
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$", re.M)
EXTERNAL = re.compile(r"^(?:[a-z][a-z0-9+.-]*:|//)", re.I)


def prose(text: str) -> str:
    """The text outside fenced blocks and code spans, where links and headings live."""
    return CODE_SPAN.sub("", FENCED.sub("", text))


def links(text: str) -> list[str]:
    """The targets of a Markdown text's links, in order."""
    body = prose(text)
    return [m.group(1) for m in INLINE.finditer(body)] + REFERENCE.findall(body)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: its text lowercased, without punctuation (letters,
    digits, ``_`` and ``-`` stay), spaces as hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text
    text = text.replace("`", "").strip().lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


@cache
def anchors(path: Path) -> frozenset[str]:
    """The anchors of a Markdown file's headings, repeated ones numbered as GitHub does."""
    seen: dict[str, int] = {}
    found = set()
    for _, heading in HEADING.findall(FENCED.sub("", path.read_text(encoding="utf-8"))):
        base = slug(heading)
        n = seen.get(base, 0)
        seen[base] = n + 1
        found.add(base if n == 0 else f"{base}-{n}")
    return frozenset(found)


def dead_links(page: Path) -> list[str]:
    """The internal links of a page that lead nowhere, with why."""
    dead = []
    for target in links(page.read_text(encoding="utf-8")):
        if EXTERNAL.match(target):
            continue
        path_part, _, anchor = target.partition("#")
        file = (page.parent / path_part).resolve() if path_part else page
        if not file.exists():
            dead.append(f"{target}: no such file")
        elif path_part and not file.is_relative_to(ROOT):
            dead.append(f"{target}: outside the repository")
        elif anchor and file.suffix == ".md" and anchor not in anchors(file):
            dead.append(f"{target}: no heading with the anchor #{anchor} in {page_id(file)}")
    return dead


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_internal_link_leads_somewhere(page):
    assert dead_links(page) == []


#: A Markdown file named in a code span: `docs/case-format.md`, `CHANGELOG.md`
NAMED_PAGE = re.compile(r"`([\w./-]+\.md)`")


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_markdown_file_the_text_names_exists(page):
    """A file named as code is a pointer too: it exists, from the repository's root or
    from the page (`CASE_FORMAT.md` was named so, and was not in the repository)."""
    text = FENCED.sub("", page.read_text(encoding="utf-8"))
    missing = [
        name
        for name in NAMED_PAGE.findall(text)
        if not (ROOT / name).exists() and not (page.parent / name).exists()
    ]
    assert missing == []


def test_the_readme_leads_to_adding_a_case_and_the_case_format():
    readme = links((ROOT / "README.md").read_text(encoding="utf-8"))
    assert "docs/adding-a-case.md" in readme and "docs/case-format.md" in readme


def test_dead_links_are_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "# A title\n\n## The `--json` output\n\n## Again\n\n## Again\n\n"
        "[ok](#a-title) [code](#the---json-output) [twice](#again-1) [gone](#nowhere)\n"
        "[file](other.md) [external](https://example.org/x.md) `[not a link](x.md)`\n\n"
        "```sh\n# not a heading\n[not a link](y.md)\n```\n\n[ref]: missing.txt\n",
        encoding="utf-8",
    )
    assert anchors(page) == {"a-title", "the---json-output", "again", "again-1"}
    assert dead_links(page) == [
        "#nowhere: no heading with the anchor #nowhere in " + str(page),
        "other.md: no such file",
        "missing.txt: no such file",
    ]
