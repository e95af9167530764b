"""Symmetries of a search's vector field, and the ansatz split along them.

A linear map G of the state x = (M, gamma) is a symmetry of the flow when
X(G x) = G X(x) (it maps trajectories to trajectories), or a reversing one when
X(G x) = -G X(x) (it maps them to trajectories run backwards). Either way F -> F o G
maps first integrals to first integrals, and d/dt o G* = +-G* o d/dt: the operator
F -> dF/dt maps each eigenspace of G* (even, odd parts) into one eigenspace of G*, a
different one for each. The linear system A(p) c = 0 of the ansatz is then block
diagonal in an eigenbasis: each block is searched on its own (smaller ranks, smaller
loci), an integral found in one block is an integral, and the kernel is the sum of
the blocks' kernels at every parameter value.

Two kinds are detected from the equations, each by an exact identity of polynomials
(a proof, not a guess), for every value of the parameters at once:

* *signed permutations* of the axes, acting alike on M and gamma, M possibly with the
  opposite sign (M is a pseudo-vector): gamma2 -> -gamma2 with M1 -> -M1, M3 -> -M3
  for a centre of mass in the x-z plane, or M1 <-> M2, gamma1 <-> gamma2 for A = B
  and a potential symmetric in gamma1, gamma2;
* the *rotation about a coordinate axis* (M and gamma turned together: Lagrange's top):
  the Lie bracket of its generator Y = (e x M, e x gamma) with X vanishes.

Commuting involutions among the signed permutations generate a group (Z/2)^k whose
characters chi are rational: the projections P_chi(m) = sum chi(g) m o g of the
monomials m (one per orbit; an orbit spans each character at most once) are the
unknowns of the split system, and since an element of one class is determined by its
coefficients at the orbits' representatives, those are its only equations. Sign
changes alone send monomials to monomials: the blocks the equations' sparsity gives
are their eigenspaces already, and they are named, not used again. A rotation is used
through the reflections that come with it (its weight spaces, complex characters, are
not formed). On a level set a map is used only where it keeps the set and its normal
forms (it maps the basis's leading monomials to leading monomials); in a ring with
inverses or roots, and for Darboux polynomials (whose cofactor is not symmetric),
nothing is split, and the note says why.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from sympy import QQ
from sympy.polys.rings import PolyElement

#: The state's names, in the ring's order.
NAMES = ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3")

#: x_i -> sign * x_j, for i = 0..5: ((j, sign), ...)
Images = tuple[tuple[int, int], ...]
#: A vector on the ansatz's columns: column index -> rational coefficient.
Combination = dict[int, Any]


@dataclass(frozen=True)
class SignedPermutation:
    """x_i -> sign_i x_{j_i}: a permutation of the axes with signs, alike on M and
    gamma (M possibly with the opposite sign); ``reversing`` when it reverses time."""

    images: Images
    reversing: bool = False

    @property
    def diagonal(self) -> bool:
        return all(j == i for i, (j, _) in enumerate(self.images))

    @property
    def involution(self) -> bool:
        return self.compose(self).images == IDENTITY

    def compose(self, other: SignedPermutation) -> SignedPermutation:
        """self after other: x -> self(other(x))."""
        images = []
        for j, s in other.images:  # other: x_i -> s x_j; then x_j -> t x_k
            k, t = self.images[j]
            images.append((k, s * t))
        return SignedPermutation(tuple(images), self.reversing != other.reversing)

    def act(self, poly: PolyElement, n: int = 6) -> PolyElement:
        """F o G, for a polynomial of the ring whose first ``n`` generators are the state."""
        out: dict[tuple[int, ...], Any] = {}
        for exps, c in poly.items():
            new = list(exps)
            for i in range(n):
                new[i] = 0
            sign = 1
            for i in range(n):
                e = exps[i]
                if e:
                    j, s = self.images[i]
                    new[j] += e
                    if s < 0 and e % 2:
                        sign = -sign
            key = tuple(new)
            out[key] = out.get(key, 0) + sign * c
        return poly.ring({k: v for k, v in out.items() if v})

    def monomial(self, exps: Sequence[int]) -> tuple[tuple[int, ...], int]:
        """The image of a state monomial: (its exponents, the sign)."""
        new = [0] * len(exps)
        sign = 1
        for i, e in enumerate(exps):
            if e:
                j, s = self.images[i]
                new[j] += e
                if s < 0 and e % 2:
                    sign = -sign
        return tuple(new), sign

    def text(self) -> str:
        moved = []
        for i, (j, s) in enumerate(self.images):
            if (j, s) != (i, 1):
                moved.append(f"{NAMES[i]} -> {'-' if s < 0 else ''}{NAMES[j]}")
        return ", ".join(moved) + (" (reversing time)" if self.reversing else "")


IDENTITY: Images = tuple((i, 1) for i in range(6))


@dataclass(frozen=True)
class Rotation:
    """M and gamma turned together about a coordinate axis (0, 1, 2)."""

    axis: int

    def generator(self) -> list[list[tuple[int, int]]]:
        """Y = (e x M, e x gamma) as linear forms: Y_i = sum c x_j, as [(j, c), ...]."""
        u, v = _plane(self.axis)
        out: list[list[tuple[int, int]]] = [[] for _ in range(6)]
        for base in (0, 3):  # e x x: the u component is -x_v, the v component x_u
            out[base + u] = [(base + v, -1)]
            out[base + v] = [(base + u, 1)]
        return out

    def text(self) -> str:
        return f"rotation about axis {self.axis + 1} (M and gamma turned together)"


def _plane(axis: int) -> tuple[int, int]:
    """The axes (u, v) with (u, v, axis) cyclic."""
    return ((1, 2), (2, 0), (0, 1))[axis]


@dataclass(frozen=True)
class Decomposition:
    """The ansatz's columns in an eigenbasis of a group (Z/2)^k of signed permutations:
    ``classes`` of column combinations (one class per character), d/dt mapping each
    class into a class of its own. An element of a class is determined by its
    coefficients on the representatives of the monomial orbits (``representative``),
    so those are the only rows a block needs. ``note`` says what was used."""

    classes: tuple[tuple[Combination, ...], ...]
    group: tuple[SignedPermutation, ...]
    note: str

    def representatives(self) -> Callable[[tuple[int, ...]], bool]:
        """Whether a state monomial is the least of its orbit under the group (cached)."""
        elements = _elements(self.group)
        cache: dict[tuple[int, ...], bool] = {}

        def least(exps: tuple[int, ...]) -> bool:
            hit = cache.get(exps)
            if hit is None:
                hit = cache[exps] = all(g.monomial(exps)[0] >= exps for g in elements)
            return hit

        return least


def _elements(group: Sequence[SignedPermutation]) -> list[SignedPermutation]:
    """Every element of the group the commuting involutions generate."""
    out = [SignedPermutation(IDENTITY)]
    for g in group:
        out += [g.compose(h) for h in out]
    return out


# ----------------------------------------------------------------------- detection


def _candidates() -> list[tuple[Images, bool]]:
    """Every signed permutation of the axes, alike on M and gamma up to M's sign, but
    the identity; with the time direction tried both ways."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            for m_sign in (1, -1):
                images = tuple((perm[a], m_sign * signs[a]) for a in range(3)) + tuple(
                    (3 + perm[a], signs[a]) for a in range(3)
                )
                if images != IDENTITY:
                    out.append(images)
    return [(images, rev) for images in out for rev in (False, True)]


