"""Publishing the registry: its tables as CSV, JSON or Parquet files, its sources as BibTeX.

>>> import registry
>>> from registry.sharing import bibtex
>>> reg = registry.open(":memory:")
>>> _ = reg.add("data/cases/yehia-2003-kovalevskaya-b.toml")
>>> print(bibtex(reg).splitlines()[0])
@article{yehia2003,
"""

from __future__ import annotations

import json
import re
import unicodedata
from collections.abc import Callable
from datetime import date, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

    from ..api import Registry

#: The file formats of ``export_tables``.
FORMATS = ("csv", "json", "parquet")

#: The tables ``export_tables`` writes, in this order.
TABLES = ("cases", "claims", "verdicts", "all_results", "repairs", "runs")

#: Columns holding JSON values (dicts or lists), written as JSON text in CSV and Parquet.
JSON_COLUMNS = ("on", "witness", "payload", "options")


# ------------------------------------------------------------------ tables


def tables(reg: Registry) -> dict[str, pd.DataFrame]:
    """The published tables of a registry, by name (see ``TABLES``)."""
    return {
        "cases": reg.cases(),
        "claims": reg.claims(),
        "verdicts": reg.verdicts(),
        "all_results": all_results(reg),
        "repairs": reg.corrections(),
        "runs": reg.runs(),
    }


def all_results(reg: Registry) -> pd.DataFrame:
    """Every stored check result of every run, oldest run first."""
    import pandas as pd

    frames = [reg.verdicts(int(run)) for run in reg.runs()["run"]]
    if not frames:
        return reg.verdicts().iloc[0:0]
    return pd.concat(frames, ignore_index=True)


def export_tables(reg: Registry, out_dir: Path, fmt: str) -> list[Path]:
    """Write every table of ``TABLES`` to ``out_dir/<name>.<fmt>``; return the paths written."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown format {fmt!r}; expected one of {', '.join(FORMATS)}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for name, frame in tables(reg).items():
        path = out_dir / f"{name}.{fmt}"
        WRITERS[fmt](frame, path)
        written.append(path)
    return written


def _json_columns(frame: pd.DataFrame) -> list[str]:
    """The columns of ``frame`` holding dicts or lists (those of ``JSON_COLUMNS`` and others)."""
    return [
        c
        for c in frame.columns
        if c in JSON_COLUMNS or any(isinstance(v, dict | list | tuple) for v in frame[c])
    ]


def _encoded(frame: pd.DataFrame) -> pd.DataFrame:
    """A copy of ``frame`` with its JSON columns as JSON text (missing values stay missing)."""
    out = frame.copy()
    for column in _json_columns(frame):
        out[column] = [_json_text(v) for v in frame[column]]
    return out


def _json_text(value: Any) -> str | None:
    """A JSON column's value as JSON text, or None when it is missing."""
    plain = _plain(value)
    return None if plain is None else json.dumps(plain, ensure_ascii=False)


def _write_csv(frame: pd.DataFrame, path: Path) -> None:
    """CSV with a header row; dates in ISO 8601."""
    import pandas as pd

    out = _encoded(frame)
    for column in out.select_dtypes(include=["datetime", "datetimetz"]).columns:
        out[column] = [None if pd.isna(t) else t.isoformat() for t in out[column]]
    out.to_csv(path, index=False)


def _write_parquet(frame: pd.DataFrame, path: Path) -> None:
    """Parquet through pyarrow, JSON columns as strings."""
    _encoded(frame).to_parquet(path, engine="pyarrow", index=False)


def _plain(value: Any) -> Any:
    """A JSON-ready value: dates as ISO 8601 text, NaN and NaT as null, numpy scalars unboxed."""
    import pandas as pd

    if isinstance(value, dict | list):
        return value
    if isinstance(value, tuple):
        return list(value)
    if isinstance(value, datetime | date):
        return value.isoformat()
    if value is None or pd.isna(value):
        return None
    return value.item() if hasattr(value, "item") else value


def _write_json(frame: pd.DataFrame, path: Path) -> None:
    """A JSON array of records (one object per row), exact floats, ISO dates."""
    records = [{k: _plain(v) for k, v in row.items()} for row in frame.to_dict("records")]
    path.write_text(json.dumps(records, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")


WRITERS: dict[str, Callable[[pd.DataFrame, Path], None]] = {
    "csv": _write_csv,
    "json": _write_json,
    "parquet": _write_parquet,
}


def read_table(path: Path) -> pd.DataFrame:
    """Read back a table written by ``export_tables``: JSON columns decoded, dates parsed."""
    import pandas as pd  # imported where used: the CLI starts faster without it

    path = Path(path)
    if path.suffix == ".json":
        frame = pd.DataFrame(json.loads(path.read_text(encoding="utf-8")))
    elif path.suffix == ".parquet":
        frame = pd.read_parquet(path)
    else:
        frame = pd.read_csv(path)
    for column in frame.columns:
        if column in JSON_COLUMNS:
            frame[column] = [_decoded(v) for v in frame[column]]
        elif column.endswith("_at"):
            frame[column] = pd.to_datetime(frame[column], utc=True, format="ISO8601")
    return frame


def _decoded(value: Any) -> Any:
    """A JSON column's value read back: JSON text decoded, a missing value as None."""
    if isinstance(value, str):
        return json.loads(value)
    return value if isinstance(value, dict | list) else None


# ------------------------------------------------------------------ BibTeX

_LATEX_SPECIALS = {
    "\\": r"\textbackslash{}",
    "{": r"\textbraceleft{}",
    "}": r"\textbraceright{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
}
_SPECIAL = re.compile("|".join(map(re.escape, _LATEX_SPECIALS)))
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


def latex_escape(text: str) -> str:
    """``text`` with LaTeX's special characters escaped (braces stay balanced in BibTeX)."""
    return _SPECIAL.sub(lambda m: _LATEX_SPECIALS[m.group()], text)


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
    lines = [f"  {name} = {{{latex_escape(value)}}}," for name, value in fields.items()]
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
