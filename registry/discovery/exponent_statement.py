"""What a Kovalevskaya analysis proves, in words: each statement exactly as strong as the
theorem it cites, with the theorem named and its hypotheses stated.

* Yoshida (Celestial Mech. 31 (1983) 363): if I is a weighted-homogeneous first integral
  of weighted degree k >= 1 of a weighted-homogeneous field and grad I(c) != 0 at a
  balance c, then k is an exponent of c. For a field that is not homogeneous, the
  leading weighted-homogeneous part of a polynomial integral is an integral of the
  field's leading part, and the theorem applies to it there.
* Yoshida (1983): n - 1 weighted-homogeneous algebraic integrals whose gradients are
  independent at a balance make every exponent of that balance rational.
* Ablowitz, Ramani and Segur (J. Math. Phys. 21 (1980) 715): the Painlevé test needs
  every exponent to be an integer and every compatibility condition to hold; a failing
  condition forces a logarithmic term (movable logarithmic branch points). Passing the
  test is necessary for the Painlevé property, never a proof of it.

The texts are written from the analysis's document (plain data), so that a stored
analysis says the same as a fresh one.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

YOSHIDA = "Yoshida (Celestial Mech. 31 (1983) 363)"
ARS = "the ARS test (Ablowitz, Ramani and Segur, J. Math. Phys. 21 (1980) 715)"
#: The most special sets of one kind a statement names; the others are counted (a grid
#: searched over several parameters can hold hundreds, all in the document's list).
NAMED = 6


def statement(document: Mapping[str, Any], weights: str, generic: Sequence[str] = ()) -> str:
    """The statement of one analysis (module doc): the scope (the whole field or its
    leading part, generic parameter values), Yoshida's degrees, what irrational exponents
    exclude, and the Painlevé test."""
    homogeneous = bool(document["homogeneous"])
    balances = document["balances"]
    where = f" for generic values of {', '.join(generic)}" if generic else ""
    scope = _scope(homogeneous, weights)
    if document.get("denominators"):
        scope += (
            f"; it divides by {', '.join(document['denominators'])}, and its balances are "
            "those where none of these vanishes (solutions along which one does are not "
            "covered)"
        )
    if not balances:
        return (
            f"{scope}. Its leading part has no balance (no solution x = c t^(-w)): "
            "Kovalevskaya's exponents, Yoshida's theorem and the Painlevé test say nothing here."
        )
    parts = [f"{scope}; {len(balances)} balance(s){where}"]
    parts.append(_yoshida(document, homogeneous))
    if not document["all_rational"]:
        whose = "the field" if homogeneous else "the leading part"
        k = _dimension(document) - 1
        parts.append(
            f"{YOSHIDA}: {k} (the dimension less one) weighted-homogeneous algebraic first "
            "integrals whose gradients are independent at a balance make every exponent of "
            "that balance rational; a balance here has an irrational or complex exponent, "
            f"so {whose} has no {k} such integrals independent there"
        )
    parts.append(_painleve(document))
    return "; ".join(parts) + "."


def _scope(homogeneous: bool, weights: str) -> str:
    """Whether the balances and exponents are the field's or its leading part's."""
    if homogeneous:
        return f"The field is weighted-homogeneous under weights {weights}"
    return (
        f"The field is not weighted-homogeneous under weights {weights}: its balances and "
        "exponents are those of its leading part (the terms of the highest shift), the "
        "lower terms entering only the Painlevé test's series"
    )


def _yoshida(document: Mapping[str, Any], homogeneous: bool) -> str:
    degrees = document["degrees"]
    if homogeneous:
        theorem = (
            f"{YOSHIDA}: a weighted-homogeneous first integral of weighted degree k >= 1 "
            "whose gradient is not zero at a balance has k among that balance's exponents"
        )
    else:
        theorem = (
            f"{YOSHIDA}, applied to the leading part: the leading weighted-homogeneous part "
            "of a polynomial first integral is a first integral of the leading part, and "
            "where its gradient is not zero at a balance, its weighted degree k is among "
            "that balance's exponents"
        )
    if degrees:
        return f"{theorem}: the degrees some balance allows are {', '.join(map(str, degrees))}"
    return (
        f"{theorem}: no balance has a positive integer exponent, so every such integral "
        "has a gradient that vanishes at every balance"
    )


def _painleve(document: Mapping[str, Any]) -> str:
    painleve = document["painleve"]
    if not document["all_integer"]:
        return f"{ARS} needs every exponent to be an integer: it fails"
    failing = painleve["conditions"]
    if failing:
        return f"{ARS}: {_obstruction(failing[0])}"
    if painleve["passes"]:
        return (
            f"{ARS} passes (integer exponents, every compatibility condition holds): "
            "necessary for the Painlevé property, not a proof of it"
        )
    return f"{ARS} was not run"


def witness_statement(
    witness: Mapping[str, Any],
    weights: str,
    generic: Sequence[str],
    homogeneous: bool,
    divided: bool = False,
) -> str:
    """The statement of an analysis over Q(parameters) that ran out of time, where one
    exact analysis at rational values found a simple balance with an exponent that is
    not an integer (``mathematics.exponent_witness``): the test fails for generic values,
    and nothing else is stated."""
    return (
        f"{_scope(homogeneous, weights)}. {_witnessed(witness, generic, divided)}. The "
        "balances of generic values were not all found within the budget, so nothing else "
        "is established: not their exponents, nor the degrees Yoshida's theorem allows."
    )


def _witnessed(witness: Mapping[str, Any], generic: Sequence[str], divided: bool) -> str:
    """That the test fails for generic values of ``generic``, by the witness, and why."""
    at = ", ".join(f"{p} = {v}" for p, v in witness["values"].items())
    exact = ", ".join(witness["rational"])
    n = witness["not_rational"]
    if not n:
        shown = f"the exponents {exact}"
    elif exact:
        shown = f"the exponents {exact} and {n} that are not rational (in the witness)"
    else:
        shown = f"{n} exponents, none rational (in the witness)"
    jacobian = (
        "the Kovalevskaya matrix times the field's denominators"
        if divided
        else "the Kovalevskaya matrix"
    )
    return (
        f"{ARS[0].upper()}{ARS[1:]} fails for generic values "
        f"of {', '.join(generic)}: at {at}, a balance has {shown}, not all integers, and "
        "none of them is 0, so the balance is a simple root of the balance equations (their "
        f"Jacobian is {jacobian}); it continues to a balance at every nearby value, with "
        "an exponent that stays off the integers there, and, the balances being algebraic "
        "in the parameters, at every value outside a set of measure zero some balance has "
        "an exponent that is not an integer"
    )


def family_statement(document: Mapping[str, Any], weights: str) -> str:
    """The statement of a family's analysis: what holds for generic values of the free
    parameters, the sets where every exponent is an integer, half an integer, rational
    (each with its Painlevé test), and whether the lists are complete ("exactly" only
    where they are; "at least" otherwise)."""
    free = ", ".join(document["free"])
    parts = [f"Kovalevskaya exponents of the family in {free} under weights {weights}"]
    if document["homogeneous"] is False:  # None: the generic analysis was not made
        parts[0] = f"{_scope(False, weights)}. {parts[0]}"
    special = document["special"]
    complete = document["complete"]
    everywhere = [s for s in special if s["kind"] == "integer" and _every_value(s)]
    if everywhere:
        parts.append(f"every exponent of every balance is an integer for every value of {free}")
        parts.append(_painleve_everywhere(document, special, complete["integer"]))
    elif document["balances"]:
        parts.append(_generic(document))
    else:
        parts.append("the generic analysis was not made (see the coverage)")
    kinds = (
        ("integer", "an integer", complete["integer"]),
        ("half-integer", "half an integer (not all integers)", complete["half_integer"]),
        ("rational", "rational (among rational parameter values)", complete["rational"]),
    )
    for kind, label, flag in kinds:
        if everywhere and kind != "half-integer":
            continue
        sets = [s for s in special if s["kind"] == kind]
        if not sets:
            if flag:
                parts.append(f"no value makes every exponent of every balance {label}")
            continue
        how = "exactly" if flag else "at least"
        listed = "; ".join(_special_text(s) for s in sets[:NAMED])
        if len(sets) > NAMED:
            listed += f"; and {len(sets) - NAMED} more (each in the list of special sets)"
        parts.append(f"every exponent of every balance is {label} {how} at: {listed}")
    if not all(complete.values()):
        parts.append("not complete: " + "; ".join(document["coverage"]))
    if "painleve_sets" in document:
        parts.append(_painleve_sets(document["painleve_sets"]))
    if "half_integer_sets" in document:
        parts.append(_half_integer_sets(document["half_integer_sets"]))
    text = "; ".join(parts) + "."
    if "witness" in document:  # the generic members' test, which the sets left unknown
        divided = bool(document.get("denominators"))
        text += f" {_witnessed(document['witness'], document['free'], divided)}."
    return text


def _painleve_sets(found: Mapping[str, Any]) -> str:
    """Where the ARS test passes with several free parameters (``painleve_strata``), and
    whether the list is complete."""
    listed = _listed(found["passing"])
    text = (
        f"{ARS} passes for the generic members of: {listed}"
        if listed
        else f"{ARS} passes on no set that was analysed"
    )
    if found["complete"]:
        return (
            f"{text}; at every admissible real value outside these sets it fails (the "
            "stratification by the conditions of the balances with constant integer "
            "exponents was completed)"
        )
    return f"{text}; {_not_complete(found)}"


def _half_integer_sets(found: Mapping[str, Any]) -> str:
    """Where every exponent is in (1/2)Z with several free parameters
    (``half_integer_strata``), those with some exponent not an integer named apart, and
    whether the list is complete."""
    sets = found["sets"]
    if not sets:
        text = "no set that was analysed has every exponent in (1/2)Z"
    else:
        head = "every exponent of every balance is in (1/2)Z for the generic members of: "
        text = head + _listed(sets)
        half = [s for s in sets if s["kind"] == "half-integer"]
        if half:
            text += f" (some exponent half an odd integer on: {_listed(half)})"
    if found["complete"]:
        return (
            f"{text}; at every admissible real value outside these sets some exponent is "
            "not in (1/2)Z"
        )
    return f"{text}; {_not_complete(found)}"


def _listed(sets: Sequence[Mapping[str, Any]]) -> str:
    """A stratification's sets: each its equations and the parameters left free on it."""
    return "; ".join(
        (", ".join(s["when"]) or "every value")
        + (f" ({', '.join(s['free'])} free)" if s["free"] else "")
        for s in sets
    )


