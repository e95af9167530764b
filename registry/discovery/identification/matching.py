"""Whether one system is a member of a catalog case, and by which transformation: the
equations of ``transformations`` solved for the transformation's unknowns and the case's
parameter values (``equation_solver``), then checked exactly.

The attempts go from the simplest to the most general, and stop at the first match:
the order of the axes (the identity first; where both inverse inertias are diagonal
numbers, only orders that match their ratios), with signs of the axes as unknowns
(+-1); then, with a residual shift (h0, then h0 + h.gamma) where both fields are in
normal form; then with a rotation about the first system's axis of symmetry where two
of its moments are equal. The other unknowns are the case's parameters and the scalings
tau, lam, rho. Equations are built over Q with p (the first system's parameters) as
generators, both fields cleared of their denominators, then read in K[unknowns], K = Q
or Q(p). Where the system has parameters, the attempts are first made at one fixed
point of them (``specialised``), over Q: a match at generic values is one there, so a
failed probe skips the generic attempt, which costs far more.

A solution is completed with the simplest values for what it leaves free (a scaling 1
or -1, so that the case's positive parameters come out positive), its values must be
real (no even root of an expression of either sign) and of the kinds the case declares,
and it is kept only when the transformed field equals the case's exactly: a match is a
proof. Finding none proves nothing: the system is then said to match no case, never
that none exists.
"""

from __future__ import annotations

import itertools
import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.polys.rings import PolyElement, PolyRing

from .equation_solver import Problem, solve
from .field_form import GAMMA, STATE, FieldForm
from .transformations import PERMUTATIONS, Transformation, axes_matrix

TAU, LAM, RHO = sp.symbols("tau_ lam_ rho_")
SIGNS = sp.symbols("e1_ e2_ e3_")
COS, SIN = sp.symbols("cos_ sin_")
SHIFT = sp.symbols("h0_ h1_ h2_ h3_")
#: The seed of the values ``specialised`` gives the first system's parameters.
PROBE_SEED = 1889
PRIMED = sp.symbols("Lp1_ Lp2_ Lp3_ gp1_ gp2_ gp3_")


@dataclass(frozen=True)
class Match:
    """The case's parameter ``values`` (expressions in the first system's parameters) and
    the ``transformation`` that carries the first system into the case."""

    values: dict[sp.Symbol, sp.Expr]
    transformation: Transformation


def match(
    mine: FieldForm,
    theirs: FieldForm,
    *,
    assumptions: Mapping[str, str] | None = None,
    orders: Sequence[Sequence[int]] | None = None,
    rotated: Sequence[Sequence[int]] | None = None,
) -> Match | None:
    """A transformation and values of ``theirs``'s parameters that make it ``mine``, or
    None where none is found (module docstring). ``assumptions`` are those of the
    case's parameters by name ("positive", "nonzero", "real", "integer"); ``orders``
    (and ``rotated``: with a rotation about ``mine``'s axis of symmetry) the orders of
    the axes to try, where ``supports`` has ruled out the others."""
    assumptions = dict(assumptions or {})
    if mine.shifted != theirs.shifted:
        return None
    if not mine.shifted and not theirs.profile() >= mine.profile():
        return None
    plain = list(orders) if orders is not None else list(_orders(mine, theirs))
    axis = _symmetry_axis(mine.kinetic)
    if axis is None:
        turned: list = []
    elif rotated is not None:
        turned = list(rotated)
    else:
        turned = plain
    attempts = [(order, None) for order in plain] + [(order, axis) for order in turned]
    if mine.parameters:  # first at a point of mine's parameters, over Q: cheap
        if _attempts(specialised(mine), theirs, assumptions, attempts, probe=True) is None:
            return None
    return _attempts(mine, theirs, assumptions, attempts)


