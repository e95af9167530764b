"""Integrals of the ansatz at one parameter value, and which of them are *extra*.

The kernel of A(p) is the space of integrals of weighted degree <= K (modulo the
level set). Products of known integrals (H, |gamma|^2, the torque's Casimir, s where
it is one) lie in it trivially; so do products with integrals found at lower degree.
Degree by degree, the extra integrals are a basis of the kernel modulo the algebra
those generate: each new one is independent of the known ones and of those found
before. The basis is canonical: kernel vectors are reduced modulo the trivial span
along its pivots, then put in echelon form.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from sympy.polys.rings import PolyElement

from .ansatz import PolynomialSystem
from .linear import Field, Span, nullspace


@dataclass(frozen=True)
class Generator:
    """An integral that generates trivial ones: its polynomial and weighted degree."""

    poly: PolyElement
    weight: int


@dataclass
class Analysis:
    """What the kernel holds at one parameter value: per degree (kernel dimension,
    dimension of the trivial span, number of extra integrals), and the extra
    integrals as vectors over the field's elements (with their degrees)."""

    counts: dict[int, tuple[int, int, int]] = field(default_factory=dict)
    extras: list[tuple[list, int]] = field(default_factory=list)
    #: (block, weight cutoff) -> dimension of the kernel of that part of the block
    nullities: dict[tuple[int, int], int] = field(default_factory=dict)
    #: degree -> an echelon basis of the trivial integrals of weighted degree <= it
    trivial: dict[int, list[list]] = field(default_factory=dict)

    @property
    def extra(self) -> int:
        return len(self.extras)


def products(system: PolynomialSystem, gens: Sequence[Generator], degree: int) -> list[PolyElement]:
    """Every product of generators (repetition allowed) of total weight <= ``degree``,
    reduced modulo the level set."""
    found: list[PolyElement] = []

    def extend(start: int, poly: PolyElement, weight: int) -> None:
        for i in range(start, len(gens)):
            g = gens[i]
            if g.weight == 0 or weight + g.weight > degree:
                continue
            product = system.reduce(poly * g.poly)
            found.append(product)
            extend(i, product, weight + g.weight)

    extend(0, system.ring.one, 0)
    return found


class KernelCache:
    """Kernels of the blocks restricted to columns of weight <= d, per field, so that a
    homogeneous block's kernel is computed once."""

    def __init__(self, system: PolynomialSystem, fld: Field):
        self.system = system
        self.field = fld
        self.kernels: dict[tuple[int, int], list[list]] = {}

    def kernel(self, degree: int) -> list[list]:
        """A basis of the integrals of weighted degree <= ``degree`` (full column vectors)."""
        n = len(self.system.columns)
        out = []
        for b, block in enumerate(self.system.blocks):
            weights = block.weights
            cutoff = min(degree, max(weights))
            if cutoff < min(weights):
                continue
            key = (b, cutoff)
            if key not in self.kernels:
                keep = [k for k, w in enumerate(weights) if w <= cutoff]
                local = {k: i for i, k in enumerate(keep)}
                entries = [
                    (r, local[k], self.field.evaluate(v))
                    for (r, k), v in block.entries.items()
                    if k in local
                ]
                basis = nullspace(block.rows, len(keep), entries, self.field)
                self.kernels[key] = [
                    self._embed(block, {keep[i]: c for i, c in enumerate(v)}, n) for v in basis
                ]
            out.extend(self.kernels[key])
        return out

    def _embed(self, block, coords: dict[int, object], n: int) -> list:
        """A kernel vector of the block (its local columns) on the system's columns."""
        full = [self.field.zero] * n
        for k, c in coords.items():
            if not c:
                continue
            if block.basis is None:
                full[block.columns[k]] = c
                continue
            for j, a in block.basis[k]:
                full[j] += c * self.field.number(a)
        return full


def vector(system: PolynomialSystem, poly: PolyElement, fld: Field) -> list:
    """The coordinates of a polynomial on the ansatz columns, in the field."""
    full = [fld.zero] * len(system.columns)
    for j, coeffs in system.coordinates(poly).items():
        full[j] = fld.evaluate(coeffs)
    return full


def analyse(
    system: PolynomialSystem,
    known: Sequence[Generator],
    fld: Field,
    *,
    to_poly=None,
) -> Analysis:
    """The extra integrals at the field's parameter value, degree by degree.

    ``to_poly`` turns an extra's vector into a ring polynomial (needed to form its
    products at higher degrees); without it (modular counting) only counts are kept
    and products with extras are not formed, which is exact as long as no extra is
    found (the case a modular count is used to prove).
    """
    cache = KernelCache(system, fld)
    result = Analysis()
    gens = list(known)
    for d in range(1, system.degree + 1):
        kernel = cache.kernel(d)
        trivial = Span(fld)
        for poly in products(system, gens, d):
            trivial.add(vector(system, poly, fld))
        residues = Span(fld)
        for v in kernel:
            residues.add(trivial.reduce(v))
        new = [row for _, row in sorted(residues.rows)]
        result.counts[d] = (len(kernel), trivial.dim, len(new))
        if fld.exact:
            result.trivial[d] = [row for _, row in trivial.rows]
        for v in new:
            result.extras.append((v, d))
            if to_poly is not None:
                gens.append(Generator(to_poly(v), d))
    result.nullities = {key: len(basis) for key, basis in cache.kernels.items()}
    return result
