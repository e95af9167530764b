"""Zero testing: does a residual vanish identically (on a level set)?

The decision is made in stages, cheapest first, and the stage is recorded:

1. *Exact probes.* Evaluate at random exact points (rational where the
   case's radicals allow it), with ``certified_evaluation.evaluate``. A value proven
   nonzero refutes the identity, and the point is the witness.
2. *Proof.* Put the residual in a normal form that is complete for its class:
   radicals b**(p/q) become new symbols rho with rho**q = b, transcendental
   terms and arbitrary functions become new symbols, the result is a rational
   function whose numerator is reduced modulo the radical relations (and the
   level-set equations, by a Groebner basis). A zero remainder is a proof.
   As a last resort, a small residual is handed to ``sympy.simplify``.
3. Otherwise the residual vanished at every probe but no proof was found:
   ``inconclusive``, never ``verified``.
"""

from __future__ import annotations

import itertools
import random
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction

import sympy as sp
from sympy.core.function import AppliedUndef

from ..model import Verdict, Witness
from .certified_evaluation import OutsideDomain, Value, evaluate, exact_root
from .mechanics import AXIS, MOMENTUM, S_VALUE, STATE, s

#: Points where every residual must vanish before a proof is attempted.
PROBES = 4
#: Attempts to find that many points inside the domain before giving up.
MAX_ATTEMPTS = 40


@dataclass(frozen=True)
class Domain:
    """Where residuals live: parameters (symbols carry assumptions), arbitrary
    functions of a family, expressions that must not vanish (moments of inertia)
    the level set ``on`` (expressions that vanish there), and expressions that must be
    defined at a sample point (the case's potential, torque and claim: a witness where
    I itself is undefined would prove nothing)."""

    parameters: tuple[sp.Symbol, ...] = ()
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = field(
        default_factory=dict
    )
    nonzero: tuple[sp.Expr, ...] = ()
    on: tuple[sp.Expr, ...] = ()
    defined: tuple[sp.Expr, ...] = ()

    def restricted(self, on: Sequence[sp.Expr]) -> Domain:
        """The same domain restricted to the level set where ``on`` vanish."""
        return replace(self, on=tuple(on))

    def requiring(self, exprs: Sequence[sp.Expr]) -> Domain:
        """The same domain where ``exprs`` must also be defined (a claim, the potential)."""
        return replace(self, defined=(*self.defined, *exprs))


@dataclass(frozen=True)
class ZeroTest:
    """The decision for a family of residuals: all zero (verified), one nonzero
    somewhere (refuted, with the witness), or undecided (inconclusive, with why)."""

    verdict: Verdict
    method: str
    reason: str = ""
    witness: Witness | None = None
    component: str | None = None


def decide(
    residuals: Mapping[str, sp.Expr],
    domain: Domain,
    *,
    probes: int = PROBES,
    seed: int = 0,
) -> ZeroTest:
    """Decide whether every residual vanishes on the domain (stages in the module doc)."""
    live = {k: e for k, e in residuals.items() if e != 0}
    if not live:
        return ZeroTest(Verdict.VERIFIED, "identically zero")
    rng = random.Random(seed)
    # one probe first: a false identity is almost always refuted there, and a true
    # one goes straight to its proof; the other probes are spent only if that fails
    probe = _probe(live, domain, 1, rng)
    if probe is not None:
        return probe
    methods = set()
    for label, expr in live.items():
        method = prove_zero(expr, domain.on) or _simplified_to_zero(expr, domain.on)
        if method is None:
            more = _probe(live, domain, probes - 1, rng) if probes > 1 else None
            if more is not None:
                return more
            return ZeroTest(
                Verdict.INCONCLUSIVE,
                "exact probes",
                reason=f"vanishes at {max(probes, 1)} random points; no symbolic proof",
                component=label,
            )
        methods.add(method)
    return ZeroTest(Verdict.VERIFIED, max(methods, key=_METHOD_ORDER.index))


_METHOD_ORDER = ["rational normal form", "algebraic normal form", "level-set reduction", "simplify"]

#: Residuals larger than this (sympy operations) are not handed to ``simplify``.
SIMPLIFY_LIMIT = 400


