"""The domain: a case from the literature, its system and the claims made for it.

These frozen dataclasses are what a parsed case file becomes; storage rows
are converted to and from them in one place (``store.conversions``). Expressions are
kept twice: as sympy objects for the algebra and as the text the author
wrote, so that what is stored and printed is what the paper says.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING, Any, NoReturn, TypedDict

import sympy as sp

from .dynamics import Weights, as_weights
from .expression import Expression

if TYPE_CHECKING:
    from .dynamics import Dynamics

__all__ = ["Expression", "Weights", "as_weights"]  # defined beside the model, used with it


class Assumption(StrEnum):
    """What a case file may declare of a parameter (all parameters are real)."""

    REAL = "real"
    POSITIVE = "positive"
    NONZERO = "nonzero"
    INTEGER = "integer"


class Provenance(StrEnum):
    """Where a claim comes from: a source in the literature, or ``registry discover``."""

    LITERATURE = "literature"
    DISCOVERED = "discovered"


class ClaimKind(StrEnum):
    """What the source claims of an expression."""

    INTEGRAL = "integral"  # conserved along every solution
    CASIMIR = "casimir"  # a Casimir function of the bracket
    MEASURE = "measure"  # the density rho of an invariant measure: div(rho v) = 0
    RELATION = "relation"  # its zero set is invariant: dF/dt vanishes where F = 0

    @property
    def conserved(self) -> bool:
        """Whether a claim of this kind is a first integral (an integral or a Casimir;
        a density or an invariant relation is none): what searches count as known."""
        return self in (ClaimKind.INTEGRAL, ClaimKind.CASIMIR)


class Verdict(StrEnum):
    """The outcome of one check. ``error`` means the check itself crashed."""

    VERIFIED = "verified"
    REFUTED = "refuted"
    INCONCLUSIVE = "inconclusive"
    ERROR = "error"

    @classmethod
    def combined(cls, verdicts: Iterable[Verdict]) -> Verdict:
        """The verdict of several checks taken together: verified only if all are; refuted
        if one is; else error if one crashed; else inconclusive (also for none at all)."""
        found = set(verdicts)
        if found == {cls.VERIFIED}:
            return cls.VERIFIED
        for verdict in (cls.REFUTED, cls.ERROR):
            if verdict in found:
                return verdict
        return cls.INCONCLUSIVE


@dataclass(frozen=True)
class Equation:
    """One level-set equation ``lhs = rhs`` of a claim's ``on`` list."""

    text: str
    lhs: sp.Expr
    rhs: sp.Expr

    @property
    def expr(self) -> sp.Expr:
        """lhs - rhs, which vanishes on the level set."""
        return self.lhs - self.rhs


@dataclass(frozen=True)
class Source:
    """Where a case comes from in the literature: the citation as a reader writes it,
    where in the source (``locator``), and the structured fields BibTeX needs."""

    citation: str
    locator: str = ""
    doi: str = ""
    authors: tuple[str, ...] = ()
    year: int | None = None
    title: str = ""
    journal: str = ""
    booktitle: str = ""
    publisher: str = ""
    volume: str = ""
    issue: str = ""
    pages: str = ""
    url: str = ""


@dataclass(frozen=True)
class Claim:
    """An integral of motion that a source claims for a system (or that a search found,
    ``provenance`` discovered)."""

    label: str
    kind: ClaimKind
    expression: Expression
    on: tuple[Equation, ...] = ()
    locator: str = ""
    notes: str = ""
    provenance: Provenance = Provenance.LITERATURE


