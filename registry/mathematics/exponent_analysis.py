"""The Kovalevskaya analysis of a polynomial field: every balance, its exponents, the
weighted degrees Yoshida's theorem leaves for first integrals, and the Painlevé test.

``exponents(variables, field, weights)`` gathers the pieces (``weighted``, ``balances``,
``kovalevskaya``, ``painleve``) into one ``ExponentAnalysis``, whose ``as_dict()`` is the
JSON document of CASE_FORMAT.md ("Kovalevskaya exponents"): expressions as sympy's text,
left to the caller to render in the case language. With parameters, everything is
computed over Q(parameters): it holds for all parameter values but a proper algebraic
subset (where a denominator or a discriminant met on the way vanishes);
``exponent_families`` finds the special values.

>>> x, y = sp.symbols("x y")
>>> analysis = exponents([x, y], [-(x**2), x * y + x**2], [1, 1])
>>> [(dict(b.balance.point), b.exponents.values) for b in analysis.balances]
[({x: 1, y: -1/2}, (-1, 2))]
>>> analysis.degrees, analysis.painleve_passes
((2,), True)
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from . import algebraic
from .balances import Balance, balances
from .factoring import factor
from .flint_gcd import flint_gcd
from .kovalevskaya import (
    LAMBDA,
    Exponents,
    balance_exponents,
    characteristic_polynomial,
    kovalevskaya_matrix,
    yoshida_degrees,
)
from .painleve import Resonance, laurent_series
from .weighted import WeightedField, split_field


@dataclass(frozen=True)
class Painleve:
    """The Painlevé (ARS) test at one balance: the step at each resonance, conditions
    written with the balance's coordinates."""

    resonances: tuple[Resonance, ...]

    @property
    def compatible(self) -> bool:
        """Every compatibility condition holds (no logarithmic term is needed)."""
        return all(r.holds for r in self.resonances)

    @property
    def obstructions(self) -> tuple[str, ...]:
        return tuple(text for r in self.resonances for text in r.obstructions)


@dataclass(frozen=True)
class BalanceResult:
    """One balance with its exponents, the Painlevé test there, and what they mean."""

    balance: Balance
    exponents: Exponents
    painleve: Painleve
    notes: tuple[str, ...] = ()

    def as_dict(self, back: Mapping[sp.Symbol, sp.Expr] | None = None) -> dict:
        """The JSON entry of the balance; ``back`` writes parameters that stand for
        combinations of others (``parameter_translations``) as those combinations."""
        b, e = self.balance, self.exponents
        extra: dict = {}
        named: dict = dict(back or {})
        if b.root is None:  # the point through a root theta of the component's polynomial
            named[b.component.symbol] = sp.Symbol("theta")
            g = b.component.minimal.as_expr().xreplace(named)
            extra["root_of"] = f"{sp.sstr(g)} = 0"
        point = {x: v.xreplace(named) for x, v in b.point.items()}
        return {
            "point": {str(x): sp.sstr(v) for x, v in point.items()},
            "exponents": _exponent_texts(e, named),
            "integer": e.integer,
            "rational": e.rational,
            "dimension": b.dimension,
            "free": [str(s) for s in b.free],
            **extra,
            "degrees": list(e.degrees),
            "painleve": {
                "compatible": self.painleve.compatible,
                "conditions": list(self.painleve.obstructions),
                "free_coefficients": {
                    str(r.order): [str(f) for f in r.free] for r in self.painleve.resonances
                },
            },
            "notes": list(self.notes),
        }


