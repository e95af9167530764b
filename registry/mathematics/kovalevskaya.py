"""Kovalevskaya exponents: the eigenvalues of K = Dv(c) + diag(w) at each balance c of
a weighted field's leading part v, exact, with multiplicities.

Substituting x = c t^(-w) + y t^(-w) (...) into the leading equations, the linear
variational equation t y' = K y has solutions t^rho for the eigenvalues rho of K: the
exponents are the powers at which a Laurent solution can carry free coefficients
(Kovalevskaya 1889; Yoshida, Celestial Mech. 31 (1983) 363). -1 is always one, with
eigenvector (w_i c_i), the shift of the singularity's time.

*Exactness.* A balance is a root of an irreducible component's minimal polynomial g,
so its exponents are computed once per component, in F = k[u]/(g): the characteristic
polynomial p(lambda) has coefficients in F; written in the power basis,
p = sum_j u^j P_j(lambda) with P_j over k, and G = gcd_j P_j is the largest factor of p
over k. Every rational (so every integer) exponent of every balance of the component is
a root of G, with the multiplicity it has in G; the other roots of p are irrational at
every balance. G is factored over k and its roots written exactly; the remaining factor
H = p/G, whose roots depend on the balance, is split through its norm over Q (the
resultant in u) and each balance's roots are picked out by ball arithmetic (the
integer and rational flags never depend on that numerical step).

*Yoshida's theorem* (1983): if I is a weighted-homogeneous first integral of
weighted degree k >= 1 and grad I(c) != 0 at a balance c, then grad I(c) is a left
eigenvector of K with eigenvalue k, so k is an exponent of c. The degrees an integral
can have are therefore among the positive integer exponents (``Exponents.degrees``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.polys.polyroots import roots_quadratic

from . import algebraic
from .balances import Balance
from .factoring import factor_list
from .flint_polys import resultant_in
from .integral_algebra import IntegralAlgebra
from .prime_components import Component
from .weighted import WeightedField

#: The variable of characteristic polynomials.
LAMBDA = sp.Symbol("lambda")


def kovalevskaya_matrix(split: WeightedField) -> sp.Matrix:
    """K(c) = Dv(c) + diag(w) for the leading part v, in the variables (put c in them)."""
    jacobian = sp.Matrix(split.leading).jacobian(sp.Matrix(split.variables))
    return jacobian + sp.diag(*split.weights)


def matrix_in(algebra: IntegralAlgebra, component: Component, matrix: sp.Matrix) -> list[list]:
    """K at the component's generic point, entry by entry in its algebra; an entry with
    a denominator in the state (a field that divides by one) is its numerator's value
    times the inverse of its denominator's, not zero where the field is defined."""
    n, state = matrix.rows, component.variables

    def value(expr: sp.Expr):
        if expr.is_polynomial(*state):
            return algebra.lift(component.evaluate(expr))
        numer, denom = sp.fraction(sp.together(expr))
        inverse = algebra.inverse(algebra.lift(component.evaluate(denom)))
        return algebra.reduce(algebra.lift(component.evaluate(numer)) * inverse)

    return [[value(matrix[i, j]) for j in range(n)] for i in range(n)]


@dataclass(frozen=True)
class Exponents:
    """The exponents of one balance, with multiplicity: ``values`` written out (sorted),
    and ``implicit`` factors of the characteristic polynomial (in ``LAMBDA``, each with
    its multiplicity) whose roots have no closed form here. ``varying``: on a family,
    some exponent changes along it (the values are then those of a generic point, as
    functions of its free coordinates)."""

    values: tuple[sp.Expr, ...]
    implicit: tuple[tuple[sp.Expr, int], ...] = ()
    varying: bool = False

    @property
    def integer(self) -> bool:
        """Every exponent is an integer (at every point of a family)."""
        return not self.implicit and all(v.is_integer for v in self.values)

    @property
    def rational(self) -> bool:
        """Every exponent is rational (at every point of a family)."""
        return not self.implicit and all(v.is_rational for v in self.values)

    @property
    def degrees(self) -> tuple[int, ...]:
        """The positive integer exponents: the only weighted degrees a weighted-homogeneous
        integral with a gradient not zero at this balance can have (Yoshida)."""
        return tuple(sorted({int(v) for v in self.values if _positive_integer(v)}))

    @property
    def resonances(self) -> dict[int, int]:
        """The positive integer exponents with their multiplicities: where the Painlevé
        test has conditions."""
        found: dict[int, int] = {}
        for v in self.values:
            if _positive_integer(v):
                found[int(v)] = found.get(int(v), 0) + 1
        return found


