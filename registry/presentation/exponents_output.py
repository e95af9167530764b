"""Presenting a Kovalevskaya analysis: the plain text ``registry exponents`` prints, from
the analysis's JSON document (docs/json-output.md), which is what the registry stores:
a fresh analysis and a stored one read the same."""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Mapping, Sequence
from typing import Any

from ..model import ExponentResult
from .text_table import wrapped

#: Expressions longer than this many characters are elided in the text (the JSON has
#: them whole): a family's generic point over Q(p) can run to pages.
LONG = 400
#: The most special sets of one kind the text shows; the others are counted (a grid
#: searched over several parameters can find hundreds; the JSON has every one).
SHOWN = 12


def exponents_text(result: ExponentResult, width: int | None = None) -> str:
    """The analysis in plain text: the weights, the leading part where the field is not
    homogeneous, each balance with its exponents and Painlevé test, Yoshida's degrees,
    a family's special sets, the statement and the time; each line wrapped to ``width``
    (None: no limit) under a hanging indent."""
    return "\n".join(_hanging(line, width) for line in _lines(result))


def _hanging(line: str, width: int | None) -> str:
    """A line wrapped to ``width``, its next lines indented two more than its first."""
    text = line.lstrip(" ")
    indent = " " * (len(line) - len(text))
    return wrapped(text, width, indent=indent, subsequent=indent + "  ")


def _lines(result: ExponentResult) -> list[str]:
    d = result.document
    lines = [_heading(d)]
    if not result.decided:
        lines.append(f"not decided: {d.get('reason', '')}")
        if "witness" in d:
            lines += _witness(d["witness"])
        lines.append(result.statement)
        return lines
    if d.get("leading"):
        lines.append("the field is not weighted-homogeneous: its leading part is analysed,")
        lines += [f"    d{x}/dt = {v}" for x, v in d["leading"].items()]
    if d.get("denominators"):
        shown = ", ".join(d["denominators"])
        lines.append(f"the field divides by {shown}: balances where none of these vanishes")
    if d.get("parameters"):
        lines.append(f"parameters (generic values): {', '.join(d['parameters'])}")
    for i, b in enumerate(d["balances"], 1):
        lines += _balance(i, b)
    if not d["balances"] and d.get("all_integer") is not None:
        lines.append("no balance: the leading part has no solution x = c t^(-w)")
    if d["balances"]:
        degrees = ", ".join(map(str, d["degrees"])) or "none"
        lines.append(f"degrees (Yoshida): {degrees}")
    if "witness" in d:  # a family whose sets left its generic members' test unknown
        lines += _witness(d["witness"])
    elif d["balances"]:
        verdict = painleve_word(d["painleve"]["passes"])
        lines.append(f"Painlevé (ARS) test{' for generic values' if d['free'] else ''}: {verdict}")
    elif "painleve_sets" in d and d["painleve"]["passes"] is not None:  # generic: not analysed
        verdict = painleve_word(d["painleve"]["passes"])
        lines.append(f"Painlevé (ARS) test for generic values: {verdict} (by the sets below)")
    if "special" in d:
        lines += _special(d["special"], d["complete"], d["coverage"])
    if "painleve_sets" in d:
        lines += _painleve_sets(d["painleve_sets"])
    if "half_integer_sets" in d:
        lines += _half_integer_sets(d["half_integer_sets"])
    lines.append(result.statement)
    lines.append(f"{result.seconds:.2f} s")
    return lines


def painleve_word(passes: bool | None) -> str:
    """The Painlevé test's verdict in a word (None: the series was not computed)."""
    return {True: "passes", False: "fails", None: "not made"}[passes]


def _heading(d: Mapping[str, Any]) -> str:
    weights = ",".join(f"{k}={v}" for k, v in d["weights"].items())
    free = f", free {', '.join(d['free'])}" if d.get("free") else ""
    return f"{d['case']}: Kovalevskaya exponents (weights {weights}{free})"


def _balance(i: int, b: Mapping[str, Any]) -> list[str]:
    point = ", ".join(f"{x} = {shown(v)}" for x, v in b["point"].items())
    lines = [f"balance {i}: {point}"]
    if b.get("root_of"):
        lines.append(f"    theta: a root of {shown(b['root_of'])}")
    if any(len(v) > LONG for v in [*b["point"].values(), b.get("root_of") or ""]):
        lines.append("    (long expressions elided: registry exponents --json prints them whole)")
    if b.get("dimension"):
        lines.append(
            f"    a family of balances of dimension {b['dimension']} (along "
            f"{', '.join(b['along'])})"
        )
    kind = "integers" if b["integer"] else "rational" if b["rational"] else "not all rational"
    lines.append(f"    exponents: {', '.join(b['exponents'])} ({kind})")
    resonances = b["painleve"]["resonances"]
    lines += [f"    {text}" for text in failures(resonances) or _holding(resonances)]
    return lines


def _witness(w: Mapping[str, Any]) -> list[str]:
    """The balance at rational values that shows the test failing for generic values."""
    at = ", ".join(f"{p} = {v}" for p, v in w["values"].items())
    point = ", ".join(f"{x} = {shown(v)}" for x, v in w["point"].items())
    lines = [
        f"Painlevé (ARS) test for generic values: fails (by a simple balance at {at})",
        f"  balance there: {point}",
        f"    theta: a root of {shown(w['root_of'])}",
        f"    exponents: {', '.join(map(shown, w['exponents']))} (not all integers; none 0)",
    ]
    if w.get("approximate"):
        numbers = ", ".join(w["approximate"])
        lines.append(f"    those not rational, at one root theta, approximately: {numbers}")
    if any(len(v) > LONG for v in [*w["point"].values(), w["root_of"], *w["exponents"]]):
        lines.append("    (long expressions elided: registry exponents --json prints them whole)")
    return lines