@dataclass(frozen=True)
class System:
    """The system of a case as its file gives it (docs/case-format.md), in one of four
    forms; ``language.forms`` turns each into the ``Dynamics`` every other layer reads.

    The inertia form: principal moments (A, B, C) and the potential U(gamma), so that
    H = M.I^-1 M/2 + U; the Hamiltonian form: ``hamiltonian`` H itself (``inertia`` is
    then empty and ``potential`` 0). Both have the torque vector mu and the bracket's
    parameter ``kappa`` (0: e(3), > 0: so(4), < 0: so(3,1)); the equations of motion are
    dx/dt = Pi grad H with Pi = [[hat(M + mu), hat(gamma)], [hat(gamma), kappa hat(M)]].
    A system on any phase space names its ``variables`` and gives either ``equations``
    (dx/dt for each variable, in their order) or ``hamiltonian`` with ``bracket`` (the
    entries {x, y} that are not zero, as (x, y, value)); ``definitions`` are names for
    sub-expressions, expanded in every expression of the case (system and claims).
    """

    inertia: tuple[Expression, ...]
    potential: Expression
    torque: tuple[Expression, Expression, Expression]
    hamiltonian: Expression | None = None
    kappa: Expression = Expression("0", sp.Integer(0))
    variables: tuple[str, ...] = ()
    equations: tuple[Expression, ...] = ()
    bracket: tuple[tuple[str, str, Expression], ...] = ()
    definitions: tuple[tuple[str, Expression], ...] = ()

    @property
    def hamiltonian_form(self) -> bool:
        """Whether the case gives H itself (``system.hamiltonian``) rather than A, B, C, U."""
        return self.hamiltonian is not None

    @property
    def form(self) -> str:
        """Which of the four forms the file uses: "inertia" or "hamiltonian" (the
        reference paper's state M, gamma), "equations" or "bracket" (a state of its own)."""
        if self.variables:
            return "bracket" if self.bracket or not self.equations else "equations"
        return "hamiltonian" if self.hamiltonian_form else "inertia"

    @property
    def inertia_exprs(self) -> tuple[sp.Expr, ...]:
        return tuple(e.expr for e in self.inertia)

    @property
    def torque_exprs(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        return tuple(e.expr for e in self.torque)

    @property
    def kappa_expr(self) -> sp.Expr:
        return self.kappa.expr


class FrozenDict(dict):
    """A read-only dict that pickles (results travel between worker processes)."""

    def _readonly(self, *args: object, **kwargs: object) -> NoReturn:
        raise TypeError("this mapping is read-only")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = _readonly

    def __reduce__(self) -> tuple[type[FrozenDict], tuple[dict]]:
        return (FrozenDict, (dict(self),))

    def __hash__(self) -> int:  # type: ignore[override]
        return hash(tuple(sorted(self.items(), key=repr)))


def _frozen(mapping: Mapping | None) -> Mapping:
    return FrozenDict(mapping or {})


@dataclass(frozen=True)
class Case:
    """One system from the literature with the claims its source makes.

    ``system`` is the system as the file states it (its form's fields, kept to be
    stored and written back); ``dynamics`` is the same system in the one form every
    other layer reads (``registry.dynamics``, built by ``language.forms``).
    ``parameters`` maps each declared constant to its sympy symbol (which carries
    the assumption); ``functions`` maps each declared arbitrary function to its
    sympy function class and argument symbols. ``text`` is the case file as
    loaded and ``content_hash`` identifies its content (see ``language.casefile``).
    """

    id: str
    title: str
    source: Source
    system: System
    dynamics: Dynamics = field(compare=False, repr=False)
    claims: tuple[Claim, ...] = ()
    parameters: Mapping[str, sp.Symbol] = field(default_factory=dict)
    assumptions: Mapping[str, Assumption] = field(default_factory=dict)
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = field(
        default_factory=dict
    )
    notes: str = ""
    topic: str = ""
    aliases: tuple[str, ...] = ()
    text: str = ""
    content_hash: str = ""
    path: str | None = None

    def __post_init__(self) -> None:
        for name in ("parameters", "assumptions", "functions"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))

    def claim(self, label: str) -> Claim:
        """The claim with this label (KeyError if the case has none)."""
        for c in self.claims:
            if c.label == label:
                return c
        raise KeyError(label)


#: Names a case file may not use for parameters or functions: the state variables and
#: ``s`` (the symbols of ``registry.mathematics.mechanics``, written out so that the
#: domain model depends on nothing else in the package).
VARIABLE_NAMES: tuple[str, ...] = ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3", "s")