def _positive_integer(v: sp.Expr) -> bool:
    """Whether an exponent is a number and a positive integer (an exponent in the
    parameters, even an integer-valued one, is not counted)."""
    return bool(v.is_Integer and v >= 1)


@dataclass(frozen=True)
class ComponentPolynomial:
    """A component's characteristic polynomial split as p = G H: ``common`` G over k (its
    irreducible factors and multiplicities: the exponents shared by every balance of the
    component) and ``rest`` H, with coefficients in k[u]/(g) (u the component's symbol)."""

    common: tuple[tuple[sp.Expr, int], ...]
    rest: sp.Expr
    varying: bool
    norm: tuple[sp.Expr, ...] = ()  # over Q: the irreducible factors of Res_u(g, H)


def characteristic_polynomial(
    component: Component, matrix: sp.Matrix, *, norm: bool = True
) -> ComponentPolynomial:
    """det(lambda - K) over the component's field, split as in the module doc (without
    H's norm where ``norm`` is False: enough to tell which exponents are rational)."""
    ext = algebraic.Extension(component.symbol, component.minimal)
    k, u = ext.domain, component.symbol
    # Berkowitz's division-free algorithm in k[u]/(g), over Z[p] (integral_algebra)
    algebra = IntegralAlgebra(u, component.minimal)
    rows = matrix_in(algebra, component, matrix)
    charpoly = [algebra.poly(c) for c in berkowitz(rows, algebra, algebra.reduce)]
    # coords[i][j]: the coefficient of u^j in the coefficient of lambda^(n-i)
    coords = [ext.coordinates(c) for c in charpoly]
    parts = [
        sp.Poly.from_list([row[j] for row in coords], LAMBDA, domain=k) for j in range(ext.degree)
    ]
    common = parts[0]
    for part in parts[1:]:
        if not part.is_zero:
            common = common.gcd(part)
    common = common.monic()
    quotient = _divide(charpoly, common, ext)
    rest = sp.Add(
        *(LAMBDA ** (len(quotient) - 1 - i) * q.as_expr() for i, q in enumerate(quotient))
    )
    gens = [LAMBDA, *sorted(common.free_symbols - {LAMBDA}, key=str)]
    factors = tuple((f, e) for f, e in factor_list(common.as_expr(), gens) if f.has(LAMBDA))
    free = set(component.free)
    varying = any(f.free_symbols & free for f, _ in factors) or bool(rest.free_symbols & free)
    norms: tuple[sp.Expr, ...] = ()
    if norm and k.is_QQ and len(quotient) > 1:
        resultant = resultant_in(component.minimal.as_expr(), rest, u)
        norms = tuple(f for f, _ in factor_list(resultant, [LAMBDA]))
    return ComponentPolynomial(factors, rest, varying, norms)


def berkowitz(matrix: list[list], ring, reduce) -> list:
    """The coefficients of det(lambda - M) (of lambda^n first) for a square matrix over a
    commutative ring, by Berkowitz's division-free algorithm, every sum of products
    passed through ``reduce`` (the remainder modulo g: the matrix's entries then lie in
    k[u]/(g) and the degrees in u stay below g's, where over k[u] they would grow with n)."""
    n = len(matrix)
    if n == 0:
        return [ring.one]
    a, row = matrix[0][0], matrix[0][1:]
    column = [r[0] for r in matrix[1:]]
    rest = [r[1:] for r in matrix[1:]]
    inner = berkowitz(rest, ring, reduce)  # det(lambda - rest), n coefficients
    # the first column of the Toeplitz matrix: 1, -a, -R C, -R A C, -R A^2 C, ...
    toeplitz = [ring.one, -a]
    power = column
    for i in range(n - 1):
        if i:
            power = [reduce(sum((x * y for x, y in zip(r, power, strict=True)), ring.zero))
                     for r in rest]  # fmt: skip
        toeplitz.append(-reduce(sum((x * y for x, y in zip(row, power, strict=True)), ring.zero)))
    return [
        reduce(sum((toeplitz[i - j] * inner[j] for j in range(min(i, n - 1) + 1)), ring.zero))
        for i in range(n + 1)
    ]


def _divide(dividend: list[sp.Poly], divisor: sp.Poly, ext) -> list[sp.Poly]:
    """The quotient (leading first) of a polynomial in lambda over F by a monic one over
    k that divides it exactly."""
    divisor_coeffs = [ext.domain.to_sympy(c) for c in divisor.all_coeffs()]
    remainder = list(dividend)
    quotient = []
    for i in range(len(dividend) - len(divisor_coeffs) + 1):
        lead = remainder[i]
        quotient.append(lead)
        for j, d in enumerate(divisor_coeffs[1:], 1):
            remainder[i + j] = ext.reduce(remainder[i + j] - lead * d)
    return quotient


