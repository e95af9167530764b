"""Publishing the registry's tables (``registry export --format``): CSV, JSON or Parquet
files, written exactly and read back with ``read_table``. A new file format is one
more writer in ``WRITERS``. The tables come from ``Registry.tables()``: this module
writes what it is given and never queries the registry.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from datetime import date, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

#: The file formats of ``export_tables``.
FORMATS = ("csv", "json", "parquet")

#: The tables ``export_tables`` writes, in this order.
TABLES = ("cases", "claims", "verdicts", "all_results", "corrections", "runs")

#: Text columns whose values may look like numbers (a volume "8"), read back as text.
TEXT_COLUMNS = (
    "volume", "issue", "pages", "doi", "locator", "citation", "label", "claim",
    "potential", "hamiltonian", "kappa", "expression",
)  # fmt: skip

#: Columns holding JSON values (dicts or lists), written as JSON text in CSV and Parquet.
JSON_COLUMNS = (
    "on", "witness", "payload", "options", "authors", "aliases", "inertia", "torque",
    "variables", "same_as", "equivalent",
)  # fmt: skip


# ------------------------------------------------------------------ tables


def export_tables(tables: Mapping[str, pd.DataFrame], out_dir: Path, fmt: str) -> list[Path]:
    """Write each table (``Registry.tables()``: name -> frame, in ``TABLES`` order) to
    ``out_dir/<name>.<fmt>``; return the paths written."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown format {fmt!r}; expected one of {', '.join(FORMATS)}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for name, frame in tables.items():
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
        header = pd.read_csv(path, nrows=0).columns
        frame = pd.read_csv(path, dtype={c: "string" for c in TEXT_COLUMNS if c in header})
        for column in TEXT_COLUMNS:
            if column in frame:
                frame[column] = frame[column].astype(object).where(frame[column].notna(), None)
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