@dataclass(frozen=True)
class ExponentAnalysis:
    """Every balance of a field's leading part with its exponents and Painlevé test."""

    variables: tuple[sp.Symbol, ...]
    weights: tuple[int, ...]
    parameters: tuple[sp.Symbol, ...]
    homogeneous: bool
    leading: tuple[sp.Expr, ...]
    balances: tuple[BalanceResult, ...]
    notes: tuple[str, ...] = ()
    seconds: float = field(default=0.0, compare=False)
    #: the polynomials of the state the field divides by (balances lie off their zeros)
    denominators: tuple[sp.Expr, ...] = ()
    #: whether the ARS test was made (an analysis of the exponents only has no series)
    tested: bool = True

    @property
    def all_integer(self) -> bool:
        return all(b.exponents.integer for b in self.balances)

    @property
    def all_rational(self) -> bool:
        return all(b.exponents.rational for b in self.balances)

    @property
    def degrees(self) -> tuple[int, ...]:
        """Yoshida's possible weighted degrees of integrals (``kovalevskaya``)."""
        return yoshida_degrees([b.exponents for b in self.balances])

    @property
    def compatible(self) -> bool:
        return all(b.painleve.compatible for b in self.balances)

    @property
    def painleve_passes(self) -> bool:
        """The ARS test passes: every exponent of every balance is an integer and every
        compatibility condition holds (necessary for the Painlevé property, not a proof).
        False where the test was not made."""
        return self.painleve_verdict is True

    @property
    def painleve_verdict(self) -> bool | None:
        """``painleve_passes`` where it is known: False wherever some exponent is not an
        integer (the series is then not needed), None where the exponents are all
        integers but the series was not computed."""
        if not self.all_integer:
            return False
        return self.compatible if self.tested else None

    @property
    def conditions(self) -> tuple[str, ...]:
        """The failing compatibility conditions, each with its balance (1-based)."""
        return tuple(
            f"balance {i}: {text}"
            for i, b in enumerate(self.balances, 1)
            for text in b.painleve.obstructions
        )

    @property
    def statement(self) -> str:
        """What the cited theorems prove from these exponents, and nothing more."""
        return _statement(self)

    def as_dict(self) -> dict:
        """The JSON document of CASE_FORMAT.md (without the case's id, which the caller
        knows); expressions in sympy's text."""
        return {
            "weights": {str(x): w for x, w in zip(self.variables, self.weights, strict=True)},
            "homogeneous": self.homogeneous,
            "parameters": [str(p) for p in self.parameters],
            **(
                {"denominators": [sp.sstr(d) for d in self.denominators]}
                if self.denominators
                else {}
            ),
            "free": [],
            "balances": [b.as_dict() for b in self.balances],
            "all_integer": self.all_integer,
            "all_rational": self.all_rational,
            "degrees": list(self.degrees),
            "painleve": {
                "passes": self.painleve_passes,
                "compatible": self.compatible,
                "conditions": list(self.conditions),
            },
            "statement": self.statement,
            "notes": list(self.notes),
            "seconds": round(self.seconds, 3),
        }


def exponents(
    variables: Sequence[sp.Symbol],
    field: Sequence[sp.Expr],
    weights: Sequence[int],
    *,
    parameters: Sequence[sp.Symbol] | None = None,
    painleve: bool = True,
    seed: int = 0,
) -> ExponentAnalysis:
    """Balances, Kovalevskaya exponents, Yoshida's degrees and (unless ``painleve`` is
    False) the ARS test of ``dx/dt = field`` under integer weights >= 1 (module doc).

    Raises ``WeightedFieldError`` for a field or weights that admit no analysis."""
    start = time.perf_counter()
    split = split_field(variables, field, weights, parameters=parameters)
    return analyse(split, painleve=painleve, seed=seed, start=start)


def analyse(
    split: WeightedField, *, painleve: bool = True, seed: int = 0, start: float | None = None
) -> ExponentAnalysis:
    """``exponents`` for a field already split (sympy's gcds by FLINT: ``flint_gcd``)."""
    start = time.perf_counter() if start is None else start
    with flint_gcd():
        return _analyse(split, painleve, seed, start)


def _analyse(split: WeightedField, painleve: bool, seed: int, start: float) -> ExponentAnalysis:
    matrix = kovalevskaya_matrix(split)
    results: list[BalanceResult] = []
    per_component: dict[int, tuple] = {}
    for balance in balances(split, seed=seed):
        key = id(balance.component)
        if key not in per_component:
            polynomial = characteristic_polynomial(balance.component, matrix)
            per_component[key] = (polynomial, None)
        polynomial, series = per_component[key]
        found = balance_exponents(balance, polynomial)
        if painleve and series is None:
            series = laurent_series(split, balance.component, matrix, found.resonances)
            per_component[key] = (polynomial, series)
        steps = () if series is None else _at_balance(series.resonances, balance)
        if painleve:
            steps = (*_leading_step(balance, found), *steps)
        results.append(
            BalanceResult(balance, found, Painleve(steps), _balance_notes(balance, found))
        )
    return ExponentAnalysis(
        split.variables,
        split.weights,
        split.parameters,
        split.homogeneous,
        split.leading,
        tuple(results),
        _notes(split, results, painleve),
        time.perf_counter() - start,
        tuple(d for d, _ in split.denominators),
        painleve,
    )


def _leading_step(balance: Balance, found: Exponents) -> tuple[Resonance, ...]:
    """The exponent 0 as a resonance of the leading order: each zero exponent needs a
    free leading coefficient, a direction along which the balances form a family. Its
    multiplicity m exceeds the family's dimension d where balances meet or degenerate
    (Hénon and Heiles's x²y + 2y³/3: the balances with x ≠ 0 need x² = 0 and merge into
    the one with x = 0), and the test then fails: m - d constants of the general
    solution are missing."""
    zeros = sum(1 for v in found.values if v.is_zero)
    if not zeros:
        return ()
    return (Resonance(0, zeros, tuple(balance.free), ()),)


def _at_balance(steps: Sequence[Resonance], balance: Balance) -> tuple[Resonance, ...]:
    """The component's conditions written at one balance (its root put for u)."""
    u, root = balance.component.symbol, balance.root
    if root is None:
        return tuple(steps)
    return tuple(
        Resonance(
            s.order, s.multiplicity, s.free, tuple(_at_root(c, u, root) for c in s.conditions)
        )
        for s in steps
    )


