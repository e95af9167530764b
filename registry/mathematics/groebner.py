"""Reduced Gröbner bases over Q and Q(parameters), the same bases sympy's ``groebner``
gives, computed fraction-free.

Over k = Q(p) sympy's Buchberger algorithm works with rational functions, and every
operation cancels a fraction by a gcd in Z[p]: on the heavy top's balances over
Q(B, C, y0, z0) it does not finish in 90 s. Here every polynomial is kept with
coefficients in Z[p] (FLINT's multivariate polynomials) and S-polynomials are reduced by
pseudo-division (f <- (lc(g)/d) f - (c/d) m g, d = gcd), each result made primitive;
fractions are formed once, when the reduced basis is made monic (4 to 8 s there). The
pairs are chosen by the normal strategy (least lcm first) and pruned by Gebauer and
Möller's criteria [GM] (R. Gebauer, H.M. Möller, J. Symbolic Comput. 6 (1988) 275; as
in Becker and Weispfenning, *Gröbner Bases* (1993), algorithm GROEBNERNEW2). The reduced
basis of an ideal is unique, so the result is sympy's own, as a ``sympy.GroebnerBasis``
(its ``fglm``, ``is_zero_dimensional`` and ``exprs`` work as usual).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import flint
import sympy as sp
from sympy.polys.polyerrors import PolificationFailed
from sympy.polys.polyoptions import build_options
from sympy.polys.polytools import parallel_poly_from_expr

from .flint_polys import fraction, numerators

#: A polynomial in the variables: exponent tuple -> coefficient in Z[p].
_Poly = dict[tuple[int, ...], flint.fmpz_mpoly]
#: The orders supported, each as a key: the larger key, the larger monomial.
ORDERS: dict[str, Callable[[tuple[int, ...]], tuple]] = {
    "grevlex": lambda m: (sum(m), tuple(-e for e in reversed(m))),
    "lex": lambda m: m,
}


def groebner(
    equations: Sequence[sp.Expr | sp.Poly],
    gens: Sequence[sp.Symbol],
    domain: sp.polys.domains.Domain,
    order: str = "grevlex",
    *,
    known: sp.GroebnerBasis | None = None,
) -> sp.GroebnerBasis:
    """The reduced Gröbner basis of ``equations`` in k[gens] (k = ``domain``: Q or
    Q(p), p free of the gens) for ``order`` ("grevlex" or "lex"): sympy's
    ``groebner(equations, *gens, order=order, domain=domain)``, computed fraction-free
    (module doc). The equations are expressions, or polynomials over ``domain`` (a basis
    found before: ``_terms``). ``known``: a reduced basis the equations are added to;
    in the same gens, domain and order its pairs are not formed again (their
    S-polynomials reduce to zero by it already), which is most of the work of adding
    one equation to a large basis. Anything else (another domain or order, a
    denominator in the gens) is left to sympy."""
    prefix: list = [] if known is None else list(known.polys)
    if order not in ORDERS or not _ours(domain):
        equations = _exprs([*prefix, *equations])
        return sp.groebner(equations, *gens, order=order, domain=domain)
    try:
        terms = _terms([*prefix, *equations], gens, domain)
    except PolificationFailed:
        equations = _exprs([*prefix, *equations])
        return sp.groebner(equations, *gens, order=order, domain=domain)
    ctx, key = _context(domain), ORDERS[order]
    same = known is not None and (known.gens, known.domain, str(known.order)) == (
        tuple(gens),
        domain,
        order,
    )
    integral = [_integral(t, domain, ctx) for t in terms if t]
    basis = _Buchberger(key).run(integral, len(prefix) if same else 0)
    options = build_options(list(gens), {"domain": domain, "order": order})
    return _result(basis, key, domain, options)


def elimination(
    equations: Sequence[sp.Expr | sp.Poly],
    eliminated: Sequence[sp.Symbol],
    gens: Sequence[sp.Symbol],
    domain: sp.polys.domains.Domain,
) -> sp.GroebnerBasis:
    """The reduced grevlex Gröbner basis of the elimination ideal (equations) ∩ k[gens],
    k = ``domain`` (Q or Q(p)): the elements free of ``eliminated`` in the reduced basis
    for the block order that compares the ``eliminated`` variables first (grevlex
    within each block; Cox, Little and O'Shea, *Ideals, Varieties, and Algorithms*,
    ch. 3 §1), which is far smaller to reach than a lex basis: 11 s against more than
    400 s for a saturation in the heavy top's balances over Q(p, q, x0, y0, z0). Over
    another domain, sympy's lex basis is filtered instead."""
    if not _ours(domain):
        lex = sp.groebner(_exprs(equations), *eliminated, *gens, order="lex", domain=domain)
        kept = [e for e in lex.exprs if not e.has(*eliminated)]
        return sp.groebner(kept, *gens, order="grevlex", domain=domain)
    terms = _terms(equations, [*eliminated, *gens], domain)
    ctx = _context(domain)
    e, grevlex = len(eliminated), ORDERS["grevlex"]
    basis = _Buchberger(lambda m: (grevlex(m[:e]), grevlex(m[e:]))).run(
        [_integral(t, domain, ctx) for t in terms if t]
    )
    kept = [{m[e:]: c for m, c in g.items()} for g in basis if not any(any(m[:e]) for m in g)]
    options = build_options(list(gens), {"domain": domain, "order": "grevlex"})
    return _result(kept, grevlex, domain, options)


