"""The symbolic objects of one case, computed once and shared by its checks and corrections.

``CaseMechanics(case)`` holds Pi (Pi_mu of the paper, deformed by kappa), the vector
field dx/dt = Pi grad H (written as (2.2) for the inertia form), H, the components of
the Jacobi identity and the domain where the case's residuals live. The residuals
of a claimed expression (dI/dt along the flow, Pi_mu grad I) are memoized per
expression: the corrections of a refuted claim read the residual its check computed.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Mapping
from functools import cached_property
from types import MappingProxyType

import sympy as sp

from ..model import Case, CheckResult, Claim
from . import mechanics as mech
from .domain import Domain

#: Residuals by component name; read-only, since every check and repair shares them.
Residuals = Mapping[str, sp.Expr]


class CaseMechanics:
    """The symbolic objects of one case, computed once: Pi_mu, X, H, the domain and the
    residuals of the expressions checked on it."""

    def __init__(self, case: Case):
        self.case = case
        system = case.system
        self.inertia = system.inertia_exprs
        self.potential = system.potential.expr
        self.mu = system.torque_exprs
        self.kappa = system.kappa_expr
        self.given_hamiltonian = None if system.hamiltonian is None else system.hamiltonian.expr
        self._memo: dict[tuple, CheckResult] = {}
        self._residuals: dict[tuple[str, sp.Expr], Residuals] = {}

    @property
    def hamiltonian_form(self) -> bool:
        """Whether the case gives H itself, so that its vector field is defined as Pi grad H."""
        return self.given_hamiltonian is not None

    @cached_property
    def domain(self) -> Domain:
        return Domain(
            parameters=tuple(self.case.parameters.values()),
            functions=dict(self.case.functions),
            nonzero=tuple(self.inertia),
            defined=(
                self.given_hamiltonian if self.hamiltonian_form else self.potential,
                *self.mu,
                *([self.kappa] if self.kappa != 0 else []),
            ),
        )

    @cached_property
    def pi(self) -> sp.Matrix:
        return mech.poisson_tensor(self.mu, self.kappa)

    @cached_property
    def field(self) -> tuple[sp.Expr, ...]:
        return mech.equations_of_motion(
            self.mu,
            self.kappa,
            h=self.given_hamiltonian,
            inertia=self.inertia,
            potential=self.potential,
        )

    @cached_property
    def hamiltonian(self) -> sp.Expr:
        if self.hamiltonian_form:
            return self.given_hamiltonian
        return mech.hamiltonian(self.inertia, self.potential)

    @cached_property
    def c1(self) -> sp.Expr:
        """The bracket's second Casimir (kappa |M|^2 + |gamma|^2)/2 for mu = 0."""
        return mech.casimir_c1(self.kappa)

    @cached_property
    def jacobiator(self) -> dict[str, sp.Expr]:
        """The 20 components of the Jacobi identity for Pi_mu, by index triple."""
        names = [str(v) for v in mech.STATE]
        return {
            f"J[{names[i]},{names[j]},{names[k]}]": value
            for (i, j, k), value in mech.jacobiator(self.pi).items()
        }

    def claim_domain(self, claim: Claim) -> Domain:
        """Where a claim is decided: the case's domain on the claim's level set (its ``on``
        equations, nothing added), at points where the claimed expression is defined."""
        return self.domain.restricted([eq.expr for eq in claim.on]).requiring(
            [claim.expression.expr]
        )

    def integral_residual(self, expr: sp.Expr) -> Residuals:
        """dI/dt = grad I . X along the flow of (2.2), as the one component ``dI/dt``
        (computed once per expression)."""
        return self._residual(
            "integral", expr, lambda: {"dI/dt": mech.time_derivative(expr, self.field)}
        )

    def casimir_residual(self, expr: sp.Expr) -> Residuals:
        """Pi_mu nabla f, by component (row of Pi_mu; computed once per expression)."""

        def compute() -> dict[str, sp.Expr]:
            values = self.pi * sp.Matrix(mech.gradient(expr))
            return {f"Pi grad[{v}]": values[i] for i, v in enumerate(mech.STATE)}

        return self._residual("casimir", expr, compute)

    def _residual(
        self, kind: str, expr: sp.Expr, compute: Callable[[], dict[str, sp.Expr]]
    ) -> Residuals:
        key = (kind, sp.sympify(expr))
        found = self._residuals.get(key)
        if found is None:
            found = self._residuals[key] = MappingProxyType(compute())
        return found

    def once(self, key: tuple, compute: Callable[[], CheckResult]) -> CheckResult:
        """Compute a result once per case (e.g. a level set's invariance, used twice)."""
        if key not in self._memo:
            self._memo[key] = compute()
        return self._memo[key]

    def seed(self, check: str, claim: str | None = None) -> int:
        """A stable seed per case and check, so verdicts and witnesses reproduce."""
        return zlib.crc32(f"{self.case.id}/{check}/{claim or ''}".encode())