def signed_permutations(field: Sequence[PolyElement], n: int = 6) -> list[SignedPermutation]:
    """The signed permutations G with X(G x) = +-G X(x), checked as polynomial identities
    in the state and the parameters (``field``: Y = D X, D free of the state)."""
    supports = [frozenset(m[:n] for m in y.monoms()) for y in field]
    found = []
    cache: dict[Images, list[PolyElement]] = {}
    for images, reversing in _candidates():
        # a quick necessary condition: X_i o G has the support of X_{j_i}
        g = SignedPermutation(images, reversing)
        if any(
            frozenset(g.monomial(m)[0] for m in supports[i]) != supports[images[i][0]]
            for i in range(n)
        ):
            continue
        moved = cache.get(images)
        if moved is None:
            moved = cache[images] = [g.act(y, n) for y in field]
        eps = -1 if reversing else 1
        if all(moved[i] == field[j] * (eps * s) for i, (j, s) in enumerate(images)):
            found.append(g)
    return found


def rotations(field: Sequence[PolyElement], n: int = 6) -> list[Rotation]:
    """The coordinate axes about which turning M and gamma together commutes with the
    flow: [Y, X] = 0, i.e. Y(X_i) = (L X)_i for Y = L x, checked exactly."""
    ring = field[0].ring
    gens = ring.gens
    found = []
    for axis in range(3):
        rot = Rotation(axis)
        y = rot.generator()
        ok = True
        for i in range(n):
            lhs = ring.zero
            for j in range(n):
                if y[j]:
                    d = field[i].diff(gens[j])
                    if d:
                        for k, c in y[j]:
                            lhs += d * gens[k] * c
            rhs = ring.zero
            for k, c in y[i]:
                rhs += field[k] * c
            if lhs != rhs:
                ok = False
                break
        if ok:
            found.append(rot)
    return found


