"""Shared test inputs: the seed catalog's location and small broken case files."""

from pathlib import Path

import sympy as sp

CASES = Path(__file__).resolve().parents[2] / "data" / "cases"
#: The tests' own data: the classical catalog, golden outputs, an old schema dump.
TEST_DATA = Path(__file__).resolve().parents[1] / "data"
#: Classical cases whose verdicts the literature settles (tests of numeric evidence).
CLASSICAL = TEST_DATA / "classical"
#: Cases in the Hamiltonian form, on e(3), so(4) and so(3,1) (issue 20), derived in
#: tests/test_hamiltonian_form.py.
HAMILTONIAN = TEST_DATA / "hamiltonian"
#: Families with free parameters, searched by ``registry discover --free`` (issue 21).
FAMILIES = TEST_DATA / "families"
#: Level sets kept by the flow, one repelling and one attracting (numeric evidence).
LEVEL_SETS = TEST_DATA / "level-sets"
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


#: A claim that is identically zero, so no probe refutes it, but whose proof must expand
#: powers of a six-variable linear form (minutes of work): a worker busy in a long check.
SLOW_CASE = """\
id = "slow-{n}"
title = "A claim whose proof takes minutes"

[source]
citation = "Test, Nowhere (2026)"

[parameters]
k = "real"

[system]
inertia = ["1", "2", "3"]
potential = "gamma3"
torque = ["0", "0", "{n}"]  # cases of different torques go to different workers

[[claims]]
label = "I"
kind = "casimir"
expression = "s + ({linear})**40 - ({square})**20"
"""


def slow_case(n: int) -> str:
    """The text of a case whose claim's proof takes minutes (see SLOW_CASE)."""
    linear = sp.sympify(f"gamma1 + gamma2 + gamma3 + M1 + k + {n}")
    return SLOW_CASE.format(n=n, linear=linear, square=sp.expand(linear**2))


def family(name: str):
    """The test family ``tests/data/families/<name>.toml``, loaded."""
    from registry.language.casefile import load_case

    return load_case(FAMILIES / f"{name}.toml")
