"""The sources of the stored cases as BibTeX (``registry export --bibtex``).

One entry per distinct source, with a stable key (first author's surname and year,
``yehia2003``; repeats suffixed a, b, ...), its type and fields taken from the
source's structured citation (authors, year, title, journal or book, volume,
number, pages, publisher, url, doi) where the case file gives them, else parsed
from the citation as a reader wrote it, and a note keeping the full citation and
the cases that cite it. Field values are escaped so that their braces stay balanced.

It takes the cases as ``Registry.cases()`` gives them (a DataFrame), never the registry:

>>> import registry
>>> reg = registry.open(":memory:")
>>> _ = reg.add("data/cases/yehia-2003-kovalevskaya-b.toml")
>>> print(bibtex(reg.cases()).splitlines()[0])
@article{yehia2003,
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass
from typing import TYPE_CHECKING

from . import latex

if TYPE_CHECKING:
    import pandas as pd

_INITIAL = r"[^\W\d_][a-z]?\.\s*-?"  # H. or Th. (any alphabet)
_NAME = re.compile(
    rf"^(?:{_INITIAL})+\s*[^\W\d_][\w'\-]+$"  # H.M. Yehia
    rf"|^[^\W\d_][\w'\-]+\s+(?:{_INITIAL})+$"  # Yehia H.M.
)
_ARTICLE = re.compile(
    r"(?P<journal>[^,;]+?)\s+(?P<volume>\d+)\s*\((?P<year>\d{4})\)\s*(?P<pages>\d+\s*-+\s*\d+)?"
)
_YEAR = re.compile(r"\b(1[5-9]\d\d|20\d\d)\b")
_PUBLISHER = re.compile(r"Springer|Verlag|Press|Publish|Nauka|Wiley|Dover|Elsevier|Birkh", re.I)


def _ascii(text: str) -> str:
    """Lowercase ASCII letters and digits of ``text`` (accents dropped)."""
    plain = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode()
    return re.sub(r"[^a-z0-9]", "", plain.lower())


def _authors(segments: list[str]) -> list[str]:
    """The leading comma-separated segments of a citation that look like author names."""
    names = []
    for segment in segments:
        if not _NAME.match(segment):
            break
        names.append(segment)
    return names


def _surname(author: str) -> str:
    """The surname in ``H.M. Yehia`` or ``Yehia H.M.``: the first word that is not an initial."""
    words = [w for w in author.split() if not w.endswith(".")]
    return words[0] if words else ""


def _year(citation: str) -> str:
    """The year of a citation: the first one in parentheses, else the last year-like number."""
    found = re.search(r"\((1[5-9]\d\d|20\d\d)\)", citation)
    if found:
        return found.group(1)
    years = _YEAR.findall(citation)
    return years[-1] if years else ""


def _fields(citation: str) -> tuple[str, dict[str, str]]:
    """The entry type (article, book or misc) and the fields parsed from a citation."""
    segments = [s.strip() for s in citation.split(",") if s.strip()]
    authors = _authors(segments)
    rest = segments[len(authors) :]
    fields = {"author": " and ".join(authors)}
    article = _ARTICLE.search(citation)
    if article:
        journal = article.group("journal").strip()
        fields["title"] = ", ".join(rest).split(journal)[0].strip(" ,;")
        fields.update(journal=journal, volume=article.group("volume"))
        fields["pages"] = re.sub(r"\s*-+\s*", "--", article.group("pages") or "")
        kind = "article"
    elif _PUBLISHER.search(citation) and rest:
        fields["title"] = rest[0]
        fields["publisher"] = ", ".join(s for s in rest[1:] if not _YEAR.fullmatch(s))
        kind = "book"
    else:
        fields["title"] = ", ".join(rest)
        kind = "misc"
    fields["year"] = _year(citation)
    return kind, {name: value for name, value in fields.items() if value}


def _key(citation: str, case_ids: list[str]) -> str:
    """A citation key: first author's surname and year (``yehia2003``), else the first case id."""
    authors = _authors([s.strip() for s in citation.split(",")])
    surname = _ascii(_surname(authors[0])) if authors else ""
    return surname + _year(citation) if surname else case_ids[0]


def _unique(keys: list[str]) -> list[str]:
    """``keys`` with repeats suffixed ``a``, ``b``, ... (all occurrences of a repeated key)."""
    counts = {k: keys.count(k) for k in keys}
    seen: dict[str, int] = {}
    out = []
    for key in keys:
        if counts[key] > 1:
            seen[key] = seen.get(key, 0) + 1
            key = f"{key}{_suffix(seen[key])}"
        out.append(key)
    return out


