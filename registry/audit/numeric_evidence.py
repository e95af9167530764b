"""Numerical evidence: integrate the equations of motion and watch each claim.

Independent of the symbolic verdicts: for every claim, the case's equations of motion
(``CaseMechanics.field``, whatever form the file gave: system (2.2), Pi grad H, or the
equations as printed) are integrated with scipy's DOP853 at tight tolerances, from
seeded random initial conditions on exactly the set where the symbolic check decided
(the claim's ``on`` equations, nothing added; for a relation, on F = 0) and for seeded
random parameter values respecting their assumptions. What is watched:

* an integral or a Casimir: I itself;
* a relation F = 0: F, which stays 0 exactly when the relation is invariant;
* a density rho: ln|rho| + s with ds/dt = div v integrated beside the state, constant
  exactly when div(rho v) = 0 along the trajectory (Liouville's equation, the method of
  the Jacobi last multiplier).

The largest relative drift of the watched quantity along the runs is compared with a
noise floor: the drift of H, conserved for every torque, where the system has one;
otherwise the change of the quantity when the trajectory is integrated back to its
start, what the integrator's own errors do to it.

Drifts are relative to the size of the terms of the expression at the start point (the
sum of the absolute values of the terms of its expanded form, or |grad I| |x| where that
is larger), the scale of its rounding error: a quantity that vanishes on its set (an
invariant relation such as Hess's x0 M1 + z0 M3 = 0, sampled at large momenta) is judged
against the size of its terms, not against 1.

On a level set the trajectories must stay on the set for the drift to speak of the
claim. Where the symbolic ``invariant`` check proved that the flow keeps the set, each
trajectory is projected back onto it (Gauss-Newton steps x -= J^+ g(x) on the set's
equations g) after each accepted step of the integrator, so that rounding errors
growing along a repelling direction are removed as they appear. Elsewhere (the
set not proven invariant, or a projection that does not converge) the trajectory is
integrated as it is. Either way its *departure*, the largest relative residual of the
set's equations where I is measured, is tracked: a trajectory whose departure exceeds
``DEPARTURE_TOL`` has left the set, and its drift measures how fast it left, not whether
the claim holds on it, so it is not compared (``reason`` says so when no trajectory
stayed).

The rules of the comparison:

* The drift of I says whether I is *conserved*, so it is compared with the claim's
  ``integral`` verdict for an integral and a Casimir alike: a true integral claimed as
  a Casimir is ``integral: verified, casimir: refuted``, and a flat drift agrees. A
  density's and a relation's are compared with their ``measure`` and ``relation``
  verdicts (``compared_check``).
* A drift far above the floor (and above the departure) contradicts ``verified``; a
  drift at the floor contradicts ``refuted``, unless the numbers stand on a smaller set
  than the claim's (one instance of a family's arbitrary functions): a refutation may
  hold elsewhere on the claim's set, so a flat drift there proves nothing.
* Only trajectories that stayed on the claim's set are compared.
* An ``inconclusive`` verdict is never contradicted.
"""

from __future__ import annotations

import math
import random
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..language.parser import FUNCTIONS
from ..mathematics import flow
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.sampling import concrete_functions, sample_point, substitute_functions
from ..model import Case, Claim, ClaimKind, DriftCurve, Evidence, Verdict

#: Integration time, tolerances and runs per claim.
T_END = 5.0
RTOL = 1e-11
ATOL = 1e-12
RUNS = 3
#: Output points of a trajectory integrated as it is (a projected one is measured at
#: each of its steps).
SEGMENTS = 200
#: A drift this many times above H's floor contradicts "verified"; one within
#: FLOOR_FACTOR of the floor contradicts "refuted".
DISAGREE_FACTOR = 1e3
FLOOR_FACTOR = 10.0
#: The smallest floor used in those comparisons (double precision noise).
MIN_FLOOR = 1e-13
#: A trajectory whose relative residual of the set's equations exceeds this has left the
#: set (a thousand times the integrator's relative tolerance).
DEPARTURE_TOL = 1e-8
#: Gauss-Newton steps of one projection, and the residual at which it stops early.
NEWTON_STEPS = 6
PROJECTED = 1e-15
#: Expressions with more terms than this once expanded are scaled by their own terms.
MAX_TERMS = 5000