@dataclass(frozen=True)
class Witness:
    """A point where a residual was evaluated and found nonzero.

    ``point`` gives exact values (expression-language text) of the state
    variables and parameters; ``functions`` the concrete functions substituted
    for a family's arbitrary ones; ``value`` the exact residual there (or a
    certified enclosure) and ``approx`` a decimal approximation of it.
    """

    point: Mapping[str, str]
    value: str
    approx: str
    component: str = ""
    functions: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", _frozen(self.point))
        object.__setattr__(self, "functions", _frozen(self.functions))

    def as_dict(self) -> dict:
        return {
            "point": dict(self.point),
            "value": self.value,
            "approx": self.approx,
            "component": self.component,
            "functions": dict(self.functions),
        }


@dataclass(frozen=True)
class CheckResult:
    """The outcome of one check on one case (and one claim, for claim checks).

    ``method`` names the stage that decided (e.g. ``exact probe``,
    ``rational normal form``); ``reason`` explains an inconclusive or error
    verdict; ``residual`` is the expression that should vanish, as text; ``detail`` what
    a verified check adds (the cofactor of an invariant relation).
    """

    check: str
    verdict: Verdict
    method: str
    claim: str | None = None
    reason: str = ""
    residual: str | None = None
    witness: Witness | None = None
    seconds: float = 0.0
    #: what a verified check adds for people (a relation's cofactor K in dF/dt = K F)
    detail: str = ""


def component_number(index: int) -> int:
    """The number people read (mu1, mu2, mu3; JSON, tables, reports) of the torque
    component with 0-based ``index``; ``component_index`` is its inverse."""
    return index + 1


def component_index(number: int) -> int:
    """The 0-based index of the torque component people number ``number`` (1, 2 or 3)."""
    return number - 1


@dataclass(frozen=True)
class Correction:
    """A correction, re-checked before it is reported (``checks``: check name -> verdict).

    ``kind`` is ``casimir`` (a Casimir of the case's own torque, ``expression``) or
    ``torque`` (a torque ``torque`` under which the claim is a Casimir, differing
    from the case's in the 0-based components ``changed``). ``claim`` is the claim
    it corrects, or None for a Casimir the case did not claim. Expressions are
    written in the case-file language.
    """

    kind: str
    claim: str | None = None
    expression: str | None = None
    torque: tuple[str, str, str] | None = None
    changed: tuple[int, ...] = ()
    method: str = ""
    checks: Mapping[str, Verdict] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "checks", _frozen(self.checks))

    @property
    def changed_components(self) -> tuple[tuple[int, str], ...]:
        """(number, corrected expression) of each changed torque component, mu_number'."""
        torque = self.torque or ()
        return tuple((component_number(k), torque[k]) for k in self.changed)

    @property
    def kept_components(self) -> tuple[int, ...]:
        """The numbers of the torque components the correction keeps as they were."""
        return tuple(component_number(k) for k in range(3) if k not in self.changed)

    def as_dict(self) -> dict:
        out: dict = {"kind": self.kind}
        if self.expression is not None:
            out["expression"] = self.expression
        if self.torque is not None:
            out["torque"] = list(self.torque)
            out["changed"] = [number for number, _ in self.changed_components]
        out["method"] = self.method
        out["checks"] = {name: str(verdict) for name, verdict in self.checks.items()}
        return out


@dataclass(frozen=True)
class Conditions:
    """Parameter equations under which a failed identity holds: ``target`` is
    ``jacobi`` or a claim label; each branch is a tuple of ``lhs = rhs`` texts,
    the most general first; ``reason`` says why there is none."""

    target: str
    branches: tuple[tuple[str, ...], ...] = ()
    reason: str = ""


@dataclass(frozen=True)
class FamilyRecord:
    """The paper's family of the case's torque, and the functions that exhibit it (as text)."""

    name: str
    phi: str | None = None
    psi: str | None = None
    a: str | None = None
    casimir: str | None = None
    method: str = ""
    reason: str = ""

    def as_dict(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if v not in (None, "")}


def nan_to_none(x: float) -> float | None:
    """A number that may not exist (NaN: nothing was integrated) as None, the form JSON
    and SQL (NULL) give it; ``none_to_nan`` is its inverse."""
    return None if x != x else float(x)