def shown(expression: str) -> str:
    """An expression as printed, or where it is longer than ``LONG``, the symbols it
    involves (not the functions, not I) and its length."""
    if len(expression) <= LONG:
        return expression
    found = set(re.findall(r"\b([A-Za-z_][A-Za-z0-9_]*)\b(?!\()", expression)) - {"I"}
    names = ", ".join(sorted(found))
    return f"<an expression in {names}: {len(expression)} characters>"


def failures(resonances: Sequence[Mapping[str, Any]]) -> list[str]:
    """Where the Painlevé test fails at one balance, resonance by resonance: each failing
    condition, each free coefficient missing (none: the test holds there)."""
    failing = []
    for r in resonances:
        failing += [f"resonance {r['order']}: condition fails: {shown(c)}" for c in r["conditions"]]
        if r["missing"] and r["order"] == 0:
            failing.append(
                f"exponent 0: {r['missing']} free leading coefficient(s) missing (the "
                "balance is not on a family of that dimension)"
            )
        elif r["missing"]:
            failing.append(
                f"resonance {r['order']}: {r['missing']} free coefficient(s) missing (a "
                "logarithmic term is needed)"
            )
    return failing


def _holding(resonances: Sequence[Mapping[str, Any]]) -> list[str]:
    """The line of a balance where every compatibility condition holds."""
    if orders := ", ".join(str(r["order"]) for r in resonances if r["order"]):
        return [f"Painlevé: every compatibility condition holds (resonances {orders})"]
    return []


def _painleve_sets(found: Mapping[str, Any]) -> list[str]:
    """The sets where the ARS test passes for generic members, and what was not decided."""
    head = f"Painlevé (ARS) test passes on ({found['strata']} strata analysed):"
    return _strata([head], found["passing"], found)


def _half_integer_sets(found: Mapping[str, Any]) -> list[str]:
    """The sets where every exponent is in (1/2)Z, each with its kind where known."""
    head = f"every exponent in (1/2)Z on ({found['strata']} strata analysed):"
    return _strata([head], found["sets"], found, kinds=True)


def _strata(
    lines: list[str], sets: Sequence[Mapping[str, Any]], found: Mapping[str, Any], kinds=False
) -> list[str]:
    for s in sets:
        free = f" ({', '.join(s['free'])} free)" if s["free"] else ""
        kind = f" [{s['kind']}]" if kinds and s.get("kind") else ""
        lines.append(f"  {', '.join(s['when']) or 'every value'}{free}{kind}")
        if "same_as" in s:
            lines.append(f"      {_same_as(s['same_as'])}")
        lines += _exponent_lines(s.get("exponents", ()))
        if "exponents" in s and not s["exponents"]:
            lines.append("      no balance: the test has nothing to check")
    if not sets:
        lines.append("  no set that was analysed")
    lines.append(f"complete: {'yes' if found['complete'] else 'no'}")
    lines += [f"  not decided: {u}" for u in found["undecided"]]
    return lines


def _exponent_lines(lists: Sequence[Sequence[str]]) -> list[str]:
    return [f"      exponents {e}" for e in distinct_exponents(lists)]


def distinct_exponents(lists: Sequence[Sequence[str]]) -> list[str]:
    """Each distinct list of a set's exponents once, with how many balances share it."""
    counts = Counter(tuple(exponents) for exponents in lists)
    return [", ".join(e) + (f" ({n} balances)" if n > 1 else "") for e, n in counts.items()]


def _same_as(cases: Sequence[str], shown: int = 3) -> str:
    """The catalog cases a set is, the most specific first (a few, then how many more)."""
    if not cases:
        return "matches no catalog case"
    more = f" and {len(cases) - shown} more" if len(cases) > shown else ""
    return f"same as {', '.join(cases[:shown])}{more}"


def _special(
    special: Sequence[Mapping[str, Any]], complete: Mapping[str, bool], coverage: Sequence[str]
) -> list[str]:
    lines = ["special sets:" if special else "special sets: none"]
    kinds = Counter(s["kind"] for s in special)
    seen: Counter[str] = Counter()
    for s in special:
        seen[s["kind"]] += 1
        if seen[s["kind"]] > SHOWN:
            if seen[s["kind"]] == kinds[s["kind"]]:
                more = kinds[s["kind"]] - SHOWN
                lines.append(f"  {s['kind']}: {more} more set(s), not shown (--json lists them)")
            continue
        when = ", ".join(s["when"]) or "every value"
        if "index" in s:
            when += f" ({s['index']['ranges']})"
        line = f"  {s['kind']}: {when}"
        if "painleve" in s:
            line += f"; Painlevé (ARS) test {painleve_word(s['painleve']['passes'])}"
        lines.append(line)
        lines += _exponent_lines(s.get("exponents", ()))
        lines += [f"      note: {n}" for n in s.get("notes", ())]
    flags = ", ".join(f"{k.replace('_', '-')} {'yes' if v else 'no'}" for k, v in complete.items())
    lines.append(f"complete: {flags}")
    if not all(complete.values()):
        lines += [f"  coverage: {c}" for c in coverage]
    return lines