def _derivation(rot: Rotation, poly: PolyElement) -> PolyElement:
    """Y(poly) for the rotation's generator Y."""
    gens = poly.ring.gens
    out = poly.ring.zero
    for j, form in enumerate(rot.generator()):
        if form:
            d = poly.diff(gens[j])
            for k, c in form:
                out += d * gens[k] * c
    return out


# -------------------------------------------------------------------- decomposition


def decompose(system: Any, *, cofactor: bool = False) -> tuple[list[Decomposition], str]:
    """Ways to split the ansatz of ``system`` (a PolynomialSystem) along the symmetries of
    its field (module docstring), each by a group of commuting involutions with a
    permutation among them, and what was found (rotations and sign changes are named:
    the sign changes are the blocks already, and a rotation is used through its
    reflections). The caller keeps the one whose blocks are cheapest, if any is cheaper
    than the blocks of the sparsity."""
    n = system.n
    if n != 6 or system.space.extended:
        return [], "not sought (the ring has inverses or roots)"
    if cofactor:
        return [], "not sought (Darboux polynomials: the cofactor is not symmetric)"
    field = system.field
    ideal = list(system.ideal)
    if any(any(m[n:]) for g in ideal for m in g.monoms()):
        return [], "not sought (the level set's basis depends on the parameters)"
    leading = set(system.leading)
    perms = [
        g
        for g in signed_permutations(field)
        if all(g.monomial(lm)[0] in leading for lm in leading)  # normal forms commute with g
        and all(not system.reduce(g.act(h)) for h in ideal)  # g keeps the level set
    ]
    rots = [r for r in rotations(field) if all(not system.reduce(_derivation(r, g)) for g in ideal)]
    diagonal = [g for g in perms if g.diagonal]
    found = []
    if rots:
        found.append(", ".join(r.text() for r in rots))
    moved = [g for g in perms if not g.diagonal and g.involution]
    if moved:
        found.append(f"{len(moved)} reflections such as [{moved[0].text()}]")
    if diagonal:
        found.append(f"{len(diagonal)} sign changes such as [{diagonal[0].text()}]")
    out: list[Decomposition] = []
    groups: list[frozenset] = []
    for seed in moved[:MAX_SEEDS]:
        group = _commuting_involutions(seed, perms)
        key = frozenset(g.images for g in _elements(group))
        if key in groups:
            continue
        groups.append(key)
        classes = _characters(system, group)
        sizes = "/".join(str(len(c)) for c in classes)
        note = (
            f"the group (Z/2)^{len(group)} of [{seed.text()}]: ansatz split into its "
            f"{len(classes)} characters ({sizes} unknowns)"
        )
        out.append(Decomposition(classes, tuple(group), note))
    return out, ", ".join(found) or "none"


#: Most groups a system tries (one per reflection it starts from).
MAX_SEEDS = 4


def _commuting_involutions(
    seed: SignedPermutation, perms: list[SignedPermutation]
) -> list[SignedPermutation]:
    """Independent commuting involutions among ``perms``, from ``seed``: permutations
    first, then sign changes (which refine the rest), greedily."""
    chosen: list[SignedPermutation] = []
    group = {IDENTITY}
    for g in [seed, *sorted(perms, key=lambda g: (g.diagonal, g.reversing, g.images))]:
        if not g.involution or g.images in group:
            continue
        if any(g.compose(h).images != h.compose(g).images for h in chosen):
            continue
        chosen.append(g)
        group |= {g.compose(SignedPermutation(h)).images for h in group}
    return chosen


def _characters(system: Any, group: list[SignedPermutation]) -> tuple:
    """The columns projected on the characters chi of the group the commuting
    involutions generate: P_chi(m) = sum over subsets S of chi(S) (prod S)* m, one orbit
    representative m each (an orbit spans each character at most once)."""
    elements: list[tuple[SignedPermutation, tuple[int, ...]]] = [(SignedPermutation(IDENTITY), ())]
    for k, g in enumerate(group):
        elements += [(g.compose(h), (*s, k)) for h, s in elements]
    characters = list(itertools.product((1, -1), repeat=len(group)))
    classes: dict[tuple[int, ...], list[Combination]] = {chi: [] for chi in characters}
    seen: set[tuple[int, ...]] = set()
    index = system.column_index
    for exps, _ in system.columns:
        if exps in seen:
            continue
        images = [(h.monomial(exps), s) for h, s in elements]
        seen.update(m for (m, _), _ in images)
        for chi in characters:
            vec: Combination = {}
            for (m, sign), s in images:
                value = sign
                for k in s:
                    value *= chi[k]
                j = index[m]
                vec[j] = vec.get(j, 0) + value
            vec = {j: QQ(c) for j, c in vec.items() if c}
            if vec:
                classes[chi].append(vec)
    return tuple(tuple(c) for c in classes.values() if c)