def specialised(form: FieldForm) -> FieldForm:
    """The form at fixed pseudo-random positive rational values of its parameters (whole
    numbers for integer ones): the same values in every run, so identification is
    reproducible."""
    rng = random.Random(PROBE_SEED)
    values = {
        p: sp.Integer(rng.randint(3, 97))
        if p.is_integer
        else sp.Rational(rng.randint(101, 997), rng.randint(101, 997))
        for p in form.parameters
    }
    kinetic = None if form.kinetic is None else sp.ImmutableMatrix(form.kinetic.xreplace(values))
    return FieldForm(
        (),
        kinetic,
        tuple(sp.sympify(e).xreplace(values) for e in form.shift),  # type: ignore[arg-type]
        tuple(sp.expand(sp.sympify(f).xreplace(values)) for f in form.field),
    )


def _attempts(mine, theirs, assumptions, attempts, probe=False) -> Match | None:
    """The attempts (an order of the axes, a rotation axis or None) in order, after the
    parameters alone (module docstring); the first match found."""
    if ((0, 1, 2), None) in [(tuple(o), a) for o, a in attempts]:  # the parameters alone
        found = _try(mine, theirs, (0, 1, 2), None, 0, assumptions, fixed=True, probe=probe)
        if found is not None:
            return found
    shifts = 4 if mine.shifted else 0
    for order, about in attempts:
        found = _try(mine, theirs, tuple(order), about, shifts, assumptions, probe=probe)
        if found is not None:
            return found
    return None


def _orders(mine: FieldForm, theirs: FieldForm):
    """Orders of the axes to try, the identity first."""
    if not mine.shifted:
        yield (0, 1, 2)
        return
    a, b = mine.kinetic, theirs.kinetic
    if a is None or b is None or not (a.is_diagonal() and b.is_diagonal()):
        yield (0, 1, 2)
        return
    for order in PERMUTATIONS:
        if _ratios_agree(a, b, order):
            yield order


def _symmetry_axis(kinetic: sp.Matrix | None) -> int | None:
    """The axis k whose two others have equal entries of a diagonal inverse inertia."""
    if kinetic is None or not kinetic.is_diagonal():
        return None
    d = [kinetic[i, i] for i in range(3)]
    for k in range(3):
        i, j = [x for x in range(3) if x != k]
        if sp.cancel(d[i] - d[j]) == 0:
            return k
    return None


def _ratios_agree(a: sp.Matrix, b: sp.Matrix, order: Sequence[int]) -> bool:
    """False where a ratio of two diagonal entries is a number on both sides (the
    parameters cancel: 2C : C) and differs between a and b, taken in ``order``."""
    da = [a[i, i] for i in range(3)]
    db = [b[order[i], order[i]] for i in range(3)]
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if da[j] == 0 or db[j] == 0:
            continue
        left, right = sp.cancel(da[i] / da[j]), sp.cancel(db[i] / db[j])
        if left.is_number and right.is_number and left != right:
            return False
    return True


class _Setting:
    """The unknowns of one attempt, the case's parameters renamed (the first system's own
    may have the same names), and the ring of the equations."""

    def __init__(self, mine: FieldForm, theirs: FieldForm, shifts: int, rotate: bool):
        self.renamed = {p: sp.Symbol(f"_r{i}_{p.name}") for i, p in enumerate(theirs.parameters)}
        self.shift = list(SHIFT[:shifts])
        self.unknowns = [
            *self.renamed.values(),
            *self.shift,
            TAU,
            LAM,
            RHO,
            *SIGNS,
            *((COS, SIN) if rotate else ()),
        ]
        domain = sp.QQ.frac_field(*mine.parameters) if mine.parameters else sp.QQ
        names = [str(u) for u in (*self.unknowns, *STATE, *PRIMED)]
        self.ring = PolyRing(names, domain)
        self.unknown_ring = PolyRing([str(u) for u in self.unknowns], domain)
        self.n = len(self.unknowns)

    def element(self, expr: sp.Expr) -> PolyElement:
        symbols = dict(zip((*self.unknowns, *STATE, *PRIMED), self.ring.symbols, strict=True))
        return self.ring.from_expr(sp.sympify(expr).xreplace(symbols))