@dataclass(frozen=True)
class Drift:
    """Largest relative drift of the claim's I and of H over ``runs`` trajectories; on a
    level set, the largest relative residual of its equations where I was measured
    (``departure``), whether the trajectories were projected onto it, and why the drift is
    not compared (``reason``: the trajectories left the set), if it is not."""

    claim: str
    drift: float
    floor: float
    runs: int
    note: str = ""

    narrowed: str = ""  # why the numbers stand on a smaller set than the claim's
    departure: float = math.nan  # nan: the claim has no level set
    projected: bool = False
    reason: str = ""

    def contradicts(self, integral: Verdict | str) -> bool:
        """True when the numbers disagree with the claim's ``integral`` verdict (rules in
        the module docstring)."""
        if self.runs == 0 or self.reason:
            return False
        floor = max(self.floor, MIN_FLOOR)
        if Verdict(integral) is Verdict.VERIFIED:
            departure = self.departure if math.isfinite(self.departure) else 0.0
            return self.drift > DISAGREE_FACTOR * max(floor, departure)
        if Verdict(integral) is Verdict.REFUTED and not self.narrowed:
            return self.drift <= FLOOR_FACTOR * floor
        return False

    def as_dict(self) -> dict:
        out = {"drift": self.drift, "floor": self.floor, "runs": self.runs, "note": self.note}
        if math.isfinite(self.departure):
            out["departure"] = self.departure
        if self.projected:
            out["projected"] = True
        if self.reason:
            out["reason"] = self.reason
        return out


def narrowing(m: CaseMechanics) -> str:
    """Why the numbers of this case stand on a smaller set than its claims' (or "")."""
    if m.case.functions:
        names = ", ".join(m.case.functions)
        return f"one instance of the family's arbitrary functions ({names})"
    return ""


@dataclass(frozen=True)
class _Compiled:
    """The vector field, H, I and the set's equations of one start's parameter values, as
    functions of the state (a list of floats), with the term lists that give their
    scales; H's are None where the system has no Hamiltonian."""

    field: Callable
    h: Callable | None
    i: Callable
    h_terms: Callable | None
    i_terms: Callable
    g: Callable | None
    g_terms: Callable | None
    jacobian: Callable | None

    def scale(self, f: Callable, terms: Callable, y: np.ndarray) -> float:
        """The size of ``f`` at ``y`` for its rounding error: the larger of the sum of the
        absolute values of its terms and |grad f| |y| (what a relative change of the state
        changes it by; the scale of a one-term relation such as M2 = 0 at M2 = 0), 1
        where both vanish."""
        total = float(np.sum(np.abs(np.asarray(terms(y.tolist()), dtype=float))))
        size = max(total, _gradient_norm(f, y) * float(np.linalg.norm(y)))
        return size if size > 0 and math.isfinite(size) else 1.0

    def residual(self, y: np.ndarray) -> float:
        """The largest relative residual of the set's equations at ``y``: |g_j(y)| over
        the larger of the sum of the absolute values of g_j's terms and |grad g_j| |y|
        (|g_j| / |grad g_j| is the distance to its zero set to first order)."""
        if self.g is None or self.g_terms is None or self.jacobian is None:
            return 0.0
        point = y.tolist()
        values = np.abs(np.asarray(self.g(point), dtype=float))
        rows = np.asarray(self.jacobian(point), dtype=float).reshape(len(values), -1)
        norm = float(np.linalg.norm(y))
        worst = 0.0
        for value, terms, row in zip(values, self.g_terms(point), rows, strict=True):
            if value == 0:
                continue
            size = max(
                float(np.sum(np.abs(np.asarray(terms, dtype=float)))),
                float(np.linalg.norm(row)) * norm,
            )
            worst = max(worst, value / size if size > 0 else math.inf)
        return worst if math.isfinite(worst) else math.inf

    def project(self, y: np.ndarray) -> np.ndarray | None:
        """``y`` moved onto the set by Gauss-Newton steps (the least-squares correction of
        the linearised equations), or None when they do not bring it within
        ``DEPARTURE_TOL``."""
        assert self.g is not None and self.jacobian is not None
        for _ in range(NEWTON_STEPS):
            if self.residual(y) <= PROJECTED:
                return y
            g = np.asarray(self.g(y.tolist()), dtype=float)
            jac = np.asarray(self.jacobian(y.tolist()), dtype=float)
            if not (np.all(np.isfinite(g)) and np.all(np.isfinite(jac))):
                return None
            step = np.linalg.lstsq(jac, g, rcond=None)[0]
            y = y - step
        return y if self.residual(y) <= DEPARTURE_TOL else None


