"""An algebraic candidate set of the rank-drop locus, split into its irreducible
components: those with a rational parametrisation become ordinary candidate sets, the
others are decided at their points (``algebraic_points``).

The splitting (``splitting``) leaves a set unsolved when its equations are nonlinear in
every free parameter: ``x0**2 - 4*z0**2 = 0`` (two rational lines), ``x0**2 + z0**2 = 0``
(no real point but the origin), ``49*x0**2 - 30*z0**2 = 0`` (two lines defined over
Q(sqrt(30)) only). Its components over Q (``prime_components``, Groebner bases and shape
position; symbolic parameters stay in the ground field) are taken one by one:

* a component on which a factor the branch assumed nonzero vanishes belongs to another
  branch, and is dropped;
* only real points matter: an equation that is a sum of positive multiples of even
  powers of single parameters vanishes on real points only where each of them is 0, so
  the component's real points are those of the component with them set to 0 (decomposed
  again); a positive parameter set to a non-positive number leaves nothing;
* a component of degree 1 over the field of its free coordinates (its bound parameters
  rational functions of the free ones) is an ordinary candidate set, searched by
  substitution like every other;
* a hypersurface f = 0 quadratic in a parameter y, a y**2 + b y + c, whose
  discriminant b**2 - 4ac is k L Q**2 with L linear in another parameter s, is rational
  with one new parameter w (``NEW``): L = k w**2 gives s, and y = (-b + k w Q)/(2a).
  Every real point where a, Q and L's coefficient of s do not vanish is reached (there
  k L = (2ay + b)**2/Q**2 >= 0, so w is real); where one of them vanishes is a smaller
  set, resolved again. This is how ``n3**2 c22**2 = c22 - 1/4`` (a quartic curve) is
  searched: c22 = w**2 + 1/4, n3 = w/c22;
* where the discriminant's odd part d is quadratic in another parameter s instead, the
  conic t**2 = k d is parametrised by the lines through a rational point of it, where
  it has one in sight (``_conic``: its coefficient of s**2 or its constant term k times
  a square, a point at infinity or at s = 0); the points the lines miss are a smaller
  set, resolved again. ``x0**2 = z0**2 (p**2 + 2 p)`` is searched so: t = p + w;
* the rest (defined over an algebraic extension, or without a rational parametrisation)
  is returned as a ``Piece``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy as sp

from ..mathematics.factoring import coefficient_and_factors
from ..mathematics.prime_components import Component, DecompositionLimit, components
from .splitting import AlgebraicSet

#: How often the real-point rule may add equations to one set before it stops.
MAX_REAL_STEPS = 8

#: The parameter a quadratic component's parametrisation introduces (module docstring).
#: Its name is no case's (case names are identifiers): the search renames it to one the
#: case does not use before it searches the set.
NEW = sp.Symbol("w'", real=True)


@dataclass(frozen=True)
class Piece:
    """An irreducible component with no rational parametrisation: the parameters the
    splitting solved (``values``, rational in the others), the ``component`` of the
    others (its prime ideal and generic point), its equations as text, and the factors
    the splitting assumed nonzero on it."""

    values: dict[sp.Symbol, sp.Expr]
    component: Component
    text: str
    units: tuple[sp.Expr, ...] = ()


@dataclass
class Resolved:
    """What an algebraic set holds: ordinary candidate sets (values of some free
    parameters), ``pieces`` to decide at their points, and ``undecided`` texts."""

    sets: list[dict[sp.Symbol, sp.Expr]] = field(default_factory=list)
    pieces: list[Piece] = field(default_factory=list)
    undecided: list[str] = field(default_factory=list)


def resolve(
    found: AlgebraicSet,
    free: Sequence[sp.Symbol],
    symbolic: Sequence[sp.Symbol] = (),
) -> Resolved:
    """The components of ``found`` (module docstring); ``free`` are the free parameters of
    the set searched, ``symbolic`` those that stay generic (the ground field's)."""
    out = Resolved()
    _resolve(found, list(free), list(symbolic), out, 0)
    return out


def _resolve(
    found: AlgebraicSet, free: list[sp.Symbol], symbolic: list[sp.Symbol], out: Resolved, depth
) -> None:
    variables = [f for f in free if f not in found.values]
    equations = [sp.numer(sp.together(e)) for e in found.equations]
    try:
        parts = components(equations, variables, symbolic, origin=())
    except DecompositionLimit as err:
        out.undecided.append(f"{found.text()} (its components were not found: {err})")
        return
    for part in parts:
        if any(part.vanishes(u) for u in found.units if u.free_symbols & set(variables)):
            continue
        zero = _real_zeros(part)
        if zero:
            if depth >= MAX_REAL_STEPS:
                out.undecided.append(f"{found.text()} (its real points were not found)")
                continue
            smaller = AlgebraicSet(found.values, (*part.equations(), *zero), found.units)
            _resolve(smaller, free, symbolic, out, depth + 1)
            continue
        if part.degree == 1:
            values = _rational(found.values, part)
            if _allowed(values) and values not in out.sets:
                out.sets.append(values)
        elif (parametrised := _parametrised(found.values, part)) is not None:
            values, misses = parametrised
            if _allowed(values) and values not in out.sets:
                out.sets.append(values)
            for factor in misses:  # in the component's own parameters
                factor = sp.numer(sp.together(sp.sympify(factor).xreplace(found.values)))
                smaller = AlgebraicSet(found.values, (*part.equations(), factor), found.units)
                _resolve(smaller, free, symbolic, out, depth + 1)
        else:
            text = AlgebraicSet(found.values, tuple(part.equations())).text()
            piece = Piece(found.values, part, text, found.units)
            if piece.text not in {p.text for p in out.pieces}:
                out.pieces.append(piece)


def _real_zeros(part: Component) -> list[sp.Symbol]:
    """Parameters that vanish at every real point of the component: those of an equation
    that is a sum of positive multiples of even powers of single parameters (beyond the
    ones already 0 on it)."""
    for equation in part.equations():
        poly = sp.Poly(sp.numer(sp.together(equation)), *part.variables)
        terms = poly.terms()
        if len(terms) < 2:
            continue
        signs = {c > 0 for _, c in terms if c.is_number}
        if len(signs) != 1 or not all(c.is_number for _, c in terms):
            continue
        if all(sum(1 for e in m if e) == 1 and all(e % 2 == 0 for e in m) for m, _ in terms):
            return [
                x
                for m, _ in terms
                for x, e in zip(part.variables, m, strict=True)
                if e and not part.vanishes(x)
            ]
    return []


def _allowed(values: dict[sp.Symbol, sp.Expr]) -> bool:
    """False where a positive parameter is set to a number that is not positive."""
    return not any(x.is_positive and v.is_number and not v > 0 for x, v in values.items())


def _parametrised(
    values: dict[sp.Symbol, sp.Expr], part: Component
) -> tuple[dict[sp.Symbol, sp.Expr], list[sp.Expr]] | None:
    """A component of degree > 1 parametrised rationally (module docstring), or None: its
    equations linear in a parameter solved for it one by one, and the one left either
    linear in a parameter too, or quadratic with a discriminant that is k L Q**2. The
    values of the parameters it solves (in w and the others, the splitting's solved
    parameters written in them too), and the factors where real points are missed."""
    names = set(part.variables)
    equations = [
        sp.expand(sp.numer(sp.together(e)))
        for e in part.equations()
        if sp.sympify(e).free_symbols & names
    ]
    bound: dict[sp.Symbol, sp.Expr] = {}
    misses: list[sp.Expr] = []

    def solve(x: sp.Symbol, at: sp.Expr, denominators: Sequence[sp.Expr]) -> None:
        for solved in bound:
            bound[solved] = sp.cancel(bound[solved].xreplace({x: at}))
        bound[x] = at
        misses.extend(d for d in denominators if sp.sympify(d).free_symbols & names)

    while equations:
        linear = next(
            (
                (e, x)
                for e in equations
                for x in part.variables
                if sp.degree(e, x) == 1 and not part.vanishes(e.coeff(x, 1))
            ),
            None,
        )
        if linear is None:
            break
        e, x = linear
        alpha, beta = e.coeff(x, 1), e.coeff(x, 0)
        solve(x, sp.cancel(-beta / alpha), [alpha])
        put = (sp.expand(sp.numer(sp.together(g.xreplace({x: bound[x]})))) for g in equations)
        equations = [f for f in put if f != 0]
    if len(equations) > 1:
        return None
    if equations:
        found = _quadratic(equations[0], [x for x in part.variables if x not in bound])
        if found is None:
            return None
        for x, at in found[0].items():
            solve(x, at, found[1])
    out = {x: sp.cancel(sp.sympify(e).xreplace(bound)) for x, e in values.items()}
    out.update(bound)
    out = _unnamed(out)
    if any(sp.cancel(sp.together(sp.sympify(e).xreplace(out))) != 0 for e in part.equations()):
        return None  # never a set off the component (the steps above should not make one)
    # where a value's denominator vanishes, the values do not reach the component's points
    for e in out.values():
        misses.extend(
            g
            for g, _ in coefficient_and_factors(sp.denom(sp.together(e)))[1]
            if g.free_symbols & (names | set(values)) and NEW not in g.free_symbols
        )
    return out, list(dict.fromkeys(misses))


def _unnamed(values: dict[sp.Symbol, sp.Expr]) -> dict[sp.Symbol, sp.Expr]:
    """The values with ``NEW`` written as a parameter that is c w + d (c a number, d free
    of w), where one is: that parameter stays free, and no new one is needed
    (b32 = -w gives w = -b32)."""
    for x, e in values.items():
        e = sp.expand(e)
        if NEW in sp.denom(sp.together(e)).free_symbols:
            continue
        if NEW in e.free_symbols and sp.degree(e, NEW) == 1:
            c, d = e.coeff(NEW, 1), e.coeff(NEW, 0)
            if c.is_number and c != 0 and NEW not in d.free_symbols and x not in d.free_symbols:
                w = (x - d) / c
                return {
                    y: sp.cancel(sp.sympify(v).xreplace({NEW: w}))
                    for y, v in values.items()
                    if y != x
                }
    return values


def _quadratic(
    f: sp.Expr, variables: Sequence[sp.Symbol]
) -> tuple[dict[sp.Symbol, sp.Expr], list[sp.Expr]] | None:
    """f = a y**2 + b y + c = 0 with b**2 - 4ac = k L Q**2, L linear in another parameter
    s: the values of s and y in ``NEW`` and the others (w scaled so that L = k0 w**2 with
    k0 the square-free part of k), and the factors where real points
    are missed (a, Q's factors, L's coefficient of s); None where f is not of this kind.
    Only an irreducible f is parametrised (a factor of f is another component)."""
    _, parts = coefficient_and_factors(f)
    if len(parts) != 1 or parts[0][1] != 1:
        return None
    names = set(variables)
    found = []
    for y in variables:
        if sp.degree(f, y) != 2:
            continue
        a, b, c = (sp.expand(f.coeff(y, k)) for k in (2, 1, 0))
        k, factors = coefficient_and_factors(sp.expand(b**2 - 4 * a * c))
        odd = sp.expand(sp.Mul(*(g for g, e in factors if e % 2)))
        if odd.is_number:
            continue
        square = sp.Mul(*(g ** (e // 2) for g, e in factors))
        # k = r**2 k0 with k0 a square-free integer: L = k0 w**2 makes k L = (r k0 w)**2
        r, root_k0 = sp.sqrt(abs(k)).as_coeff_Mul()
        k0 = sp.sign(k) * root_k0**2
        for s in variables:
            if s == y or sp.degree(odd, s) not in (1, 2):
                continue
            fixed = [a, *(g for g, e in factors if e > 1)]
            if sp.degree(odd, s) == 2:  # t**2 = k odd, a conic in (s, t): t = (2ay + b)/Q
                t_here = (2 * a * y + b) / square
                for at_s, t, missed in _conic(sp.expand(k * odd), s):
                    root = sp.cancel(((-b + t * square) / (2 * a)).xreplace({s: at_s}))
                    misses = [
                        *fixed,
                        *(sp.numer(sp.together(m.xreplace({T: t_here}))) for m in missed),
                    ]
                    found.append(
                        (
                            {s: at_s, y: root},
                            [g for g in misses if sp.sympify(g).free_symbols & names],
                        )
                    )
                continue
            alpha, beta = odd.coeff(s, 1), odd.coeff(s, 0)
            at_s = sp.cancel((k0 * NEW**2 - beta) / alpha)
            root = sp.cancel(((-b + r * k0 * NEW * square) / (2 * a)).xreplace({s: at_s}))
            misses = [g for g in (*fixed, alpha) if sp.sympify(g).free_symbols & names]
            found.append(({s: at_s, y: root}, misses))
    # the simplest: fewest factors where points are missed (a polynomial parametrisation
    # where there is one), then the shortest values
    return min(
        found,
        key=lambda option: (len(option[1]), sum(sp.count_ops(e) for e in option[0].values())),
        default=None,
    )


#: The conic's second coordinate t in ``_conic``'s missed sets.
T = sp.Dummy("t")


def _conic(d: sp.Expr, s: sp.Symbol) -> list[tuple[sp.Expr, sp.Expr, list[sp.Expr]]]:
    """The conic t**2 = d = alpha s**2 + beta s + gamma parametrised by the lines through
    a rational point, where alpha (a point at infinity) or gamma (the point s = 0) is the
    square of a polynomial A: s and t in ``NEW`` (the line's slope or intercept), and the
    polynomials in s and ``T`` that vanish at the points the lines miss. For t = A s + w,
    s = (gamma - w**2)/(2 A w - beta); for t = A + w s, s = (beta - 2 A w)/(w**2 - alpha)."""
    alpha, beta, gamma = (sp.expand(d).coeff(s, j) for j in (2, 1, 0))
    found = []
    root = _square_root(alpha)
    if root is not None:
        at_s = sp.cancel((gamma - NEW**2) / (2 * root * NEW - beta))
        found.append((at_s, sp.cancel(root * at_s + NEW), [root, 2 * root * (T - root * s) - beta]))
    root = _square_root(gamma)
    if root is not None:
        at_s = sp.cancel((beta - 2 * root * NEW) / (NEW**2 - alpha))
        found.append((at_s, sp.cancel(root + NEW * at_s), [s, (T - root) ** 2 - alpha * s**2]))
    return found


def _square_root(e: sp.Expr) -> sp.Expr | None:
    """A polynomial A with A**2 = e (e's factors all of even multiplicity, its constant a
    rational square), or None."""
    e = sp.expand(e)
    if e == 0:
        return None
    c, factors = coefficient_and_factors(e)
    root = sp.sqrt(c)
    if not root.is_Rational or any(m % 2 for _, m in factors):
        return None
    return root * sp.Mul(*(g ** (m // 2) for g, m in factors))


def _rational(values: dict[sp.Symbol, sp.Expr], part: Component) -> dict[sp.Symbol, sp.Expr]:
    """A degree-1 component as values of its bound parameters (rational in its free
    ones), with the splitting's solved parameters written in the same free ones."""
    u = part.symbol
    root = -part.minimal.nth(0) / part.minimal.nth(1)
    bound = {
        x: sp.cancel(sp.sympify(e).subs(u, root))
        for x, e in part.coordinates.items()
        if x not in part.free
    }
    out = {s: sp.cancel(sp.sympify(e).xreplace(bound)) for s, e in values.items()}
    out.update(bound)
    return out