def none_to_nan(x: float | None) -> float:
    """A number read back from JSON or SQL: None (NULL) becomes NaN again."""
    return float("nan") if x is None else x


@dataclass(frozen=True)
class Evidence:
    """Numerical evidence for a claim: the largest relative drift of I along integrated
    trajectories, that of H (the noise floor), how many runs, and whether the numbers
    contradict the symbolic verdict they were compared with (``compared_with``: the
    ``integral`` check for an integral or a Casimir, since a drift speaks of
    conservation only; ``measure`` or ``relation`` for those kinds). ``narrowed``
    says why the trajectories stand on a smaller set than the claim's, if they do. On a
    level set, ``departure`` is the largest relative residual of its equations where the
    drift was measured, ``projected`` whether the trajectories were projected back onto
    it, and ``reason`` why the drift was not compared (they left the set), if it was not."""

    claim: str
    drift: float
    floor: float
    runs: int
    contradicts: bool = False
    note: str = ""
    compared_with: str = "integral"
    narrowed: str = ""
    departure: float | None = None
    projected: bool = False
    reason: str = ""

    def as_dict(self) -> dict:
        return {
            "drift": nan_to_none(self.drift),
            "floor": nan_to_none(self.floor),
            "runs": self.runs,
            "agrees": not self.contradicts,
            "compared_with": self.compared_with,
            **({"narrowed": self.narrowed} if self.narrowed else {}),
            **({"departure": self.departure} if self.departure is not None else {}),
            **({"projected": True} if self.projected else {}),
            **({"reason": self.reason} if self.reason else {}),
            **({"note": self.note} if self.note else {}),
        }


@dataclass(frozen=True)
class DriftCurve:
    """One integrated trajectory of a claim, as data to draw: the times and the changes
    I(t) - I(0) and H(t) - H(0) there (H's is empty for a system without one)."""

    case: str
    claim: str
    t: tuple[float, ...]
    di: tuple[float, ...]
    dh: tuple[float, ...] = ()


@dataclass(frozen=True)
class CaseAudit:
    """All check results for one case version, with the corrections derived from them."""

    case: str
    content_hash: str
    results: tuple[CheckResult, ...]
    family: FamilyRecord | None = None
    corrections: tuple[Correction, ...] = ()
    conditions: tuple[Conditions, ...] = ()
    evidence: tuple[Evidence, ...] = ()
    #: the trajectories integrated for refuted claims, to draw their drift
    curves: tuple[DriftCurve, ...] = ()

    def result(self, check: str, claim: str | None = None) -> CheckResult:
        """The result of ``check`` (on ``claim``); KeyError if it was not run."""
        for r in self.results:
            if r.check == check and r.claim == claim:
                return r
        raise KeyError((check, claim))


class CaseFilter(TypedDict, total=False):
    """Which cases to list (``Registry.cases``), every filter optional, None for none,
    and all of them combined. Text filters ignore case."""

    #: text in the citation, the source's title or its journal
    source: str | None
    #: text in an author's name
    author: str | None
    #: a year, or an inclusive range of years
    year: int | tuple[int, int] | None
    topic: str | None
    #: the torque family the case's newest audit found (exact)
    family: str | None
    #: some claim's overall verdict (its kind's check)
    verdict: str | Verdict | None


def case_filter(filters: Mapping[str, Any]) -> CaseFilter:
    """``filters`` as a ``CaseFilter``; a TypeError naming any keyword that is not one of
    its filters (a misspelt filter must not list every case)."""
    unknown = sorted(set(filters) - set(CaseFilter.__annotations__))
    if unknown:
        known = ", ".join(CaseFilter.__annotations__)
        raise TypeError(f"no case filter {', '.join(map(repr, unknown))}; the filters are {known}")
    return CaseFilter(**filters)  # type: ignore[typeddict-item]


@dataclass(frozen=True)
class VerdictChange:
    """A verdict that differs between two audit runs of a case: of ``check`` on ``claim``
    (None for a check of the case itself); ``before`` or ``after`` is None where that
    run has no such result."""

    case: str
    claim: str | None
    check: str
    before: Verdict | None
    after: Verdict | None