@dataclass(frozen=True)
class _Run:
    """One trajectory: times, H and I along it (H empty where the system has none), the
    departure from the set, whether it was projected, and the integrator's noise floor:
    H's relative drift, or without H the relative change of I after integrating the
    trajectory back to its start (what the integrator's errors alone do to I)."""

    t: np.ndarray
    h: np.ndarray
    i: np.ndarray
    departure: float
    projected: bool
    scale_i: float
    floor: float

    @property
    def drift(self) -> float:
        return float(np.max(np.abs(self.i - self.i[0]))) / self.scale_i


@dataclass(frozen=True)
class _Watched:
    """What the numbers of one claim watch: the state integrated and its vector field
    (for a density, the system's state and field with the integral s of div v beside
    them), H (None: the system has none), the watched quantity and the set's equations."""

    state: tuple[sp.Symbol, ...]
    field: tuple[sp.Expr, ...]
    h: sp.Expr | None
    i: sp.Expr
    on: tuple[sp.Expr, ...]

    def exprs(self) -> list[sp.Expr]:
        return [*self.field, *([] if self.h is None else [self.h]), self.i, *self.on]

    def at(self, values: Mapping[sp.Symbol, sp.Expr]) -> _Watched:
        """The same with the parameters replaced by ``values``."""

        def put(e: sp.Expr) -> sp.Expr:
            return e.xreplace(values)

        return _Watched(
            self.state,
            tuple(map(put, self.field)),
            None if self.h is None else put(self.h),
            put(self.i),
            tuple(map(put, self.on)),
        )


#: The variable that integrates div v along a trajectory, for a density's evidence.
_DIVERGENCE = sp.Symbol("s_div", real=True)


def compared_check(claim: Claim) -> str:
    """The symbolic check a claim's numbers speak to: conservation (``integral``) for an
    integral or a Casimir, ``measure`` for a density, ``relation`` for a relation."""
    if claim.kind is ClaimKind.MEASURE:
        return "measure"
    if claim.kind is ClaimKind.RELATION:
        return "relation"
    return "integral"


def _setup(m: CaseMechanics, claim: Claim, rng: random.Random):
    """Where to start, the concrete functions of a family, and what to watch.

    Starts lie on the set where the symbolic check decided (the claim's ``on``
    equations; for a relation, also F = 0). The watched quantity is I itself for an
    integral or a Casimir, F for a relation (it stays 0 exactly when the relation is
    invariant), and ln|rho| + s for a density rho, where ds/dt = div v: by Liouville's
    equation d ln rho/dt = -div v along the flow exactly when div(rho v) = 0.
    """
    funcs = concrete_functions(m.case.functions, rng)
    dyn = m.dynamics

    def ready(e: sp.Expr) -> sp.Expr:
        return dyn.expanded(substitute_functions(e, funcs))

    domain = m.claim_domain(claim)
    state, field = tuple(dyn.variables), tuple(map(ready, m.field))
    watched = ready(claim.expression.expr)
    if claim.kind is ClaimKind.RELATION:
        domain = domain.restricted([*domain.on, claim.expression.expr])
    if claim.kind is ClaimKind.MEASURE:
        state += (_DIVERGENCE,)
        field += (ready(flow.divergence(dyn)),)
        watched = sp.log(sp.Abs(watched)) + _DIVERGENCE
    h = None if m.hamiltonian is None else ready(m.hamiltonian)
    on = tuple(ready(eq.expr) for eq in claim.on)
    return domain, funcs, _Watched(state, field, h, watched, on)


