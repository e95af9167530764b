"""The forms a case file may give its system in, turned into one ``Dynamics``.

This is the only module that knows which form a case used (docs/case-format.md): the
reference paper's moments of inertia, potential and torque; a Hamiltonian with the
bracket parameter kappa. Everything else reads the ``Dynamics`` it builds (the state,
the vector field, the bracket and Hamiltonian where there are some) and asks what the
system has, never how it was written; ``tests/test_layers.py`` checks that no module
outside the case language reads the form's fields.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import replace
from functools import partial

import sympy as sp

from ..dynamics import Dynamics, Given, Vector
from ..mathematics import flow, grading
from ..mathematics import mechanics as mech
from ..model import Assumption, Case, Equation, Expression, System, Weights, as_weights
from .parser import Namespace
from .printer import to_text

Functions = Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]]


def dynamics(system: System, parameters: Mapping[str, sp.Symbol], functions: Functions) -> Dynamics:
    """The ``Dynamics`` of a system in any of the forms a case file may use."""
    if system.variables:
        return _own_state(system, parameters, functions)
    return _paper_state(system, parameters, functions)


def _paper_state(
    system: System, parameters: Mapping[str, sp.Symbol], functions: Functions
) -> Dynamics:
    """The reference paper's state (M, gamma): its equations (2.2) with Pi_mu, or a
    Hamiltonian's Pi grad H, on the bracket deformed by kappa."""
    mu = system.torque_exprs
    kappa = sp.sympify(system.kappa.expr)
    pi = sp.ImmutableMatrix(mech.poisson_tensor(mu, kappa))
    if system.hamiltonian is not None:
        h = system.hamiltonian.expr
        field = flow.hamiltonian_field(pi, h, mech.STATE, mech.SHORTHANDS)
        energy: tuple[Given, ...] = (_given("H", "Hamiltonian H", "H", system.hamiltonian),)
        nonzero: tuple[sp.Expr, ...] = ()
        defining = h
        graded = partial(_field_grading, tuple(field))
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
        graded = partial(_potential_grading, system.potential.expr)
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
        given=(*energy, *torque, *deformed, *_definitions(system)),
        graded=graded,
    )


def _own_state(
    system: System, parameters: Mapping[str, sp.Symbol], functions: Functions
) -> Dynamics:
    """A system on a state of its own: its equations as given, or the bracket given entry
    by entry (antisymmetry filling in the rest) with dx/dt = {x, H} = (Pi grad H)_x."""
    symbols = tuple(sp.Symbol(name, real=True) for name in system.variables)
    position = {name: i for i, name in enumerate(system.variables)}
    pi: sp.ImmutableMatrix | None = None
    h = None if system.hamiltonian is None else system.hamiltonian.expr
    if system.equations:
        field = tuple(e.expr for e in system.equations)
        given = tuple(
            Given(
                f"d({x})/dt",
                f"d{x}/dt",
                sp.Derivative(sp.Function(x)(sp.Symbol("t")), sp.Symbol("t")),
                e.expr,
                e.text,
            )
            for x, e in zip(system.variables, system.equations, strict=True)
        )
    else:
        n = len(symbols)
        matrix = sp.zeros(n, n)
        for x, y, value in system.bracket:
            matrix[position[x], position[y]] = value.expr
            matrix[position[y], position[x]] = -value.expr
        pi = sp.ImmutableMatrix(matrix)
        assert system.hamiltonian is not None  # the reader requires it with a bracket
        field = flow.hamiltonian_field(pi, h, symbols)
        given = (_given("H", "Hamiltonian H", "H", system.hamiltonian),) + tuple(
            Given(
                f"{{{x}, {y}}}", f"bracket {{{x}, {y}}}", sp.Symbol(f"{{{x}, {y}}}"), v.expr, v.text
            )
            for x, y, v in system.bracket
        )
    vectors = _vectors(system.variables, symbols)
    graded = grading.homogeneous_weights(field, vectors, {}, symbols)
    if graded is not None:
        weight = dict(graded)
        vectors = tuple(replace(v, weight=weight[v.name]) for v in vectors)
    defined = (*field, *([] if h is None else [h]))
    if pi is not None:
        defined += tuple(pi)
    return Dynamics(
        variables=symbols,
        vectors=vectors,
        field=tuple(field),
        hamiltonian=h,
        bracket=pi,
        from_bracket=pi is not None,
        parameters=tuple(parameters.values()),
        functions=functions,
        defined=defined,
        given=(*given, *_definitions(system)),
    )


def _vectors(names: Sequence[str], symbols: Sequence[sp.Symbol]) -> tuple[Vector, ...]:
    """The state grouped into vectors: a stem with components 1, 2, 3 listed together
    (``alpha1 alpha2 alpha3``) is the vector ``alpha`` (drawn on a sphere of rational
    radius at sample points), any other variable a vector of its own."""
    by_name = dict(zip(names, symbols, strict=True))
    out: list[Vector] = []
    taken: set[str] = set()
    for name in names:
        if name in taken:
            continue
        found = re.fullmatch(r"(.*?)[123]", name)
        stem = found.group(1) if found else ""
        parts = [f"{stem}{k}" for k in "123"] if stem else []
        if parts and all(p in by_name for p in parts) and not taken & set(parts):
            out.append(Vector(stem, tuple(by_name[p] for p in parts), rational_norm=True))
            taken.update(parts)
        else:
            out.append(Vector(name, (by_name[name],)))
            taken.add(name)
    # the state's order is the variables' order: a vector's components are listed together
    return tuple(out)


