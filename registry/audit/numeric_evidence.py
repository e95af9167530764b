"""Numerical evidence: integrate the equations of motion and watch each claimed integral.

Independent of the symbolic verdicts: for every claim, system (2.2) is
integrated with scipy's DOP853 at tight tolerances, from seeded random initial
conditions on exactly the set where the symbolic check decided (the claim's
``on`` equations, nothing added) and for seeded random parameter values
respecting their assumptions. The largest relative drift of I along the runs is
compared with that of H, which is conserved for every torque and so measures
the integrator's own noise floor.

The rules of the comparison:

* The drift says whether I is *conserved*, so it is compared with the claim's
  ``integral`` verdict, whatever the claim's kind: a true integral claimed as a
  Casimir is ``integral: verified, casimir: refuted``, and a flat drift agrees.
* A drift far above the floor contradicts ``verified``; a drift at the floor
  contradicts ``refuted``, unless the numbers stand on a smaller set than the
  claim's (one instance of a family's arbitrary functions): a refutation may
  hold elsewhere on the claim's set, so a flat drift there proves nothing.
* An ``inconclusive`` verdict is never contradicted.
"""

from __future__ import annotations

import math
import random
import warnings
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..language.parser import FUNCTIONS
from ..mathematics import mechanics as mech
from ..mathematics.case_mechanics import CaseMechanics
from ..mathematics.sampling import concrete_functions, sample_point, substitute_functions
from ..model import Claim, Evidence, Verdict

#: Integration time, tolerances and runs per claim.
T_END = 5.0
RTOL = 1e-11
ATOL = 1e-12
RUNS = 3
#: A drift this many times above H's floor contradicts "verified"; one within
#: FLOOR_FACTOR of the floor contradicts "refuted".
DISAGREE_FACTOR = 1e3
FLOOR_FACTOR = 10.0
#: The smallest floor used in those comparisons (double precision noise).
MIN_FLOOR = 1e-13


@dataclass(frozen=True)
class Drift:
    """Largest relative drift of the claim's I and of H over ``runs`` trajectories."""

    claim: str
    drift: float
    floor: float
    runs: int
    note: str = ""

    narrowed: str = ""  # why the numbers stand on a smaller set than the claim's

    def contradicts(self, integral: Verdict | str) -> bool:
        """True when the numbers disagree with the claim's ``integral`` verdict (rules in
        the module docstring)."""
        if self.runs == 0:
            return False
        floor = max(self.floor, MIN_FLOOR)
        if Verdict(integral) is Verdict.VERIFIED:
            return self.drift > DISAGREE_FACTOR * floor
        if Verdict(integral) is Verdict.REFUTED and not self.narrowed:
            return self.drift <= FLOOR_FACTOR * floor
        return False

    def as_dict(self) -> dict:
        return {"drift": self.drift, "floor": self.floor, "runs": self.runs, "note": self.note}


def narrowing(m: CaseMechanics) -> str:
    """Why the numbers of this case stand on a smaller set than its claims' (or "")."""
    if m.case.functions:
        names = ", ".join(m.case.functions)
        return f"one instance of the family's arbitrary functions ({names})"
    return ""


def _setup(m: CaseMechanics, claim: Claim, rng: random.Random):
    """Where to start (the set where the symbolic check decided), the concrete functions
    of a family, and the vector field, H and I ready to evaluate."""
    funcs = concrete_functions(m.case.functions, rng)
    exprs = [*m.field, m.hamiltonian, claim.expression.expr]
    exprs = [substitute_functions(e, funcs).subs(mech.s, mech.S_VALUE) for e in exprs]
    return m.claim_domain(claim), funcs, exprs


def claim_drift(m: CaseMechanics, claim: Claim, seed: int = 0, runs: int = RUNS) -> Drift:
    """Integrate from ``runs`` random points of the claim's level set; measure the drifts."""
    rng = random.Random(seed)
    domain, funcs, exprs = _setup(m, claim, rng)
    drifts: list[float] = []
    floors: list[float] = []
    notes: list[str] = []
    attempts = 0
    while len(drifts) < runs and attempts < 4 * runs:
        attempts += 1
        point = sample_point(domain, rng, funcs)
        if point is None:
            continue
        params = {p: point[p] for p in m.domain.parameters}
        run = _integrate([e.xreplace(params) for e in exprs], [float(point[v]) for v in mech.STATE])
        if isinstance(run, str):
            notes.append(run)
            continue
        drifts.append(run[0])
        floors.append(run[1])
    narrowed = narrowing(m)
    if not drifts:
        why = notes[0] if notes else "found no start point on the claim's set"
        return Drift(claim.label, math.nan, math.nan, 0, why, narrowed)
    return Drift(claim.label, max(drifts), max(floors), len(drifts), narrowed=narrowed)