def _simplified_to_zero(expr: sp.Expr, on: Sequence[sp.Expr]) -> str | None:
    """The last resort, for identities outside the normal forms' classes (such as
    sin**2 + cos**2 = 1): sympy's ``simplify``, on small residuals only and, like
    every stage, under the check's time budget."""
    if on or sp.count_ops(expr) > SIMPLIFY_LIMIT:
        return None
    return "simplify" if sp.simplify(expr.subs(s, S_VALUE)) == 0 else None


# --- stage 1: exact probes ---------------------------------------------------


def _probe(live, domain: Domain, probes: int, rng: random.Random) -> ZeroTest | None:
    """Refute at a random exact point, or return None when every probe vanished.

    For a family, two concrete instances of its arbitrary functions alternate.
    """
    n_choices = 2 if domain.functions else 1
    choices = [_concrete_functions(domain.functions, rng) for _ in range(n_choices)]
    instances = [{k: _substitute_functions(e, f) for k, e in live.items()} for f in choices]
    bases = _radical_bases(instances[0].values())
    good = 0
    for attempt in range(MAX_ATTEMPTS):
        funcs, residuals = choices[attempt % len(choices)], instances[attempt % len(choices)]
        point = _sample_point(domain, rng, funcs, bases)
        if point is None:
            continue
        try:
            values = {label: evaluate(expr, point) for label, expr in residuals.items()}
        except OutsideDomain:
            continue
        for label, value in values.items():
            if value.certainly_nonzero():
                return ZeroTest(
                    Verdict.REFUTED,
                    "exact probe" if value.is_exact else "interval probe",
                    witness=_witness(point, value, label, funcs, domain),
                    component=label,
                )
        good += 1
        if good >= probes:
            return None
    if good == 0:
        return ZeroTest(
            Verdict.INCONCLUSIVE,
            "exact probes",
            reason="found no sample point where the residual is defined",
        )
    return None


def _witness(point, value: Value, label: str, funcs, domain: Domain) -> Witness:
    names = {str(k): sp.sstr(v) for k, v in point.items()}
    shown = {
        f"{name}({', '.join(map(str, args))})": sp.sstr(funcs[name].expr)
        for name, (_, args) in domain.functions.items()
    }
    return Witness(names, value.text(), value.approx(), component=label, functions=shown)


def _rational(rng: random.Random, *, positive=False, nonzero=False, integer=False) -> Fraction:
    """A small random rational (or integer) respecting the assumptions."""
    while True:
        if integer:
            v = Fraction(rng.randint(1 if positive else -6, 6))
        else:
            num = rng.randint(1 if positive else -23, 23)
            v = Fraction(num, rng.randint(1, 11))
        if v != 0 or not (positive or nonzero):
            return v


def _parameter_value(sym: sp.Symbol, rng: random.Random) -> Fraction:
    return _rational(
        rng,
        positive=bool(sym.is_positive),
        nonzero=bool(sym.is_nonzero),
        integer=bool(sym.is_integer),
    )


def _pythagorean(rng: random.Random, radius: Fraction) -> tuple[Fraction, Fraction]:
    """A rational point on the circle of the given radius."""
    t = _rational(rng)
    return radius * (1 - t * t) / (1 + t * t), radius * 2 * t / (1 + t * t)


def _axis_points(rng: random.Random) -> list[list[Fraction]]:
    """Rational gamma with |gamma| and one planar radius rational, so that square roots
    of |gamma|**2 and of gamma_i**2 + gamma_j**2 evaluate exactly; the three
    arrangements make each planar radius the rational one in turn."""
    big = _rational(rng, positive=True)
    r, third = _pythagorean(rng, big)
    a, b = _pythagorean(rng, r)
    if rng.random() < 0.5:
        a, b = b, a
    return [[a, b, third], [third, a, b], [a, third, b]]


def _radical_bases(exprs) -> list[tuple[sp.Expr, int]]:
    """The bases and root orders of the radicals in ``exprs``."""
    found = {
        (p.base, int(p.exp.q))
        for e in exprs
        for p in e.atoms(sp.Pow)
        if p.exp.is_Rational and not p.exp.is_Integer and p.base.free_symbols
    }
    return sorted(found, key=str)


