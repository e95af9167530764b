"""The sources of the stored cases as BibTeX (``registry export --bibtex``).

One entry per distinct source, with a stable key (first author's surname and year,
``yehia2003``; repeats suffixed a, b, ...), its type and fields parsed from the
citation as a reader wrote it, and a note keeping the full citation and the cases
that cite it. Field values are escaped so that their braces stay balanced.

>>> import registry
>>> reg = registry.open(":memory:")
>>> _ = reg.add("data/cases/yehia-2003-kovalevskaya-b.toml")
>>> print(bibtex(reg).splitlines()[0])
@article{yehia2003,
"""

from __future__ import annotations

import re
import unicodedata
from typing import TYPE_CHECKING

from . import latex

if TYPE_CHECKING:
    from ..api import Registry

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


def _sources(reg: Registry) -> list[tuple[str, str, list[str]]]:
    """(citation, doi, case ids citing it) for every distinct source, sorted by citation."""
    cases = reg.cases()
    grouped: dict[tuple[str, str], list[str]] = {}
    for row in cases.itertuples(index=False):
        doi = row.doi if isinstance(row.doi, str) else ""
        grouped.setdefault((row.citation, doi), []).append(row.case)
    return [(c, d, sorted(ids)) for (c, d), ids in sorted(grouped.items())]


def _entry(key: str, citation: str, doi: str, case_ids: list[str]) -> str:
    """One BibTeX entry; its note keeps the full citation and the citing case ids."""
    kind, fields = _fields(citation)
    fields["note"] = f"{citation}. Registry cases: {', '.join(case_ids)}"
    lines = [
        f"  {name} = {{{latex.escape(value, balanced=True)}}}," for name, value in fields.items()
    ]
    if doi:  # verbatim in biblatex: only braces and spaces removed
        verbatim = re.sub(r"[{}\s]", "", doi)
        lines.insert(-1, f"  doi = {{{verbatim}}},")
    return "\n".join([f"@{kind}{{{key},", *lines, "}"])


def bibtex(reg: Registry) -> str:
    """One BibTeX entry per distinct source of the stored cases, with unique stable keys."""
    sources = _sources(reg)
    keys = _unique([_key(citation, ids) for citation, _, ids in sources])
    entries = [_entry(k, *source) for k, source in sorted(zip(keys, sources, strict=True))]
    return "\n\n".join(entries) + ("\n" if entries else "")
