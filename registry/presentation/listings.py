"""The listings the command line prints (``registry cases``, ``verdicts``,
``corrections``, ``runs``, ``searches``, ``list-checks``), as plain text that fits a
terminal ``width`` wide (None: no limit).

Each takes the facade's data (the DataFrames of ``store.frames``, the recorded searches,
the checks) and lays it out with the one table printer (``text_table``): a listing of
cases is grouped under each case's id, which is too long to share a line with the rest
at 80 columns and must stay whole (it is what ``--case`` takes); long text (a title, an
expression, a method) wraps in its column.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, Protocol

from .search_output import ansatz_text, short_result, statement
from .text_table import grouped_table, text_table, wrapped

if TYPE_CHECKING:
    import pandas as pd

    from ..model import CaseIdentification, Search

#: What a listing with no rows prints.
NONE = "(none)"


class CheckLike(Protocol):
    """What ``checks_listing`` reads of a check (``api.CheckInfo``)."""

    @property
    def name(self) -> str: ...
    @property
    def per_claim(self) -> bool: ...
    @property
    def cost(self) -> str: ...
    @property
    def statement(self) -> str: ...


def _missing(value: Any) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value))


def _text(value: Any, missing: str = "") -> str:
    """A frame's cell as text: NaN and None as ``missing``, a whole float as an integer."""
    if _missing(value):
        return missing
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def _grouped(
    frame: pd.DataFrame,
    heading: str,
    title: Any,
    columns: Sequence[tuple[str, str]],
    width: int | None,
    wrap: Iterable[int] = (),
    missing: str = "",
) -> str:
    """The rows of ``frame`` grouped under ``title(row)`` (consecutive rows with the same
    title share it), showing ``columns`` as (frame column, header) pairs."""
    if not len(frame):
        return NONE
    groups: list[tuple[str, list[tuple[str, ...]]]] = []
    for row in frame.to_dict("records"):
        head = title(row)
        cells = tuple(_text(row.get(column), missing) for column, _ in columns)
        if groups and groups[-1][0] == head:
            groups[-1][1].append(cells)
        else:
            groups.append((head, [cells]))
    header = tuple(name for _, name in columns)
    return grouped_table(heading, header, groups, width=width, wrap=set(wrap))


def cases_listing(frame: pd.DataFrame, width: int | None = None) -> str:
    """``registry cases``: each case (its latest version) headed by its id, version and
    title, then its year, number of claims, topic, torque family and authors."""
    frame = frame.assign(
        authors=[", ".join(a) if isinstance(a, list) else "" for a in frame["authors"]],
    )
    columns = [
        ("year", "year"),
        ("n_claims", "claims"),
        ("topic", "topic"),
        ("family", "family"),
        ("authors", "authors"),
    ]
    return _grouped(
        frame,
        "case (version): title",
        lambda row: f"{row['case']} (version {row['version']}): {row['title']}",
        columns,
        width,
        wrap=(2, 3, 4),
    )


def verdicts_listing(frame: pd.DataFrame, width: int | None = None) -> str:
    """``registry verdicts``: under each case (and version), each check of the case and
    of its claims with its verdict, the method that decided, and the run."""
    columns = [
        ("claim", "claim"),
        ("check", "check"),
        ("verdict", "verdict"),
        ("method", "method"),
        ("run", "run"),
    ]
    return _grouped(
        frame,
        "case (version)",
        lambda row: f"{row['case']} (version {row['version']})",
        columns,
        width,
        wrap=(3,),
        missing="-",
    )


def corrections_listing(frame: pd.DataFrame, width: int | None = None) -> str:
    """``registry corrections``: under each case (and version), the torque's family, each
    re-checked correction and each branch of a parameter condition (its equations as
    the expression, or why none was found), with its method and verdict."""
    if not len(frame):
        return NONE
    rows = []
    for row in frame.to_dict("records"):
        payload = row.pop("payload", None) or {}
        if row["kind"] != "conditions":
            rows.append(row)
        elif not payload.get("branches"):
            rows.append({**row, "expression": payload.get("reason", "")})
        else:
            rows += [{**row, "expression": ", ".join(b)} for b in payload["branches"]]
    import pandas as pd

    listed = pd.DataFrame(rows)
    columns = [
        ("claim", "claim"),
        ("kind", "kind"),
        ("expression", "expression"),
        ("method", "method"),
        ("verdict", "verdict"),
    ]
    text = _grouped(
        listed,
        "case (version)",
        lambda row: f"{row['case']} (version {row['version']})",
        columns,
        width,
        wrap=(2, 3),
        missing="-",
    )
    runs = sorted({int(r) for r in frame["run"] if not _missing(r)})
    return f"run {', '.join(map(str, runs))}\n{text}" if runs else text