def _suffix(n: int) -> str:
    """a, b, ..., z, aa, ab, ... for n = 1, 2, ..."""
    letters = ""
    while n:
        n, r = divmod(n - 1, 26)
        letters = chr(ord("a") + r) + letters
    return letters


#: Structured fields of a source (columns of ``Registry.cases``) and their BibTeX names.
_STRUCTURED = {
    "source_title": "title",
    "journal": "journal",
    "booktitle": "booktitle",
    "publisher": "publisher",
    "volume": "volume",
    "issue": "number",
    "pages": "pages",
    "url": "url",
}


def _sources(cases: pd.DataFrame) -> list[tuple[str, str, list[str], dict[str, str]]]:
    """(citation, doi, case ids citing it, structured BibTeX fields) for every distinct
    source of the rows of ``Registry.cases()``, sorted by citation."""
    grouped: dict[tuple[str, str], tuple[list[str], dict[str, str]]] = {}
    for row in cases.to_dict("records"):
        doi = row["doi"] if isinstance(row["doi"], str) else ""
        ids, fields = grouped.setdefault((row["citation"], doi), ([], {}))
        ids.append(row["case"])
        for column, name in _STRUCTURED.items():
            value = row.get(column)
            if isinstance(value, str) and value and name not in fields:
                fields[name] = value
        authors = row.get("authors")
        if isinstance(authors, list) and authors and "author" not in fields:
            fields["author"] = " and ".join(authors)
        year = row.get("year")
        if year is not None and year == year and "year" not in fields:  # not NaN
            fields["year"] = str(int(year))
    return [(c, d, sorted(ids), fields) for (c, d), (ids, fields) in sorted(grouped.items())]


def _structured_kind(fields: dict[str, str]) -> str | None:
    """The entry type the structured fields call for, or None when they are too few."""
    if "title" not in fields or "author" not in fields:
        return None
    if "journal" in fields:
        return "article"
    if "booktitle" in fields:
        return "incollection"
    if "publisher" in fields:
        return "book"
    return "misc"


def _entry(key: str, citation: str, doi: str, case_ids: list[str], given: dict[str, str]) -> str:
    """One BibTeX entry; its note keeps the full citation and the citing case ids."""
    kind = _structured_kind(given)
    if kind is None:
        kind, fields = _fields(citation)
        fields.update(given)
    else:
        fields = dict(given)
    if "pages" in fields:
        fields["pages"] = re.sub(r"\s*-+\s*", "--", fields["pages"])
    fields["note"] = f"{citation}. Registry cases: {', '.join(case_ids)}"
    lines = [
        f"  {name} = {{{latex.escape(value, balanced=True)}}}," for name, value in fields.items()
    ]
    if doi:  # verbatim in biblatex: only braces and spaces removed
        verbatim = re.sub(r"[{}\s]", "", doi)
        lines.insert(-1, f"  doi = {{{verbatim}}},")
    return "\n".join([f"@{kind}{{{key},", *lines, "}"])


def _source_key(citation: str, case_ids: list[str], fields: dict[str, str]) -> str:
    """The key from the structured first author and year where given, else the citation."""
    if "author" in fields and "year" in fields:
        surname = _ascii(_surname(fields["author"].split(" and ")[0]))
        if surname:
            return surname + fields["year"]
    return _key(citation, case_ids)


@dataclass(frozen=True)
class BibEntry:
    """One source as BibTeX: its key, the entry's text, and the cases that cite it."""

    key: str
    text: str
    cases: tuple[str, ...]


def entries(cases: pd.DataFrame) -> list[BibEntry]:
    """One entry per distinct source of the rows of ``Registry.cases()``, with unique
    stable keys, sorted by key."""
    sources = _sources(cases)
    keys = _unique([_source_key(citation, ids, fields) for citation, _, ids, fields in sources])
    return [
        BibEntry(k, _entry(k, *source), tuple(source[2]))
        for k, source in sorted(zip(keys, sources, strict=True))
    ]


def bibtex(cases: pd.DataFrame) -> str:
    """The BibTeX file of the sources of the rows of ``Registry.cases()``."""
    texts = [e.text for e in entries(cases)]
    return "\n\n".join(texts) + ("\n" if texts else "")