@dataclass(frozen=True)
class SearchOptions:
    """What an integral search looks for: the ansatz's largest weighted degree, the
    weights of the state's vectors (M and gamma for the reference paper's state), the
    level set (``on``), and the parameters whose special values are sought (``free``;
    the others stay symbolic and generic). With ``relations`` it looks for Darboux
    polynomials instead (dF/dt = K F, the cofactor K's coefficients sought like free
    parameters): invariant relations F = 0."""

    degree: int = 4
    weights: Weights = (("M", 1), ("gamma", 2))
    on: tuple[Equation, ...] = ()
    free: tuple[str, ...] = ()
    relations: bool = False

    def __post_init__(self) -> None:
        if self.degree < 1:
            raise ValueError(f"the degree of the ansatz must be at least 1, not {self.degree}")
        object.__setattr__(self, "weights", as_weights(self.weights))
        object.__setattr__(self, "on", tuple(self.on))
        object.__setattr__(self, "free", tuple(self.free))

    @property
    def weight_of(self) -> dict[str, int]:
        """The weights by vector name."""
        return dict(self.weights)

    def weights_text(self, sep: str = ": ") -> str:
        """``M: 1, gamma: 2`` (or with another separator, ``M=1,gamma=2``)."""
        glue = ", " if sep.endswith(" ") else ","
        return glue.join(f"{name}{sep}{w}" for name, w in self.weights)

    def as_dict(self) -> dict:
        """The options as plain data (stored with a search; the key of its reuse)."""
        return {
            "degree": self.degree,
            "weights": dict(self.weights),
            "on": [eq.text for eq in self.on],
            "free": list(self.free),
        } | ({"relations": True} if self.relations else {})


@dataclass(frozen=True)
class IntegralStatus:
    """Whether an integral a search found is ``new`` or a ``rediscovered`` claim of the
    searched case or of a catalog case that is the same system (``equals`` then names it
    ``case-id:label``): it equals the claims ``equals`` modulo the known integrals
    ``modulo`` (H, |gamma|^2, ...) and their products, by the exact identity
    ``relation`` (``F = K + 2*H**2``, checked in the system's ring)."""

    status: str
    equals: tuple[str, ...] = ()
    modulo: tuple[str, ...] = ()
    relation: str = ""

    @property
    def new(self) -> bool:
        return self.status == "new"