def runs_listing(frame: pd.DataFrame, width: int | None = None) -> str:
    """``registry runs``: each audit run with when it started, how long it took, its
    status, how many cases and results it has by verdict, and the code version."""
    if not len(frame):
        return NONE
    rows = []
    for row in frame.to_dict("records"):
        started, finished = row["started_at"], row["finished_at"]
        took = "" if _missing(finished) else f"{(finished - started).total_seconds():.0f} s"
        counts = [
            f"{int(row[f'n_{v}'])} {v}"
            for v in ("verified", "refuted", "inconclusive", "error")
            if row.get(f"n_{v}")
        ]
        reused = f"; {int(row['n_reused'])} reused" if row.get("n_reused") else ""
        rows.append(
            (
                row["run"],
                f"{started:%Y-%m-%d %H:%M}",
                took,
                row["status"],
                row["n_cases"],
                (", ".join(counts) or "none") + reused,
                row["code_version"],
            )
        )
    header = ("run", "started", "took", "status", "cases", "results", "code version")
    return text_table(header, rows, width=width, wrap={5})


def checks_listing(checks: Iterable[CheckLike], width: int | None = None) -> str:
    """``registry list-checks``: each check the audit runs, whether it runs once per case
    or per claim, its cost, and the statement it tests."""
    rows = [
        (c.name, "per claim" if c.per_claim else "per case", c.cost, c.statement) for c in checks
    ]
    return text_table(("check", "runs", "cost", "statement"), rows, width=width, wrap={3})


def searches_listing(searches: Sequence[tuple[int, Search]], width: int | None = None) -> str:
    """``registry searches``: one row per recorded search (its number and ``Search``),
    under the case searched: the ansatz, whether the search is complete, and its result
    in short. Consecutive searches of a case share its heading."""
    if not searches:
        return NONE
    groups: list[tuple[str, list[tuple[object, ...]]]] = []
    for number, s in searches:
        row = (number, ansatz_text(s.options), "yes" if s.complete else "no", short_result(s))
        if groups and groups[-1][0] == s.case:
            groups[-1][1].append(row)
        else:
            groups.append((s.case, [row]))
    header = ("search", "ansatz", "complete", "result")
    return grouped_table("case", header, groups, width=width, wrap={1, 3})


def searches_long(searches: Sequence[tuple[int, Search]], width: int | None = None) -> str:
    """``registry searches --long``: each recorded search as its number, case and ansatz,
    then its result in one sentence, wrapped."""
    if not searches:
        return NONE
    blocks = []
    for number, s in searches:
        head = f"search {number}: {s.case}, {ansatz_text(s.options)}"
        blocks.append(
            wrapped(head, width, subsequent="    ")
            + "\n"
            + wrapped(statement(s), width, indent="  ", subsequent="  ")
        )
    return "\n\n".join(blocks)


def survey_listing(searches: Sequence[Search], width: int | None = None) -> str:
    """``registry survey``: each search as its case (and level set) and its result in
    one sentence, wrapped under a hanging indent."""
    lines = []
    for s in searches:
        on = f" on {', '.join(e.text for e in s.options.on)}" if s.options.on else ""
        lines.append(wrapped(f"{s.case}{on}: {statement(s)}", width, subsequent="    "))
    return "\n".join(lines)


def identify_listing(found: Sequence[CaseIdentification], width: int | None = None) -> str:
    """``registry identify``: each case with the catalog cases it is the same system as
    (their parameter values), how many were compared, and those left uncompared."""
    lines = []
    for f in found:
        same = "; ".join(
            s.case + (f" at {', '.join(f'{k} = {v}' for k, v in s.values)}" if s.values else "")
            for s in f.same_as
        )
        if same:
            text = f"{f.case}: the same system as {same}"
        elif f.note:
            text = f"{f.case}: {f.note}"
        else:
            text = f"{f.case}: no case found"
        text += f" ({len(f.compared)} compared"
        if f.skipped:
            text += f"; {len(f.skipped)} not compared, time ran out"
        if f.failed:
            text += f"; {len(f.failed)} comparisons failed"
        text += ", reused)" if f.reused else ")"
        lines.append(wrapped(text, width, subsequent="    "))
    return "\n".join(lines) if lines else NONE