def _definitions(system: System) -> tuple[Given, ...]:
    """The definitions of a case, as parts of its system to show."""
    return tuple(
        Given(name, f"definition {name}", sp.Symbol(name), e.expr, e.text)
        for name, e in system.definitions
    )


def _field_grading(field: tuple[sp.Expr, ...]) -> Weights:
    """The first of the paper state's gradings that makes a Hamiltonian's field homogeneous,
    else M: 1, gamma: 1 (the weights of its quadratic part)."""
    return grading.homogeneous_weights(field) or as_weights((1, 1))


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

    # values with denominators (a component's rational parametrisation) leave fractions
    # that cancel: a moment 1 + a**2 c**2 at a = 2w/(w**2 + 1), c = (w**2 + 1)/4 is
    # 1 + w**2/4, so that the system reads (and is identified) as what it is
    fractions = any(sp.denom(sp.together(v)).free_symbols for v in values.values())

    def put(e: Expression) -> Expression:
        new = sp.sympify(e.expr).xreplace(values)
        if new.has(sp.zoo, sp.nan, sp.oo):
            raise Undefined
        if fractions and new.free_symbols:
            new = sp.cancel(new)
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
            # a state of its own: its equations, or its bracket (with the Hamiltonian)
            equations=tuple(put(e) for e in system.equations),
            bracket=tuple((x, y, put(v)) for x, y, v in system.bracket),
            definitions=tuple((name, put(e)) for name, e in system.definitions),
        )
    except Undefined:  # a value where a denominator vanishes
        return None
    kept = {n: s for n, s in case.parameters.items() if s not in values}
    # a parameter the values bring in (a component's parametrisation) is a real one
    brought = set().union(*(v.free_symbols for v in values.values())) - set(kept.values())
    kept.update({str(s): s for s in sorted(brought, key=str)})
    return replace(
        case,
        system=system,
        claims=(),
        parameters=kept,
        assumptions={n: a for n, a in case.assumptions.items() if n in kept}
        | {str(s): Assumption.REAL for s in brought},
        dynamics=dynamics(system, kept, case.functions),
    )


def equation_with_values(equation: Equation, values: Mapping[sp.Symbol, sp.Expr]) -> Equation:
    """A level-set equation at these parameter values (``k1 = 0`` in ``s + k1 gamma1 =
    0``): what a claim of the case at those values is restricted to."""
    if not values:
        return equation
    lhs, rhs = equation.lhs.xreplace(values), equation.rhs.xreplace(values)
    return Equation(f"{to_text(lhs)} = {to_text(rhs)}", lhs, rhs)


def with_system(case: Case, system: System) -> Case:
    """The same case with another system (its dynamics built again)."""
    return replace(case, system=system, dynamics=dynamics(system, case.parameters, case.functions))


def with_torque(case: Case, torque: tuple[Expression, Expression, Expression]) -> Case:
    """The same case with another gyroscopic torque (a corrected one)."""
    return with_system(case, replace(case.system, torque=torque))


def columns(system: System) -> dict:
    """The system's fields as the store keeps them in its columns, as written; ``form``
    holds those of a system on its own state (and definitions), None for the paper's."""
    own = {
        "variables": list(system.variables),
        "equations": {x: e.text for x, e in zip(system.variables, system.equations, strict=False)},
        "bracket": {f"{x}, {y}": v.text for x, y, v in system.bracket},
        "definitions": {name: e.text for name, e in system.definitions},
    }
    return {
        "inertia": [e.text for e in system.inertia],
        "potential": system.potential.text,
        "torque": [e.text for e in system.torque],
        "hamiltonian": system.hamiltonian.text if system.hamiltonian else None,
        "kappa": system.kappa.text,
        "form": {k: v for k, v in own.items() if v} or None,
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
    form = found["form"] or {}
    texts.update({f"equations.{x}": t for x, t in form.get("equations", {}).items()})
    texts.update({f"bracket.{k}": t for k, t in form.get("bracket", {}).items()})
    texts.update({f"definitions.{k}": t for k, t in form.get("definitions", {}).items()})
    return texts


def namespace(case: Case) -> Namespace:
    """The names an expression of ``case`` may use (its parameters, functions, and for a
    system on its own state its variables and definitions): the namespace in which a
    level set, a residual or a correction stored as text is parsed again."""
    system = case.system
    variables = (
        {name: sp.Symbol(name, real=True) for name in system.variables}
        if system.variables
        else None
    )
    parts: dict[str, int] = {}
    definitions: dict[str, tuple[sp.Expr, int]] = {}
    for name, value in system.definitions:
        own = len(re.findall(r"[\w.]+|\*\*|[-+*/]", value.text))
        used = sum(parts[n] for n in re.findall(r"[A-Za-z_]\w*", value.text) if n in parts)
        parts[name] = own + used
        definitions[name] = (value.expr, parts[name])
    return Namespace(case.parameters, case.functions, variables, definitions)