def _try(mine, theirs, order, axis, shifts, assumptions, fixed=False, probe=False):
    """One attempt: an order of the axes, a rotation axis or None, how many shift
    coefficients; ``fixed``: the identity transformation, the case's parameters alone
    unknown; ``probe``: at a specialisation of the first system (``specialised``, its
    values allowed by its assumptions), where the solver keeps its positivity rule (a
    value positive for all the system's parameter values is positive there) but any
    finite solution counts, complex or not (``_allowed``), so that a match at generic
    values is one there: only a failed probe skips the generic attempt."""
    setting = _Setting(mine, theirs, shifts, axis is not None)
    rotation = (axis, COS, SIN) if axis is not None else None
    matrix = axes_matrix(order, (1, 1, 1) if fixed else SIGNS, rotation)
    shift = _shift(setting, theirs, matrix) if shifts else (sp.Integer(0),) * 3
    one = sp.Integer(1)
    scalings = (one, one, one) if fixed else (TAU, LAM, RHO)
    transformation = Transformation(*scalings, sp.ImmutableMatrix(matrix), shift)
    index = {u: i for i, u in enumerate(setting.unknowns)}
    circle = [setting.unknown_ring.from_expr(COS**2 + SIN**2 - 1)] if rotation else []
    kinetic = _kinetic(setting, mine, theirs, matrix, transformation.tau, transformation.lam)
    if kinetic is not None:  # the inverse inertias first: most orders fail there, cheaply
        problem = _problem(setting, theirs, assumptions, index, probe)
        if solve([*kinetic, *circle], problem) is None:
            return None
    equations = _equations(setting, mine, theirs, transformation)
    if equations is None:
        return None
    equations += circle
    solution = solve(equations, _problem(setting, theirs, assumptions, index, probe))
    if solution is None:
        return None
    by_name = {str(u): u for u in setting.unknowns}
    solution = {by_name[str(k)]: v for k, v in solution.items()}
    back = {v: k for k, v in setting.renamed.items()}
    return _completed(mine, theirs, transformation, solution, setting, back, assumptions, probe)


def _kinetic(setting: _Setting, mine, theirs, matrix, tau=TAU, lam=LAM) -> list[PolyElement] | None:
    """The equations tau A = lam P^T A' P of the inverse inertias (dgamma/dt's part
    linear in L), numerators; None where the forms have none."""
    if mine.kinetic is None or theirs.kinetic is None:
        return None
    theirs_kinetic = theirs.kinetic.xreplace(setting.renamed)
    out = []
    for e in tau * mine.kinetic - lam * matrix.T * theirs_kinetic * matrix:
        numer = sp.numer(sp.together(sp.expand(e)))
        if numer != 0:
            try:
                out.append(setting.unknown_ring.from_expr(sp.expand(numer)))
            except (sp.PolynomialError, sp.CoercionFailed, ValueError):
                return None
    return out


def _problem(setting: _Setting, theirs, assumptions, index, probe=False) -> Problem:
    """The unknowns' constraints and default values (``equation_solver.Problem``)."""
    nonzero = {TAU, LAM, RHO, *SIGNS} | {
        setting.renamed[p]
        for p in theirs.parameters
        if assumptions.get(str(p)) in ("positive", "nonzero")
    }
    # signs first (most matches need none), then shifts 0, then scalings 1; a rotation's
    # cos and sin are left to the last few equations (radicals)
    defaults = {index[u]: (1, -1) for u in SIGNS}
    defaults.update({index[h]: (0,) for h in setting.shift})
    defaults.update({index[u]: (1, -1) for u in (TAU, LAM, RHO)})
    positive = frozenset(
        index[setting.renamed[p]]
        for p in theirs.parameters
        if assumptions.get(str(p)) == "positive"
    )
    return Problem(
        setting.unknown_ring,
        frozenset(index[u] for u in nonzero),
        frozenset(index[u] for u in SIGNS),
        positive,
        defaults,
        complex_values=probe,
    )