@dataclass(frozen=True)
class SameSystem:
    """A catalog case that a set of parameter values of a search (or a case) is the same
    system as: the ``case`` id, the values of its parameters (text, in the set's own
    parameters), the ``transformation`` (the case's variables and time as expressions of
    the set's), and the labels of the case's claims the set's integrals equal."""

    case: str
    values: tuple[tuple[str, str], ...] = ()
    transformation: tuple[tuple[str, str], ...] = ()
    claims: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        return {
            "case": self.case,
            "values": dict(self.values),
            "transformation": dict(self.transformation),
            "claims": list(self.claims),
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> SameSystem:
        return cls(
            str(data["case"]),
            tuple((str(k), str(v)) for k, v in dict(data.get("values", {})).items()),
            tuple((str(k), str(v)) for k, v in dict(data.get("transformation", {})).items()),
            tuple(str(c) for c in data.get("claims", ())),
        )


@dataclass(frozen=True)
class CaseIdentification:
    """Which catalog cases one case version is the same system as (issue 33): each with
    the values of its parameters and the transformation (``same_as``); the cases it was
    compared with, those left when the time ran out (``skipped``) and those whose
    comparison failed (never said to be other systems); the ``catalog`` compared with (a
    digest of its case versions: a new case makes it stale) and whether a recorded
    identification was ``reused``. Finding no case proves nothing."""

    case: str
    version: int
    catalog: str
    same_as: tuple[SameSystem, ...] = ()
    compared: tuple[str, ...] = ()
    skipped: tuple[str, ...] = ()
    failed: tuple[tuple[str, str], ...] = ()
    seconds: float = 0.0
    reused: bool = False
    #: why the case itself was compared with none (its field has no normal form)
    note: str = ""

    @property
    def complete(self) -> bool:
        """Whether every case was compared (none skipped or failed)."""
        return not self.skipped and not self.failed

    def as_dict(self) -> dict:
        """The JSON of ``registry identify --json`` for this case."""
        return {
            "case": self.case,
            "version": self.version,
            "same_as": [s.as_dict() for s in self.same_as],
            "compared": len(self.compared),
            "skipped": list(self.skipped),
            "failed": [{"case": c, "error": e} for c, e in self.failed],
            "complete": self.complete,
            "seconds": round(self.seconds, 3),
            "reused": self.reused,
            "note": self.note,
        }


@dataclass(frozen=True)
class IntegralSet:
    """The extra integrals on a set of parameter values: ``when`` (equations taken
    together, as text; empty for the generic values), how many there are, a basis of
    them (expressions as text, each proven an integral by the audit's zero test), and
    the audit's ``casimir`` verdict on each, for information."""

    when: tuple[str, ...]
    extra: int
    integrals: tuple[str, ...] = ()
    casimir: tuple[Verdict, ...] = ()
    #: per integral: new, or a claim rediscovered (empty where it was not decided)
    status: tuple[IntegralStatus, ...] = ()
    #: a search for relations: the cofactor K of these Darboux polynomials (dF/dt = K F)
    cofactor: str = ""
    #: the catalog cases that are the same system here (``discovery.identification``)
    same_as: tuple[SameSystem, ...] = ()

    @property
    def new(self) -> tuple[str, ...]:
        """The integrals that are not (combinations of) the case's claims."""
        if not self.status:
            return self.integrals
        return tuple(i for i, s in zip(self.integrals, self.status, strict=True) if s.new)

    @property
    def rediscovered(self) -> tuple[str, ...]:
        return tuple(i for i, s in zip(self.integrals, self.status, strict=True) if not s.new)


@dataclass(frozen=True)
class Density:
    """A density rho = prod F**a (``factors``: (F, a) as text), the audit's ``measure``
    verdict on it, and the factors where it is singular or undefined (a negative or
    fractional exponent: rho has no finite positive value where that F vanishes)."""

    expression: str
    factors: tuple[tuple[str, str], ...]
    verdict: Verdict
    singular: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        return {
            "density": self.expression,
            "factors": [{"F": f, "exponent": a} for f, a in self.factors],
            "measure": str(self.verdict),
            "singular_where": [f"{f} = 0" for f in self.singular],
        }


@dataclass(frozen=True)
class MeasureSearch:
    """What the search for densities prod F_i**a_i of a case found: the Darboux
    polynomials of the ansatz with their cofactors (of the case's own field), the
    densities (one per solution; the ansatz's every density is one of them times a
    function of ``integrals``), the first integrals prod F_i**b_i the homogeneous
    system gives, what was left undecided, the statement, and the time."""

    case: str
    darboux: tuple[tuple[str, str], ...]
    densities: tuple[Density, ...]
    integrals: tuple[str, ...]
    candidates: tuple[str, ...]
    complete: bool
    statement: str
    undecided: tuple[str, ...] = ()
    seconds: float = 0.0

    @property
    def smooth(self) -> tuple[Density, ...]:
        """The densities that are polynomials (defined and finite everywhere)."""
        return tuple(d for d in self.densities if not d.singular)

    def as_dict(self) -> dict:
        return {
            "case": self.case,
            "ansatz": "rho = prod F_i**a_i",
            "candidates": list(self.candidates),
            "darboux": [{"F": f, "cofactor": k} for f, k in self.darboux],
            "densities": [d.as_dict() for d in self.densities],
            "integrals": list(self.integrals),
            "complete": self.complete,
            "undecided": list(self.undecided),
            "statement": self.statement,
            "seconds": round(self.seconds, 3),
        }


@dataclass(frozen=True)
class Search:
    """The outcome of an integral search of a case (a family, with ``options.free``).

    ``generic`` holds for all values of the free parameters that the assumptions allow
    (outside ``special``); ``special`` lists every set of values with more extra
    integrals. ``complete`` is true only when the method guarantees that no other
    special set exists for this ansatz; ``coverage`` says what was covered.
    ``dimensions`` gives, for generic values and each weighted degree d, (d, integrals
    of degree <= d, trivial ones among them, extra ones found at d).
    """

    case: str
    content_hash: str
    options: SearchOptions
    known: tuple[str, ...]
    generic: IntegralSet
    special: tuple[IntegralSet, ...]
    complete: bool
    coverage: tuple[str, ...] = ()
    dimensions: tuple[tuple[int, int, int, int], ...] = ()
    seconds: float = 0.0
    method: str = ""
    #: the case's claims proven integrals (on the searched level set) and counted as known
    claims: tuple[str, ...] = ()

    @property
    def decided(self) -> bool:
        """Whether the generic values were searched to the end (``dimensions`` then holds
        their counts). A search refused or cut short before that establishes nothing."""
        return bool(self.dimensions)

    @property
    def claims_complete(self) -> bool:
        """Whether the case's claims span every integral of the ansatz beyond the known
        ones: the search is complete, has claims, and every generic integral it found is
        one of them rediscovered (a family: and no special set carries more)."""
        return self.complete and bool(self.claims) and not self.special and not self.generic.new


@dataclass(frozen=True)
class ExponentOptions:
    """What a Kovalevskaya analysis is asked: the weights of the state's vectors (every
    vector named, ``("M", 1), ("gamma", 2)``) and the parameters whose special values are
    sought (``free``; the others stay symbolic and generic)."""

    weights: Weights
    free: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "weights", as_weights(self.weights))
        object.__setattr__(self, "free", tuple(self.free))

    def weights_text(self, sep: str = ": ") -> str:
        """``M: 1, gamma: 2`` (or with another separator, ``M=1,gamma=2``)."""
        glue = ", " if sep.endswith(" ") else ","
        return glue.join(f"{name}{sep}{w}" for name, w in self.weights)

    def as_dict(self) -> dict:
        """The options as plain data (stored with an analysis; the key of its reuse)."""
        return {"weights": dict(self.weights), "free": list(self.free)}


