"""Presenting an integral search: the JSON document of docs/json-output.md (section
Search output), a plain-text summary, the result in one sentence, and in a few words;
and a measure search in plain text."""

from __future__ import annotations

from ..model import IntegralSet, IntegralStatus, MeasureSearch, SameSystem, Search, SearchOptions
from .text_table import wrapped


def statement(search: Search) -> str:
    """The result in one sentence, as a paper would state it: what exists for generic
    values, where more exists, and whether the method guarantees that nothing else does."""
    o = search.options
    ansatz = f"of weighted degree <= {o.degree} (weights {o.weights_text()}"
    ansatz += f"; on {', '.join(eq.text for eq in o.on)})" if o.on else ")"
    values = f"values of {', '.join(o.free)}" if o.free else "values of the parameters"
    if o.relations and search.decided:
        return _relations_statement(search, ansatz)
    if not search.decided:
        return (
            f"Nothing is established about integrals {ansatz}: " + "; ".join(search.coverage) + "."
        )
    if search.generic.extra:
        text = f"{search.generic.extra} extra integral(s) {ansatz} exist for generic {values}"
        again = search.generic.rediscovered if search.generic.status else ()
        named = sorted({c for st in search.generic.status for c in st.equals})
        if again:
            text += (
                f" ({len(search.generic.new)} new, {len(again)} the case's claims "
                f"{', '.join(named)} again)"
            )
        if search.claims_complete and named:
            beyond = f" beyond {', '.join(search.known)}" if search.known else ""
            text += (
                f"; the claims {', '.join(named)} span every integral of weighted degree "
                f"<= {o.degree}{beyond}"
            )
    else:
        text = f"No extra integral {ansatz} exists for generic {values}"
    if search.special:
        text += "; more exist exactly where " + "; or ".join(
            ", ".join(s.when) + _known_as(s) for s in search.special
        )
    if search.complete:
        return text + ("" if not o.free else "; no other values carry more") + "."
    return text + " (the search is not complete: see its coverage)."


def _known_as(entry: IntegralSet) -> str:
    """`` (kovalevskaya-1889-heavy-top)`` where the set is a catalog case whose claims its
    integrals are, `` (new)`` where an integral there is no claim of any case it is."""
    named = [s.case for s in entry.same_as if s.claims]
    if entry.status and entry.new:
        return " (new" + (f"; the system of {named[0]}" if named else "") + ")"
    if named:
        return f" ({named[0]})"
    return ""


def _relations_statement(search: Search, ansatz: str) -> str:
    """A search for invariant relations in one sentence: the cofactors that carry them."""
    found = [
        f"{', '.join(f'{t} = 0' for t in s.integrals)} "
        + (
            f"(cofactor {s.cofactor})"
            if s.cofactor not in ("", "0")
            else f"(cofactor 0: first integral{'s' * (len(s.integrals) != 1)})"
        )
        for s in search.special
    ]
    if found:
        text = f"Invariant relations (Darboux polynomials {ansatz}) exist exactly: " + "; ".join(
            found
        )
    else:
        text = f"No invariant relation (Darboux polynomial {ansatz}) exists beyond first integrals"
    if search.complete:
        return text + "; no other cofactor carries one."
    return text + " (the search is not complete: see its coverage)."


def same_text(same: SameSystem) -> str:
    """``kovalevskaya-1889-heavy-top (C = 1, a = 1; claims K)``: a case the set is."""
    values = ", ".join(f"{k} = {v}" for k, v in same.values)
    moved = [f"{k} -> {v}" for k, v in same.transformation if k != v]
    parts = [p for p in (values, "; ".join(moved)) if p]
    if same.claims:
        parts.append(f"its integrals are {', '.join(same.claims)}")
    return same.case + (f" ({'; '.join(parts)})" if parts else "")


def ansatz_text(options: SearchOptions) -> str:
    """The ansatz in short: ``degree 4; M=1,gamma=2; on s = 0; free a,b`` (and
    ``relations`` for a search of invariant relations)."""
    parts = [f"degree {options.degree}", options.weights_text("=")]
    if options.on:
        parts.append("on " + ", ".join(eq.text for eq in options.on))
    if options.free:
        parts.append("free " + ",".join(options.free))
    if options.relations:
        parts.append("relations")
    return "; ".join(parts)


def short_result(search: Search) -> str:
    """The result in a few words: ``no extra integral``, ``1 extra (new)``, ``2 extra (1
    new, 1 rediscovered)``, ``; 2 special sets`` after it, or ``not decided``.

    A search of invariant relations says for how many cofactors relations exist."""
    if not search.decided:
        return "not decided"
    n = len(search.special)
    if search.options.relations:
        return f"relations for {n} cofactor{'s' * (n != 1)}" if n else "no invariant relation"
    generic = search.generic
    if not generic.extra:
        text = "no extra integral"
    elif not generic.status:  # searched before integrals were compared with the claims
        text = f"{generic.extra} extra"
    else:
        new, again = len(generic.new), len(generic.rediscovered)
        if new and again:
            detail = f"{new} new, {again} rediscovered"
        else:
            detail = "new" if new else "rediscovered"
        text = f"{generic.extra} extra ({detail})"
    if n:
        text += f"; {n} special set{'s' * (n != 1)}"
    return text


def status_text(status: IntegralStatus) -> str:
    """``new``, or ``= K modulo H, |gamma|^2``: what a found integral is."""
    if status.new:
        return "new"
    text = f"= {', '.join(status.equals)}"
    return text + (f" modulo {', '.join(status.modulo)}" if status.modulo else "")