class NormalForms:
    """Normal forms modulo a reduced Gröbner basis over k = Q or Q(p), by pseudo-division
    over Z[p] with one scale kept, s f = r mod I, then r/s: sympy's ``rem`` over Q(p)
    cancels a gcd in Z[p] after every step, minutes for the monomials of an algebra of
    the heavy top's balances over Q(b, c, x0, y0, z0)."""

    def __init__(self, basis: sp.GroebnerBasis, domain):
        if str(basis.order) not in ORDERS or not _ours(domain):
            raise ValueError(f"normal forms for {basis.order} bases over {domain}: not here")
        self.domain, self.ctx, self.key = domain, _context(domain), ORDERS[str(basis.order)]
        self.divisors = []
        for poly in basis.polys:
            g = _integral(poly.rep.to_dict(), domain, self.ctx)
            self.divisors.append((g, max(g, key=self.key)))

    def of_monomial(self, monomial: tuple[int, ...]) -> dict[tuple[int, ...], object]:
        """The normal form of x^monomial: {exponents: coefficient in k}."""
        one = self.ctx.from_dict({}) + 1
        done, scale = _pseudo_remainder({monomial: one}, self.divisors, self.key)
        scale = one if scale is None else scale
        if self.domain.is_QQ:
            return {m: self.domain(_constant(c), _constant(scale)) for m, c in done.items()}
        return {m: fraction(self.domain.field, c, scale) for m, c in done.items()}


def _ours(domain) -> bool:
    """Whether the bases over ``domain`` are computed here: Q and Q(p) over Q."""
    return domain.is_QQ or (domain.is_FractionField and domain.domain.is_QQ)


def _context(domain) -> flint.fmpz_mpoly_ctx:
    """FLINT's ring Z[p] for the coefficients of k = Q(p) (one unused variable for Q)."""
    count = len(domain.symbols) if domain.is_FractionField else 0
    return flint.fmpz_mpoly_ctx.get(tuple(f"p{i}" for i in range(count)) or ("p",), "lex")


def _result(basis: list[_Poly], key, domain, options) -> sp.GroebnerBasis:
    """A reduced basis over Z[p] as sympy's: made monic, listed as sympy lists it."""
    basis = sorted(basis, key=lambda g: key(max(g, key=key)), reverse=True)
    return sp.GroebnerBasis._new(
        [sp.Poly._from_dict(_monic(g, key, domain), options) for g in basis], options
    )