@dataclass(frozen=True)
class Prepared:
    """What every match with a case needs, computed once: its field as N / D
    (``denominator`` D and each N_k as {exponents of (parameters, L, gamma): rational}),
    and the adjugate of its inverse inertia with denominators cleared (A'^-1 up to a
    factor, polynomial in its parameters; None without one)."""

    denominator: dict
    numerators: tuple[dict, ...]
    adjugate: sp.ImmutableMatrix | None


_PREPARED: dict[FieldForm, Prepared] = {}


def prepare(form: FieldForm) -> Prepared:
    """The case's ``Prepared``, computed once per form in this process."""
    found = _PREPARED.get(form)
    if found is None:
        denominator, numerators = _case_polynomials(form)
        adjugate = None
        if form.kinetic is not None:
            common = sp.Integer(1)
            for e in form.kinetic:
                common = sp.lcm(common, sp.denom(sp.together(e)))
            adjugate = sp.ImmutableMatrix((form.kinetic * common).applyfunc(sp.cancel).adjugate())
        found = Prepared(denominator, tuple(numerators), adjugate)
        _PREPARED[form] = found
    return found


def remember(form: FieldForm, prepared: Prepared) -> None:
    """Use a ``Prepared`` computed before (read from a cache)."""
    _PREPARED.setdefault(form, prepared)


def _shift(setting: _Setting, theirs: FieldForm, matrix: sp.Matrix):
    """(h0 + h.gamma) rho adj(A') P gamma: the residual shift, with A'^-1's denominator
    absorbed into the h's (unknowns anyway)."""
    adjugate = prepare(theirs).adjugate
    assert adjugate is not None  # a shift is tried only between forms with a kinetic matrix
    adjugate = adjugate.xreplace(setting.renamed)
    h = setting.shift[0] + sum(
        (c * g for c, g in zip(setting.shift[1:], GAMMA, strict=False)), sp.Integer(0)
    )
    vector = h * RHO * adjugate * matrix * sp.Matrix(GAMMA)
    return tuple(sp.expand(e) for e in vector)


