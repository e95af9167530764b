"""The forms a case file may give its system in, turned into one ``Dynamics``.

This is the only module that knows which form a case used (docs/case-format.md): the
reference paper's moments of inertia, potential and torque; a Hamiltonian with the
bracket parameter kappa. Everything else reads the ``Dynamics`` it builds (the state,
the vector field, the bracket and Hamiltonian where there are some) and asks what the
system has, never how it was written; ``tests/test_layers.py`` checks that no module
outside the case language reads the form's fields.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import sympy as sp

from ..dynamics import Dynamics, Given
from ..mathematics import flow, grading
from ..mathematics import mechanics as mech
from ..model import Case, Expression, System, Weights, as_weights
from .printer import to_text

Functions = Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]]


def dynamics(system: System, parameters: Mapping[str, sp.Symbol], functions: Functions) -> Dynamics:
    """The ``Dynamics`` of a system in any of the forms a case file may use."""
    mu = system.torque_exprs
    kappa = sp.sympify(system.kappa.expr)
    pi = sp.ImmutableMatrix(mech.poisson_tensor(mu, kappa))
    if system.hamiltonian is not None:
        h = system.hamiltonian.expr
        field = flow.hamiltonian_field(pi, h, mech.STATE, mech.SHORTHANDS)
        energy: tuple[Given, ...] = (_given("H", "Hamiltonian H", "H", system.hamiltonian),)
        nonzero: tuple[sp.Expr, ...] = ()
        defining = h
        graded = grading.homogeneous_weights(field) or as_weights((1, 1))
    else:
        inertia = system.inertia_exprs
        h = mech.hamiltonian(inertia, system.potential.expr)
        field = mech.vector_field(inertia, system.potential.expr, mu, kappa)
        energy = (
            *(_given(n, f"moment {n}", n, e) for n, e in zip("ABC", system.inertia, strict=True)),
            _given("U", "potential U", "U", system.potential),
        )
        nonzero = tuple(inertia)
        defining = system.potential.expr
        graded = _potential_grading(system.potential.expr)
    torque = tuple(
        _given(f"mu{k}", f"torque μ{k}", f"mu_{k}", e) for k, e in enumerate(system.torque, start=1)
    )
    deformed = (_given("kappa", "bracket κ", "kappa", system.kappa),) if kappa != 0 else ()
    if kappa == 0:
        casimirs: tuple[sp.Expr, ...] = (2 * mech.C1,)
    else:
        casimirs = (2 * mech.casimir_c1(kappa), mech.S_VALUE)
    return Dynamics(
        variables=mech.STATE,
        vectors=mech.VECTORS,
        field=tuple(field),
        hamiltonian=h,
        bracket=pi,
        from_bracket=system.hamiltonian is not None,
        torque=system.torque,
        kappa=system.kappa,
        c1=mech.casimir_c1(kappa),
        casimirs=tuple((to_text(sp.expand(c)), c) for c in casimirs),
        shorthands=mech.SHORTHANDS,
        parameters=tuple(parameters.values()),
        functions=functions,
        nonzero=nonzero,
        defined=(defining, *mu, *([kappa] if kappa != 0 else [])),
        given=(*energy, *torque, *deformed),
        grading=graded,
    )


def _potential_grading(potential: sp.Expr) -> Weights:
    """M: 1, gamma: 1 where the potential has terms of degree >= 2 in gamma (which make H
    homogeneous there), else M: 1, gamma: 2."""
    gamma_only = {**{m: 0 for m in mech.MOMENTUM}, **{g: 1 for g in mech.AXIS}}
    degree = grading.ring_degree(potential, gamma_only) or 0
    return as_weights((1, 1) if degree >= 2 else (1, 2))


def _given(name: str, label: str, symbol: str, value: Expression) -> Given:
    """A part named like an identifier, shown with ``label``, typeset as the sympy symbol
    ``symbol``."""
    return Given(name, label, sp.Symbol(symbol), value.expr, value.text)


class Undefined(Exception):
    """A parameter value where an expression of the case is undefined."""


def with_values(case: Case, values: Mapping[sp.Symbol, sp.Expr]) -> Case | None:
    """The case with these parameter values (its claims dropped), or None where it is not
    defined: an assumption broken (a positive parameter not positive, ...), a moment of
    inertia zero or undefined, an expression of the system undefined."""
    values = {p: sp.sympify(v) for p, v in values.items()}
    for p, v in values.items():
        if v.is_number and (
            (p.is_positive and not v > 0)
            or (p.is_nonzero and v == 0)
            or (p.is_integer and not v.is_integer)
        ):
            return None

    def put(e: Expression) -> Expression:
        new = sp.sympify(e.expr).xreplace(values)
        if new.has(sp.zoo, sp.nan, sp.oo):
            raise Undefined
        return Expression(to_text(new), new)

    system = case.system
    try:
        inertia = tuple(put(e) for e in system.inertia)  # none in the Hamiltonian form
        if any(sp.simplify(e.expr) == 0 for e in inertia):
            return None
        given = system.hamiltonian
        system = replace(
            system,
            inertia=inertia,
            potential=put(system.potential),
            torque=(put(system.torque[0]), put(system.torque[1]), put(system.torque[2])),
            hamiltonian=None if given is None else put(given),
            kappa=put(system.kappa),
        )
    except Undefined:  # a value where a denominator vanishes
        return None
    kept = {n: s for n, s in case.parameters.items() if s not in values}
    return replace(
        case,
        system=system,
        claims=(),
        parameters=kept,
        assumptions={n: a for n, a in case.assumptions.items() if n in kept},
        dynamics=dynamics(system, kept, case.functions),
    )


def with_system(case: Case, system: System) -> Case:
    """The same case with another system (its dynamics built again)."""
    return replace(case, system=system, dynamics=dynamics(system, case.parameters, case.functions))


def with_torque(case: Case, torque: tuple[Expression, Expression, Expression]) -> Case:
    """The same case with another gyroscopic torque (a corrected one)."""
    return with_system(case, replace(case.system, torque=torque))


def columns(system: System) -> dict:
    """The system's fields as the store keeps them in its columns, as written."""
    return {
        "inertia": [e.text for e in system.inertia],
        "potential": system.potential.text,
        "torque": [e.text for e in system.torque],
        "hamiltonian": system.hamiltonian.text if system.hamiltonian else None,
        "kappa": system.kappa.text,
    }


def stored_texts(system: System) -> dict[str, str]:
    """Every expression of the system by the place ``registry verify-db`` names it in
    (``torque[0]``, ``hamiltonian``), as written."""
    found = columns(system)
    texts = {"potential": found["potential"]}
    texts.update({f"torque[{i}]": t for i, t in enumerate(found["torque"])})
    texts.update({f"inertia[{i}]": t for i, t in enumerate(found["inertia"])})
    if found["hamiltonian"] is not None:
        texts["hamiltonian"] = found["hamiltonian"]
    texts["kappa"] = found["kappa"]
    return texts