def _terms(equations: Sequence, gens: Sequence[sp.Symbol], domain) -> list[dict]:
    """The equations as dicts {exponents in ``gens``: coefficient in ``domain``}. A
    ``sympy.Poly`` over ``domain`` in some of the gens (a basis computed before) is read
    as it is: its expression would be expanded again, which over Q(p) takes minutes for
    a basis of the heavy top's balances (the coefficients' numerators distributed term by
    term, then summed back in Q(p) with a gcd at each sum)."""
    gens = list(gens)
    found: list[dict | None] = [None] * len(equations)
    exprs = []
    for i, f in enumerate(equations):
        if isinstance(f, sp.Poly) and f.domain == domain and set(f.gens) <= set(gens):
            where = [gens.index(g) for g in f.gens]
            terms = {}
            for monomial, c in f.rep.to_dict().items():
                exponents = [0] * len(gens)
                for j, e in zip(where, monomial, strict=True):
                    exponents[j] = e
                terms[tuple(exponents)] = c
            found[i] = terms
        else:
            exprs.append((i, f.as_expr() if isinstance(f, sp.Poly) else f))
    if exprs:
        polys, _ = parallel_poly_from_expr([f for _, f in exprs], *gens, domain=domain)
        for (i, _), p in zip(exprs, polys, strict=True):
            found[i] = p.rep.to_dict()
    return [t for t in found if t is not None]


def _exprs(equations: Sequence) -> list[sp.Expr]:
    """The equations as expressions, for sympy's own bases."""
    return [f.as_expr() if isinstance(f, sp.Poly) else f for f in equations]