def _equations(setting: _Setting, mine, theirs, transformation) -> list[PolyElement] | None:
    """The coefficients, in the state, of D_m (D tau dPhi F - N(Phi)), with the case's
    field F' = N / D (D its common denominator in its parameters) and D_m the common
    denominator of the first system's field in its own parameters p: every product is
    then taken over Q with p as generators (sympy's arithmetic in Q(p) cancels a gcd at
    each step), and only the equations are brought into K[unknowns], K = Q(p)."""
    n = setting.n
    own = list(mine.parameters)
    names = [str(u) for u in (*setting.unknowns, *STATE, *PRIMED, *own)]
    ring = PolyRing(names, sp.QQ)
    prepared = prepare(theirs)
    denominator, polys = prepared.denominator, prepared.numerators
    k = len(theirs.parameters)
    pad = (0,) * (n - k + 6)
    tail = (0,) * len(own)

    def lifted(terms: dict) -> PolyElement:  # the case's parameters, then its state primed
        return ring.from_dict({(*e[:k], *pad, *e[k:], *tail): c for e, c in terms.items()})

    symbols = dict(zip((*setting.unknowns, *STATE, *PRIMED, *own), ring.symbols, strict=True))

    def element(expr: sp.Expr) -> PolyElement:
        return ring.from_expr(sp.sympify(expr).xreplace(symbols))

    try:
        field = [sp.together(f) for f in mine.field]
        common = sp.Integer(1)
        for f in field:
            common = sp.lcm(common, sp.denom(f))
        mine_field = [element(sp.expand(sp.cancel(f * common))) for f in field]
        cleared = element(common)
        numerators = [lifted(terms) for terms in polys]
        scale = lifted(denominator) * element(transformation.tau)
        images = transformation.images()
        images_l = [element(e) for e in images[0]]
        images_g = [element(e) for e in images[1]]
    except (sp.PolynomialError, sp.CoercionFailed, ValueError):
        return None
    primed = ring.gens[n + 6 : n + 12]
    substitution = list(zip(primed, (*images_l, *images_g), strict=True))
    out: dict = {}
    for component in range(6):
        image = images_l[component] if component < 3 else images_g[component - 3]
        pushed = ring.zero
        for j in range(6):
            derivative = image.diff(n + j)
            if derivative:
                pushed += derivative * mine_field[j]
        pulled = numerators[component].compose(substitution)
        for monom, c in (scale * pushed - cleared * pulled).iterterms():
            key = (component, monom[n : n + 12])  # one equation per component and monomial
            unknowns, params = monom[:n], monom[n + 12 :]
            terms = out.setdefault(key, {}).setdefault(unknowns, {})
            terms[params] = terms.get(params, 0) + c
    target = setting.unknown_ring
    domain = target.domain
    if own:
        params_ring = domain.field.ring
        lift = lambda terms: domain.field.new(params_ring.from_dict(terms))  # noqa: E731
    else:
        lift = lambda terms: domain.convert(terms[()])  # noqa: E731
    equations = []
    for per_unknowns in out.values():
        terms = {m: {e: c for e, c in t.items() if c} for m, t in per_unknowns.items()}
        terms = {m: lift(t) for m, t in terms.items() if t}
        if terms:
            equations.append(target.from_dict(terms))
    return equations


def _case_polynomials(form: FieldForm) -> tuple[dict, list[dict]]:
    """A case's field as N / D: D (its parameters' common denominator) and each N_k as
    {exponents of (parameters, L, gamma): rational coefficient}, computed once."""
    field = [sp.together(f) for f in form.field]
    common = sp.Integer(1)
    for f in field:
        common = sp.lcm(common, sp.denom(f))
    gens = (*form.parameters, *STATE)
    polys = [
        dict(sp.Poly(sp.expand(sp.cancel(f * common)), *gens, domain=sp.QQ).terms()) for f in field
    ]
    return dict(sp.Poly(common, *gens, domain=sp.QQ).terms()), polys


def _completed(mine, theirs, transformation, solution, setting, back, assumptions, probe=False):
    """The solution with its free unknowns given their simplest values (scalings and
    signs +-1 so that positive parameters come out positive), checked exactly."""
    free = [u for u in setting.unknowns if u not in solution]
    signed = [u for u in free if u in (TAU, LAM, RHO, *SIGNS)]
    fixed: dict[sp.Symbol, sp.Expr] = {}
    for u in free:
        if u in signed:
            continue
        kind = assumptions.get(str(back.get(u, u)))
        fixed[u] = sp.Integer(1) if u == COS or kind in ("positive", "nonzero") else sp.Integer(0)
    for choice in itertools.product((1, -1), repeat=len(signed)):
        values = {**fixed, **dict(zip(signed, map(sp.Integer, choice), strict=True))}
        full = {k: _simplified(sp.sympify(v).xreplace(values)) for k, v in solution.items()}
        full.update(values)
        case_values = {back[u]: full[u] for u in setting.renamed.values()}
        if not _allowed(case_values, assumptions, probe=probe):
            continue
        renamed_values = {u: full[u] for u in setting.renamed.values()}
        concrete = transformation.substitute({**full, **renamed_values})
        concrete = Transformation(
            concrete.tau,
            concrete.lam,
            concrete.rho,
            concrete.matrix,
            tuple(sp.sympify(e).xreplace(back).xreplace(case_values) for e in concrete.shift),  # type: ignore[arg-type]
        )
        if _checked(mine, theirs, concrete, case_values):
            return Match(case_values, concrete)
    return None


