"""Writing a corrected case back as a case file (CASE_FORMAT.md), with its provenance.

A torque correction gives the same case with the repaired torque and the
claim unchanged; a Casimir correction gives the same system with the derived
Casimir as its claim. Either file loads with ``registry add``.
"""

from __future__ import annotations

import tomllib

import tomli_w

from ..model import Case, Correction


def corrected_case_text(case: Case, correction: Correction, run: int | None = None) -> str:
    """The TOML text of ``case`` repaired by ``correction``."""
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