def balance_exponents(balance: Balance, polynomial: ComponentPolynomial) -> Exponents:
    """The exponents of one balance of a component, from its split polynomial."""
    values: list[sp.Expr] = []
    implicit: list[tuple[sp.Expr, int]] = []
    for factor, multiplicity in polynomial.common:
        roots = algebraic.exact_roots(_poly(factor))
        if roots is None:
            implicit.append((factor, multiplicity))
        else:
            values.extend(r for r in roots for _ in range(multiplicity))
    rest = polynomial.rest
    if sp.Poly(rest, LAMBDA).degree() > 0:
        found = _balance_roots(balance, polynomial)
        if found is None:
            shown = (
                rest if balance.root is None else rest.subs(balance.component.symbol, balance.root)
            )
            implicit.append((sp.expand(shown), 1))
        else:
            values.extend(found)
    return Exponents(
        tuple(sorted(values, key=algebraic.numeric_key)), tuple(implicit), polynomial.varying
    )


def _poly(factor: sp.Expr) -> sp.Poly:
    symbols = factor.free_symbols - {LAMBDA}
    domain = sp.QQ.frac_field(*sorted(symbols, key=str)) if symbols else sp.QQ
    return sp.Poly(factor, LAMBDA, domain=domain)


def _balance_roots(balance: Balance, polynomial: ComponentPolynomial) -> list[sp.Expr] | None:
    """The roots of H at one balance: over Q, the roots of H's norm at which H vanishes
    at the balance (ball arithmetic), counted to H's degree; elsewhere the roots of H with
    the balance's root put in, where sympy writes them briefly. None when neither works.

    Where that root brings radicals among the parameters (sympy's domain EX), H is not
    factored: sympy's ``roots`` factors over the algebraic extension first, a minute for a
    quadratic. Nothing is lost by not factoring: a root of H in k = Q(p) at one balance
    is fixed by the conjugations of k[u]/(g), so it is a root at every conjugate balance,
    a factor of G already; H's roots are never in k, never rational. A quadratic's are
    then written by the formula, a higher degree's are left implicit."""
    component, u, rest = balance.component, balance.component.symbol, polynomial.rest
    if balance.root is None:  # written in terms of u, a root of the minimal polynomial
        linear = sp.Poly(rest, LAMBDA)
        if linear.degree() != 1:
            return None
        return [sp.factor_terms(sp.together(-linear.nth(0) / linear.nth(1)))]
    if polynomial.norm:
        return _roots_by_norm(component, polynomial, balance.root)
    at = sp.Poly(sp.expand(rest.subs(u, balance.root)), LAMBDA)
    if at.domain == sp.EX and at.free_symbols - {LAMBDA}:
        if at.degree() == 1:
            return [sp.together(-at.nth(0) / at.nth(1))]
        return list(roots_quadratic(at)) if at.degree() == 2 else None
    roots = sp.roots(at)
    if sum(roots.values()) != at.degree():
        return None
    return [r for r, m in roots.items() for _ in range(m)]


def _roots_by_norm(
    component: Component, polynomial: ComponentPolynomial, root: sp.Expr
) -> list[sp.Expr] | None:
    """The roots of H(lambda, root) among those of its norm, each as often as H and its
    lambda-derivatives vanish there: their balls contain 0 at ``algebraic.DIGITS`` digits
    (numerical evidence that picks the exact root; the flags never depend on it)."""
    u = component.symbol
    h = sp.Poly(polynomial.rest, LAMBDA)
    theta = algebraic.to_acb(root)
    found: list[sp.Expr] = []
    for factor in polynomial.norm:
        for candidate in algebraic.exact_roots(sp.Poly(factor, LAMBDA, domain=sp.QQ)) or ():
            value = algebraic.to_acb(candidate)
            derivative = h
            while not derivative.is_zero and algebraic.evaluate(
                derivative.as_expr(), {u: theta, LAMBDA: value}
            ).contains(0):
                found.append(candidate)
                derivative = derivative.diff(LAMBDA)
    return found if len(found) == h.degree() else None


def yoshida_degrees(exponents: Sequence[Exponents]) -> tuple[int, ...]:
    """The weighted degrees k >= 1 a weighted-homogeneous integral whose gradient is not
    zero at some balance could have: the union of the balances' positive integer
    exponents (Yoshida 1983)."""
    return tuple(sorted(set().union(*(e.degrees for e in exponents))))