def _start(point: Mapping[sp.Symbol, sp.Expr], state: Sequence[sp.Symbol]) -> list[float]:
    """The start of a trajectory: the sampled point's state (s = 0 for a density)."""
    return [float(point.get(v, 0)) for v in state]


def _terms(expr: sp.Expr) -> list[sp.Expr]:
    """The terms of ``expr`` expanded (``expr`` itself when that gives too many)."""
    expanded = sp.expand(expr)
    terms = list(sp.Add.make_args(expanded))
    return terms if len(terms) <= MAX_TERMS else [expr]


def _gradient_norm(f: Callable, y: np.ndarray) -> float:
    """|grad f(y)| by central differences (a scale, not a value: six digits suffice)."""
    step = 1e-6 * max(1.0, float(np.linalg.norm(y)))
    grad = []
    for k in range(len(y)):
        e = np.zeros_like(y)
        e[k] = step
        try:
            grad.append((float(f((y + e).tolist())) - float(f((y - e).tolist()))) / (2 * step))
        except (ValueError, TypeError, ZeroDivisionError, OverflowError):
            return 0.0  # a step left the domain (a boundary nearby): no scale from here
    norm = float(np.linalg.norm(grad))
    return norm if math.isfinite(norm) else 0.0


def _compile(w: _Watched) -> _Compiled:
    """Functions of the state (a list of floats) for the field, H, I and the set's
    equations with their Jacobian. Generated for Python's ``math`` on scalars, with
    common subexpressions taken out: a field with square roots is evaluated tens of
    thousands of times per trajectory, and numpy's per-call cost dominates there."""
    _only_numeric(w.exprs(), w.state)

    def fn(e, cse: bool = True):
        return sp.lambdify([list(w.state)], e, modules="math", cse=cse)

    g = g_terms = jacobian = None
    if w.on:
        g = fn(list(w.on))
        g_terms = fn([_terms(e) for e in w.on], cse=False)
        jacobian = fn([[sp.diff(e, v) for v in w.state] for e in w.on])
    h = h_terms = None
    if w.h is not None:
        h, h_terms = fn(w.h), fn(_terms(w.h), cse=False)
    return _Compiled(
        fn(list(w.field)), h, fn(w.i), h_terms, fn(_terms(w.i), cse=False), g, g_terms, jacobian
    )


def claim_drift(
    m: CaseMechanics,
    claim: Claim,
    seed: int = 0,
    runs: int = RUNS,
    invariant: Verdict | None = None,
    starts: Sequence[Mapping[sp.Symbol, sp.Expr]] | None = None,
) -> Drift:
    """Integrate from ``runs`` random points of the claim's level set (or from the exact
    points ``starts``, parameters included); measure the drifts and the departure from
    the set. Trajectories are projected back onto the set where ``invariant`` is
    ``verified`` (the flow keeps it)."""
    rng = random.Random(seed)
    domain, funcs, watched = _setup(m, claim, rng)
    project = bool(claim.on) and invariant is not None and Verdict(invariant) is Verdict.VERIFIED
    done: list[_Run] = []
    notes: list[str] = []
    points = iter(starts) if starts is not None else None
    attempts = 0
    while len(done) < runs and attempts < 4 * runs:
        attempts += 1
        if points is not None:
            point = next(points, None)
            if point is None:
                break
        else:
            point = sample_point(domain, rng, funcs)
            if point is None:
                continue
        params = {p: point[p] for p in m.domain.parameters}
        compiled = _compile(watched.at(params))
        run = _solve(compiled, _start(point, watched.state), T_END, project)
        if isinstance(run, str):
            notes.append(run)
            continue
        done.append(run)
    return _summary(claim, done, notes, narrowing(m), on_set=bool(claim.on))


