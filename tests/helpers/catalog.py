"""The seed catalog as an identification index, built once per test session."""

from __future__ import annotations

import functools
from pathlib import Path

from registry.discovery.identification.catalog_index import CatalogIndex
from registry.language.casefile import load_case

CASES = Path(__file__).resolve().parents[2] / "data" / "cases"


@functools.cache
def catalog_cases() -> tuple:
    return tuple(load_case(p) for p in sorted(CASES.rglob("*.toml")))


@functools.cache
def catalog_index() -> CatalogIndex:
    return CatalogIndex.of(catalog_cases())


def catalog_case(case_id: str):
    return next(c for c in catalog_cases() if c.id == case_id)
