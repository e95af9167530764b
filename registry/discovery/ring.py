"""The ring a system lives in: the state variables, the inverse of each denominator factor
of its equations of motion, and each square root they contain, with their relations.

A potential b/gamma3^2 makes the equations of motion rational with the factor gamma3 in
the denominators; a potential with sqrt(gamma1^2 + gamma2^2) makes them radical. Their
integrals (Goryachev's 1916 one has 1/gamma3^2) lie in the ring

    Q(p)[M, gamma, u, rho, r] / (u f - 1, rho^2 - b, r rho - 1)

with u = 1/f for a denominator factor f, rho = sqrt(b) for a radicand b and r = 1/rho.
A Groebner basis of these relations (with the level set's equations) gives the normal
form the search works with: Laurent polynomials in the denominators, polynomials in rho
reduced by rho^2 = b. The adjoined variables come first in the ring's order, so that
rho^2, not gamma1^2, is the leading term of rho^2 - b. In the ansatz the inverse
variables weigh nothing and their exponents are bounded by those the Hamiltonian uses
(at least one); rho weighs half its radicand. What is not in such a ring (an arbitrary
function, a transcendental one, another root) is refused with the reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef

from ..errors import DiscoveryError
from ..mathematics import factoring
from ..mathematics import mechanics as mech


def _outside(node: sp.Expr) -> str:
    """Why a function node is outside every ring of the method, naming the function."""
    arbitrary = sorted({str(f.func) for f in node.atoms(AppliedUndef)})
    if arbitrary:
        what = f"the arbitrary function(s) {', '.join(arbitrary)} (a family of systems)"
    else:
        what = f"the transcendental function {node.func.__name__}"
    return (
        f"the equations of motion contain {what}: they are not rational in the state "
        "variables, nor in square roots of polynomials, so no ring the ansatz can span "
        "holds them"
    )


class NotInRingError(DiscoveryError):
    """An expression is not in the ring the search works in (an arbitrary function, a
    transcendental function, a root other than a square root of a polynomial, a
    denominator factor the system does not have)."""


@dataclass(frozen=True)
class Adjoined:
    """A variable adjoined to the state's: ``symbol`` stands for ``value`` (1/f, sqrt(b)
    or 1/sqrt(b)); ``base`` is f or b; ``kind`` is ``inverse``, ``root`` or
    ``root_inverse``; ``weight`` its weight in the ansatz, ``bound`` the largest exponent
    the ansatz gives it (None: as large as the weight allows)."""

    symbol: sp.Symbol
    kind: str
    base: sp.Expr
    value: sp.Expr
    weight: int
    bound: int | None


def _polynomial(expr: sp.Expr, state: set[sp.Symbol]) -> bool:
    """Whether ``expr`` is visibly polynomial in the state (no state in a denominator, a
    root or a function): the common case, which needs no ring beyond the state's."""
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Pow):
            if not (node.exp.is_Integer and node.exp >= 0) and node.base.free_symbols & state:
                return False
        elif isinstance(node, (sp.Function, sp.Derivative)) and node.free_symbols & state:
            return False
    return True


def _primitive(poly: sp.Expr, state: Sequence[sp.Symbol]) -> sp.Expr:
    """A state polynomial up to a constant factor: primitive, leading coefficient positive."""
    p = sp.Poly(sp.expand(poly), *state)
    _, p = p.primitive()
    if p.LC().could_extract_minus_sign():
        p = -p
    return p.as_expr()