def _set(entry: IntegralSet) -> dict:
    out = {
        "extra": entry.extra,
        "integrals": list(entry.integrals),
        "casimir": [str(v) for v in entry.casimir],
    }
    if entry.cofactor:
        out["cofactor"] = entry.cofactor
    if entry.status:
        out["status"] = [
            {
                "expression": text,
                "status": st.status,
                "equals": list(st.equals),
                "modulo": list(st.modulo),
                "relation": st.relation,
            }
            for text, st in zip(entry.integrals, entry.status, strict=True)
        ]
    out["new"] = len(entry.new)
    out["rediscovered"] = len(entry.integrals) - len(entry.new)
    out["same_as"] = [s.as_dict() for s in entry.same_as]
    return out


def search_document(search: Search) -> dict:
    """The document ``registry discover --json`` prints."""
    o = search.options
    document = {
        "case": search.case,
        "degree": o.degree,
        "weights": dict(o.weights),
        "on": [eq.text for eq in o.on],
        "free": list(o.free),
        **({"relations": True} if o.relations else {}),
        "known": list(search.known),
        "claims": list(search.claims),
        "claims_complete": search.claims_complete,
        "generic": _set(search.generic),
        "special": [{"when": list(s.when), **_set(s)} for s in search.special],
        "complete": search.complete,
        "decided": search.decided,
        "coverage": list(search.coverage),
        "statement": statement(search),
        "dimensions": [
            {"degree": d, "integrals": n, "trivial": t, "extra": e}
            for d, n, t, e in search.dimensions
        ],
        "method": search.method,
        "seconds": round(search.seconds, 3),
    }
    return document


def recorded_search_document(number: int, version: int, search: Search) -> dict:
    """The document of a recorded search (``registry searches --json``): its number,
    the version of the case searched, then the search's document (``search_document``)."""
    return {"search": number, "version": version, **search_document(search)}


def search_text(search: Search, width: int | None = None) -> str:
    """A plain-text summary of a search: the ansatz, the known integrals, what exists for
    generic values and on each special set, whether the search is complete; each line
    wrapped to ``width`` (None: no limit) under a hanging indent."""
    o = search.options
    lines = [
        f"{search.case}: integrals of weighted degree <= {o.degree} "
        f"(weights {o.weights_text('=')})"
        + (f" on {', '.join(eq.text for eq in o.on)}" if o.on else "")
        + (f", free {', '.join(o.free)}" if o.free else ""),
        f"known: {', '.join(search.known)}"
        + (f"; the case's claims {', '.join(search.claims)}" if search.claims else ""),
    ]

    def describe(entry: IntegralSet, where: str) -> None:
        # a set of invariant relations F = 0 (dF/dt = K F, K not 0) has no Casimir verdicts
        relations = o.relations and entry.cofactor not in ("", "0")
        if not entry.extra:
            lines.append(f"{where}: no {'invariant relation' if relations else 'extra integral'}")
            return
        if relations:
            lines.append(f"{where}: {entry.extra} invariant relation(s), cofactor {entry.cofactor}")
            lines.extend(f"    {text} = 0    (dF/dt = K F verified)" for text in entry.integrals)
            return
        lines.append(f"{where}: {entry.extra} extra integral(s)")
        status = entry.status or (None,) * len(entry.integrals)
        casimirs = entry.casimir or (None,) * len(entry.integrals)  # None: no bracket
        for text, casimir, st in zip(entry.integrals, casimirs, status, strict=True):
            what = f"; {status_text(st)}" if st is not None else ""
            bracket = f"; casimir {casimir}" if casimir is not None else ""
            lines.append(f"    {text}    (integral verified{bracket}{what})")
        lines.extend(f"    same system as {same_text(s)}" for s in entry.same_as)

    if search.decided:
        describe(search.generic, "generic")
    else:
        lines.append("generic: not decided")
    for s in search.special:
        describe(s, ", ".join(s.when))
    lines.extend(
        f"ansatz: {part}"
        for part in search.method.split("; ")
        if part.startswith("the vector field is not weighted-homogeneous")
    )
    lines.extend(part for part in search.method.split("; ") if part.startswith("symmetries"))
    lines.append(f"complete: {'yes' if search.complete else 'no'}")
    lines.extend(f"  coverage: {c}" for c in search.coverage if not search.complete)
    lines.append(statement(search))
    lines.append(f"{search.seconds:.2f} s")
    return "\n".join(_hanging(line, width) for line in lines)


def measure_text(search: MeasureSearch, width: int | None = None) -> str:
    """A plain-text summary of a measure search: the Darboux polynomials of the ansatz
    with their cofactors, each density with the factors where it is singular, the first
    integrals it may be multiplied by, completeness and the statement."""
    lines = [f"{search.case}: invariant densities rho = prod F_i**a_i"]
    if search.darboux:
        lines.append("Darboux polynomials among the factors tried (dF/dt = K F):")
        lines.extend(f"    F = {f}    (K = {k})" for f, k in search.darboux)
    else:
        lines.append(f"Darboux polynomials: none among the {len(search.candidates)} factors tried")
    for d in search.densities:
        lines.append(f"density: rho = {d.expression}    (measure {d.verdict})")
        lines.extend(f"    singular or undefined where {f} = 0" for f in d.singular)
    if not search.densities:
        lines.append("density: none of this form")
    lines.extend(f"first integral: {i}" for i in search.integrals)
    lines.append(f"complete: {'yes' if search.complete else 'no'}")
    lines.extend(f"  undecided: {u}" for u in search.undecided)
    lines.append(search.statement)
    lines.append(f"{search.seconds:.2f} s")
    return "\n".join(_hanging(line, width) for line in lines)


def _hanging(line: str, width: int | None) -> str:
    """A line wrapped to ``width``, its next lines indented two more than its first."""
    text = line.lstrip(" ")
    indent = " " * (len(line) - len(text))
    return wrapped(text, width, indent=indent, subsequent=indent + "  ")
