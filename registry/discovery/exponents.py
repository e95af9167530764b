"""The Kovalevskaya analysis of a case (``registry exponents``): its system's field split
into weighted-homogeneous parts under weights given by vector, every balance of the
leading part with its exponents, Yoshida's degrees and the Painlevé (ARS) test; with
free parameters, the values where every exponent is an integer, half an integer or
rational (``mathematics.exponent_families``).

The system is read from ``Case.dynamics`` whatever form its file gave it in (moments of
inertia, a Hamiltonian with kappa, equations, a Hamiltonian with a bracket); nothing of
the file is executed. The result is an ``ExponentResult``: the JSON document of
docs/json-output.md, every expression written as text (algebraic numbers exactly:
``sqrt(7)``, ``I``), with a statement that says only what the cited theorems prove.
A system the method cannot analyse is refused with an ``ExponentError`` naming the file,
the field and the text (``case_field``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import sympy as sp

from ..dynamics import Dynamics
from ..errors import ExponentError, Problem, WeightedFieldError
from ..execution.executor import Executor, InProcess, LocalPool, in_order, timed
from ..execution.serving import Failure
from ..execution.time_budget import BudgetExceeded, time_limit
from ..language.forms import with_values
from ..mathematics.exponent_analysis import BalanceResult, ExponentAnalysis, analyse, exponents
from ..mathematics.exponent_families import (
    GRID,
    ExponentFamily,
    SpecialSet,
    exponent_family,
    kind_of,
)
from ..mathematics.exponent_witness import Witness, approximate, witness
from ..mathematics.grading import candidates, per_variable, shift
from ..mathematics.kovalevskaya import LAMBDA
from ..mathematics.leading_weights import leading_weights
from ..mathematics.parameter_translations import Reduction, reduction
from ..mathematics.weighted import WeightedField, by_denominator, expanded, split_field
from ..model import Case, ExponentOptions, ExponentResult, Weights, as_weights
from .exponent_statement import family_statement, statement, witness_statement
from .identification.catalog_index import CatalogIndex
from .identification.identify import identify
from .painleve_strata import Strata, half_integer_strata, painleve_strata

#: What the analysis says of how it works (in every document).
METHOD = (
    "weighted split of the field (polynomial, or divided by weighted-homogeneous "
    "polynomials of the state); balances by Groebner bases in shape position "
    "over Q(parameters) and its algebraic extensions; exponents exact, per component in "
    "k[u]/(g); the ARS recursion to the last resonance, its conditions decided exactly"
)

#: With several free parameters: the share of the budget the search for the sets where
#: the Painlevé test can pass may take (``painleve_strata``), first; then the same share
#: of what is left for the sets where every exponent is in (1/2)Z (``half_integer_strata``).
STRATA_SHARE = 0.5
#: Why the grid of small values was not searched: the budget ran out, or both
#: stratifications were complete (the grid's points would only repeat their sets).
OUT_OF_TIME = "several free parameters: the grid of small values was not searched within the budget"
SUPERSEDED = (
    "several free parameters: small values not searched one by one (the sets where the "
    "Painlevé test passes and where every exponent is in (1/2)Z are complete below)"
)
#: Then the share of what is left that the generic analysis over Q(free) may take
#: before the grid of small values is searched without it.
GENERIC_SHARE = 0.3
#: A single system with symbolic parameters: the share of the budget kept, at most
#: WITNESS_SECONDS, to look for a witness of the test's failure at rational values
#: (``exponent_witness``) where the analysis over Q(parameters) runs out of time (one
#: analysis over Q, a second or less for the catalog's tops).
WITNESS_SHARE = 0.25
WITNESS_SECONDS = 10.0


@dataclass(frozen=True)
class CaseField:
    """A case's system as the analysis reads it: the state, dx/dt as polynomials in it
    (shorthands such as ``s`` written out), each variable's weight, the parameters left
    generic and those whose special values are sought."""

    variables: tuple[sp.Symbol, ...]
    field: tuple[sp.Expr, ...]
    weights: tuple[int, ...]
    parameters: tuple[sp.Symbol, ...]
    free: tuple[sp.Symbol, ...]


def exponent_options(
    case: Case,
    weights: Weights | Mapping[str, int] | tuple[int, int] | None = None,
    free: Sequence[str] = (),
) -> ExponentOptions:
    """The options for analysing ``case``: a weight for every vector of its state (those
    given, the others ``_default_weights``) and the ``free`` parameters (each must be one
    the case declares)."""
    dynamics = case.dynamics
    names = [v.name for v in dynamics.vectors]
    problems = []
    try:
        given = dict(as_weights(weights)) if weights is not None else {}
    except ValueError as err:
        given = {}
        problems.append(Problem("--weights", str(err)))
    unknown = [n for n in given if n not in names]
    if unknown:
        problems.append(
            Problem(
                "--weights",
                f"names a vector the case's state does not have (its vectors: {', '.join(names)})",
                ", ".join(unknown),
            )
        )
    strangers = [f for f in free if f not in case.parameters]
    if strangers:
        declared = ", ".join(case.parameters) or "none"
        problems.append(
            Problem(
                "--free",
                f"names a parameter the case does not declare (its parameters: {declared})",
                ", ".join(strangers),
            )
        )
    if problems:
        raise ExponentError(_file(case), problems)
    default = dict(_default_weights(dynamics))
    chosen = tuple((v.name, given.get(v.name, default[v.name])) for v in dynamics.vectors)
    return ExponentOptions(chosen, tuple(dict.fromkeys(free)))


def _default_weights(dynamics: Dynamics) -> Weights:
    """The weights an analysis uses unless told: the system's grading where its field is
    homogeneous under it; else the first of the vectors' own weights (M: 1, gamma: 2 for
    the reference paper's state, under which a deformation such as so(4)'s is of lower
    shift) and the other gradings tried (``grading.candidates``) under which the field has
    a leading part (no term of shift above 1) keeping a term of every component that is
    not zero; else the weights of the integer program that asks the same
    (``leading_weights``: Hénon and Heiles's x, y: 2, px, py: 3); else, of the first of
    those tried with a leading part at all and the integer program's weights keeping the
    most components (Rössler's x: 1, y, z: 2), the one that keeps more; else the
    vectors' own weights."""
    own = tuple((v.name, v.weight) for v in dynamics.vectors)
    if dynamics.grading and (
        shift(
            dynamics.field,
            dynamics.grading,
            dynamics.vectors,
            dynamics.shorthands,
            dynamics.variables,
        )
        is not None
    ):
        return dynamics.grading
    field = [expanded(dynamics.expanded(v), dynamics.variables) for v in dynamics.field]
    moving = sum(1 for f in field if f != 0)
    partial = None  # the first weights with a leading part that drops some component
    for weights in (own, *candidates(dynamics.vectors)):
        kept = _leading_components(dynamics, field, weights)
        if kept == moving:
            return weights
        if kept is not None and partial is None:
            partial = (weights, kept)
    found = leading_weights(field, dynamics.vectors, dynamics.variables)
    if found:
        return found
    most = leading_weights(field, dynamics.vectors, dynamics.variables, most=True)
    if most and (partial is None or (_leading_components(dynamics, field, most) or 0) > partial[1]):
        return most
    return partial[0] if partial else own


def _leading_components(
    dynamics: Dynamics, field: Sequence[sp.Expr], weights: Weights
) -> int | None:
    """How many components keep a term in the leading part under ``weights`` (None: some
    term dominates, no leading part)."""
    try:
        split = split_field(
            dynamics.variables, field, per_variable(weights, dynamics.vectors, dynamics.variables)
        )
    except WeightedFieldError:
        return None
    return sum(1 for v, f in zip(split.leading, field, strict=True) if f != 0 and v != 0)


def case_field(case: Case, options: ExponentOptions) -> CaseField:
    """The polynomial field of ``case`` under ``options`` (ExponentError, every problem
    at once, for a system that is not polynomial in its state, arbitrary functions, or a
    family whose other parameters are neither free nor fixed)."""
    dynamics = case.dynamics
    problems = []
    if dynamics.functions:
        problems.append(
            Problem(
                "functions",
                "arbitrary functions leave the field's degree unknown: the analysis needs "
                "a polynomial field",
                ", ".join(dynamics.functions),
            )
        )
    state = set(dynamics.variables)
    field = []
    for x, v in zip(dynamics.variables, dynamics.field, strict=True):
        expr = expanded(dynamics.expanded(v), dynamics.variables)
        polynomial = expr.is_polynomial(*dynamics.variables)
        groups = {} if polynomial else by_denominator(expr, dynamics.variables)
        denominators = [sp.fraction(sp.together(expr))[1]] if groups is None else list(groups)
        below = sorted({str(s) for d in denominators for s in d.free_symbols & state})
        if groups is None:
            why = f" (divided by a function of {', '.join(below)})" if below else ""
            problems.append(
                Problem(
                    f"d{x}/dt",
                    f"not a polynomial in the state variables{why}, nor a polynomial divided by "
                    "one: the analysis seeks balances x = c t^(-w) of a polynomial or rational "
                    "field",
                    sp.sstr(expr),
                )
            )
        elif below and options.free:
            problems.append(
                Problem(
                    f"d{x}/dt",
                    f"divided by a function of {', '.join(below)}: the special values of a "
                    "family (--free) are sought for polynomial fields only; without --free "
                    "the analysis runs where the denominators do not vanish",
                    sp.sstr(expr),
                )
            )
        field.append(expr)
    free = tuple(case.parameters[f] for f in options.free)
    present = set().union(*(e.free_symbols for e in field)) - state
    if free:
        others = sorted((str(p) for p in present if p not in set(free)), key=str)
        if others:
            problems.append(
                Problem(
                    "--free",
                    "every other parameter of the field must be free too, or be fixed in the "
                    "case (the special values of a family are sought over Q(free))",
                    ", ".join(others),
                )
            )
    if problems:
        raise ExponentError(_file(case), problems)
    weights = per_variable(options.weights, dynamics.vectors, dynamics.variables)
    parameters = tuple(p for p in dynamics.parameters if p in present and p not in set(free))
    return CaseField(dynamics.variables, tuple(field), weights, parameters, free)


def analyse_case(
    case: Case,
    options: ExponentOptions,
    *,
    budget: float | None = None,
    executor: Executor | None = None,
    seed: int = 0,
    catalog: CatalogIndex | None = None,
) -> ExponentResult:
    """The analysis of ``case`` (module doc); with ``options.free``, the family's special
    values, their exact analyses run by ``executor`` (default: in this process), and with
    a ``catalog`` each set of a stratification named by the catalog cases it is
    (``identification``). Past ``budget`` seconds the analysis stops and the result is
    not decided (its reason says so); ExponentError for a system the method cannot
    analyse."""
    start = time.perf_counter()
    found = case_field(case, options)
    if not found.free and isinstance(executor, LocalPool) and budget:
        return _apart(case, options, budget, executor, seed)
    try:
        if not found.free:
            document = _single(case, options, found, budget, seed)
        else:
            document = _family_analysis(
                case, options, found, executor or InProcess(), budget, seed, catalog
            )
    except BudgetExceeded:
        document = _out_of_time(case, options, budget)
    seconds = time.perf_counter() - start
    document["seconds"] = round(seconds, 3)
    return ExponentResult(case.id, case.content_hash, options, document, seconds)


def _single(
    case: Case, options: ExponentOptions, found: CaseField, budget: float | None, seed: int
) -> dict[str, Any]:
    """The document of one system. With symbolic parameters and a budget, the analysis
    over Q(parameters) leaves ``WITNESS_SHARE`` of it (at most ``WITNESS_SECONDS``);
    where it runs out, the rest seeks a witness at rational values that the test fails
    for generic values (an analysis out of time that says so); BudgetExceeded where none
    is found."""
    started = time.perf_counter()
    exact = budget
    if budget and found.parameters:
        exact = budget - _reserve(budget)
    split: WeightedField | None = None
    reduced: Reduction | None = None
    try:
        with time_limit(exact):
            reduced = _reduced(found)
            split = _split(case, found) if reduced is None else _split_reduced(case, found, reduced)
            analysis = analyse(split, seed=seed, start=started)
            return _document(case, options, found, analysis, reduced)
    except BudgetExceeded:
        left = (budget or 0.0) - (time.perf_counter() - started)
        if exact == budget or left <= 0 or split is None:
            raise
    with time_limit(left):  # BudgetExceeded past it, as for the analysis itself
        found_witness = witness(split, seed=seed)
    if found_witness is None:
        raise BudgetExceeded
    if reduced is not None:  # the reduced field at p' is the case's at p'_j, p_k = 0
        found_witness = Witness(
            {
                **{_original(found, p): v for p, v in found_witness.values.items()},
                **{p: sp.Integer(0) for p in reduced.removed},
            },
            found_witness.balance,
        )
    document = _out_of_time(case, options, budget)
    document |= _witness_part(options, split, found_witness, found.parameters)
    return document


def _reduced(found: CaseField) -> Reduction | None:
    """The field with a parameter set to 0 for each translation of the parameters that
    keeps it (``parameter_translations``); None where there is none, where the field
    divides by a function of the state (its denominators stay as they are), or where a
    parameter is declared an integer (the reduced ones would not be, and a witness at
    rational values would then speak for values the case excludes)."""
    if (
        len(found.parameters) < 2
        or any(p.is_integer for p in found.parameters)
        or any(not e.is_polynomial(*found.variables) for e in found.field)
    ):
        return None
    return reduction(found.field, found.parameters)


def _split_reduced(case: Case, found: CaseField, reduced: Reduction) -> WeightedField:
    """``_split`` of the reduced field, over its remaining parameters."""
    return _split(case, replace(found, field=reduced.field, parameters=reduced.parameters))


def _original(found: CaseField, p: sp.Symbol) -> sp.Symbol:
    """The case's parameter of the name of a reduced one."""
    return next(q for q in found.parameters if q.name == p.name)


def _reserve(budget: float) -> float:
    """The seconds of ``budget`` kept for a witness: ``WITNESS_SHARE``, at most
    ``WITNESS_SECONDS``."""
    return min(budget * WITNESS_SHARE, WITNESS_SECONDS)


def _family_analysis(
    case: Case,
    options: ExponentOptions,
    found: CaseField,
    executor: Executor,
    budget: float | None,
    seed: int,
    catalog: CatalogIndex | None,
) -> dict[str, Any]:
    """A family's document (``_family``), each set of a stratification named with a
    ``catalog``. With a budget, its reserve (``_reserve``) seeks a witness at rational
    values that the test fails for generic members, where their test is left unknown
    (their balances not found, and a stratification not complete), or where one free
    parameter's analysis runs out of time (a document that then stays undecided, as for
    a single system); BudgetExceeded where that finds none."""
    started = time.perf_counter()
    reserve = _reserve(budget) if budget else 0.0
    try:
        family, strata = _family(case, found, executor, budget and budget - reserve, seed)
    except BudgetExceeded:
        if not reserve:
            raise
        document = _out_of_time(case, options, budget)
    else:
        document = _family_document(case, options, found, family, *strata)
        if catalog is not None:
            _name_sets(case, strata, document, catalog)
        unknown = document["painleve"]["passes"] is None and document["all_integer"] is None
        if not reserve or not unknown:  # generic integer exponents: no witness exists
            return document
    left = (budget or 0.0) - (time.perf_counter() - started)
    split = _split(case, found, found.free)
    found_witness = None
    if left > 0:
        try:
            with time_limit(left):
                found_witness = witness(split, seed=seed)
        except BudgetExceeded:
            pass
    if found_witness is None:
        if not document["decided"]:
            raise BudgetExceeded
        return document
    part = _witness_part(options, split, found_witness)
    if not document["decided"]:
        return document | part
    document["painleve"]["passes"] = False
    document["witness"] = part["witness"]
    document["statement"] = family_statement(document, options.weights_text())
    return document


def _witness_part(
    options: ExponentOptions,
    split: WeightedField,
    w: Witness,
    parameters: Sequence[sp.Symbol] | None = None,
) -> dict[str, Any]:
    """The test's verdict from a witness, the witness itself and the statement of an
    undecided document, whose balances, exponents and degrees of generic values stay
    unknown (a decided family's document takes the witness alone). The statement names
    ``parameters`` (default: the split field's)."""
    entry = _balance(w.balance, tested=False)
    e = w.balance.exponents
    rational = [v for v in e.values if v.is_rational]
    implicit = sum(int(sp.degree(f, LAMBDA)) * m for f, m in e.implicit)
    not_rational = len(e.values) - len(rational) + implicit
    witnessed = {
        "values": {str(p): sp.sstr(v) for p, v in w.values.items()},
        "point": entry["point"],
        "root_of": entry["root_of"],
        "exponents": entry["exponents"],
        "rational": [sp.sstr(v) for v in rational],
        "not_rational": not_rational,
        "approximate": [_approximately(z) for z in approximate(w)],
    }
    return {
        "painleve": {"passes": False, "compatible": None, "conditions": []},
        "witness": witnessed,
        "statement": witness_statement(
            witnessed,
            options.weights_text(),
            [str(p) for p in (split.parameters if parameters is None else parameters)],
            split.homogeneous,
            bool(split.denominators),
        ),
    }


def _approximately(z: complex) -> str:
    """A number to six digits in the case language (``0.5 - 2.13094*I``)."""
    if abs(z.imag) <= 1e-12 * max(1.0, abs(z.real)):
        return f"{z.real:.6g}"
    sign = "-" if z.imag < 0 else "+"
    return f"{z.real:.6g} {sign} {abs(z.imag):.6g}*I"


@dataclass(frozen=True)
class _Refusal:
    """An ExponentError as a worker hands it back (the exception itself does not pickle)."""

    file: str
    problems: tuple[Problem, ...]


def _apart(
    case: Case, options: ExponentOptions, budget: float, executor: LocalPool, seed: int
) -> ExponentResult:
    """One system's analysis in a local worker process, killed a grace after ``budget``:
    the timer stops Python code, not a long product or division inside FLINT, which the
    kill does, so that the analysis ends in its budget as the command promises."""
    ((_, outcome),) = list(
        executor.map(
            _whole,
            [(case, options, budget, seed)],
            deadline=timed(budget),
            label=lambda w: w[0].id,
            name="registry-exponents",
        )
    )
    if isinstance(outcome, _Refusal):
        raise ExponentError(outcome.file, list(outcome.problems))
    if isinstance(outcome, Failure):
        if outcome.kind != "killed":
            return refused(case, options, f"no result came back: {outcome.reason}")
        document = _out_of_time(case, options, budget)
        document["seconds"] = outcome.seconds or budget
        return ExponentResult(case.id, case.content_hash, options, document, document["seconds"])
    return outcome


def _whole(work) -> ExponentResult | _Refusal:
    """``analyse_case`` in a worker (``_apart``)."""
    case, options, budget, seed = work
    try:
        return analyse_case(case, options, budget=budget, seed=seed)
    except ExponentError as err:
        return _Refusal(err.file, tuple(err.problems))


def _out_of_time(case: Case, options: ExponentOptions, budget: float | None) -> dict[str, Any]:
    """The document of an analysis whose budget ran out, with the budget: a larger one
    may decide it, and is not answered by this one (``runs.exponents_run``)."""
    document = undecided_document(
        case, options, f"time budget exceeded ({budget:g} s) before the analysis ended"
    )
    document["budget"] = budget
    return document


def refused(case: Case, options: ExponentOptions, reason: str) -> ExponentResult:
    """The record of an analysis the method refuses: nothing established, and why."""
    return ExponentResult(
        case.id, case.content_hash, options, undecided_document(case, options, reason)
    )


def undecided_document(case: Case, options: ExponentOptions, reason: str) -> dict[str, Any]:
    """The document of an analysis that establishes nothing, with the reason."""
    return {
        "case": case.id,
        "weights": dict(options.weights),
        "free": list(options.free),
        "decided": False,
        "reason": reason,
        "balances": [],
        "statement": f"Nothing is established about the Kovalevskaya exponents: {reason}.",
        "seconds": 0.0,
    }


def analysed(
    work: Sequence[tuple[Case, ExponentOptions]],
    *,
    budget: float | None,
    executor: Executor | None = None,
) -> Iterator[ExponentResult]:
    """The analysis of each (case, options), in order, by ``executor`` (default: in this
    process), one call each (the survey's); an analysis the method refuses, or that came
    back with no result, is recorded as ``refused`` with the reason."""
    executor = executor or InProcess()
    calls = executor.map(
        _analysed_apart,
        [(item, budget) for item in work],
        deadline=timed(budget),
        label=lambda w: w[0][0].id,
        name="registry-exponents",
    )
    for index, outcome in in_order(calls, len(work)):
        if isinstance(outcome, Failure):
            case, options = work[index]
            outcome = refused(case, options, f"no result came back: {outcome.reason}")
        yield outcome


def _analysed_apart(work) -> ExponentResult:
    (case, options), budget = work
    try:
        return analyse_case(case, options, budget=budget)
    except ExponentError as err:
        return refused_by(case, options, err)


def refused_by(case: Case, options: ExponentOptions, err: ExponentError) -> ExponentResult:
    """``refused`` for the error's reason, saying which weights would do where the weights
    asked leave the field no leading part and its default weights give one (a search's
    weights, M: 1, gamma: 2, under which an affine torque's terms dominate)."""
    return refused(case, options, str(err) + _default_would_do(case, options))


def _default_would_do(case: Case, options: ExponentOptions) -> str:
    """The hint of ``refused_by``: empty where the default weights are those asked, or
    leave no leading part either, or the field is refused for another reason."""
    try:
        default = exponent_options(case, None, options.free)
        if default.weights == options.weights:
            return ""
        found = case_field(case, default)
        split_field(found.variables, found.field, found.weights, parameters=found.parameters)
    except (ExponentError, WeightedFieldError):
        return ""
    weights = ",".join(f"{name}={w}" for name, w in default.weights)
    return (
        f"\nunder its default weights, {weights}, the field has a leading part "
        f"(registry exponents {case.id})"
    )


# ------------------------------------------------------------------ one system


def _split(
    case: Case, found: CaseField, parameters: Sequence[sp.Symbol] | None = None
) -> WeightedField:
    """The case's field split under its weights, with its symbolic ``parameters`` (default:
    those that are not free); its problems named by the case's file."""
    if parameters is None:
        parameters = found.parameters
    try:
        return split_field(found.variables, found.field, found.weights, parameters=parameters)
    except WeightedFieldError as err:
        raise _named(case, found, err) from None


def _named(case: Case, found: CaseField, err: WeightedFieldError) -> ExponentError:
    """The maths' problems with the field's components named dx/dt, for the case's file."""
    names = {f"field[{i}]": f"d{x}/dt" for i, x in enumerate(found.variables)}
    return ExponentError(
        _file(case), [Problem(names.get(p.field, p.field), p.message, p.text) for p in err.problems]
    )


def _document(
    case: Case,
    options: ExponentOptions,
    found: CaseField,
    analysis: ExponentAnalysis,
    reduced: Reduction | None = None,
) -> dict[str, Any]:
    """The JSON document of one analysis (docs/json-output.md); an analysis of the
    ``reduced`` field is written back in the case's parameters."""
    back = {} if reduced is None else reduced.back
    document: dict[str, Any] = {
        "case": case.id,
        "weights": dict(options.weights),
        "homogeneous": analysis.homogeneous,
        "free": list(options.free),
        "parameters": [str(p) for p in (found.parameters if reduced else analysis.parameters)],
    }
    if analysis.denominators:
        document["denominators"] = [sp.sstr(d.xreplace(back)) for d in analysis.denominators]
    if not analysis.homogeneous:
        document["leading"] = {
            str(x): sp.sstr(v.xreplace(back))
            for x, v in zip(analysis.variables, analysis.leading, strict=True)
        }
    document |= _analysis_part(analysis, back)
    document["statement"] = statement(
        document, options.weights_text(), [str(p) for p in found.parameters]
    )
    document["notes"] = (
        list(analysis.notes) if reduced is None else _notes_back(analysis, found, reduced)
    )
    document["method"] = METHOD
    document["decided"] = True
    return document


def _notes_back(analysis: ExponentAnalysis, found: CaseField, reduced: Reduction) -> list[str]:
    """The analysis's notes with the one on its generic parameters said of the case's,
    and how the field was reduced (``parameter_translations``)."""
    kept = [n for n in analysis.notes if not n.startswith("parameters ")]
    names = ", ".join(map(str, found.parameters))
    moves = "; ".join(
        ", ".join(
            f"{p} -> {sp.sstr(p + c * _T)}" for p, c in zip(found.parameters, v, strict=True) if c
        )
        for v in reduced.translations
    )
    written = ", ".join(
        f"{sp.sstr(e)} for {p}" for p, e in reduced.back.items() if sp.sstr(e) != p.name
    )
    return [
        *kept,
        f"parameters {names} are treated as generic: the results hold outside a proper "
        "algebraic subset of their values (exponent_family finds special values)",
        f"the field is the same after {moves} for every t: it was analysed with "
        f"{', '.join(f'{p} = 0' for p in reduced.removed)}, its results written back with "
        f"{written}",
    ]


#: The parameter of a translation, in the notes.
_T = sp.Symbol("t")


def _analysis_part(
    analysis: ExponentAnalysis, back: Mapping[sp.Symbol, sp.Expr] | None = None
) -> dict[str, Any]:
    """Balances, exponents, degrees and the Painlevé test of one analysis (``back``: the
    reduced parameters written as the case's, ``parameter_translations``)."""
    balances = [_balance(b, analysis.tested, back) for b in analysis.balances]
    conditions = [
        {"balance": i, **c}
        for i, b in enumerate(balances, 1)
        for r in b["painleve"]["resonances"]
        for c in _obstructions(r)
    ]
    return {
        "balances": balances,
        "all_integer": analysis.all_integer,
        "all_rational": analysis.all_rational,
        "degrees": list(analysis.degrees),
        "painleve": {  # passes: None where only the exponents were computed
            "passes": analysis.painleve_verdict,
            "compatible": analysis.compatible if analysis.tested else None,
            "conditions": conditions,
        },
    }


def _balance(
    b: BalanceResult, tested: bool, back: Mapping[sp.Symbol, sp.Expr] | None = None
) -> dict[str, Any]:
    """One balance: the maths' entry, with its Painlevé test resonance by resonance (its
    ``compatible`` null where the analysis computed no series) and its coordinates along
    a family of balances named ``along``."""
    entry = b.as_dict(back)
    named = dict(back or {})
    if b.balance.root is None:
        named[b.balance.component.symbol] = sp.Symbol("theta")
    entry["along"] = entry.pop("free")
    entry["painleve"] = {
        "compatible": b.painleve.compatible if tested else None,
        "resonances": [
            {
                "order": r.order,
                "multiplicity": r.multiplicity,
                "free": [str(f) for f in r.free],
                "conditions": [f"{sp.sstr(c.xreplace(named))} = 0" for c in r.conditions],
                "missing": r.missing,
            }
            for r in b.painleve.resonances
        ],
    }
    return entry


def _obstructions(resonance: Mapping[str, Any]) -> list[dict[str, Any]]:
    """What fails at one resonance: each condition that does not hold, and a missing free
    coefficient (a Jordan block) as an entry without a condition."""
    found = [
        {"resonance": resonance["order"], "condition": c, "missing": 0}
        for c in resonance["conditions"]
    ]
    if resonance["missing"]:
        found.append(
            {"resonance": resonance["order"], "condition": "", "missing": resonance["missing"]}
        )
    return found


# ------------------------------------------------------------------ families


def _family(
    case: Case, found: CaseField, executor: Executor, budget: float | None, seed: int
) -> tuple[ExponentFamily, tuple[Strata, ...]]:
    """The family's special values, the exact analyses at its candidates run by the
    executor (each bounded by what is left of the budget); with several free parameters
    also the sets where the Painlevé test can pass (``painleve_strata``) and those where
    every exponent is in (1/2)Z (``half_integer_strata``)."""
    started = time.perf_counter()

    def left(share: float = 1.0) -> float | None:
        """The given share of what is left of the budget (None: no budget)."""
        if budget is None:
            return None
        return share * max(1.0, budget - (time.perf_counter() - started))

    mapper = _mapper(executor, left)
    system = (found.variables, found.field, found.weights, found.free)
    try:
        if len(found.free) == 1:
            with time_limit(budget):
                family = exponent_family(*system, seed=seed, mapper=mapper)
            return family, ()
        strata = tuple(
            stratify(*system, seed=seed, budget=left(STRATA_SHARE), mapper=mapper)
            for stratify in (painleve_strata, half_integer_strata)
        )
        generic = None
        try:
            with time_limit(left(GENERIC_SHARE)):
                generic = exponents(
                    found.variables,
                    found.field,
                    found.weights,
                    parameters=found.free,
                    painleve=False,
                )
        except BudgetExceeded:
            pass
        try:
            if all(s.complete for s in strata):
                family = _grid_not_searched(found.free, SUPERSEDED)
            else:
                with time_limit(left()):
                    family = exponent_family(
                        *system, seed=seed, mapper=mapper, grid=_grid(found.free), generic=False
                    )
        except BudgetExceeded:  # the sets where the test can pass are kept
            family = _grid_not_searched(found.free, OUT_OF_TIME)
    except WeightedFieldError as err:
        raise _named(case, found, err) from None
    if generic is None:
        return family, strata
    coverage = tuple(c for c in family.coverage if "generic analysis" not in c)
    family = ExponentFamily(
        family.free,
        generic,
        family.factors,
        family.exceptional,
        family.unexamined,
        family.integer,
        family.rational,
        False,
        False,
        coverage,
        family.seconds,
        family.half_integer,
        False,
    )
    return family, strata


def _grid_not_searched(free: Sequence[sp.Symbol], note: str) -> ExponentFamily:
    """A family whose grid of small values was not searched, and why."""
    return ExponentFamily(tuple(free), None, (), (), (), (), (), False, False, (note,))


def _mapper(executor: Executor, left: Callable[[], float | None]):
    """``mapper(fn, items)`` of the executor: results in order, None where a call failed
    (a value whose analysis did not come back is then not reported)."""

    def mapper(fn, items):
        if not items:
            return []
        calls = executor.map(
            fn,
            list(items),
            deadline=left(),
            label=lambda item: ", ".join(f"{k} = {v}" for k, v in item[3].items()),
            name="registry-exponents",
        )
        return [
            None if isinstance(outcome, Failure) else outcome
            for _, outcome in in_order(calls, len(items))
        ]

    return mapper


def _grid(free: Sequence[sp.Symbol]) -> dict[sp.Symbol, tuple[sp.Expr, ...]]:
    """The small values tried for each free parameter, those its assumptions allow."""
    return {p: tuple(v for v in GRID if _allowed(p, v)) for p in free}


def _allowed(p: sp.Symbol, value: sp.Expr) -> bool:
    """Whether a value respects the parameter's declared assumption (a real algebraic
    value's sign decided exactly)."""
    value = sp.nsimplify(value) if value.is_Float else value
    if value.is_real is False:
        return False
    if p.is_positive and not bool(value > 0):
        return False
    if p.is_nonzero and value == 0:
        return False
    return not (p.is_integer and value.is_integer is not True)


def _family_document(
    case: Case,
    options: ExponentOptions,
    found: CaseField,
    family: ExponentFamily,
    strata: Strata | None = None,
    half: Strata | None = None,
) -> dict[str, Any]:
    """The JSON document of a family: the generic analysis (where it was made) and the
    ``special`` list, each set with its exponents and Painlevé test."""
    generic = family.generic
    document: dict[str, Any] = {
        "case": case.id,
        "weights": dict(options.weights),
        "homogeneous": generic.homogeneous if generic is not None else None,
        "free": list(options.free),
        "parameters": [],
    }
    if generic is not None:
        if not generic.homogeneous:
            document["leading"] = {
                str(x): sp.sstr(v) for x, v in zip(generic.variables, generic.leading, strict=True)
            }
        document |= _analysis_part(generic)  # the Painlevé test of generic members
    else:
        document |= {"balances": [], "all_integer": None, "all_rational": None, "degrees": []}
        document["painleve"] = {"passes": None, "compatible": None, "conditions": []}
    dropped: list[str] = []
    special = [s for s in family.special if _kept(s, dropped)]
    document["special"] = [_special(s) for s in special]
    document["exponent_polynomial"] = [
        {"factor": sp.sstr(f), "multiplicity": m} for f, m in family.factors
    ]
    document["exceptional"] = [f"{sp.sstr(q)} = 0" for q in family.exceptional]
    document["complete"] = {
        "integer": family.complete_integer,
        "half_integer": family.complete_half_integer,
        "rational": family.complete_rational,
    }
    coverage = list(family.coverage)
    if dropped:
        coverage.append(f"left out, against the declared assumptions: {', '.join(dropped)}")
    document["coverage"] = coverage
    if strata is not None:
        document["painleve_sets"] = _painleve_sets(strata)
        if document["painleve"]["passes"] is None:
            document["painleve"]["passes"] = _generic_verdict(strata)
    if half is not None:
        document["half_integer_sets"] = _half_integer_sets(half)
    document["statement"] = family_statement(document, options.weights_text())
    document["notes"] = list(generic.notes) if generic is not None else []
    document["method"] = METHOD
    document["decided"] = True
    return document


def _generic_verdict(strata: Strata) -> bool | None:
    """The generic members' Painlevé test where the family's own analysis did not make it
    (several parameters), read from the stratification: passing where the whole space is
    a passing set (its series computed over Q(p)), failing where the list is complete
    and every passing set is smaller, unknown otherwise."""
    if any(not s.values for s in strata.passing):
        return True
    return False if strata.complete else None


def _kept(s: SpecialSet, dropped: list[str]) -> bool:
    """Whether a special point respects the declared assumptions (an infinite family is
    kept whole: its index ranges over every value the equations allow)."""
    if s.index is not None or all(_allowed(p, v) for p, v in s.values.items()):
        return True
    dropped.append(", ".join(f"{p} = {sp.sstr(v)}" for p, v in s.values.items()))
    return False


def _special(s: SpecialSet) -> dict[str, Any]:
    """One special set: its equations, kind, and exponents with the Painlevé test (of the
    point, or of a few members of an infinite family)."""
    entry: dict[str, Any] = {
        "when": [f"{p} = {sp.sstr(v)}" for p, v in s.values.items()],
        "kind": s.kind,
    }
    if s.index is not None:
        entry["index"] = {"name": str(s.index), "ranges": s.ranges}
        entry["members"] = [_member(a) for a in s.members]
    if s.analysis is not None:
        entry |= _member(s.analysis)
    entry["notes"] = list(s.notes)
    return entry


def _painleve_sets(strata: Strata) -> dict[str, Any]:
    """The sets where the Painlevé test passes (``painleve_strata``): each with its
    equations, the parameters left free on it, and its exponents and test."""
    return {"passing": [_stratum(s) for s in strata.passing], **_coverage(strata)}


def _half_integer_sets(strata: Strata) -> dict[str, Any]:
    """The sets where every exponent is in (1/2)Z (``half_integer_strata``), each as in
    ``_painleve_sets`` with its ``kind``: "integer", "half-integer", or None where the
    set's exponents vary (an infinite family) and no single analysis stands for it."""
    sets = []
    for s in strata.passing:
        kind = kind_of(s.analysis) if s.analysis is not None else None
        sets.append({**_stratum(s), "kind": kind if kind in ("integer", "half-integer") else None})
    return {"sets": sets, **_coverage(strata)}


#: The note of a set whose leading part has no balance: it passes, but vacuously.
NO_BALANCE = "the leading part has no balance here: the test has nothing to check"


def _stratum(s) -> dict[str, Any]:
    """One set found by a stratification: equations, free parameters, analysis, notes."""
    entry: dict[str, Any] = {
        "when": [f"{p} = {sp.sstr(v)}" for p, v in s.values.items()],
        "free": [str(p) for p in s.free],
    }
    vacuous = []
    if s.analysis is not None:
        entry |= _member(s.analysis)
        if not s.analysis.balances:
            vacuous = [NO_BALANCE]
    integers = [f"{p} runs over the integers" for p in s.free if p.is_integer]
    entry["notes"] = [*s.notes, *vacuous, *integers]
    return entry


def _name_sets(
    case: Case, strata: Sequence[Strata], document: dict[str, Any], catalog: CatalogIndex
) -> None:
    """Each set of the stratifications (its generic member: the case at the set's values)
    with ``same_as``, the catalog cases it is the same system as, most specific first
    (empty: none matched under the equivalences ``identification`` tries). A set given
    through a new parameter (w1, an index n1), where the case is not defined, or whose
    identification could not compare every catalog case, gets no ``same_as``."""
    own = set(case.parameters.values())
    keys = (("painleve_sets", "passing"), ("half_integer_sets", "sets"))
    for found, (key, inner) in zip(strata, keys, strict=False):
        for s, entry in zip(found.passing, document[key][inner], strict=True):
            if not all(sp.sympify(v).free_symbols <= own for v in s.values.values()):
                continue
            sub = with_values(case, s.values)
            if sub is None:
                continue
            result = identify(sub.dynamics, catalog, exclude=(case.id,))
            if result.skipped or result.failed:
                entry["notes"].append("not identified with the whole catalog in time")
                continue
            entry["same_as"] = [same.case for same in result.same]


def _coverage(strata: Strata) -> dict[str, Any]:
    """Whether a stratification's list is complete, and what it left undecided."""
    return {
        "complete": strata.complete,
        "undecided": list(strata.undecided),
        "strata": strata.visited,
        "seconds": round(strata.seconds, 3),
    }


def _member(analysis: ExponentAnalysis) -> dict[str, Any]:
    part = _analysis_part(analysis)
    return {
        "exponents": [b["exponents"] for b in part["balances"]],
        "degrees": part["degrees"],
        "painleve": {
            "passes": part["painleve"]["passes"],
            "conditions": part["painleve"]["conditions"],
        },
    }


# ------------------------------------------------------------------ helpers


def _file(case: Case) -> str:
    """How an error names the case: its file's path, else its id."""
    return case.path or case.id
