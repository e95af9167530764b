"""Writing a case back as a case file (docs/case-format.md), with its provenance.

A torque correction gives the same case with the corrected torque and the
claim unchanged; a Casimir correction gives the same system with the derived
Casimir as its claim. A special set of an integral search gives the case with
those parameter values and the integrals found there as claims. Every such file
loads with ``registry add``.
"""

from __future__ import annotations

import hashlib
import re
import tomllib

import sympy as sp
import tomli_w

from ..model import Case, Correction, IntegralSet, SearchOptions
from . import forms
from .parser import parse_equation
from .printer import to_text


def corrected_case_text(case: Case, correction: Correction, run: int | None = None) -> str:
    """The TOML text of ``case`` corrected by ``correction``."""
    data = tomllib.loads(case.text)
    label = correction.claim or "C"
    provenance = (
        f"Derived by the registry audit{'' if run is None else f' (run {run})'} from case "
        f"{case.id!r}, claim {label!r}: {correction.method}. Re-checked: "
        + ", ".join(f"{k} {v}" for k, v in correction.checks.items())
        + "."
    )
    if correction.kind == "torque":
        data["id"] = f"{case.id}-corrected-torque"
        data["title"] = f"{case.title} (corrected torque under which {label} is a Casimir)"
        data.setdefault("system", {})["torque"] = list(correction.torque or ())
    elif correction.kind == "casimir":
        data["id"] = f"{case.id}-corrected-casimir"
        data["title"] = f"{case.title} (corrected Casimir for the same torque)"
        data["claims"] = [
            {
                "label": f"{label}-corrected" if correction.claim else label,
                "kind": "casimir",
                "expression": correction.expression,
            }
        ]
    else:
        raise ValueError(f"cannot export a correction of kind {correction.kind!r}")
    original = data.get("notes", "")
    data["notes"] = provenance + (f"\n\nNotes of the original case: {original}" if original else "")
    return tomli_w.dumps(data)


#: Longest readable part of a derived case's id (beyond it a digest keeps ids distinct).
MAX_SLUG = 60


def derived_case_text(case: Case, found: IntegralSet, options: SearchOptions) -> str:
    """The TOML text of the case that a search's special set defines: ``case`` with the
    parameter values of ``found.when`` substituted (those parameters no longer
    declared) and its integrals as claims, provenance ``discovered``, on the search's
    level set. ``registry audit`` then decides them like any literature claim."""
    ns = forms.namespace(case)
    values = {}
    for equation in found.when:
        if options.relations and equation.split("=")[0].strip() not in case.parameters:
            continue  # a value of the cofactor's coefficients, not of the case's parameters
        lhs, rhs = parse_equation(equation, ns)
        values[lhs] = rhs

    def put(expr) -> str:
        return to_text(sp.sympify(expr).xreplace(values))

    data = tomllib.loads(case.text)
    data["id"] = derived_id(case.id, found.when)
    data["title"] = f"{case.title}, where {', '.join(found.when)}"
    data.pop("aliases", None)
    system = data.setdefault("system", {})
    if case.system.hamiltonian is not None:
        system["hamiltonian"] = put(case.system.hamiltonian.expr)
    else:
        system["inertia"] = [put(e) for e in case.system.inertia_exprs]
        system["potential"] = put(case.system.potential.expr)
    system["torque"] = [put(e) for e in case.system.torque_exprs]
    if "kappa" in system:
        system["kappa"] = put(case.system.kappa_expr)
    names = {str(p) for p in values}
    data["parameters"] = {k: v for k, v in data.get("parameters", {}).items() if k not in names}
    if not data["parameters"]:
        del data["parameters"]
    ansatz = f"weighted degree <= {options.degree}, weights {options.weights_text()}" + (
        f", on {', '.join(e.text for e in options.on)}" if options.on else ""
    )
    data["claims"] = [
        {
            "label": f"F{i + 1}",
            "kind": "integral",
            "expression": text,
            **(
                {"on": [forms.equation_with_values(e, values).text for e in options.on]}
                if options.on
                else {}
            ),
            **({"on": [f"{text} = 0"]} if options.relations else {}),
            "provenance": "discovered",
            "notes": f"Found by registry discover ({ansatz}) on case {case.id!r}"
            + (
                f": an invariant relation, dF/dt = ({found.cofactor}) F."
                if options.relations
                else "."
            ),
        }
        for i, text in enumerate(found.integrals)
    ]
    original = data.get("notes", "")
    data["notes"] = (
        f"Derived by registry discover from case {case.id!r}: the parameter values "
        f"{', '.join(found.when)}, where the search found {found.extra} extra integral(s) "
        f"({ansatz})." + (f"\n\nNotes of the original case: {original}" if original else "")
    )
    return tomli_w.dumps(data)


def derived_id(case_id: str, when: tuple[str, ...]) -> str:
    """A readable, stable id for the case of a special set: the searched case's id and
    the equations, lowercased, with anything but letters, digits and '.' as '-'."""
    slug = re.sub(r"[^a-z0-9.]+", "-", " ".join(when).lower()).strip("-")
    if len(slug) > MAX_SLUG:
        digest = hashlib.sha256(" ".join(when).encode()).hexdigest()[:8]
        slug = f"{slug[:MAX_SLUG].rstrip('-')}-{digest}"
    return f"{case_id}-where-{slug}"
