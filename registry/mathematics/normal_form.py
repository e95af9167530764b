"""The normal form in which the zero test proves a residual zero.

Radicals b**(p/q) become new symbols rho with rho**q = b, transcendental terms and
arbitrary functions become new symbols (``Atoms``); the result is a rational function
whose numerator is reduced modulo the relations those symbols satisfy: the radicals'
rho**q = b, sin(u)**2 + cos(u)**2 = 1 and cosh(u)**2 - sinh(u)**2 = 1 for the atoms of
one argument (tan and tanh written as quotients), and the level-set equations (by a
Groebner basis). Every relation is a true identity, so a zero remainder is a proof
(``prove_zero``); a non-zero one proves nothing. The parameter conditions read their
polynomial system off the same numerator (``numerator``, ``reduce_radical``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import sympy as sp
from sympy.core.function import AppliedUndef

from .mechanics import SHORTHANDS


class Atoms:
    """Rewrites an expression as a rational function of new symbols for its
    radicals (rho**q = base) and its transcendental or arbitrary-function terms."""

    def __init__(self, shorthands: Mapping[sp.Symbol, sp.Expr] = SHORTHANDS) -> None:
        #: names that stand for expressions of the state (the paper's s = M.gamma)
        self.shorthands = dict(shorthands)
        self.radicals: dict[tuple[sp.Expr, int], sp.Symbol] = {}
        self.others: dict[sp.Expr, sp.Symbol] = {}
        self._memo: dict[sp.Expr, sp.Expr] = {}

    def relations(self) -> list[tuple[sp.Symbol, int, sp.Expr]]:
        return [(rho, q, base) for (base, q), rho in self.radicals.items()]

    def pythagorean(self) -> list[tuple[sp.Symbol, int, sp.Expr]]:
        """The relations between the atoms of one argument, written like a radical's
        (symbol, 2, square): sin(u)**2 = 1 - cos(u)**2, sinh(u)**2 = cosh(u)**2 - 1
        (true identities: a remainder of zero modulo them is still a proof)."""
        out = []
        for (odd, even), sign in ((_CIRCULAR, -1), (_HYPERBOLIC, 1)):
            for key, s in self.others.items():
                if isinstance(key, odd):
                    c = self.others.get(even(*key.args))
                    if c is not None:
                        out.append((s, 2, sign * (c**2 - 1)))
        return out

    def rewrite(self, expr: sp.Expr) -> sp.Expr:
        hit = self._memo.get(expr)
        if hit is None:
            hit = self._rewrite(expr)
            self._memo[expr] = hit
        return hit

    def _key(self, expr: sp.Expr) -> sp.Expr:
        return sp.expand(self.rewrite(expr).xreplace(self.shorthands))

    def _rewrite(self, expr: sp.Expr) -> sp.Expr:
        if expr.is_Atom:
            return expr
        if isinstance(expr, (AppliedUndef, sp.Derivative, sp.Subs)):
            return self._symbol_for(expr)
        if expr.is_Pow:
            base, exp = expr.base, expr.exp
            if exp.is_Integer:
                return self.rewrite(base) ** exp
            if exp.is_Rational:
                # (p/q)**e = p**e * q**-e wherever the left side is real
                num, den = sp.fraction(sp.together(self._key(base)))
                return self._radical(sp.expand(num), exp) * self._radical(sp.expand(den), -exp)
            return self._symbol_for(sp.Pow(self._key(base), self._key(exp)))
        if isinstance(expr, (sp.tan, sp.tanh)):
            odd, even = _CIRCULAR if isinstance(expr, sp.tan) else _HYPERBOLIC
            (arg,) = expr.args
            return self.rewrite(odd(arg)) / self.rewrite(even(arg))
        if isinstance(expr, sp.Function):
            return self._symbol_for(expr.func(*(self._key(a) for a in expr.args)))
        return expr.func(*(self.rewrite(a) for a in expr.args))

    def _radical(self, base: sp.Expr, exp: sp.Rational) -> sp.Expr:
        """base**exp as rho**p with rho**q = base (exp = p/q)."""
        if base == 1 or exp.is_Integer:
            return base**exp
        key = (base, int(exp.q))
        rho = self.radicals.get(key)
        if rho is None:
            rho = self.radicals[key] = sp.Dummy(f"rho{len(self.radicals)}")
        return rho ** int(exp.p)

    def _symbol_for(self, key: sp.Expr) -> sp.Symbol:
        sym = self.others.get(key)
        if sym is None:
            sym = self.others[key] = sp.Dummy(f"tau{len(self.others)}")
        return sym


def prove_zero(
    expr: sp.Expr,
    on: Sequence[sp.Expr] = (),
    shorthands: Mapping[sp.Symbol, sp.Expr] = SHORTHANDS,
    state: Sequence[sp.Symbol] = (),
) -> str | None:
    """Prove ``expr`` == 0 (on the level set ``on``); return the method, or None.

    Given the ``state``, the proof is first tried with every sum of parameters alone
    (I1 + m*R**2) replaced by a new symbol: an identity in independent symbols stays one
    when they take those values, so a zero there is a proof, found in far smaller
    polynomials; only where that fails is the residual expanded in the parameters.
    """
    if state:
        general = _ParameterSums({*state, *shorthands})
        found = _prove_zero(general(expr), [general(e) for e in on], shorthands)
        if found is not None:
            return found
    return _prove_zero(expr, on, shorthands)


class _ParameterSums:
    """Replaces each sum free of the state by a symbol of its own (one per sum)."""

    def __init__(self, state: set[sp.Symbol]):
        self.state = state
        self.symbols: dict[sp.Expr, sp.Symbol] = {}

    def __call__(self, expr: sp.Expr) -> sp.Expr:
        expr = sp.sympify(expr)
        if expr.is_Atom:
            return expr
        if expr.is_Add and not (expr.free_symbols & self.state):
            found = self.symbols.get(expr)
            if found is None:
                found = self.symbols[expr] = sp.Dummy(f"p{len(self.symbols)}")
            return found
        return expr.func(*(self(a) for a in expr.args))


def _prove_zero(
    expr: sp.Expr, on: Sequence[sp.Expr], shorthands: Mapping[sp.Symbol, sp.Expr]
) -> str | None:
    """``prove_zero`` in the parameters as they are.

    The rewritten residual becomes an element of the field Q(x1, ..., xn) of
    rational functions in the state variables, parameters and atom symbols
    (sparse polynomial arithmetic, far cheaper than manipulating expression
    trees); its numerator is then reduced modulo rho**q - base for every radical.
    """
    atoms = Atoms(shorthands)
    numer, ring = numerator_poly(atoms.rewrite(expr), atoms)
    if not numer:
        return "rational normal form"
    relations = relation_polys(atoms, ring)
    if not on:
        if relations and not numer.rem(relations):
            return "algebraic normal form"
        return None
    eqs = [numerator(atoms.rewrite(e), atoms.shorthands).xreplace(CONSTANTS) for e in on]
    eqs += [rho**q - base.xreplace(CONSTANTS) for rho, q, base in atoms.relations()]
    eqs += [s**q - square for s, q, square in atoms.pythagorean()]
    numer_expr = numer.as_expr()
    gens = sorted(set().union(*(e.free_symbols for e in [numer_expr, *eqs])), key=str)
    basis = sp.groebner(eqs, *gens, order="grevlex", domain=sp.QQ)
    _, remainder = basis.reduce(numer_expr)
    return "level-set reduction" if remainder == 0 else None


def relation_polys(atoms: Atoms, ring) -> list:
    """The relations of the atoms (the radicals' rho**q = base, sin**2 + cos**2 = 1) as
    polynomials of ``ring`` (``numerator_poly``'s), each led by its atom's power."""
    return [
        ring(rho) ** q - ring.from_expr(base.xreplace(CONSTANTS))
        for rho, q, base in atoms.relations()
    ] + [
        ring(s) ** q - ring.from_expr(square)
        for s, q, square in atoms.pythagorean()
        if {s, *square.free_symbols} <= set(ring.symbols)
    ]


def numerator_poly(rewritten: sp.Expr, atoms: Atoms):
    """The numerator of the rewritten expression as a sparse polynomial over QQ, with
    the radical symbols first in a lex order (so rho**q leads its relation), and its
    ring (pi and E as indeterminates of it)."""
    expr = rewritten.xreplace({**atoms.shorthands, **CONSTANTS})
    radicals = list(reversed(atoms.radicals.values()))  # outer radicals before inner ones
    bases = set().union(*(b.xreplace(CONSTANTS).free_symbols for b, _ in atoms.radicals))
    others = sorted((expr.free_symbols | bases) - set(radicals), key=str)
    ring = sp.polys.rings.PolyRing([*radicals, *others] or [sp.Dummy("x")], sp.QQ, sp.lex)
    numer, _ = _fraction(expr, ring, {})
    return numer, ring


def as_fraction(expr: sp.Expr, ring, cache: dict | None = None):
    """A rational function of the ring's generators as its numerator (a polynomial of
    ``ring``) and its denominator as {polynomial factor: exponent} (not multiplied out:
    no gcd is computed). ValueError when ``expr`` is no rational function of them."""
    return _fraction(expr, ring, {} if cache is None else cache)


def _fraction(expr: sp.Expr, ring, cache: dict):
    """expr as numerator and denominator, the denominator kept as a product of factors
    {polynomial: exponent} so that no polynomial gcd is ever needed (gcds of many-variable
    polynomials are what makes ``together`` and rational-function fields slow)."""
    hit = cache.get(expr)
    if hit is not None:
        return hit
    value: tuple[Any, dict]
    if expr.is_Rational:
        value = (ring(expr), {})
    elif expr.is_Symbol:
        value = (ring(expr), {})
    elif expr.is_Add:
        parts = [_fraction(a, ring, cache) for a in expr.args]
        common: dict = {}
        for _, den in parts:
            for f, e in den.items():
                common[f] = max(common.get(f, 0), e)
        total = ring.zero
        for num, den in parts:
            for f, e in common.items():
                if e > den.get(f, 0):
                    num = num * f ** (e - den.get(f, 0))
            total += num
        value = (total, common)
    elif expr.is_Mul:
        num, den = ring.one, {}
        for a in expr.args:
            n, d = _fraction(a, ring, cache)
            num = num * n
            for f, e in d.items():
                den[f] = den.get(f, 0) + e
        value = (num, den)
    elif expr.is_Pow and expr.exp.is_Integer:
        n, d = _fraction(expr.base, ring, cache)
        k = int(expr.exp)
        if k >= 0:
            value = (n**k, {f: e * k for f, e in d.items()})
        else:
            num = ring.one
            for f, e in d.items():
                num = num * f ** (-e * k)
            value = (num, {n: -k})
    else:
        raise ValueError(f"not a rational function: {expr}")
    cache[expr] = value
    return value


#: The pairs of functions of one argument whose squares are related (``pythagorean``).
_CIRCULAR = (sp.sin, sp.cos)
_HYPERBOLIC = (sp.sinh, sp.cosh)

#: pi and E as indeterminates: an identity in them holds for their values too.
CONSTANTS = {sp.pi: sp.Dummy("pi"), sp.E: sp.Dummy("E")}


def numerator(rewritten: sp.Expr, shorthands: Mapping[sp.Symbol, sp.Expr] = SHORTHANDS) -> sp.Expr:
    """The expanded numerator of an expression rewritten by ``Atoms`` (shorthands such as
    s written out as M . gamma)."""
    rational = rewritten.xreplace(dict(shorthands))
    return sp.expand(sp.numer(sp.together(rational)))


def reduce_radical(numer: sp.Expr, rho: sp.Symbol, q: int, base: sp.Expr) -> sp.Expr:
    """numer modulo rho**q - base: every rho**k becomes base**(k // q) * rho**(k % q)."""
    if not numer.has(rho):
        return numer
    poly = sp.Poly(numer, rho)
    reduced = sp.Add(*(c * base ** (k // q) * rho ** (k % q) for (k,), c in poly.terms()))
    return sp.expand(reduced)