def _simplified(expr: sp.Expr) -> sp.Expr:
    expr = sp.cancel(expr)
    return sp.radsimp(expr) if expr.has(sp.Pow) else expr


def _allowed(
    values: Mapping[sp.Symbol, sp.Expr], assumptions: Mapping[str, str], probe: bool = False
) -> bool:
    """Whether the case's parameter values are allowed for every value of the first
    system's parameters: real (no even root of a base not shown nonnegative: sqrt(c2 -
    c1) is real only where c2 >= c1), positive, nonzero or integer as the case declares.
    At a ``probe`` point only a value that is not finite is refused: a value complex or
    of the wrong sign there may come from a branch the generic attempt leaves for
    another (the probe only decides whether the generic attempt is made)."""
    for p, v in values.items():
        if v.has(sp.zoo, sp.nan):
            return False
        if probe:
            continue
        kind = assumptions.get(str(p))
        if v.has(sp.I) or not _real_radicals(v):
            return False
        if kind == "positive" and v.is_positive is not True:
            return False
        if kind == "nonzero" and v.is_zero is not False:
            return False
        if kind == "integer" and v.is_integer is not True:
            return False
    return True


def _real_radicals(value: sp.Expr) -> bool:
    """Whether every even root in ``value`` is of a base shown to be nonnegative."""
    for power in value.atoms(sp.Pow):
        exp = power.exp
        if exp.is_Rational and not exp.is_Integer and exp.q % 2 == 0:
            if power.base.is_nonnegative is not True:
                return False
    return True


def _checked(mine, theirs, transformation: Transformation, values) -> bool:
    """tau dPhi F = F'(Phi) exactly, with the case's parameter values put in."""
    at = FieldForm(
        theirs.parameters,
        theirs.kinetic,
        theirs.shift,
        tuple(sp.sympify(f).xreplace(values) for f in theirs.field),
    )
    for left, right in zip(transformation.pushed(mine), transformation.pulled(at), strict=True):
        if not _is_zero(sp.expand(left - right)):
            return False
    return True


def _is_zero(difference: sp.Expr) -> bool:
    """Whether an expanded difference is zero. ``cancel`` decides it for a rational
    function of the state and the parameters. Radicals b**(p/q) (a rotation's cos and
    sin, a shift's square roots) are first made symbols: for each base b, with L the lcm
    of its q's, a root r with r**L = b, and b**(p/q) = r**(pL/q) (an identity of the
    principal roots for every complex b; b itself elsewhere is left as it is); the
    numerator is then reduced by r**L - b. A zero remainder proves zero; otherwise
    ``simplify`` decides (radicals may depend on each other: sqrt(b c) and sqrt(b)
    sqrt(c) are not identified, and are equal only where signs allow)."""
    if difference == 0:
        return True
    if all(p.exp.is_Integer for p in difference.atoms(sp.Pow)):
        return sp.cancel(difference) == 0
    radicals = [p for p in difference.atoms(sp.Pow) if not p.exp.is_Integer]
    if any(
        not p.exp.is_Rational or any(not q.exp.is_Integer for q in p.base.atoms(sp.Pow))
        for p in radicals
    ):
        return sp.simplify(difference) == 0  # an irrational exponent, a nested radical
    orders: dict[sp.Expr, int] = {}
    for p in radicals:
        orders[p.base] = int(sp.ilcm(orders.get(p.base, 1), p.exp.q))
    roots = {base: sp.Dummy(f"r{k}") for k, base in enumerate(orders)}
    replace = {p: roots[p.base] ** int(p.exp * orders[p.base]) for p in radicals}
    numerator = sp.numer(sp.cancel(difference.xreplace(replace)))
    for base, root in roots.items():
        numerator = sp.rem(numerator, root ** orders[base] - base, root)
    if sp.expand(numerator) == 0:
        return True
    return sp.simplify(difference) == 0