def _exact_radicals(point: Mapping, bases: Sequence[tuple[sp.Expr, int]]) -> int:
    """How many of the radicals are rational at the point (higher is better)."""
    count = 0
    for base, q in bases:
        try:
            value = evaluate(base, point)
        except (OutsideDomain, ValueError):
            continue
        if value.is_exact and value.exact >= 0 and exact_root(value.exact, q) is not None:
            count += 1
    return count


def _sample_point(domain: Domain, rng: random.Random, funcs, bases=()) -> dict | None:
    """A random exact point of the domain (on the level set), or None.

    Of the candidate arrangements of gamma, the one where most of the ``bases``
    (radicals of the residuals) are rational is taken, so values stay exact.
    """
    point: dict[sp.Symbol, sp.Expr] = {}
    for sym in domain.parameters:
        point[sym] = sp.Rational(_parameter_value(sym, rng))
    for sym in MOMENTUM:
        point[sym] = sp.Rational(_rational(rng))
    best, best_score = None, -1
    for axis in _axis_points(rng):
        candidate = {**point, **{g: sp.Rational(v) for g, v in zip(AXIS, axis, strict=True)}}
        candidate[s] = sp.expand(S_VALUE.xreplace(candidate))
        score = _exact_radicals(candidate, bases) if bases else 0
        if score > best_score:
            best, best_score = candidate, score
    point = best
    if domain.on:
        del point[s]
        if not _place_on_set(point, domain.on, rng, funcs):
            return None
        point[s] = sp.expand(S_VALUE.xreplace(point))
    try:
        if not all(evaluate(e, point).certainly_nonzero() for e in domain.nonzero):
            return None
        for expr in domain.defined:
            evaluate(_substitute_functions(expr, funcs), point)
    except OutsideDomain:
        return None
    return point


def _place_on_set(point: dict, equations: Sequence[sp.Expr], rng, funcs) -> bool:
    """Move ``point`` onto the level set, solving the equations one variable at a time.

    Each equation pins unpinned state variables: linearly, by scaling a homogeneous
    group (M or gamma), or by a real root of a quadratic. Orders are tried until the
    exact point satisfies every equation.
    """
    eqs = [_substitute_functions(e, funcs).xreplace({s: S_VALUE}) for e in equations]
    start = dict(point)
    for order in itertools.islice(itertools.permutations(eqs), 6):
        point.clear()
        point.update(start)
        pinned: set[sp.Symbol] = set()
        if all(_pin(eq, point, pinned, rng) for eq in order) and _on_set(point, eqs):
            return True
    return False


def _pin(eq: sp.Expr, point: dict, pinned: set, rng: random.Random) -> bool:
    free = [v for v in STATE if v not in pinned and eq.has(v)]
    if not free:
        return False
    known = {k: v for k, v in point.items() if k not in free}
    reduced = sp.together(eq.xreplace(known))
    numer = sp.numer(reduced)
    for v in free:  # linear in one variable: a rational solution
        fixed = {k: point[k] for k in free if k != v}
        expr = numer.xreplace(fixed)
        if not expr.is_polynomial(v):
            continue
        poly = sp.Poly(expr, v)
        if poly.degree() == 1 and poly.nth(1) != 0:
            point[v] = sp.expand(-poly.nth(0) / poly.nth(1))
            pinned.add(v)
            return True
    for group in (AXIS, MOMENTUM):  # homogeneous in a group: scale the group
        if _scale_group(numer, group, free, point, pinned):
            return True
    for v in free:  # quadratic (or higher) in one variable: a real root
        fixed = {k: point[k] for k in free if k != v}
        expr = numer.xreplace(fixed)
        if not expr.is_polynomial(v):
            continue
        poly = sp.Poly(expr, v)
        if poly.degree() > 2:  # roots would be CRootOf, which the evaluator cannot certify
            continue
        roots = [r for r in poly.all_roots() if r.is_real]
        if roots:
            point[v] = rng.choice(roots)
            pinned.add(v)
            return True
    return False


