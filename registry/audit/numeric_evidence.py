"""Numerical evidence: integrate the equations of motion and watch each claimed integral.

Independent of the symbolic verdicts: for every claim, the case's equations of motion
(``CaseMechanics.field``: system (2.2), or Pi grad H) are integrated with scipy's DOP853
at tight tolerances, from seeded random initial conditions on exactly the set where the
symbolic check decided (the claim's ``on`` equations, nothing added) and for seeded
random parameter values respecting their assumptions. The largest relative drift of I
along the runs is compared with that of H, which is conserved for every torque and so
measures the integrator's own noise floor.

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

* The drift says whether I is *conserved*, so it is compared with the claim's
  ``integral`` verdict, whatever the claim's kind: a true integral claimed as a
  Casimir is ``integral: verified, casimir: refuted``, and a flat drift agrees.
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
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.sampling import concrete_functions, sample_point, substitute_functions
from ..model import Case, Claim, DriftCurve, Evidence, Verdict

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
    numpy functions of the state, with the term lists that give their scales."""

    field: Callable
    h: Callable
    i: Callable
    h_terms: Callable
    i_terms: Callable
    g: Callable | None
    g_terms: Callable | None
    jacobian: Callable | None

    def scale(self, f: Callable, terms: Callable, y: np.ndarray) -> float:
        """The size of ``f`` at ``y`` for its rounding error: the larger of the sum of the
        absolute values of its terms and |grad f| |y| (what a relative change of the state
        changes it by; the scale of a one-term relation such as M2 = 0 at M2 = 0), 1
        where both vanish."""
        total = float(np.sum(np.abs(np.asarray(terms(y), dtype=float))))
        size = max(total, _gradient_norm(f, y) * float(np.linalg.norm(y)))
        return size if size > 0 and math.isfinite(size) else 1.0

    def residual(self, y: np.ndarray) -> float:
        """The largest relative residual of the set's equations at ``y``: |g_j(y)| over
        the larger of the sum of the absolute values of g_j's terms and |grad g_j| |y|
        (|g_j| / |grad g_j| is the distance to its zero set to first order)."""
        if self.g is None or self.g_terms is None or self.jacobian is None:
            return 0.0
        values = np.abs(np.asarray(self.g(y), dtype=float))
        rows = np.asarray(self.jacobian(y), dtype=float).reshape(len(values), -1)
        norm = float(np.linalg.norm(y))
        worst = 0.0
        for value, terms, row in zip(values, self.g_terms(y), rows, strict=True):
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
            g = np.asarray(self.g(y), dtype=float)
            jac = np.asarray(self.jacobian(y), dtype=float)
            if not (np.all(np.isfinite(g)) and np.all(np.isfinite(jac))):
                return None
            step = np.linalg.lstsq(jac, g, rcond=None)[0]
            y = y - step
        return y if self.residual(y) <= DEPARTURE_TOL else None


@dataclass(frozen=True)
class _Run:
    """One trajectory: times, H and I along it, the departure from the set at each time,
    and whether it was projected."""

    t: np.ndarray
    h: np.ndarray
    i: np.ndarray
    departure: float
    projected: bool
    scale_h: float
    scale_i: float

    @property
    def drift(self) -> float:
        return float(np.max(np.abs(self.i - self.i[0]))) / self.scale_i

    @property
    def floor(self) -> float:
        return float(np.max(np.abs(self.h - self.h[0]))) / self.scale_h


def _setup(m: CaseMechanics, claim: Claim, rng: random.Random):
    """Where to start (the set where the symbolic check decided), the concrete functions
    of a family, and the vector field, H, I and the set's equations ready to evaluate."""
    funcs = concrete_functions(m.case.functions, rng)
    exprs = [*m.field, m.hamiltonian, claim.expression.expr, *(eq.expr for eq in claim.on)]
    exprs = [m.dynamics.expanded(substitute_functions(e, funcs)) for e in exprs]
    return m.claim_domain(claim), funcs, exprs


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
        grad.append((float(f(y + e)) - float(f(y - e))) / (2 * step))
    norm = float(np.linalg.norm(grad))
    return norm if math.isfinite(norm) else 0.0