@dataclass(frozen=True)
class Trajectory:
    """One integrated trajectory: times and the changes I(t) - I(0), H(t) - H(0)."""

    claim: str
    t: np.ndarray
    di: np.ndarray
    dh: np.ndarray
    start: dict[str, float]


def trajectory(m: CaseMechanics, claim: Claim, seed: int = 0, t_end: float = T_END) -> Trajectory:
    """The first trajectory ``claim_drift`` would integrate (same seed, same start), in full.

    Raises ValueError when no trajectory could be integrated.
    """
    rng = random.Random(seed)
    domain, funcs, exprs = _setup(m, claim, rng)
    for _ in range(4 * RUNS):
        point = sample_point(domain, rng, funcs)
        if point is None:
            continue
        params = {p: point[p] for p in m.domain.parameters}
        y0 = [float(point[v]) for v in mech.STATE]
        run = _solve([e.xreplace(params) for e in exprs], y0, t_end)
        if isinstance(run, str):
            continue
        t, hs, is_ = run
        start = {str(k): float(v) for k, v in point.items()}
        return Trajectory(claim.label, t, is_ - is_[0], hs - hs[0], start)
    raise ValueError(f"no trajectory could be integrated for claim {claim.label!r}")


def _integrate(exprs: list[sp.Expr], y0: list[float]) -> tuple[float, float] | str:
    """(drift of I, drift of H) along one trajectory, or why it failed."""
    run = _solve(exprs, y0, T_END)
    if isinstance(run, str):
        return run
    _, hs, is_ = run
    return _relative(is_), _relative(hs)


def _only_numeric(exprs: list[sp.Expr]) -> None:
    """Refuse to generate code for anything but the state variables, numbers, arithmetic
    and the elementary functions of the case-file language (defence in depth: the trees
    come from the whitelist parser, with parameters and functions already replaced)."""
    allowed = set(mech.STATE)
    for e in exprs:
        if not e.free_symbols <= allowed:
            raise ValueError(f"unexpected symbols {e.free_symbols - allowed} in {e}")
        for f in e.atoms(sp.Function):
            if type(f).__name__ not in FUNCTIONS and not isinstance(f, (sp.Abs, sp.sign)):
                raise ValueError(f"unexpected function {type(f).__name__} in {e}")


def _solve(exprs: list[sp.Expr], y0: list[float], t_end: float):
    """(times, H, I) along the trajectory from y0, or why it failed."""
    from scipy.integrate import solve_ivp  # only here: the audit starts faster without scipy

    _only_numeric(exprs)
    field = sp.lambdify([mech.STATE], exprs[:6], modules="numpy")
    h = sp.lambdify([mech.STATE], exprs[6], modules="numpy")
    i = sp.lambdify([mech.STATE], exprs[7], modules="numpy")
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        try:
            sol = solve_ivp(
                lambda t, y: np.asarray(field(y), dtype=float),
                (0.0, t_end),
                y0,
                method="DOP853",
                rtol=RTOL,
                atol=ATOL,
                t_eval=np.linspace(0.0, t_end, 201),
            )
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as exc:
            return f"integration failed: {exc}"
        if not sol.success or not np.all(np.isfinite(sol.y)):
            return f"integration failed: {sol.message}"
        hs = np.array([h(y) for y in sol.y.T], dtype=float)
        is_ = np.array([i(y) for y in sol.y.T], dtype=float)
    if not (np.all(np.isfinite(hs)) and np.all(np.isfinite(is_))):
        return "the trajectory reached a singular set"
    return sol.t, hs, is_


def _relative(values: np.ndarray) -> float:
    return float(np.max(np.abs(values - values[0])) / max(1.0, abs(values[0])))


def evidence(m: CaseMechanics, integral: dict[str, Verdict], seed: int = 0) -> tuple[Evidence, ...]:
    """Evidence for every claim, compared with its ``integral`` verdict (label -> verdict)."""
    out = []
    for claim in m.case.claims:
        d = claim_drift(m, claim, seed=seed)
        verdict = integral.get(claim.label, Verdict.INCONCLUSIVE)
        out.append(
            Evidence(
                claim.label,
                d.drift,
                d.floor,
                d.runs,
                d.contradicts(verdict),
                d.note,
                compared_with="integral",
                narrowed=d.narrowed,
            )
        )
    return tuple(out)
