"""The documentation's Markdown read as the tests need it: its pages, their fenced blocks
with the marker comment before each, and a folder in which a page's examples run as a
reader would run them (the catalog at ``data/cases``, a database of its own)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from tests.helpers.clocks import HANG

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"

#: A marker comment alone on its line: ``<!-- runs -->``, ``<!-- file: NAME -->``, ...
MARKER = re.compile(r"<!--\s*(.*?)\s*-->")
FENCE = re.compile(r"^(\s*)(`{3,})\s*([\w+-]*)")


def pages() -> list[Path]:
    """The README and every Markdown page of docs/ (not the build's output)."""
    found = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.relative_to(DOCS).parts)
    return [ROOT / "README.md", *found]


def page_id(path: Path) -> str:
    """A page's path from the repository's root (as given, for a page elsewhere)."""
    return path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)


@dataclass(frozen=True)
class Block:
    """One fenced block: its language, its text (dedented like the fence), the marker
    comment on the line before it ("" if none) and its line in the page."""

    page: Path
    line: int
    lang: str
    text: str
    marker: str

    @property
    def where(self) -> str:
        return f"{page_id(self.page)}:{self.line}"


def blocks(page: Path) -> list[Block]:
    """The fenced blocks of a page, in order."""
    lines = page.read_text(encoding="utf-8").splitlines()
    found, i = [], 0
    while i < len(lines):
        opening = FENCE.match(lines[i])
        if not opening:
            i += 1
            continue
        indent, fence, lang = opening.groups()
        before = lines[i - 1].strip() if i else ""
        marked = MARKER.fullmatch(before)
        body, j = [], i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence):
            body.append(lines[j][len(indent) :] if lines[j].startswith(indent) else lines[j])
            j += 1
        text = "\n".join(body) + "\n"
        found.append(Block(page, i + 1, lang, text, marked.group(1) if marked else ""))
        i = j + 1
    return found


def prepare(folder: Path) -> dict[str, str]:
    """Make ``folder`` a place where the docs' examples run as in a clone of the
    repository: the catalog at ``data/cases`` and the test families at ``tests/data``
    (links to the repository's, read only by the examples), and a database of its own
    at ``data/registry.sqlite``, which the commands (``$REGISTRY_DB``) and the Python
    examples (``registry.open("data/registry.sqlite")``) both use. Returns the
    environment to run them in."""
    (folder / "data").mkdir(exist_ok=True)
    (folder / "tests").mkdir(exist_ok=True)
    for name in ("data/cases", "tests/data"):
        if not (folder / name).exists():
            (folder / name).symlink_to(ROOT / name, target_is_directory=True)
    env = dict(os.environ)
    env["REGISTRY_DB"] = str(folder / "data" / "registry.sqlite")
    # the `registry` of this interpreter's environment, whatever PATH said
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    env["PYTHONUNBUFFERED"] = "1"  # stdout and stderr interleaved as a terminal shows them
    env["MPLBACKEND"] = "Agg"
    return env


def run(
    command: list[str], folder: Path, env: dict[str, str], *, merge: bool = True
) -> subprocess.CompletedProcess:
    """Run a command in ``folder``, with stdout and stderr together (``merge``, as a
    terminal shows them) or apart; a hang fails the test."""
    return subprocess.run(
        command,
        cwd=folder,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT if merge else subprocess.PIPE,
        text=True,
        timeout=4 * HANG,
        stdin=subprocess.DEVNULL,
    )


def catalog_file(case_id: str) -> Path:
    """The catalog's file of ``case_id`` (the file stem is the id)."""
    (path,) = (ROOT / "data" / "cases").rglob(f"{case_id}.toml")
    return path