def _compile(exprs: list[sp.Expr], state: Sequence[sp.Symbol]) -> _Compiled:
    """numpy functions of the state for the field, H, I and the set's equations with
    their Jacobian."""
    _only_numeric(exprs, state)
    n = len(state)
    field, h, i, on = exprs[:n], exprs[n], exprs[n + 1], exprs[n + 2 :]

    def fn(e):
        return sp.lambdify([list(state)], e, modules="numpy")

    g = g_terms = jacobian = None
    if on:
        g = fn(on)
        g_terms = fn([_terms(e) for e in on])
        jacobian = fn([[sp.diff(e, v) for v in state] for e in on])
    return _Compiled(fn(field), fn(h), fn(i), fn(_terms(h)), fn(_terms(i)), g, g_terms, jacobian)


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
    domain, funcs, exprs = _setup(m, claim, rng)
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
        state = m.dynamics.variables
        compiled = _compile([e.xreplace(params) for e in exprs], state)
        run = _solve(compiled, [float(point[v]) for v in state], T_END, project)
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
    domain, funcs, exprs = _setup(m, claim, rng)
    project = bool(claim.on) and invariant is not None and Verdict(invariant) is Verdict.VERIFIED
    for _ in range(4 * RUNS):
        point = sample_point(domain, rng, funcs)
        if point is None:
            continue
        params = {p: point[p] for p in m.domain.parameters}
        state = m.dynamics.variables
        y0 = [float(point[v]) for v in state]
        run = _solve(_compile([e.xreplace(params) for e in exprs], state), y0, t_end, project)
        if isinstance(run, str):
            continue
        start = {str(k): float(v) for k, v in point.items()}
        return Trajectory(claim.label, run.t, run.i - run.i[0], run.h - run.h[0], start)
    raise ValueError(f"no trajectory could be integrated for claim {claim.label!r}")


def drift_curve(case: Case, label: str, seed: int = 0, points: int = 200) -> DriftCurve:
    """The first trajectory the numerical evidence of claim ``label`` integrates (same
    seed, same start), at about ``points`` times, as data a plot draws. KeyError for an
    unknown claim, ValueError when nothing could be integrated."""
    run = trajectory(CaseMechanics(case), case.claim(label), seed)
    step = max(1, len(run.t) // points)
    return DriftCurve(
        case.id,
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
    at ``SEGMENTS`` + 1 equally spaced times.
    """
    from scipy.integrate import DOP853, solve_ivp  # only here: the audit starts faster

    def fun(t, y):
        return np.asarray(c.field(y), dtype=float)

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
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as exc:
            return f"integration failed: {exc}"
        hs = np.array([c.h(y) for y in states], dtype=float)
        is_ = np.array([c.i(y) for y in states], dtype=float)
        departure = float(max(c.residual(y) for y in states))
        scale_h = c.scale(c.h, c.h_terms, states[0])
        scale_i = c.scale(c.i, c.i_terms, states[0])
    if not (np.all(np.isfinite(hs)) and np.all(np.isfinite(is_))):
        return "the trajectory reached a singular set"
    return _Run(t, hs, is_, departure, project, scale_h, scale_i)


def evidence(
    m: CaseMechanics,
    integral: Mapping[str, Verdict],
    seed: int = 0,
    invariant: Mapping[str, Verdict] | None = None,
) -> tuple[Evidence, ...]:
    """Evidence for every claim, compared with its ``integral`` verdict (label -> verdict);
    on a level set whose ``invariant`` verdict is ``verified``, the trajectories are
    projected back onto it."""
    invariant = invariant or {}
    out = []
    for claim in m.case.claims:
        d = claim_drift(m, claim, seed=seed, invariant=invariant.get(claim.label))
        verdict = integral.get(claim.label, Verdict.INCONCLUSIVE)
        out.append(
            Evidence(
                claim.label,
                d.drift,
                d.floor,
                d.runs,
                bool(d.contradicts(verdict)),
                d.note,
                compared_with="integral",
                narrowed=d.narrowed,
                departure=float(d.departure) if math.isfinite(d.departure) else None,
                projected=d.projected,
                reason=d.reason,
            )
        )
    return tuple(out)
