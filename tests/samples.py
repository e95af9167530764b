"""Shared test inputs: the seed catalog's location and small broken case files."""

from pathlib import Path

CASES = Path(__file__).resolve().parents[1] / "data" / "cases"
#: The tests' own data: the classical catalog, golden outputs, an old schema dump.
TEST_DATA = Path(__file__).resolve().parent / "data"
#: Classical cases whose verdicts the literature settles (tests of numeric evidence).
CLASSICAL = TEST_DATA / "classical"
#: The seed catalog: the reference paper's cases (and one classical case) at the top of
#: data/cases; the literature catalog lives in its sub-folders.
SEED_FILES = sorted(CASES.glob("*.toml"))
YEHIA_B = "yehia-2003-kovalevskaya-b"
ZHUKOVSKY = "zhukovsky-gyrostat"
AFFINE = "affine-nonsymmetric"
#: Three seed cases that between them refute, verify and break Jacobi.
SEED = (YEHIA_B, ZHUKOVSKY, AFFINE)

UNDECLARED = """\
id = "bad-undeclared-name"
title = "A claim that uses a name nobody declared"

[source]
citation = "Nobody, Nowhere (2024)"

[parameters]
C = "positive"

[system]
inertia = ["C", "C", "2*C"]

[[claims]]
label = "I1"
kind = "integral"
expression = "M1 + bogus*gamma1"
"""


def case_file(case_id: str) -> Path:
    """The seed catalog's file for ``case_id``."""
    return CASES / f"{case_id}.toml"