def _not_complete(found: Mapping[str, Any]) -> str:
    return f"not complete: {len(found['undecided'])} set(s) were not decided"


def _generic(document: Mapping[str, Any]) -> str:
    """What the exponents are for generic values of the free parameters."""
    if document["all_integer"]:
        return "for generic values every exponent of every balance is an integer"
    if document["all_rational"]:
        return f"for generic values some exponent is not an integer, so {ARS} fails there"
    k = _dimension(document) - 1
    return (
        f"for generic values some exponent is irrational or complex: {ARS} fails there, and "
        f"by {YOSHIDA} the leading part has no {k} (the dimension less one) "
        "weighted-homogeneous algebraic integrals independent at that balance"
    )


def _painleve_everywhere(
    document: Mapping[str, Any], special: Sequence[Mapping[str, Any]], complete: bool
) -> str:
    """The Painlevé test of a family whose exponents are integers for every value: for
    generic values, and the values where its failing conditions hold."""
    failing = document["painleve"]["conditions"]
    if document["painleve"]["passes"] is None:
        return f"{ARS} was not run for generic values"
    if not failing:
        return f"{ARS} passes for generic values (necessary for the Painlevé property, not a proof)"
    passing = [
        ", ".join(s["when"])
        for s in special
        if s["kind"] == "integer" and not _every_value(s) and s.get("painleve", {}).get("passes")
    ]
    fails = f"for generic values {_obstruction(failing[0])}"
    if not passing:
        return f"{fails}; {ARS} passes at no value found"
    how = "exactly" if complete else "at least"
    return f"{fails}; {ARS} passes {how} at: {'; '.join(passing)}"