def _at_root(condition: sp.Expr, u: sp.Symbol, root: sp.Expr) -> sp.Expr:
    """A condition (a polynomial in u) at a balance: over square roots in their normal
    form (``algebraic.value_at_root``: Bobylev's top, 0.3 s by radsimp per condition,
    0.01 s so), else simplified after substitution."""
    value = algebraic.value_at_root(condition, u, root)
    return _tidy(condition.subs(u, root)) if value is None else value


def _tidy(expr: sp.Expr) -> sp.Expr:
    expr = sp.expand(expr)
    if expr.has(sp.I, sp.CRootOf) or any(
        p.exp.is_Rational and not p.exp.is_integer for p in expr.atoms(sp.Pow)
    ):
        return sp.radsimp(expr)
    return factor(expr)


def _exponent_texts(e: Exponents, named: dict) -> list[str]:
    """The exponents as text, with multiplicity; a factor whose roots are not written
    out appears once per root, as "root of <factor>"."""
    texts = [sp.sstr(v.xreplace(named)) for v in e.values]
    for f, m in e.implicit:
        degree = sp.Poly(f, LAMBDA).degree()
        texts += [f"root of {sp.sstr(f.xreplace(named))}"] * (degree * m)
    return texts


def _balance_notes(balance: Balance, e: Exponents) -> tuple[str, ...]:
    notes = []
    if balance.dimension:
        free = ", ".join(map(str, balance.free))
        notes.append(
            f"a family of balances of dimension {balance.dimension} (free: {free}); "
            + (
                "its exponents change along it: those of a generic point"
                if e.varying
                else "its exponents are the same at every point"
            )
        )
    negative = [v for v in e.values if v.is_negative]
    if len(negative) > 1:
        shown = ", ".join(sp.sstr(v) for v in negative)
        notes.append(
            f"negative exponents {shown}: beyond the single -1 of the time shift, "
            "so not a principal balance (its series has fewer free coefficients)"
        )
    fractions = [v for v in e.values if v.is_rational and not v.is_integer]
    if fractions:
        shown = ", ".join(sp.sstr(v) for v in fractions)
        notes.append(
            f"non-integer rational exponents {shown}: the solutions branch algebraically "
            "at the singularity (at most the weak Painlevé property)"
        )
    if e.implicit or any(not v.is_rational for v in e.values):
        notes.append("irrational or complex exponents: the solutions branch (no Painlevé property)")
    return tuple(notes)


def _notes(split: WeightedField, results, painleve: bool) -> tuple[str, ...]:
    notes = []
    if not split.homogeneous:
        lower = ", ".join(str(s) for s in split.shifts[1:])
        notes.append(
            "the field is not weighted-homogeneous under these weights: the balances and "
            "exponents are those of its leading part (shift 1); the parts of shift "
            f"{lower} enter the Painlevé test's series, and Yoshida's degrees constrain the "
            "leading weighted-homogeneous part of an integral"
        )
    if split.denominators:
        shown = ", ".join(sp.sstr(d) for d, _ in split.denominators)
        notes.append(
            f"the field divides by {shown}: its balances are sought where none of these "
            "vanishes (each weighted-homogeneous, so every term keeps one shift); a solution "
            "whose leading term makes one vanish is not covered"
        )
    if split.parameters:
        names = ", ".join(map(str, split.parameters))
        notes.append(
            f"parameters {names} are treated as generic: the results hold outside a proper "
            "algebraic subset of their values (exponent_family finds special values)"
        )
    if not results:
        where = " where the field is defined" if split.denominators else ""
        notes.append(f"the leading part has no balance{where}: no Laurent solution x = c t^(-w)")
    if not painleve:
        notes.append("the Painlevé test was not run")
    return tuple(notes)


def _statement(analysis: ExponentAnalysis) -> str:
    parts = []
    if analysis.balances:
        degrees = ", ".join(map(str, analysis.degrees)) or "none"
        parts.append(
            "Yoshida (Celestial Mech. 31 (1983) 363): a weighted-homogeneous "
            "first integral of weighted degree k >= 1 whose gradient is not zero at a "
            "balance has k among that balance's exponents; the degrees allowed by some "
            f"balance here are: {degrees}"
        )
    if not analysis.all_rational:
        parts.append(
            "Yoshida (1983): n - 1 weighted-homogeneous algebraic first integrals whose "
            "gradients are independent at a balance make every exponent of that balance "
            "rational; a balance here has an irrational or complex exponent, so no such "
            "integrals exist for it"
        )
    if analysis.balances and analysis.conditions:
        parts.append(
            "Ablowitz, Ramani and Segur (J. Math. Phys. 21 (1980) 715): a failing "
            "compatibility condition forces a logarithmic term in the Laurent series, so "
            "the general solution has movable logarithmic branch points: the field does "
            "not have the Painlevé property"
        )
    elif analysis.balances and analysis.painleve_passes and analysis.compatible:
        parts.append(
            "the ARS test passes (integer exponents, every compatibility condition holds): "
            "necessary for the Painlevé property, not a proof of it"
        )
    return "; ".join(parts) + ("." if parts else "")
