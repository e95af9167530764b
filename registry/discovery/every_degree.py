"""The two halves of a classification together: what a completed integral search up to
weighted degree K and the Kovalevskaya exponents under the same weights prove about
first integrals of *every* degree, and nothing more.

Yoshida's theorem (Celestial Mech. 31 (1983) 363): a weighted-homogeneous first integral
I of weighted degree k of a weighted-homogeneous field, with grad I(c) != 0 at a balance
c, has k among the exponents of c. Let D be the degrees some balance allows.

* A weighted-homogeneous field: every polynomial integral is a sum of weighted-homogeneous
  integrals (d/dt maps each degree to one other). Where max D <= K, each summand whose
  gradient is not zero at some balance has a degree in D, at most K, and so lies among
  the integrals the complete search determined up to degree K; what remains are
  weighted-homogeneous integrals whose gradients vanish at every balance, of any degree.
* A field that is not homogeneous: the leading weighted-homogeneous part of a polynomial
  integral is an integral of the field's leading part; where its gradient is not zero at
  a balance of the leading part, its degree is in D. Where max D <= K, such an integral
  has degree at most K and lies in the search's ansatz (every monomial of weighted
  degree <= K), so the complete search determined it.

The hypotheses are checked, and a statement is made only where they hold: the search is
decided and complete, on the whole phase space (Yoshida's theorem says nothing of
integrals on a level set), for integrals (not invariant relations); the analysis is
decided, under the search's weights, with at least one balance. With free or generic
parameters both halves hold for generic values, and so does the statement. For a
family, the search's special sets are set beside the exponents' special sets: which are
consistent with integer exponents, and what holds for generic members.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..model import ExponentResult, Search
from .exponent_statement import ARS, YOSHIDA


def every_degree(search: Search, exponents: ExponentResult | None) -> str:
    """The statement at every degree of a search with the analysis under its weights
    (module doc); a sentence saying why nothing is combined where a hypothesis fails."""
    why = _not_combined(search, exponents)
    if why:
        return f"Nothing is stated beyond degree {search.options.degree}: {why}."
    assert exponents is not None  # _not_combined said so
    d = exponents.document
    K = search.options.degree
    degrees = [int(k) for k in d["degrees"]]
    beyond = [k for k in degrees if k > K]
    generic = _generic(search, d)
    if not degrees:
        text = f"{YOSHIDA}: no balance has a positive integer exponent{generic}, so every " + (
            "weighted-homogeneous first integral has a gradient that vanishes at every balance"
            if d["homogeneous"]
            else "polynomial first integral's leading weighted-homogeneous part has a "
            "gradient that vanishes at every balance of the leading part"
        )
    elif beyond:
        shown = ", ".join(map(str, beyond))
        which = (
            f"integrals of degree {shown} with a gradient not zero at some balance"
            if d["homogeneous"]
            else f"integrals whose leading weighted-homogeneous part has degree {shown} and a "
            "gradient not zero at some balance of the leading part"
        )
        text = (
            f"{YOSHIDA} allows the degrees {', '.join(map(str, degrees))}{generic}; the "
            f"complete search reached {K}, so {which} are not excluded: a complete search "
            f"to degree {max(degrees)} would cover every degree Yoshida allows"
        )
    elif d["homogeneous"]:
        text = (
            f"{YOSHIDA} allows only the degrees {', '.join(map(str, degrees))}, all within "
            f"the complete search to degree {K}{generic}: every polynomial first integral, "
            "of any degree, is the sum of one the search determined and of "
            "weighted-homogeneous integrals whose gradients vanish at every balance"
        )
    else:
        text = (
            f"{YOSHIDA}, applied to the field's leading part, allows only the degrees "
            f"{', '.join(map(str, degrees))}, all within the complete search to degree "
            f"{K}{generic}: every polynomial first integral whose leading "
            "weighted-homogeneous part has a gradient not zero at some balance of the "
            "leading part is one the search determined"
        )
    family = _family(search, d)
    return text + (f"; {family}" if family else "") + "."


def bounded(search: Search, exponents: ExponentResult | None) -> bool:
    """Whether the two halves combine and every degree Yoshida's theorem allows lies
    within the complete search: then the integrals Yoshida's theorem speaks of (module doc:
    a gradient not zero at some balance) are all among those the search determined."""
    if _not_combined(search, exponents):
        return False
    assert exponents is not None
    return all(int(k) <= search.options.degree for k in exponents.document["degrees"])


def _not_combined(search: Search, exponents: ExponentResult | None) -> str:
    """Why the two halves cannot be combined ("" where they can)."""
    o = search.options
    if o.relations:
        return "a search for invariant relations, not for integrals"
    if o.on:
        return (
            "the search is on a level set, and Yoshida's theorem speaks of integrals of the "
            "whole phase space"
        )
    if not search.decided or not search.complete:
        return "the search is not complete"
    if exponents is None:
        return "no Kovalevskaya analysis under the search's weights"
    if not exponents.decided:
        reason = exponents.document.get("reason", "")
        return f"the Kovalevskaya analysis was not decided ({reason})"
    if dict(exponents.options.weights) != dict(o.weights):
        return (
            "the Kovalevskaya analysis used other weights "
            f"({exponents.options.weights_text()}) than the search ({o.weights_text()})"
        )
    if not exponents.document["balances"] and exponents.document.get("all_integer") is None:
        return (
            "the balances of generic values were not found (the family's analysis over "
            "Q(parameters) was not made)"
        )
    if not exponents.document["balances"]:
        return "the leading part has no balance, so Yoshida's theorem says nothing"
    return ""


def _generic(search: Search, d: Mapping[str, Any]) -> str:
    names = list(dict.fromkeys([*search.options.free, *d.get("parameters", ())]))
    return f" (for generic values of {', '.join(names)})" if names else ""


def _family(search: Search, d: Mapping[str, Any]) -> str:
    """A family: the search's special sets beside the exponents' special sets, and what
    the exponents say of generic members."""
    if not search.options.free or "special" not in d:
        return ""
    points = {tuple(s["when"]): s for s in d["special"] if s["when"]}
    everywhere = any(not s["when"] and s["kind"] == "integer" for s in d["special"])
    parts = []
    for s in search.special:
        where = ", ".join(s.when)
        match = points.get(tuple(s.when))
        if match is not None:
            passes = match.get("painleve", {}).get("passes")
            verdict = {
                True: "the ARS test passes",
                False: "the ARS test fails",
                None: "the ARS test not made",
            }[passes]
            parts.append(
                f"where {where} the search finds more integrals and every exponent is "
                f"{_kind(match['kind'])} ({verdict})"
            )
        elif everywhere:
            parts.append(f"where {where} the search finds more integrals (integer exponents)")
        elif _complete(d) and _one_value(s.when, d["free"]):
            parts.append(
                f"where {where} the search finds more integrals, yet not every exponent is "
                "an integer there"
            )
        else:
            parts.append(f"where {where} the search finds more integrals (not compared)")
    if d.get("all_integer") is False:
        parts.insert(
            0, f"generic members have exponents that are not all integers: {ARS} fails for them"
        )
    elif "witness" in d:
        at = ", ".join(f"{p} = {v}" for p, v in d["witness"]["values"].items())
        parts.insert(
            0,
            f"{ARS} fails for generic members (a simple balance at {at} has an exponent that "
            "is not an integer)",
        )
    return "; ".join(parts)


def _one_value(when: Sequence[str], free: Sequence[str]) -> bool:
    """Whether ``when`` fixes the one free parameter to a value (``lam = 2``)."""
    return len(when) == 1 and len(free) == 1 and when[0].split(" = ")[0] == free[0]


def _complete(d: Mapping[str, Any]) -> bool:
    return bool(d.get("complete", {}).get("integer"))


def _kind(kind: str) -> str:
    return {"integer": "an integer", "half-integer": "half an integer"}.get(kind, "rational")


def summary(result: ExponentResult) -> dict[str, Any]:
    """What a search's document says of the analysis it was combined with."""
    d = result.document
    return {
        "weights": dict(result.options.weights),
        "decided": result.decided,
        "homogeneous": d.get("homogeneous"),
        "degrees": list(d.get("degrees", ())),
        "all_integer": d.get("all_integer"),
        "painleve": (d.get("painleve") or {}).get("passes"),
        "statement": result.statement,
    }