def _obstruction(first: Mapping[str, Any]) -> str:
    """What fails first, and what follows from it: a compatibility condition or a free
    coefficient missing at a resonance r > 0 (a logarithmic term, so no Painlevé
    property), or a free leading coefficient missing at the exponent 0 (the general
    solution is not a Laurent series about that balance: the test fails)."""
    where = f"balance {first['balance']}, resonance {first['resonance']}"
    if first["missing"] and first["resonance"] == 0:
        return (
            f"at balance {first['balance']} the exponent 0 is more frequent than the "
            f"dimensions of the family of balances there ({first['missing']} free leading "
            "coefficient(s) missing), so the general solution is not a Laurent series "
            "about that balance and the test fails"
        )
    if first["missing"]:
        what = f"{first['missing']} free coefficient(s) missing ({where})"
    else:
        what = f"a compatibility condition fails ({where}: {first['condition']})"
    return (
        f"{what}, so the Laurent series needs a logarithmic term: the general solution "
        "has movable logarithmic branch points and the field does not have the Painlevé "
        "property"
    )


def _every_value(entry: Mapping[str, Any]) -> bool:
    return not entry["when"] and "index" in entry


def _dimension(document: Mapping[str, Any]) -> int:
    """The dimension of the state (the number of coordinates of a balance)."""
    return len(document["balances"][0]["point"])


def _special_text(entry: Mapping[str, Any]) -> str:
    when = ", ".join(entry["when"]) or "every value"
    if "index" in entry:
        when += f" ({entry['index']['ranges']})"
        return when
    painleve = entry.get("painleve")
    if painleve is None:
        return f"{when} (not analysed: {'; '.join(entry['notes'])})"
    if entry["kind"] != "integer":
        return when
    verdict = {True: "ARS test passes", False: "ARS test fails", None: "ARS test not made"}[
        painleve["passes"]
    ]
    return f"{when} ({verdict})"