def _scale_group(numer, group, free, point, pinned) -> bool:
    if not all(g in free for g in group):
        return False
    lam = sp.Dummy("lam", positive=True)
    others = {k: point[k] for k in free if k not in group}
    scaled = sp.expand(numer.xreplace(others).xreplace({g: lam * point[g] for g in group}))
    if not scaled.is_polynomial(lam):
        return False
    poly = sp.Poly(scaled, lam)
    terms = [(m[0], c) for m, c in poly.terms() if c != 0]
    if len(terms) != 2 or min(d for d, _ in terms) != 0:
        return False
    (d, a), (_, c) = sorted(terms, reverse=True)
    ratio = -c / a
    if not (ratio.is_positive):
        return False
    factor = ratio ** sp.Rational(1, d)
    for g in group:
        point[g] = point[g] * factor
        pinned.add(g)
    return True


def _on_set(point: dict, eqs: Sequence[sp.Expr]) -> bool:
    """Exact check that the point satisfies the equations."""
    for eq in eqs:
        value = eq.xreplace(point)
        if sp.simplify(value) != 0:
            return False
    return True


# --- arbitrary functions: concrete choices for probes -----------------------


def _concrete_functions(functions, rng: random.Random) -> dict[str, sp.Lambda]:
    """A random quadratic polynomial for each declared function (a family's instance)."""
    chosen = {}
    for name, (_, args) in functions.items():
        terms = [sp.Rational(_rational(rng, nonzero=True))]
        terms += [sp.Rational(_rational(rng)) * a for a in args]
        terms += [
            sp.Rational(_rational(rng)) / 2 * a * b
            for a, b in itertools.combinations_with_replacement(args, 2)
        ]
        chosen[name] = sp.Lambda(args, sp.Add(*terms))
    return chosen


def _substitute_functions(expr: sp.Expr, funcs: Mapping[str, sp.Lambda]) -> sp.Expr:
    """Replace each declared function by its concrete choice and its derivatives by the
    derivatives of that choice (one substitution; ``replace`` + ``doit`` where other
    structures such as Subs appear)."""
    if not funcs or not expr.has(AppliedUndef):
        return expr
    if expr.has(sp.Subs):

        def concrete(e) -> bool:
            return isinstance(e, AppliedUndef) and e.func.__name__ in funcs

        return expr.replace(concrete, lambda e: funcs[e.func.__name__](*e.args)).doit()
    mapping: dict[sp.Expr, sp.Expr] = {}
    for f in expr.atoms(AppliedUndef):
        if f.func.__name__ in funcs:
            mapping[f] = funcs[f.func.__name__](*f.args)
    for d in expr.atoms(sp.Derivative):
        if d.expr in mapping:
            mapping[d] = _derivative(mapping[d.expr], d.variable_count)
    return expr.xreplace(mapping)


def _derivative(value: sp.Expr, variable_count) -> sp.Expr:
    """A derivative of a concrete function (a polynomial): through Poly, which skips the
    assumption queries of ``sp.diff`` (most of the cost of probing a family)."""
    variables = [v for v, _ in variable_count]
    if all(isinstance(v, sp.Symbol) for v in variables) and value.is_polynomial(*variables):
        poly = sp.Poly(value, *variables)
        return poly.diff(*((v, int(n)) for v, n in variable_count)).as_expr()
    return sp.diff(value, *variable_count)


# --- stage 2: proof by normal form ------------------------------------------


class _Atoms:
    """Rewrites an expression as a rational function of new symbols for its
    radicals (rho**q = base) and its transcendental or arbitrary-function terms."""

    def __init__(self) -> None:
        self.radicals: dict[tuple[sp.Expr, int], sp.Symbol] = {}
        self.others: dict[sp.Expr, sp.Symbol] = {}
        self._memo: dict[sp.Expr, sp.Expr] = {}

    def relations(self) -> list[tuple[sp.Symbol, int, sp.Expr]]:
        return [(rho, q, base) for (base, q), rho in self.radicals.items()]

    def rewrite(self, expr: sp.Expr) -> sp.Expr:
        hit = self._memo.get(expr)
        if hit is None:
            hit = self._rewrite(expr)
            self._memo[expr] = hit
        return hit

    def _key(self, expr: sp.Expr) -> sp.Expr:
        return sp.expand(self.rewrite(expr).xreplace({s: S_VALUE}))

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