def _integral(terms: dict, domain, ctx) -> _Poly:
    """A polynomial over k (Q or Q(p)), as {exponents: coefficient}, times a common
    denominator: over Z[p] in ctx."""
    if domain.is_QQ:
        scale = 1
        for c in terms.values():
            scale = math.lcm(scale, int(domain.denom(c)))
        one = (0,) * ctx.nvars()
        return {
            m: ctx.from_dict({one: int(domain.numer(c)) * (scale // int(domain.denom(c)))})
            for m, c in terms.items()
        }
    flat, _ = numerators(ctx, list(terms.values()))
    return dict(zip(terms, flat, strict=True))


def _monic(g: _Poly, key, domain) -> dict:
    """g / lc(g) with coefficients in ``domain`` (Q or Q(p)), lc for the order's
    ``key``."""
    lead = g[max(g, key=key)]
    if domain.is_QQ:
        scale = _constant(lead)
        return {m: domain(_constant(c), scale) for m, c in g.items()}
    field = domain.field
    found = {}
    for m, c in g.items():
        found[m] = fraction(field, c, lead)
    return found


def _constant(c: flint.fmpz_mpoly) -> int:
    return int(c.to_dict().get((0,) * c.context().nvars(), 0))


class _Buchberger:
    """Buchberger's algorithm with Gebauer and Möller's criteria on primitive
    polynomials over Z[p] (module doc)."""

    def __init__(self, key: Callable[[tuple[int, ...]], tuple]):
        self.key = key
        self.polys: list[_Poly] = []
        self.leads: list[tuple[int, ...]] = []
        self.basis: list[int] = []
        self.pairs: list[tuple[tuple[int, ...], int, int]] = []

    def lead(self, f: _Poly) -> tuple[int, ...]:
        return max(f, key=self.key)

    def run(self, inputs: list[_Poly], known: int = 0) -> list[_Poly]:
        """The reduced basis of the inputs, of which the first ``known`` are a reduced
        basis already (no pairs among them)."""
        for f in inputs[:known]:
            self.basis.append(self.add(_primitive(f)))
        for f in inputs[known:]:
            h = self.reduce(_primitive(f), self.basis)
            if h:
                self.update(self.add(h))
        while self.pairs:
            self.pairs.sort(key=lambda t: self.key(t[0]), reverse=True)
            lcm, i, j = self.pairs.pop()
            h = self.reduce(self.spoly(lcm, i, j), self.basis)
            if h:
                self.update(self.add(h))
        return self.reduced()

    def add(self, f: _Poly) -> int:
        self.polys.append(f)
        self.leads.append(self.lead(f))
        return len(self.polys) - 1

    def update(self, h: int) -> None:
        """Gebauer and Möller's update: the new pairs with h that the chain and product
        criteria keep, the old pairs h makes redundant dropped, and the basis elements
        whose leading monomial h's divides removed (their pairs stay)."""
        lead, leads = self.leads[h], self.leads
        candidates = [(_lcm(leads[g], lead), g) for g in self.basis]
        kept: list[tuple[tuple[int, ...], int]] = []
        while candidates:
            lcm, g = candidates.pop()
            if _disjoint(leads[g], lead) or not any(
                _divides(other, lcm) for other, _ in (*candidates, *kept)
            ):
                kept.append((lcm, g))
        new = [(lcm, g, h) for lcm, g in kept if not _disjoint(leads[g], lead)]
        self.pairs = [
            (lcm, i, j)
            for lcm, i, j in self.pairs
            if not (
                _divides(lead, lcm) and _lcm(leads[i], lead) != lcm and _lcm(lead, leads[j]) != lcm
            )
        ] + new
        self.basis = [g for g in self.basis if not _divides(lead, leads[g])] + [h]

    def spoly(self, lcm, i: int, j: int) -> _Poly:
        f, g = self.polys[i], self.polys[j]
        cf, cg = f[self.leads[i]], g[self.leads[j]]
        d = cf.gcd(cg)
        s = _scaled(f, cg / d, _minus(lcm, self.leads[i]))
        _subtract(s, g, cf / d, _minus(lcm, self.leads[j]))
        return s

    def reduce(self, f: _Poly, among: Sequence[int]) -> _Poly:
        """The primitive normal form of f by the basis elements ``among``: each term
        reduced in turn, largest first, by pseudo-division."""
        divisors = [(self.polys[g], self.leads[g]) for g in among]
        done, _ = _pseudo_remainder(f, divisors, self.key)
        return _primitive(done)

    def reduced(self) -> list[_Poly]:
        """The reduced basis (up to the units of Z[p]): each element of the minimal
        basis reduced by the others."""
        basis = self.basis
        return [self.reduce(self.polys[g], [o for o in basis if o != g]) for g in basis]


def _pseudo_remainder(f: _Poly, divisors, key) -> tuple[_Poly, flint.fmpz_mpoly | None]:
    """(r, s) with s f = r modulo the ``divisors`` (g, leading monomial of g for the
    order's ``key``), r reduced: each term reduced in turn, largest first, by
    pseudo-division over Z[p], s the product of the scales it took (None: none)."""
    f = dict(f)
    done: _Poly = {}
    scale = None
    while f:
        m = max(f, key=key)
        for g, lead in divisors:
            if _divides(lead, m):
                c, lc = f[m], g[lead]
                d = c.gcd(lc)
                a = lc / d
                if not a.is_one():
                    f = {k: v * a for k, v in f.items()}
                    done = {k: v * a for k, v in done.items()}
                    scale = a if scale is None else scale * a
                _subtract(f, g, c / d, _minus(m, lead))
                break
        else:
            done[m] = f.pop(m)
    return done, scale


def _primitive(f: _Poly) -> _Poly:
    """f divided by the gcd of its coefficients in Z[p]."""
    content = None
    for c in f.values():
        content = c if content is None else content.gcd(c)
        if content.is_one():
            return f
    if content is None or content.is_one():
        return f
    return {m: c / content for m, c in f.items()}


def _scaled(f: _Poly, c, shift) -> _Poly:
    return {_plus(m, shift): v * c for m, v in f.items()}


def _subtract(f: _Poly, g: _Poly, c, shift) -> None:
    """f -= c x^shift g, in place."""
    for m, v in g.items():
        k = _plus(m, shift)
        value = f[k] - c * v if k in f else -c * v
        if value.is_zero():
            f.pop(k, None)
        else:
            f[k] = value


def _divides(a, b) -> bool:
    return all(x <= y for x, y in zip(a, b, strict=True))


def _disjoint(a, b) -> bool:
    return all(x == 0 or y == 0 for x, y in zip(a, b, strict=True))


def _lcm(a, b) -> tuple[int, ...]:
    return tuple(max(x, y) for x, y in zip(a, b, strict=True))


def _plus(a, b) -> tuple[int, ...]:
    return tuple(x + y for x, y in zip(a, b, strict=True))


def _minus(a, b) -> tuple[int, ...]:
    return tuple(x - y for x, y in zip(a, b, strict=True))