class SystemRing:
    """The variables of a system's ring and their relations (module docstring), found from
    the expressions the system is built from (the field and the Hamiltonian). ``state``
    are the state variables and ``shorthands`` the names standing for expressions of them
    (s = M.gamma), written out before anything else."""

    def __init__(
        self,
        expressions: Sequence[sp.Expr],
        weights: Sequence[int],
        *,
        state: Sequence[sp.Symbol] = mech.STATE,
        shorthands=mech.SHORTHANDS,
        bound_from=(),
    ):
        self.state = tuple(state)
        self._state_set = set(self.state)
        self.shorthands = dict(shorthands or {})
        self.state_weights = tuple(weights)
        self.roots: dict[sp.Expr, tuple[sp.Symbol, sp.Symbol]] = {}
        self.inverses: dict[sp.Expr, sp.Symbol] = {}
        prepared = [self._prepare(e) for e in expressions]
        for e in prepared:
            self._collect(e)
        bounds: dict[sp.Symbol, int] = {}
        for e in bound_from if (self.roots or self.inverses) else ():
            lifted = self.lift(e)
            for symbol in [*self.inverses.values(), *(r for _, r in self.roots.values())]:
                degree = sp.Poly(lifted, symbol).degree() if lifted.has(symbol) else 0
                bounds[symbol] = max(bounds.get(symbol, 1), degree)
        self.adjoined: list[Adjoined] = []
        for b, (rho, r) in self.roots.items():
            w = self._weight(b)
            self.adjoined.append(Adjoined(rho, "root", b, sp.sqrt(b), (w + 1) // 2, None))
            self.adjoined.append(
                Adjoined(r, "root_inverse", b, 1 / sp.sqrt(b), 0, bounds.get(r, 1))
            )
        for f, u in self.inverses.items():
            self.adjoined.append(Adjoined(u, "inverse", f, 1 / f, 0, bounds.get(u, 1)))

    # ------------------------------------------------------------------ finding

    def _prepare(self, expr: sp.Expr) -> sp.Expr:
        expr = sp.sympify(expr)
        return expr.subs(self.shorthands) if self.shorthands else expr

    def _weight(self, poly: sp.Expr) -> int:
        p = sp.Poly(poly, *self.state)
        return max(
            sum(a * w for a, w in zip(m, self.state_weights, strict=True)) for m in p.monoms()
        )

    def _collect(self, expr: sp.Expr) -> None:
        """Record the radicands and denominator factors of ``expr``."""
        if _polynomial(expr, self._state_set):
            return
        for node in sp.preorder_traversal(expr):
            if isinstance(node, sp.Pow) and not node.exp.is_Integer:
                self._root_of(node)
            elif isinstance(node, (sp.Function, sp.Derivative)) and (
                node.free_symbols & self._state_set
            ):
                raise NotInRingError(_outside(node))
        rooted = self._roots_replaced(expr)
        _, denominator = sp.fraction(sp.together(rooted))
        for factor, _ in factoring.coefficient_and_factors(denominator)[1]:
            if factor.free_symbols & self._state_set and not self._rooted_factor(factor):
                f = _primitive(factor, self.state)
                if f not in self.inverses:
                    self.inverses[f] = sp.Symbol(f"ring_u{len(self.inverses) + 1}")

    def _root_of(self, node: sp.Pow) -> tuple[sp.Symbol, sp.Symbol] | None:
        base = node.base
        if not (base.free_symbols & self._state_set):
            return None
        if node.exp.is_Rational and node.exp.q == 2 and base.is_polynomial(*self.state):
            b = sp.expand(base)
            if b not in self.roots:
                i = len(self.roots) + 1
                self.roots[b] = (sp.Symbol(f"ring_rho{i}"), sp.Symbol(f"ring_r{i}"))
            return self.roots[b]
        raise NotInRingError(
            f"the equations of motion contain {node}, a root that is not the square root of "
            "a polynomial in the state; the ansatz cannot hold its integrals"
        )

    def _roots_replaced(self, expr: sp.Expr, *, learn: bool = True) -> sp.Expr:
        """``expr`` with sqrt(b)^p written rho^p or r^-p (new radicands recorded if
        ``learn``, else refused)."""

        def replace(node):
            pair = self._root_of(node) if learn else self._known_root(node)
            if pair is None:
                return node
            rho, r = pair
            p = node.exp.p
            return rho**p if p > 0 else r ** (-p)

        return sp.sympify(expr).replace(
            lambda n: isinstance(n, sp.Pow) and not n.exp.is_Integer, replace
        )

    def _known_root(self, node: sp.Pow):
        if not (node.base.free_symbols & self._state_set):
            return None
        pair = self.roots.get(sp.expand(node.base))
        if pair is None or not (node.exp.is_Rational and node.exp.q == 2):
            raise NotInRingError(f"{node} is not in the system's ring")
        return pair

    def _rooted_factor(self, factor: sp.Expr) -> sp.Symbol | None:
        """The r of a radicand equal to ``factor`` up to a constant (1/b = r^2)."""
        f = _primitive(factor, self.state)
        for b, (_, r) in self.roots.items():
            if _primitive(b, self.state) == f:
                return r
        return None

    # --------------------------------------------------------------- the ring

    @property
    def extended(self) -> bool:
        return bool(self.adjoined)

    @property
    def variables(self) -> tuple[sp.Symbol, ...]:
        """The ring's variables: the adjoined ones first, then the state."""
        return (*(a.symbol for a in self.adjoined), *self.state)

    @property
    def weights(self) -> tuple[int, ...]:
        return (*(a.weight for a in self.adjoined), *self.state_weights)

    @property
    def bounds(self) -> tuple[int | None, ...]:
        return (*(a.bound for a in self.adjoined), *(None,) * len(self.state))

    def relations(self) -> list[sp.Expr]:
        """The relations of the adjoined variables (expressions that vanish)."""
        out = []
        for a in self.adjoined:
            if a.kind == "root":
                out.append(a.symbol**2 - a.base)
            elif a.kind == "root_inverse":
                (rho,) = [b.symbol for b in self.adjoined if b.kind == "root" and b.base == a.base]
                out.append(a.symbol * rho - 1)
            else:
                out.append(a.symbol * a.base - 1)
        return out

    def lift(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` as a polynomial in the ring's variables (parameter denominators may
        remain); NotInRingError where it is not in the ring."""
        e = self._prepare(expr)
        for node in sp.preorder_traversal(e):
            if isinstance(node, (sp.Function, sp.Derivative)) and (
                node.free_symbols & self._state_set
            ):
                raise NotInRingError(_outside(node))
        rooted = self._roots_replaced(e, learn=False)
        numerator, denominator = sp.fraction(sp.together(rooted))
        coefficient, factors = factoring.coefficient_and_factors(denominator)
        out = numerator / coefficient
        for factor, k in factors:
            if not (factor.free_symbols & self._state_set):
                out /= factor**k
                continue
            r = self._rooted_factor(factor)
            f = _primitive(factor, self.state)
            if r is not None:
                (b,) = [b for b, (_, rr) in self.roots.items() if rr == r]
                scale = sp.cancel(factor / b)
                out *= r ** (2 * k) / scale**k
            elif f in self.inverses:
                scale = sp.cancel(factor / f)
                out *= self.inverses[f] ** k / scale**k
            else:
                raise NotInRingError(
                    f"the denominator {factor} is not a denominator of the equations of motion"
                )
        return sp.expand(out)

    def lower(self, expr: sp.Expr) -> sp.Expr:
        """An expression in the ring's variables as one in the state: each adjoined
        variable replaced by what it stands for."""
        return sp.sympify(expr).xreplace({a.symbol: a.value for a in self.adjoined})

    def rates(self, field: Sequence[sp.Expr]) -> list[sp.Expr]:
        """d/dt of every variable of the ring (adjoined first), lifted, from the state's
        field (six expressions)."""
        lifted = [self.lift(x) for x in field]

        def along(poly: sp.Expr) -> sp.Expr:
            return sp.expand(
                sum(sp.diff(poly, v) * x for v, x in zip(self.state, lifted, strict=True))
            )

        out = []
        for a in self.adjoined:
            if a.kind == "root":
                (r,) = [
                    b.symbol for b in self.adjoined if b.kind == "root_inverse" and b.base == a.base
                ]
                out.append(sp.expand(along(a.base) * r / 2))
            elif a.kind == "root_inverse":
                out.append(sp.expand(-(a.symbol**3) * along(a.base) / 2))
            else:
                out.append(sp.expand(-(a.symbol**2) * along(a.base)))
        return [*out, *lifted]