@dataclass(frozen=True)
class ExponentResult:
    """A Kovalevskaya analysis of a case: its options and its JSON ``document`` (the
    format of docs/json-output.md, "Kovalevskaya exponents": every balance, its exponents,
    Yoshida's degrees, the Painlevé test and the statement, every expression as text),
    which is what the registry stores. ``decided`` is false for an analysis the method
    refused or did not finish (``document["reason"]`` says why): it establishes nothing."""

    case: str
    content_hash: str
    options: ExponentOptions
    document: Mapping[str, Any]
    seconds: float = 0.0

    @property
    def decided(self) -> bool:
        return bool(self.document.get("decided", True))

    @property
    def homogeneous(self) -> bool:
        return bool(self.document.get("homogeneous", False))

    @property
    def all_integer(self) -> bool:
        return bool(self.document.get("all_integer", False))

    @property
    def all_rational(self) -> bool:
        return bool(self.document.get("all_rational", False))

    @property
    def degrees(self) -> tuple[int, ...]:
        """Yoshida's degrees: the weighted degrees an integral with a gradient not zero at
        some balance can have (meaningful only where ``decided``)."""
        return tuple(int(d) for d in self.document.get("degrees", ()))

    @property
    def balances(self) -> int:
        """How many balances (a family of balances counted once)."""
        return len(self.document.get("balances", ()))

    @property
    def passes(self) -> bool | None:
        """The Painlevé (ARS) test's verdict: True where it passes (integer exponents,
        every condition holding), False where it fails (also where an analysis out of
        time found a ``witness`` of the failure), None where it was not made (an
        undecided analysis, or integer exponents whose Laurent series was not computed)."""
        painleve = self.document.get("painleve") or {}
        verdict = painleve.get("passes") if self.decided or "witness" in self.document else None
        return None if verdict is None else bool(verdict)

    @property
    def statement(self) -> str:
        return str(self.document.get("statement", ""))
