"""The symbolic objects of one case, computed once and shared by its checks and corrections.

``CaseMechanics(case)`` reads the case's ``Dynamics`` (its state, vector field, bracket
and Hamiltonian, whatever form the file gave them in) and holds what the checks share:
the components of the Jacobi identity and the domain where the case's residuals live.
The residuals of a claimed expression (dI/dt along the flow, Pi grad I) are memoized
per expression: the corrections of a refuted claim read the residual its check
computed.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Mapping
from functools import cached_property
from types import MappingProxyType

import sympy as sp

from ..dynamics import Dynamics
from ..model import Case, CheckResult, Claim
from . import flow
from .domain import Domain

#: Residuals by component name; read-only, since every check and correction shares them.
Residuals = Mapping[str, sp.Expr]


class CaseMechanics:
    """The symbolic objects of one case, computed once: its dynamics, the domain and the
    residuals of the expressions checked on it."""

    def __init__(self, case: Case):
        self.case = case
        self.dynamics: Dynamics = case.dynamics
        self._memo: dict[tuple, CheckResult] = {}
        self._residuals: dict[tuple[str, sp.Expr], Residuals] = {}
        self._gradients: dict[sp.Expr, tuple[sp.Expr, ...]] = {}

    # the system's parts, as the checks name them

    @property
    def field(self) -> tuple[sp.Expr, ...]:
        return self.dynamics.field

    @property
    def pi(self) -> sp.MatrixBase | None:
        """The bracket's Poisson tensor (None where the system has none)."""
        return self.dynamics.bracket

    @property
    def hamiltonian(self) -> sp.Expr | None:
        return self.dynamics.hamiltonian

    @property
    def mu(self) -> tuple[sp.Expr, ...] | None:
        """The paper's gyroscopic torque (None where the bracket is not Pi_mu)."""
        return self.dynamics.torque_exprs

    @property
    def kappa(self) -> sp.Expr:
        """The bracket's deformation parameter (0 on e(3) and for other brackets)."""
        return self.dynamics.kappa.expr

    @property
    def c1(self) -> sp.Expr | None:
        """The bracket's second Casimir (kappa |M|^2 + |gamma|^2)/2 for mu = 0."""
        return self.dynamics.c1

    @cached_property
    def domain(self) -> Domain:
        return Domain.of(self.dynamics)

    @cached_property
    def jacobiator(self) -> dict[str, sp.Expr]:
        """The components of the Jacobi identity of the bracket, by index triple."""
        names = [str(v) for v in self.dynamics.variables]
        return {
            f"J[{names[i]},{names[j]},{names[k]}]": value
            for (i, j, k), value in flow.jacobiator(self.dynamics, self.gradient).items()
        }

    def gradient(self, expr: sp.Expr) -> tuple[sp.Expr, ...]:
        """(d expr/d x_i) over the state (computed once per expression of this case: dI/dt
        and Pi grad I of a claim, dH/dt and Pi grad H read the same one)."""
        key = sp.sympify(expr)
        found = self._gradients.get(key)
        if found is None:
            found = self._gradients[key] = flow.gradient(self.dynamics, key)
        return found

    def time_derivative(self, expr: sp.Expr) -> sp.Expr:
        """d expr/dt along the flow (``flow.time_derivative``)."""
        return flow.along(self.dynamics.field, self.gradient(expr))

    def claim_domain(self, claim: Claim) -> Domain:
        """Where a claim is decided: the case's domain on the claim's level set (its ``on``
        equations, nothing added), at points where the claimed expression is defined."""
        return self.domain.restricted([eq.expr for eq in claim.on]).requiring(
            [claim.expression.expr]
        )

    def integral_residual(self, expr: sp.Expr) -> Residuals:
        """dI/dt = grad I . X along the flow, as the one component ``dI/dt``
        (computed once per expression)."""
        return self._residual("integral", expr, lambda: {"dI/dt": self.time_derivative(expr)})

    def casimir_residual(self, expr: sp.Expr) -> Residuals:
        """Pi grad f, by component (row of Pi; computed once per expression)."""

        def compute() -> dict[str, sp.Expr]:
            if self.dynamics.bracket is None:
                raise ValueError("the system has no bracket")
            values = flow.apply_bivector(self.dynamics.bracket, self.gradient(expr))
            return {f"Pi grad[{v}]": values[i] for i, v in enumerate(self.dynamics.variables)}

        return self._residual("casimir", expr, compute)

    def measure_residual(self, density: sp.Expr) -> Residuals:
        """div(rho X), Liouville's equation for the density rho (computed once)."""
        return self._residual(
            "measure", density, lambda: {"div(rho v)": flow.divergence(self.dynamics, density)}
        )

    def relation_domain(self, claim: Claim) -> Domain:
        """Where a relation F = 0 is decided: the claim's domain on F = 0 as well."""
        domain = self.claim_domain(claim)
        return domain.restricted([*domain.on, claim.expression.expr])

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