def _summary(claim: Claim, done: list[_Run], notes: list[str], narrowed: str, on_set: bool):
    """The Drift of the runs that stayed on the set (all of them where none did, with the
    reason the drift is not compared)."""
    if not done:
        why = notes[0] if notes else "found no start point on the claim's set"
        return Drift(claim.label, math.nan, math.nan, 0, why, narrowed)
    stayed = [r for r in done if r.departure <= DEPARTURE_TOL]
    reason = ""
    note = ""
    if not stayed:
        worst = max(r.departure for r in done)
        reason = (
            f"every trajectory left the claim's set (relative residual of its equations "
            f"up to {worst:.1e}, above {DEPARTURE_TOL:.0e}): the drift measures how fast "
            "it left, not whether the claim holds on it"
        )
        stayed = done
    elif len(stayed) < len(done):
        note = f"{len(done) - len(stayed)} of {len(done)} trajectories left the set; not compared"
    return Drift(
        claim.label,
        max(r.drift for r in stayed),
        max(r.floor for r in stayed),
        len(stayed),
        note,
        narrowed,
        departure=max(r.departure for r in stayed) if on_set else math.nan,
        projected=any(r.projected for r in stayed),
        reason=reason,
    )


@dataclass(frozen=True)
class Trajectory:
    """One integrated trajectory: times and the changes I(t) - I(0), H(t) - H(0)."""

    claim: str
    t: np.ndarray
    di: np.ndarray
    dh: np.ndarray
    start: dict[str, float]


def trajectory(
    m: CaseMechanics,
    claim: Claim,
    seed: int = 0,
    t_end: float = T_END,
    invariant: Verdict | None = None,
) -> Trajectory:
    """The first trajectory ``claim_drift`` would integrate (same seed, same start), in full.

    Raises ValueError when no trajectory could be integrated.
    """
    rng = random.Random(seed)
    domain, funcs, watched = _setup(m, claim, rng)
    project = bool(claim.on) and invariant is not None and Verdict(invariant) is Verdict.VERIFIED
    for _ in range(4 * RUNS):
        point = sample_point(domain, rng, funcs)
        if point is None:
            continue
        params = {p: point[p] for p in m.domain.parameters}
        y0 = _start(point, watched.state)
        run = _solve(_compile(watched.at(params)), y0, t_end, project)
        if isinstance(run, str):
            continue
        start = {str(k): float(v) for k, v in point.items()}
        dh = run.h - run.h[0] if len(run.h) else run.h
        return Trajectory(claim.label, run.t, run.i - run.i[0], dh, start)
    raise ValueError(f"no trajectory could be integrated for claim {claim.label!r}")


