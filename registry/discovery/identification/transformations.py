"""The equivalences identification uses, as one change of variables of the state and of
time, and what it does to a field and to an integral.

A transformation carries the state x = (L, gamma) of one system to the state of a
catalog case (in normal form, ``field_form``):

    L' = lam P L + sigma(gamma),   gamma' = rho P gamma,   t' = t / tau

* ``tau``, ``lam``, ``rho``: scalings of time and of each vector by its own factor
  (each nonzero; tau < 0 reverses time, which keeps integrals);
* ``P``: a permutation of the axes with sign changes, times a rotation about an axis
  of symmetry of the first system (cos, sin with cos^2 + sin^2 = 1) where it has one;
  an improper P reverses the cross products, absorbed by the sign of tau;
* ``sigma``: the shift (h0 + h.gamma) rho A'^-1 P gamma that keeps the normal form's
  dgamma/dt = gamma x A L (A' the case's inverse inertia): with the normal form's own
  shift L = M + A^-1 g(gamma), every shift M -> M + f(gamma) by a polynomial f of degree
  <= 2 whose gamma x A f part is what the normal form removes. This is the shift that
  carries the reference paper's torque mu into mu + (tr I - 2 I) h0 gamma with the
  potential changed by h0^2 gamma.I gamma / 2 (Yehia's Kovalevskaya torques), and a
  gyrostat or Kirchhoff's M.B gamma terms into the torque form;
* Casimirs added to H change no vector field, so they need nothing.

The transformed field is tau * (dPhi) F(x); two systems are the same when it equals the
case's field at Phi(x) for some values of the case's parameters.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from ...language.printer import to_text
from ...mathematics import mechanics as mech
from .field_form import GAMMA, L_STATE, FieldForm

#: The six permutations of the axes, the identity first.
PERMUTATIONS: tuple[tuple[int, ...], ...] = tuple(itertools.permutations(range(3)))


@dataclass(frozen=True)
class Transformation:
    """One change of variables (module docstring), its entries sympy expressions (in the
    unknowns while it is being solved for, in the first system's parameters after)."""

    tau: sp.Expr
    lam: sp.Expr
    rho: sp.Expr
    matrix: sp.ImmutableMatrix
    shift: tuple[sp.Expr, sp.Expr, sp.Expr]

    def substitute(self, values: Mapping[sp.Symbol, sp.Expr]) -> Transformation:
        """The transformation with unknowns replaced by their values."""

        def put(e):
            return sp.cancel(sp.sympify(e).xreplace(values))

        return Transformation(
            put(self.tau),
            put(self.lam),
            put(self.rho),
            sp.ImmutableMatrix(self.matrix.applyfunc(put)),
            tuple(put(e) for e in self.shift),  # type: ignore[arg-type]
        )

    def images(self) -> tuple[list[sp.Expr], list[sp.Expr]]:
        """(L', gamma') as expressions of the first system's L and gamma."""
        lv, gv = sp.Matrix(L_STATE), sp.Matrix(GAMMA)
        new_l = self.lam * self.matrix * lv + sp.Matrix(self.shift)
        new_g = self.rho * self.matrix * gv
        return list(new_l), list(new_g)

    def pushed(self, form: FieldForm) -> list[sp.Expr]:
        """tau dPhi F: the first system's field in the case's variables (as functions of the
        first system's state)."""
        new_l, new_g = self.images()
        jacobian = sp.Matrix([*new_l, *new_g]).jacobian([*L_STATE, *GAMMA])
        return list(self.tau * jacobian * sp.Matrix(form.field))

    def pulled(self, form: FieldForm) -> list[sp.Expr]:
        """The case's field (``form``) at Phi(x)."""
        new_l, new_g = self.images()
        values = dict(zip((*L_STATE, *GAMMA), (*new_l, *new_g), strict=True))
        return [sp.sympify(f).xreplace(values) for f in form.field]

    def pullback(self, expr: sp.Expr, case: FieldForm, mine: FieldForm) -> sp.Expr:
        """An expression of the case's M and gamma as one of the first system's M and gamma:
        into the case's normal form, through Phi, out of the first system's."""
        new_l, new_g = self.images()
        in_l = case.momentum(expr)
        values = dict(zip((*L_STATE, *GAMMA), (*new_l, *new_g), strict=True))
        pulled = sp.sympify(in_l).xreplace(values)
        back = {lv: m + f for lv, m, f in zip(L_STATE, mech.MOMENTUM, mine.shift, strict=True)}
        return sp.expand(pulled.xreplace(back))

    def description(
        self, mine: FieldForm, case: FieldForm, values: Mapping[sp.Symbol, sp.Expr]
    ) -> dict[str, str]:
        """The case's variables (and time) as expressions of the first system's M, gamma
        and t, the case's parameters at ``values``:
        ``{"M1": "2*M3", ..., "gamma1": "gamma3", ..., "t": "t/2"}``."""
        new_l, new_g = self.images()
        into = {lv: m + f for lv, m, f in zip(L_STATE, mech.MOMENTUM, mine.shift, strict=True)}
        out = {}
        for k in range(3):
            theirs = sp.sympify(case.shift[k]).xreplace(values)
            momentum = sp.expand(
                new_l[k].xreplace(into) - theirs.xreplace(dict(zip(GAMMA, new_g, strict=True)))
            )
            out[str(mech.MOMENTUM[k])] = to_text(sp.factor_terms(momentum))
        for k in range(3):
            out[str(GAMMA[k])] = to_text(sp.expand(new_g[k]))
        out["t"] = to_text(sp.Symbol("t") / self.tau)
        return out

    def is_identity(self) -> bool:
        return (
            self.tau == 1
            and self.lam == 1
            and self.rho == 1
            and self.matrix == sp.eye(3)
            and not any(self.shift)
        )


def axes_matrix(
    order: Sequence[int],
    signs: Sequence[sp.Expr],
    rotation: tuple[int, sp.Expr, sp.Expr] | None = None,
) -> sp.Matrix:
    """P = Pi D R: R rotates about axis ``rotation[0]`` by (cos, sin), D changes signs,
    Pi sends axis i to axis order[i]."""
    perm = sp.zeros(3, 3)
    for i, j in enumerate(order):
        perm[j, i] = 1
    diag = sp.diag(*signs)
    rot = sp.eye(3)
    if rotation is not None:
        axis, cos, sin = rotation
        i, j = [k for k in range(3) if k != axis]
        rot[i, i], rot[i, j], rot[j, i], rot[j, j] = cos, -sin, sin, cos
    return perm * diag * rot


def residual_shift(
    coefficients: Sequence[sp.Expr], rho: sp.Expr, kinetic: sp.Matrix, matrix: sp.Matrix
) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """sigma(gamma) = (h0 + h.gamma) rho A'^-1 P gamma, the shifts that keep the normal
    form (``coefficients`` = h0, h1, h2, h3; fewer means a constant h0 only)."""
    h = coefficients[0] + sum(
        (c * g for c, g in zip(coefficients[1:], GAMMA, strict=False)), sp.Integer(0)
    )
    vector = h * rho * kinetic.inv() * matrix * sp.Matrix(GAMMA)
    return tuple(vector)  # type: ignore[return-value]
