"""A case's vector field in the form identification compares: polynomial in the state
(M, gamma), with the gamma-dependent part of the angular velocity shifted away.

On e(3) and its torques, dgamma/dt = gamma x w with w = A M + g(gamma) (A the inverse
inertia, g from M.B gamma terms of a Hamiltonian, a gyrostatic moment, ...). The shift
L = M + A^-1 g(gamma) makes it gamma x A L: a torque form (the reference paper's, mu(gamma)
in the bracket) and a Hamiltonian form with M-gamma terms (Kirchhoff's, Wolf's) of the
same system then have the same *normal form*, up to the residual shifts
L -> L + h(gamma) A^-1 gamma that keep it (``matching``). Adding Casimirs to H changes no
vector field, so it needs nothing here.

A field that is not polynomial in the state (radicals, functions of s over a
denominator) has no form: such cases are not compared (said where it matters). A field
whose dgamma/dt is not gamma x (A M + g) (so(4), another phase space) keeps its field as
it is, with no shift (``shifted`` false).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from ...dynamics import Dynamics
from ...mathematics import mechanics as mech

#: The normal form's momentum variables (L = M + A^-1 g(gamma)).
L_STATE: tuple[sp.Symbol, ...] = sp.symbols("L1 L2 L3", real=True)
GAMMA: tuple[sp.Symbol, ...] = mech.AXIS
STATE = (*L_STATE, *GAMMA)


@dataclass(frozen=True)
class FieldForm:
    """A system in normal form: its ``parameters``, the inverse inertia ``kinetic`` (A,
    None where dgamma/dt is not gamma x (A M + g)), the ``shift`` f(gamma) = A^-1 g with
    L = M + f, and the ``field`` (dL/dt, dgamma/dt) as expressions of L, gamma and the
    parameters (rational in the parameters, polynomial in the state)."""

    parameters: tuple[sp.Symbol, ...]
    kinetic: sp.ImmutableMatrix | None
    shift: tuple[sp.Expr, sp.Expr, sp.Expr]
    field: tuple[sp.Expr, ...]

    @property
    def shifted(self) -> bool:
        return self.kinetic is not None

    def profile(self) -> frozenset[tuple[str, int, int]]:
        """(component, degree in L, degree in gamma) of every term of the field, with the
        component "L" or "gamma": unchanged by permutations, rotations and scalings."""
        out = set()
        for i, f in enumerate(self.field):
            kind = "L" if i < 3 else "gamma"
            if f == 0:  # the zero polynomial's monoms() is [(0, ..., 0)]: no term
                continue
            for monomial in sp.Poly(f, *STATE).monoms():
                out.add((kind, sum(monomial[:3]), sum(monomial[3:])))
        return frozenset(out)

    def support(self) -> frozenset[tuple[int, tuple[int, ...]]]:
        """(component, exponents of L1 L2 L3 gamma1 gamma2 gamma3) of every term of the
        field, at generic parameter values."""
        return frozenset(
            (i, monomial)
            for i, f in enumerate(self.field)
            if f != 0  # the zero polynomial's monoms() is [(0, ..., 0)]: no constant term
            for monomial in sp.Poly(f, *STATE).monoms()
        )

    def momentum(self, expr: sp.Expr) -> sp.Expr:
        """An expression of M and gamma written in L and gamma (M = L - f(gamma))."""
        values = {m: lv - f for m, lv, f in zip(mech.MOMENTUM, L_STATE, self.shift, strict=True)}
        return sp.sympify(expr).xreplace(values)


def field_form(dynamics: Dynamics) -> FieldForm | None:
    """The normal form of a system (module docstring), None where the state is not
    (M, gamma) or the field is not polynomial in it."""
    if tuple(dynamics.variables) != mech.STATE:
        return None
    field = [sp.expand(dynamics.expanded(f)) for f in dynamics.field]
    if any(not _polynomial(f) for f in field):
        return None
    parameters = tuple(sorted(set(dynamics.parameters), key=str))
    found = _angular_velocity(field[3:])
    if found is None:
        plain = tuple(e.xreplace(dict(zip(mech.MOMENTUM, L_STATE, strict=True))) for e in field)
        return FieldForm(parameters, None, (sp.Integer(0),) * 3, plain)
    kinetic, g = found
    if kinetic.det() == 0:
        return None
    shift = tuple(sp.cancel(e) for e in kinetic.inv() * sp.Matrix(g))
    values = {m: lv - f for m, lv, f in zip(mech.MOMENTUM, L_STATE, shift, strict=True)}
    vm, vg = sp.Matrix(field[:3]), sp.Matrix(field[3:])
    jacobian = sp.Matrix(shift).jacobian(GAMMA)
    dl = (vm + jacobian * vg).xreplace(values)
    dg = vg.xreplace(values)
    out = tuple(sp.expand(e) for e in (*dl, *dg))
    return FieldForm(parameters, sp.ImmutableMatrix(kinetic), shift, out)  # type: ignore[arg-type]


def _polynomial(expr: sp.Expr) -> bool:
    try:
        sp.Poly(expr, *mech.STATE)
    except sp.PolynomialError:
        return False
    return not any(a.has(*mech.STATE) for a in sp.Poly(expr, *mech.STATE).coeffs())


def _angular_velocity(vg: Sequence[sp.Expr]) -> tuple[sp.Matrix, list[sp.Expr]] | None:
    """(A, g) with dgamma/dt = gamma x (A M + g(gamma)), or None where it is not of that
    form. g is the solution of the linear system with its free coefficients 0 (defined
    up to a multiple of gamma, which the residual shifts of ``matching`` absorb)."""
    m, g = mech.MOMENTUM, GAMMA
    polys = [sp.Poly(e, *m, *g) for e in vg]
    kinetic = sp.zeros(3, 3)
    for col in range(3):
        kinetic[2, col] = polys[0].coeff_monomial(g[1] * m[col])
        kinetic[0, col] = polys[1].coeff_monomial(g[2] * m[col])
        kinetic[1, col] = polys[2].coeff_monomial(g[0] * m[col])
    gv = sp.Matrix(g)
    # as polynomials in the state, so that coefficients written apart (4/(w**2 + 4) and
    # 1/(w**2/4 + 1)) cancel
    rest = [
        sp.Poly(sp.expand(e), *m, *g).as_expr()
        for e in sp.Matrix(vg) - gv.cross(kinetic * sp.Matrix(m))
    ]
    if any(e.has(*m) for e in rest):
        return None
    degree = max([sp.Poly(e, *g).total_degree() for e in rest if e != 0], default=0)
    top = max(degree - 1, 0)
    monomials = [
        sp.Mul(*(x**k for x, k in zip(g, exps, strict=True)))
        for exps in itertools.product(range(top + 1), repeat=3)
        if sum(exps) <= top
    ]
    unknowns = sp.symbols(f"q0:{3 * len(monomials)}")
    vector = sp.Matrix(
        [sum(unknowns[3 * i + k] * mono for i, mono in enumerate(monomials)) for k in range(3)]
    )
    equations: list[sp.Expr] = []
    for e in gv.cross(vector) - sp.Matrix(rest):
        equations.extend(sp.Poly(sp.expand(e), *g).coeffs())
    if not any(equations):
        return kinetic, [sp.Integer(0)] * 3
    solution = sp.linsolve(equations, unknowns)
    if not solution:
        return None
    (values,) = solution
    chosen = dict(zip(unknowns, values, strict=True))
    free = {u: 0 for u in unknowns}
    g_value = [sp.expand(e.xreplace(chosen).xreplace(free)) for e in vector]
    return kinetic, g_value