def drift_curve(
    case: Case | CaseMechanics, label: str, seed: int = 0, points: int = 200
) -> DriftCurve:
    """The first trajectory the numerical evidence of claim ``label`` integrates (same
    seed, same start), at about ``points`` times, as data a plot draws. KeyError for an
    unknown claim, ValueError when nothing could be integrated."""
    m = case if isinstance(case, CaseMechanics) else CaseMechanics(case)
    run = trajectory(m, m.case.claim(label), seed)
    step = max(1, len(run.t) // points)
    return DriftCurve(
        m.case.id,
        label,
        tuple(float(x) for x in run.t[::step]),
        tuple(float(x) for x in run.di[::step]),
        tuple(float(x) for x in run.dh[::step]),
    )


def drift_curves(
    claims: Sequence[tuple[Case, str]], seed: int = 0
) -> dict[tuple[str, str], DriftCurve | str]:
    """The drift curve of each (case, claim label), by (case id, label), or why there is
    none (nothing could be integrated)."""
    out: dict[tuple[str, str], DriftCurve | str] = {}
    for case, label in claims:
        try:
            out[case.id, label] = drift_curve(case, label, seed)
        except (ValueError, KeyError) as exc:
            out[case.id, label] = str(exc)
    return out


def _only_numeric(exprs: list[sp.Expr], state: Sequence[sp.Symbol]) -> None:
    """Refuse to generate code for anything but the state variables, numbers, arithmetic
    and the elementary functions of the case-file language (defence in depth: the trees
    come from the whitelist parser, with parameters and functions already replaced)."""
    allowed = set(state)
    for e in exprs:
        if not e.free_symbols <= allowed:
            raise ValueError(f"unexpected symbols {e.free_symbols - allowed} in {e}")
        for f in e.atoms(sp.Function):
            if type(f).__name__ not in FUNCTIONS and not isinstance(f, (sp.Abs, sp.sign)):
                raise ValueError(f"unexpected function {type(f).__name__} in {e}")


def _solve(c: _Compiled, y0: list[float], t_end: float, project: bool) -> _Run | str:
    """H, I and the departure from the set along the trajectory from y0, or why it failed.

    Where ``project``, the integrator is stepped by hand and each accepted step is
    projected back onto the set before the next (H, I and the departure measured at each
    step); a point where the projection does not converge (a singular point of the set)
    sends the trajectory back to be integrated as it is. Otherwise the values are taken
    at ``SEGMENTS`` + 1 equally spaced times. Without H, the end point is integrated back
    to t = 0 for the noise floor.
    """
    from scipy.integrate import DOP853, solve_ivp  # only here: the audit starts faster

    def fun(t, y):
        return np.asarray(c.field(y.tolist()), dtype=float)

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        start = np.asarray(y0, dtype=float)
        if project:
            moved = c.project(start)
            project = moved is not None
            start = moved if moved is not None else start
        try:
            if project:
                times, states = [0.0], [start]
                solver = DOP853(fun, 0.0, start, t_end, rtol=RTOL, atol=ATOL)
                while solver.status == "running":
                    message = solver.step()
                    if solver.status == "failed" or not np.all(np.isfinite(solver.y)):
                        return f"integration failed: {message or 'not finite'}"
                    moved = c.project(solver.y)
                    if moved is None:
                        return _solve(c, y0, t_end, project=False)
                    solver.y, solver.f = moved, fun(solver.t, moved)
                    times.append(solver.t)
                    states.append(moved)
                t = np.asarray(times)
            else:
                t = np.linspace(0.0, t_end, SEGMENTS + 1)
                sol = solve_ivp(fun, (0.0, t_end), start, "DOP853", t, rtol=RTOL, atol=ATOL)
                if not sol.success or not np.all(np.isfinite(sol.y)):
                    return f"integration failed: {sol.message}"
                states = list(sol.y.T)
            back = None
            if c.h is None:
                sol = solve_ivp(fun, (t_end, 0.0), states[-1], "DOP853", rtol=RTOL, atol=ATOL)
                if not sol.success or not np.all(np.isfinite(sol.y)):
                    return f"integration back to the start failed: {sol.message}"
                back = sol.y[:, -1]
            is_ = np.array([c.i(y.tolist()) for y in states], dtype=float)
            scale_i = c.scale(c.i, c.i_terms, states[0])
            if c.h is None or c.h_terms is None:
                assert back is not None
                hs = np.array([], dtype=float)
                floor = abs(float(c.i(back.tolist())) - float(is_[0])) / scale_i
            else:
                hs = np.array([c.h(y.tolist()) for y in states], dtype=float)
                floor = float(np.max(np.abs(hs - hs[0]))) / c.scale(c.h, c.h_terms, states[0])
            departure = float(max(c.residual(y) for y in states))
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as exc:
            return f"integration failed: {exc}"
    if not (np.all(np.isfinite(hs)) and np.all(np.isfinite(is_)) and math.isfinite(floor)):
        return "the trajectory reached a singular set"
    return _Run(t, hs, is_, departure, project, scale_i, floor)


def evidence(
    m: CaseMechanics, verdicts: Mapping[tuple[str, str], Verdict], seed: int = 0
) -> tuple[Evidence, ...]:
    """Evidence for every claim, compared with the verdict of the check its numbers speak
    to (``compared_check``; ``verdicts`` by (check, claim label)); on a level set whose
    ``invariant`` verdict is ``verified``, the trajectories are projected back onto it."""
    out = []
    for claim in m.case.claims:
        invariant = verdicts.get(("invariant", claim.label))
        d = claim_drift(m, claim, seed=seed, invariant=invariant)
        check = compared_check(claim)
        verdict = verdicts.get((check, claim.label), Verdict.INCONCLUSIVE)
        out.append(
            Evidence(
                claim.label,
                d.drift,
                d.floor,
                d.runs,
                bool(d.contradicts(verdict)),
                d.note,
                compared_with=check,
                narrowed=d.narrowed,
                departure=float(d.departure) if math.isfinite(d.departure) else None,
                projected=d.projected,
                reason=d.reason,
            )
        )
    return tuple(out)