def prove_zero(expr: sp.Expr, on: Sequence[sp.Expr] = ()) -> str | None:
    """Prove ``expr`` == 0 (on the level set ``on``); return the method, or None.

    The rewritten residual becomes an element of the field Q(x1, ..., xn) of
    rational functions in the state variables, parameters and atom symbols
    (sparse polynomial arithmetic, far cheaper than manipulating expression
    trees); its numerator is then reduced modulo rho**q - base for every radical.
    """
    atoms = _Atoms()
    numer, ring = _numerator_poly(atoms.rewrite(expr), atoms)
    if not numer:
        return "rational normal form"
    relations = [
        ring(rho) ** q - ring.from_expr(base.xreplace(_CONSTANTS))
        for rho, q, base in atoms.relations()
    ]
    if not on:
        if relations and not numer.rem(relations):
            return "algebraic normal form"
        return None
    eqs = [_numerator(atoms.rewrite(e)).xreplace(_CONSTANTS) for e in on]
    eqs += [rho**q - base.xreplace(_CONSTANTS) for rho, q, base in atoms.relations()]
    numer_expr = numer.as_expr()
    gens = sorted(set().union(*(e.free_symbols for e in [numer_expr, *eqs])), key=str)
    basis = sp.groebner(eqs, *gens, order="grevlex", domain=sp.QQ)
    _, remainder = basis.reduce(numer_expr)
    return "level-set reduction" if remainder == 0 else None


def _numerator_poly(rewritten: sp.Expr, atoms: _Atoms):
    """The numerator of the rewritten expression as a sparse polynomial over QQ, with
    the radical symbols first in a lex order (so rho**q leads its relation)."""
    expr = rewritten.xreplace({s: S_VALUE, **_CONSTANTS})
    radicals = list(reversed(atoms.radicals.values()))  # outer radicals before inner ones
    bases = set().union(*(b.xreplace(_CONSTANTS).free_symbols for b, _ in atoms.radicals))
    others = sorted((expr.free_symbols | bases) - set(radicals), key=str)
    ring = sp.polys.rings.PolyRing([*radicals, *others] or [sp.Dummy("x")], sp.QQ, sp.lex)
    numer, _ = _fraction(expr, ring, {})
    return numer, ring


def _fraction(expr: sp.Expr, ring, cache: dict):
    """expr as numerator and denominator, the denominator kept as a product of factors
    {polynomial: exponent} so that no polynomial gcd is ever needed (gcds of many-variable
    polynomials are what makes ``together`` and rational-function fields slow)."""
    hit = cache.get(expr)
    if hit is not None:
        return hit
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


#: pi and E as indeterminates: an identity in them holds for their values too.
_CONSTANTS = {sp.pi: sp.Dummy("pi"), sp.E: sp.Dummy("E")}


def _numerator(rewritten: sp.Expr) -> sp.Expr:
    rational = rewritten.xreplace({s: S_VALUE})
    return sp.expand(sp.numer(sp.together(rational)))


def _reduce_radical(numer: sp.Expr, rho: sp.Symbol, q: int, base: sp.Expr) -> sp.Expr:
    """numer modulo rho**q - base: every rho**k becomes base**(k // q) * rho**(k % q)."""
    if not numer.has(rho):
        return numer
    poly = sp.Poly(numer, rho)
    reduced = sp.Add(*(c * base ** (k // q) * rho ** (k % q) for (k,), c in poly.terms()))
    return sp.expand(reduced)


def sample_points(domain: Domain, count: int, seed: int = 0) -> Iterator[dict]:
    """Exact random points of the domain (used by tests and numeric evidence)."""
    rng = random.Random(seed)
    funcs = _concrete_functions(domain.functions, rng)
    produced = 0
    while produced < count:
        point = _sample_point(domain, rng, funcs)
        if point is not None:
            produced += 1
            yield point
