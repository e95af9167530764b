"""The ``[system]`` table of a case file, in every form the format allows.

* the reference paper's form: ``inertia`` (A, B, C), ``potential`` U(gamma), ``torque``
  mu and the bracket parameter ``kappa``;
* a Hamiltonian: ``hamiltonian`` instead of ``inertia`` and ``potential``;
* a phase space of the case's own: ``variables``, with ``equations`` (dx/dt for each
  variable) or with ``hamiltonian`` and ``bracket`` (the entries {x, y} that are not zero);
* in any form, ``definitions``: names for sub-expressions, expanded in every expression
  of the case, each using only the ones above it.

``SystemReader`` is the part of the case-file reader (``casefile``) that reads this
table: it reports problems through the reader's ``problem`` and parses expressions with
its ``expression``, in the namespace the reader keeps (``ns``).
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import sympy as sp
from sympy.core.function import AppliedUndef

from ..errors import ExpressionError
from ..expression import Expression
from ..mathematics.mechanics import MOMENTUM, STATE, s
from ..model import System
from .limits import MAX_NODES
from .parser import CONSTANTS, FUNCTIONS, parse_expression
from .toml_input import field_name, kind_of, quoted

#: The keys of ``[system]``.
SYSTEM_KEYS = (
    "inertia",
    "potential",
    "torque",
    "hamiltonian",
    "kappa",
    "variables",
    "equations",
    "bracket",
    "definitions",
)
#: The keys of the reference paper's forms, which a system on its own state may not use.
PAPER_KEYS = ("inertia", "potential", "torque", "kappa")
#: Most state variables of a system, and most definitions of a case.
MAX_VARIABLES = 30
MAX_DEFINITIONS = 50
#: An identifier of the expression language, as a definition's text names it.
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ZERO = Expression("0", sp.Integer(0))


def _first_of(expr: sp.Expr, symbols: tuple[sp.Symbol, ...]) -> sp.Symbol | None:
    """The first of ``symbols`` that ``expr`` depends on, or None."""
    free = expr.free_symbols
    return next((x for x in symbols if x in free), None)


def _new_name_problem(name: str, what: str) -> str | None:
    """Why ``name`` cannot name a variable or a definition (``what``), or None."""
    if not (name.isascii() and name.isidentifier()):
        return (
            f"{quoted(name)} is not a valid name "
            "(use ASCII letters, digits and '_', not starting with a digit)"
        )
    if keyword.iskeyword(name):
        return f"{quoted(name)} is a reserved name (a Python keyword)"
    if name in FUNCTIONS or name == "diff":
        return f"{quoted(name)} is a function of the language; a {what} may not take its name"
    if name in CONSTANTS:
        return f"{quoted(name)} is a constant of the language; a {what} may not take its name"
    return None


class SystemReader:
    """The reading of ``[system]`` (module docstring), mixed into the case-file reader."""

    # provided by the case-file reader
    ns: Any
    problem: Callable[..., None]
    expression: Callable[[Any, str], Expression | None]
    table: Callable[[dict, str, str], dict | None]
    check_keys: Callable[[dict, tuple[str, ...], str], None]

    # ----------------------------------------------------------------- the state

    def state_variables(
        self, data: dict, parameters: dict[str, sp.Symbol]
    ) -> dict[str, sp.Symbol] | None:
        """``system.variables``: the case's own state, by name (None: the reference paper's
        M, gamma and s). Read before anything that may use the names."""
        table = data.get("system")
        if not isinstance(table, dict) or "variables" not in table:
            return None
        field = "system.variables"
        value = table["variables"]
        if not isinstance(value, list) or not value:
            found = kind_of(value) if not isinstance(value, list) else "an empty array"
            self.problem(field, f"expected an array of variable names, found {found}")
            return {}
        if len(value) > MAX_VARIABLES:
            self.problem(field, f"too many variables ({len(value)}; at most {MAX_VARIABLES})")
            return {}
        names: dict[str, sp.Symbol] = {}
        for i, name in enumerate(value):
            where = f"{field}[{i}]"
            if not isinstance(name, str):
                self.problem(where, f"expected a string, found {kind_of(name)}")
                continue
            bad = _new_name_problem(name, "variable")
            if bad is None and name in parameters:
                bad = f"{quoted(name)} is declared as a parameter too"
            if bad is None and name in names:
                bad = f"the variable {quoted(name)} is listed twice"
            if bad is not None:
                self.problem(where, bad)
                continue
            names[name] = sp.Symbol(name, real=True)
        return names

    def definitions(self, table: dict) -> tuple[tuple[str, Expression], ...] | None:
        """``system.definitions``: name -> expression, each expanded in every expression
        after it (system and claims), each using only the ones above it."""
        value = table.get("definitions")
        if value is None:
            return ()
        if not isinstance(value, dict):
            self.problem("system.definitions", f"expected a table, found {kind_of(value)}")
            return None
        if len(value) > MAX_DEFINITIONS:
            self.problem(
                "system.definitions",
                f"too many definitions ({len(value)}; at most {MAX_DEFINITIONS})",
            )
            return None
        names = list(value)
        found: list[tuple[str, Expression]] = []
        ok = True
        for i, name in enumerate(names):
            field = field_name("system.definitions", name)
            bad = _new_name_problem(name, "definition")
            if bad is None and (
                name in self.ns.state or name in self.ns.parameters or name in self.ns.functions
            ):
                bad = f"{quoted(name)} is already a variable, a parameter or a function"
            text = value[name]
            if bad is None and isinstance(text, str):
                used = set(_NAME.findall(text))
                if name in used:
                    bad = f"the definition of {quoted(name)} uses itself"
                else:
                    below = [n for n in names[i + 1 :] if n in used]
                    if below:
                        bad = (
                            f"uses {quoted(below[0])}, which is defined below it "
                            "(a definition may use only the ones above it)"
                        )
            if bad is not None:
                self.problem(field, bad, text if isinstance(text, str) else None)
                ok = False
                self._stand_in(name)
                continue
            expr = self.expression(text, field)
            if expr is None:
                ok = False
                self._stand_in(name)
                continue
            found.append((name, expr))
            parts = self._parts(expr.text)
            defined = {**self.ns.definitions, name: (expr.expr, parts)}
            self.ns = replace(self.ns, definitions=defined)
        return tuple(found) if ok else None

    def _stand_in(self, name: str) -> None:
        """A refused definition's name stays known (as a symbol of its own), so that the
        expressions that use it are not reported as using an unknown name as well."""
        if _new_name_problem(name, "definition") is None and name not in (
            *self.ns.state,
            *self.ns.parameters,
            *self.ns.functions,
        ):
            defined = {**self.ns.definitions, name: (sp.Dummy(name), 1)}
            self.ns = replace(self.ns, definitions=defined)

    def _parts(self, text: str) -> int:
        """The parts a definition counts for each time it is used: those of its text and of
        the definitions it uses (so that definitions of definitions are bounded too)."""
        own = len(re.findall(r"[\w.]+|\*\*|[-+*/]", text))
        defined = self.ns.definitions
        used = sum(defined[n][1] for n in _NAME.findall(text) if n in defined)
        return min(own + used, 10 * MAX_NODES)

    # ---------------------------------------------------------------- the system

    def system(self, data: dict) -> System | None:
        """[system] in whichever form it is given (module docstring)."""
        table = self.table(data, "system", "system")
        if table is None:
            if "system" not in data:
                self.problem("system.inertia", "required field is missing")
            return None
        self.check_keys(table, SYSTEM_KEYS, "system")
        definitions = self.definitions(table)
        if "variables" in table:
            system = self.own_state_system(table)
        elif "equations" in table or "bracket" in table:
            key = "equations" if "equations" in table else "bracket"
            self.problem(
                f"system.{key}",
                "needs system.variables: name the state variables the system is written in",
            )
            return None
        elif "hamiltonian" in table:
            system = self.hamiltonian_system(table)
        else:
            system = self.paper_system(table)
        if system is None or definitions is None:
            return None
        return replace(system, definitions=definitions)

    def paper_system(self, table: dict) -> System | None:
        """The reference paper's form: inertia (required), potential, torque, kappa."""
        if "inertia" not in table:
            self.problem("system.inertia", "required field is missing")
            inertia = None
        else:
            inertia = self.triple(table["inertia"], "system.inertia", self.check_moment)
        potential: Expression | None = _ZERO
        if "potential" in table:
            potential = self.expression(table["potential"], "system.potential")
            if potential is not None:
                self.check_potential(potential)
        torque, kappa = self.torque_and_kappa(table)
        if inertia is None or potential is None or torque is None or kappa is None:
            return None
        return System(inertia, potential, torque, kappa=kappa)  # type: ignore[arg-type]

    def torque_and_kappa(
        self, table: dict
    ) -> tuple[tuple[Expression, ...] | None, Expression | None]:
        """``torque`` (default 0, 0, 0) and ``kappa`` (default 0), each None if refused."""
        torque: tuple[Expression, ...] | None = (_ZERO,) * 3
        if "torque" in table:
            torque = self.triple(table["torque"], "system.torque")
        kappa: Expression | None = _ZERO
        if "kappa" in table:
            kappa = self.kappa(table["kappa"])
        return torque, kappa

    def hamiltonian_system(self, table: dict) -> System | None:
        """The Hamiltonian form: H itself, which excludes inertia and potential."""
        hamiltonian = self.expression(table["hamiltonian"], "system.hamiltonian")
        conflict = [key for key in ("inertia", "potential") if key in table]
        if conflict:
            both = " and ".join(f"system.{key}" for key in conflict)
            self.problem(
                "system.hamiltonian",
                f"give either the Hamiltonian or {both}, not both: with system.hamiltonian, "
                "H is the whole energy (inertia and potential are part of it)",
            )
        torque, kappa = self.torque_and_kappa(table)
        if conflict or hamiltonian is None or torque is None or kappa is None:
            return None
        return System((), _ZERO, torque, hamiltonian=hamiltonian, kappa=kappa)  # type: ignore[arg-type]

    def own_state_system(self, table: dict) -> System | None:
        """A system on its own state: ``variables`` with ``equations``, or with
        ``hamiltonian`` and ``bracket``; the paper's keys do not apply."""
        variables = tuple(self.ns.state) if self.ns.variables is not None else ()
        conflict = [key for key in PAPER_KEYS if key in table]
        into = "equations" if "equations" in table else "Hamiltonian"
        for key in conflict:
            self.problem(
                f"system.{key}",
                "a system given by its variables takes no inertia, potential, torque or "
                f"kappa: write them into its {into}",
            )
        given = [key for key in ("equations", "hamiltonian") if key in table]
        if len(given) != 1:
            self.problem(
                "system.variables",
                "give the equations of motion (system.equations) or a Hamiltonian with its "
                "bracket (system.hamiltonian and system.bracket), "
                + ("not both" if given else "one of them"),
            )
            return None
        if not variables or conflict:
            return None
        if given == ["equations"]:
            if "bracket" in table:
                self.problem(
                    "system.bracket",
                    "a bracket goes with system.hamiltonian; system.equations give the field",
                )
                return None
            equations = self.equations(table["equations"], variables)
            if equations is None:
                return None
            return System((), _ZERO, (_ZERO,) * 3, variables=variables, equations=equations)  # type: ignore[arg-type]
        hamiltonian = self.expression(table["hamiltonian"], "system.hamiltonian")
        if "bracket" not in table:
            self.problem("system.bracket", "required with system.variables and system.hamiltonian")
            return None
        bracket = self.bracket(table["bracket"], variables)
        if hamiltonian is None or bracket is None:
            return None
        return System(
            (),
            _ZERO,
            (_ZERO,) * 3,  # type: ignore[arg-type]
            hamiltonian=hamiltonian,
            variables=variables,
            bracket=bracket,
        )

    def equations(self, value: Any, variables: tuple[str, ...]) -> tuple[Expression, ...] | None:
        """``system.equations``: dx/dt for each variable, exactly once (a table)."""
        if not isinstance(value, dict):
            self.problem("system.equations", f"expected a table, found {kind_of(value)}")
            return None
        ok = True
        for key in value:
            if key not in variables:
                self.problem(
                    field_name("system.equations", key),
                    f"{quoted(key)} is not a variable of the system "
                    f"(its variables: {', '.join(variables)})",
                )
                ok = False
        missing = [x for x in variables if x not in value]
        if missing:
            self.problem(
                "system.equations",
                f"no equation for {', '.join(missing)}: give d/dt of every variable",
            )
            ok = False
        found = {
            x: self.expression(value[x], field_name("system.equations", x))
            for x in variables
            if x in value
        }
        if not ok or any(e is None for e in found.values()):
            return None
        return tuple(found[x] for x in variables)  # type: ignore[misc]

    def bracket(
        self, value: Any, variables: tuple[str, ...]
    ) -> tuple[tuple[str, str, Expression], ...] | None:
        """``system.bracket``: ``"x, y" = "{x, y}"`` for the pairs that are not zero; the
        rest of the bracket follows by antisymmetry."""
        if not isinstance(value, dict):
            self.problem("system.bracket", f"expected a table, found {kind_of(value)}")
            return None
        entries: list[tuple[str, str, Expression]] = []
        seen: set[frozenset[str]] = set()
        ok = True
        for key, text in value.items():
            field = field_name("system.bracket", key)
            pair = [part.strip() for part in key.split(",")]
            if len(pair) != 2:
                self.problem(field, 'a bracket entry is named by two variables: "x, y"')
                ok = False
                continue
            unknown = [x for x in pair if x not in variables]
            if unknown:
                self.problem(
                    field,
                    f"{quoted(unknown[0])} is not a variable of the system "
                    f"(its variables: {', '.join(variables)})",
                )
                ok = False
                continue
            x, y = pair
            if x == y:
                self.problem(field, f"{{{x}, {x}}} is zero by antisymmetry; give no entry for it")
                ok = False
                continue
            if frozenset(pair) in seen:
                self.problem(
                    field,
                    f"{{{x}, {y}}} is given twice (antisymmetry gives {{{y}, {x}}} from it)",
                )
                ok = False
                continue
            seen.add(frozenset(pair))
            expr = self.expression(text, field)
            if expr is None:
                ok = False
                continue
            entries.append((x, y, expr))
        return tuple(entries) if ok else None

    # ------------------------------------------------------- the paper's fields

    def kappa(self, value: Any) -> Expression | None:
        """``kappa``: a number or an expression in the parameters (a constant)."""
        field = "system.kappa"
        if isinstance(value, int) and not isinstance(value, bool):
            value = str(value)
        elif isinstance(value, float):
            if value != value or value in (float("inf"), float("-inf")):
                self.problem(field, "expected a finite number or an expression", repr(value))
                return None
            value = repr(value)
        kappa = self.expression(value, field)
        if kappa is None:
            return None
        var = _first_of(kappa.expr, (*STATE, s))
        if var is not None or kappa.expr.atoms(AppliedUndef):
            what = var if var is not None else "a declared function"
            self.problem(
                field,
                f"kappa must be a constant (the parameters only); it depends on {what}",
                kappa.text,
            )
            return None
        return kappa

    def triple(
        self, value: Any, field: str, check: Callable[[Expression, str], None] | None = None
    ) -> tuple[Expression, ...] | None:
        """An array of exactly three expressions, each passed to ``check(expr, field)``."""
        if not isinstance(value, list):
            self.problem(field, f"expected an array of 3 strings, found {kind_of(value)}")
            return None
        if len(value) != 3:
            self.problem(field, f"expected 3 entries, found {len(value)}")
        items = []
        for i, text in enumerate(value[:3]):
            expr = self.expression(text, f"{field}[{i}]")
            if expr is not None and check is not None:
                check(expr, f"{field}[{i}]")
            items.append(expr)
        if len(items) != 3 or None in items:
            return None
        return tuple(items)  # type: ignore[arg-type]

    def check_moment(self, moment: Expression, field: str) -> None:
        """A moment of inertia is a nonzero constant."""
        var = _first_of(moment.expr, (*STATE, s))
        if var is not None:
            self.problem(
                field, f"a moment of inertia must be constant; it depends on {var}", moment.text
            )
        elif moment.expr == 0:
            self.problem(field, "a moment of inertia is zero", moment.text)

    def check_potential(self, potential: Expression) -> None:
        """The potential U(gamma) depends on gamma1..gamma3 and parameters only."""
        var = _first_of(potential.expr, (*MOMENTUM, s))
        if var is not None:
            self.problem(
                "system.potential",
                f"the potential may depend on gamma only, not on {var}",
                potential.text,
            )


def parses(text: str, ns: Any) -> bool:
    """Whether ``text`` parses in ``ns`` (for tests of what a namespace holds)."""
    try:
        parse_expression(text, ns)
    except ExpressionError:
        return False
    return True
