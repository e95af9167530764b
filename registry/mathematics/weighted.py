"""The weighted-homogeneous split of a polynomial vector field: the first step of the
Kovalevskaya (Painlevé) analysis.

Under integer weights w_i >= 1, a monomial x^m of dx_i/dt = v_i(x) has weighted degree
|m| = sum_j m_j w_j and *shift* |m| - w_i. Put x = c t^(-w) in the equations: the left
side is of order t^(-w_i - 1) and a term of shift s of order t^(-w_i - s). The terms of
shift 1 balance the derivative: they form the *leading part*, for which
v_i(a^w x) = a^(w_i + 1) v_i(x). Terms of lower shift are corrections of relative order
t^(1 - s); a term of shift above 1 would dominate the derivative, and no solution behaves
like c t^(-w) under those weights. The field is *weighted-homogeneous* when it is its own
leading part.

A field may also divide by polynomials D(x) of the state (1/gamma3^2 in Goryachev's
heavy top) when each D is weighted-homogeneous: a term x^m / D^e then has weighted degree
|m| - e deg D, and along x = c t^(-w) with D(c) != 0 it is of order t^(e deg D - |m|),
so the same shifts apply. Such a field is analysed where no D vanishes
(``WeightedField.denominators``).

>>> x, y = sp.symbols("x y")
>>> split = split_field([x, y], [y + x**2, x * y + 1], [1, 2])
>>> split.leading, split.homogeneous, split.shifts
((x**2 + y, x*y), False, (1, -2))
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from ..errors import Problem, WeightedFieldError

#: A term of a divided field multiplies at most this many series (the numerator's
#: variables and each power of a denominator): the Laurent series forms its products
#: factor by factor, and x^1001 / y^1000 has shift 1 under weights (1, 1).
MAX_DIVIDED_FACTORS = 100


@dataclass(frozen=True)
class Term:
    """One term coefficient * x^monomial / prod_d D_d^powers[d] of dx_i/dt (i =
    ``component``), with its shift."""

    component: int
    coefficient: sp.Expr
    monomial: tuple[int, ...]
    powers: tuple[int, ...]
    shift: int


@dataclass(frozen=True)
class WeightedField:
    """A field dx_i/dt = v_i(x) split into parts of one shift each (``parts[s]``: the
    terms of shift s of every component, highest shift 1 first), term by term
    (``terms``); ``denominators``: the weighted-homogeneous polynomials D_d of the state
    it divides by (none for a polynomial field), each with its weighted degree."""

    variables: tuple[sp.Symbol, ...]
    weights: tuple[int, ...]
    parameters: tuple[sp.Symbol, ...]
    field: tuple[sp.Expr, ...]
    parts: Mapping[int, tuple[sp.Expr, ...]]
    terms: tuple[Term, ...] = ()
    denominators: tuple[tuple[sp.Expr, int], ...] = ()

    @property
    def leading(self) -> tuple[sp.Expr, ...]:
        """The leading part: the terms of shift 1, which balance dx/dt for x = c t^(-w)."""
        return self.parts[1]

    @property
    def homogeneous(self) -> bool:
        """Whether the field is weighted-homogeneous (it is its leading part)."""
        return tuple(self.parts) == (1,)

    @property
    def shifts(self) -> tuple[int, ...]:
        """The shifts present, highest (1) first."""
        return tuple(self.parts)


def split_field(
    variables: Sequence[sp.Symbol],
    field: Sequence[sp.Expr],
    weights: Sequence[int],
    *,
    parameters: Sequence[sp.Symbol] | None = None,
) -> WeightedField:
    """The field split by shift under ``weights``; every problem is reported at once
    (``WeightedFieldError``).

    The coefficients must be rational functions over Q of the parameters (the names
    other than the variables; when ``parameters`` is given, exactly those).
    """
    variables = tuple(variables)
    field = tuple(expanded(v, variables) for v in field)
    problems = _shape_problems(variables, field, weights)
    if len(field) != len(variables) or len(weights) != len(variables):
        raise WeightedFieldError(problems)
    weighted = not problems  # shifts are computed only under valid weights
    others = sorted(set().union(*(v.free_symbols for v in field)) - set(variables), key=str)
    if parameters is None:
        parameters = others
    else:
        undeclared = [str(p) for p in others if p not in set(parameters)]
        if undeclared:
            problems.append(
                Problem("field", "names neither a variable nor a parameter", ", ".join(undeclared))
            )
    parts: dict[int, list[list[sp.Expr]]] = {}
    raw: list[tuple[int, sp.Expr, tuple[int, ...], dict[int, int], int]] = []
    denominators: list[tuple[sp.Expr, int]] = []
    for i, component in enumerate(field):
        read = _fraction(component, variables, weights if weighted else None, denominators)
        if isinstance(read, Problem):
            problems.append(Problem(f"field[{i}]", read.message, read.text))
            continue
        for monomial, coeff, powers in read:
            term = coeff * sp.Mul(*(x**m for x, m in zip(variables, monomial, strict=True)))
            term /= sp.Mul(*(denominators[d][0] ** e for d, e in powers.items()))
            if powers and sum(monomial) + sum(powers.values()) > MAX_DIVIDED_FACTORS:
                problems.append(
                    Problem(
                        f"field[{i}]",
                        f"a divided term of more than {MAX_DIVIDED_FACTORS} factors (numerator "
                        "and denominator): beyond what the Laurent series multiplies out",
                        str(term),
                    )
                )
            elif not _rational_over_q(coeff, parameters):
                problems.append(
                    Problem(
                        f"field[{i}]",
                        "a coefficient is not a rational function over Q of the parameters",
                        str(coeff),
                    )
                )
            elif weighted:
                shift = sum(m * int(w) for m, w in zip(monomial, weights, strict=True))
                shift -= sum(e * denominators[d][1] for d, e in powers.items())
                shift -= int(weights[i])
                parts.setdefault(shift, [[] for _ in field])[i].append(term)
                raw.append((i, coeff, tuple(monomial), powers, shift))
    too_high = sorted(s for s in parts if s > 1)
    for s in too_high:
        dominating = [t for component in parts[s] for t in component]
        problems.append(
            Problem(
                "field",
                f"terms of shift {s} > 1 dominate dx/dt under these weights, so no solution "
                "behaves like c t^(-w)",
                str(sp.Add(*dominating)),
            )
        )
    if not problems and 1 not in parts:
        problems.append(
            Problem("field", "no term of shift 1 under these weights: no leading part", None)
        )
    if problems:
        raise WeightedFieldError(problems)
    weights = tuple(int(w) for w in weights)
    ordered = {
        s: tuple(sp.Add(*component) for component in parts[s]) for s in sorted(parts, reverse=True)
    }
    terms = tuple(
        Term(i, coeff, monomial, tuple(powers.get(d, 0) for d in range(len(denominators))), shift)
        for i, coeff, monomial, powers, shift in raw
    )
    return WeightedField(
        variables, weights, tuple(parameters), field, ordered, terms, tuple(denominators)
    )


def _fraction(component, variables, weights, denominators):
    """The terms of dx_i/dt as (monomial, coefficient, {d: power}), the factors in the
    state of its denominators entered in ``denominators`` (each weighted-homogeneous,
    with its degree; None for weights: degrees not wanted); a Problem where it is not a
    sum of polynomials divided by such products."""
    if component.is_polynomial(*variables):
        poly = sp.Poly(component, *variables)
        return [(m, c, {}) for m, c in poly.terms() if c != 0]
    groups = by_denominator(component, variables)
    if groups is None:
        return Problem(
            "", "not a polynomial in the variables, nor a polynomial divided by one", str(component)
        )
    merged: dict[tuple[tuple[int, int], ...], sp.Expr] = {}
    for denom, numer in groups.items():
        read = _factors(denom, variables, weights, denominators)
        if isinstance(read, Problem):
            return read
        scale, powers = read
        key = tuple(sorted(powers.items()))
        merged[key] = merged.get(key, sp.S.Zero) + numer / scale
    return [
        (monomial, coeff, dict(key))
        for key, numer in merged.items()
        for monomial, coeff in sp.Poly(numer, *variables).terms()
        if coeff != 0  # the zero polynomial's one term
    ]


def _factors(denom, variables, weights, denominators):
    """(constant, {d: power}) of one denominator over the factors in ``denominators``,
    or a Problem for a factor that is not weighted-homogeneous."""
    scale: sp.Expr = sp.S.One
    powers: dict[int, int] = {}
    for factor, e in _factored(denom, tuple(variables)):
        if not factor.free_symbols & set(variables):
            scale *= factor**e
            continue
        if sp.Poly(factor, *variables).LC().could_extract_minus_sign():
            factor, scale = -factor, scale * (-1) ** e
        degrees = () if weights is None else weighted_degrees(factor, variables, weights)
        if len(degrees) > 1:
            return Problem(
                "",
                "divides by a polynomial that is not weighted-homogeneous under these weights, "
                "so the terms have no single shift",
                str(factor),
            )
        known = [d for d, (f, _) in enumerate(denominators) if sp.expand(f - factor) == 0]
        if not known:
            denominators.append((factor, degrees[0] if degrees else 0))
        d = known[0] if known else len(denominators) - 1
        powers[d] = powers.get(d, 0) + e
    return scale, powers


def by_denominator(expr: sp.Expr, variables: Sequence[sp.Symbol]) -> dict[sp.Expr, sp.Expr] | None:
    """``expr``'s terms summed by their denominator ({denominator: numerator}, the
    denominator left in factors, 1 for the polynomial part); None where a term is not a
    polynomial in the variables divided by one. Terms are not brought to one fraction:
    a polynomial term times (gamma1 + gamma2 + gamma3)^60 would be thousands."""
    groups: dict[sp.Expr, sp.Expr] = {}
    for term in sp.Add.make_args(sp.expand_mul(sp.sympify(expr))):
        numer, denom = sp.fraction(term)
        if not (numer.is_polynomial(*variables) and denom.is_polynomial(*variables)):
            return None
        if not denom.free_symbols & set(variables):
            numer, denom = numer / denom, sp.S.One
        groups[denom] = groups.get(denom, sp.S.Zero) + numer
    return groups


def expanded(expr: sp.Expr, variables: Sequence[sp.Symbol]) -> sp.Expr:
    """``expr`` expanded; where it divides by the variables, each numerator expanded over
    its denominator kept in factors (``by_denominator``; sympy's expand would multiply
    out a power such as (gamma1 + gamma2 + gamma3)^60 in a denominator, term by term)."""
    expr = sp.sympify(expr)
    groups = None if expr.is_polynomial(*variables) else by_denominator(expr, variables)
    if groups is None:
        return sp.expand(expr)
    return sp.Add(*(sp.expand(numer) / denom for denom, numer in groups.items()))


def polynomial_only(split: WeightedField, what: str) -> WeightedField:
    """``split`` itself where its field is polynomial; WeightedFieldError for a divided
    field, whose balance equations (multiplied by the denominators) only the single
    analysis reads right (``balances``)."""
    if split.denominators:
        shown = ", ".join(sp.sstr(d) for d, _ in split.denominators)
        raise WeightedFieldError(
            [
                Problem(
                    "field",
                    f"{what} are sought for polynomial fields only; this one divides by",
                    shown,
                )
            ]
        )
    return split


@functools.lru_cache(maxsize=256)
def _factored(denom: sp.Expr, variables: tuple[sp.Symbol, ...]) -> tuple:
    """The factors of a denominator over the variables (sympy's factor_list, which
    factors the base of a power once); kept, since the default weights try several
    splits of one field."""
    constant, factors = sp.factor_list(denom, *variables)
    return (*factors, (constant, 1))


def _shape_problems(variables, field, weights) -> list[Problem]:
    problems = []
    if len(set(variables)) != len(variables) or not all(
        isinstance(x, sp.Symbol) for x in variables
    ):
        problems.append(Problem("variables", "must be distinct symbols", str(variables)))
    if len(field) != len(variables):
        problems.append(
            Problem("field", f"{len(field)} components for {len(variables)} variables", None)
        )
    if len(weights) != len(variables):
        problems.append(
            Problem("weights", f"{len(weights)} weights for {len(variables)} variables", None)
        )
    for i, w in enumerate(weights):
        if isinstance(w, bool) or not isinstance(w, int | sp.Integer) or int(w) < 1:
            problems.append(Problem(f"weights[{i}]", "not a positive integer", str(w)))
    return problems


def _rational_over_q(coeff: sp.Expr, parameters: Sequence[sp.Symbol]) -> bool:
    """Whether ``coeff`` is a rational function with rational coefficients of the
    parameters (no floats, no radicals, no I)."""
    if not parameters:
        return bool(coeff.is_Rational)
    if coeff.has(sp.Float) or not coeff.is_rational_function(*parameters):
        return False
    try:
        for part in sp.fraction(sp.together(coeff)):
            sp.Poly(part, *parameters, domain=sp.QQ)
    except (sp.CoercionFailed, sp.PolynomialError):
        return False
    return True


def weighted_degrees(
    expr: sp.Expr, variables: Sequence[sp.Symbol], weights: Sequence[int]
) -> tuple[int, ...]:
    """The weighted degrees of the monomials of a polynomial, highest first (one entry
    for a weighted-homogeneous one, none for 0).

    >>> x, y = sp.symbols("x y")
    >>> weighted_degrees(x**4 + y**2 + x, [x, y], [1, 2])
    (4, 1)
    """
    expr = sp.expand(sp.sympify(expr))
    if expr == 0:
        return ()
    monomials = sp.Poly(expr, *variables).monoms()
    degrees = {sum(m * w for m, w in zip(mono, weights, strict=True)) for mono in monomials}
    return tuple(sorted(degrees, reverse=True))
