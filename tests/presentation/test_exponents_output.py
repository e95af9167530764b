"""The plain text of an exponent analysis: each balance with its exponents and where the
Painlevé test fails, the leading part where the field is not homogeneous, a family's
special sets, and an undecided analysis saying why."""

from __future__ import annotations

from registry.model import ExponentOptions, ExponentResult
from registry.presentation.exponents_output import exponents_text

OPTIONS = ExponentOptions((("x", 1), ("y", 3)))


def result(document):
    base = {"case": "demo", "weights": {"x": 1, "y": 3}, "free": [], "statement": "S."}
    return ExponentResult("demo", "h", OPTIONS, base | document, 0.25)


def test_a_balance_with_a_failing_condition_and_a_leading_part():
    balance = {
        "point": {"x": "1", "y": "0"}, "exponents": ["-1", "8"], "integer": True,
        "rational": True, "dimension": 0, "along": [],
        "painleve": {"compatible": False, "resonances": [
            {"order": 8, "multiplicity": 1, "free": [], "conditions": ["-f4**2 = 0"],
             "missing": 0}]},
    }  # fmt: skip
    text = exponents_text(
        result(
            {
                "leading": {"x": "-x**2", "y": "5*x*y"},
                "balances": [balance],
                "degrees": [8],
                "painleve": {"passes": False},
            }
        )
    )
    assert text.splitlines() == [
        "demo: Kovalevskaya exponents (weights x=1,y=3)",
        "the field is not weighted-homogeneous: its leading part is analysed,",
        "    dx/dt = -x**2",
        "    dy/dt = 5*x*y",
        "balance 1: x = 1, y = 0",
        "    exponents: -1, 8 (integers)",
        "    resonance 8: condition fails: -f4**2 = 0",
        "degrees (Yoshida): 8",
        "Painlevé (ARS) test: fails",
        "S.",
        "0.25 s",
    ]


def test_a_family_lists_its_special_sets_and_completeness():
    special = [
        {"when": ["n = 2"], "kind": "integer", "exponents": [["-1", "0"]],
         "painleve": {"passes": True}, "notes": []},
        {"when": ["n = t**2"], "kind": "rational", "index": {"name": "t", "ranges": "t in Q"},
         "members": [], "notes": []},
    ]  # fmt: skip
    text = exponents_text(
        result(
            {
                "free": ["n"],
                "balances": [],
                "all_integer": None,
                "special": special,
                "complete": {"integer": True, "half_integer": False, "rational": True},
                "coverage": ["half-integer: searched"],
            }
        )
    )
    assert "  integer: n = 2; Painlevé (ARS) test passes" in text
    assert "      exponents -1, 0" in text
    assert "  rational: n = t**2 (t in Q)" in text
    assert "complete: integer yes, half-integer no, rational yes" in text
    assert "  coverage: half-integer: searched" in text


def test_a_grid_with_hundreds_of_special_sets_shows_a_dozen_of_each_kind_and_counts_the_rest():
    """A family searched on a grid over several parameters (Lotka-Volterra's ABC system
    finds 518 sets on 11 values per parameter) lists a dozen sets of each kind."""
    special = [
        {"when": [f"a = {k}", "b = 1"], "kind": kind, "exponents": [["-1", "1"]], "notes": []}
        for kind, count in (("integer", 15), ("rational", 3))
        for k in range(count)
    ]
    text = exponents_text(
        result(
            {
                "free": ["a", "b"],
                "balances": [],
                "all_integer": None,
                "special": special,
                "complete": {"integer": False, "half_integer": False, "rational": False},
                "coverage": ["a grid"],
            }
        )
    )
    lines = text.splitlines()
    assert "  integer: a = 11, b = 1" in lines and "  integer: a = 12, b = 1" not in lines
    assert "  integer: 3 more set(s), not shown (--json lists them)" in lines
    assert "  rational: a = 2, b = 1" in lines and "rational: 0 more" not in text
    assert lines.index("  integer: 3 more set(s), not shown (--json lists them)") < lines.index(
        "  rational: a = 0, b = 1"
    )


def test_an_undecided_analysis_says_why():
    text = exponents_text(result({"decided": False, "reason": "too slow"}))
    assert text.splitlines()[1:] == ["not decided: too slow", "S."]


def test_the_sets_of_a_stratification_with_their_kinds_and_the_cases_they_are():
    """Each set with its free parameters and kind; the catalog cases it is, three shown
    and the others counted; a set that matched none says so; one not identified (no
    registry) has no such line."""
    sets = [
        {"when": ["z0 = 0"], "free": ["x0"], "kind": "half-integer",
         "same_as": ["gc", "gc-all-s", "sretensky", "birtea", "grioli"]},
        {"when": ["x0 = 0"], "free": ["z0"], "kind": "integer", "same_as": []},
        {"when": ["n1 = 0"], "free": [], "kind": None},
    ]  # fmt: skip
    found = {"sets": sets, "complete": False, "undecided": ["b**2 = 1/2: not analysed"],
             "strata": 7}  # fmt: skip
    document = {"balances": [], "painleve": {"passes": False}, "half_integer_sets": found}
    lines = exponents_text(result(document)).splitlines()
    start = lines.index("every exponent in (1/2)Z on (7 strata analysed):")
    assert lines[start + 1 : start + 8] == [
        "  z0 = 0 (x0 free) [half-integer]",
        "      same as gc, gc-all-s, sretensky and 2 more",
        "  x0 = 0 (z0 free) [integer]",
        "      matches no catalog case",
        "  n1 = 0",
        "complete: no",
        "  not decided: b**2 = 1/2: not analysed",
    ]


def test_a_sets_exponents_shared_by_several_balances_are_shown_once_with_their_count():
    """Euler's top has four balances with exponents -1, 1, 2, 2, 2, 3: one line says so;
    a list of its own stays a line of its own."""
    euler = ["-1", "1", "2", "2", "2", "3"]
    sets = [{"when": ["x0 = 0"], "free": ["b"], "exponents": [euler] * 4 + [["-1", "4"]]}]
    found = {"passing": sets, "complete": True, "undecided": [], "strata": 3}
    document = {"balances": [], "painleve": {"passes": False}, "painleve_sets": found}
    lines = exponents_text(result(document)).splitlines()
    start = lines.index("  x0 = 0 (b free)")
    assert lines[start + 1 : start + 4] == [
        "      exponents -1, 1, 2, 2, 2, 3 (4 balances)",
        "      exponents -1, 4",
        "complete: yes",
    ]


def test_a_long_point_is_elided_to_its_symbols_and_length():
    """Schottky's so(4) body has one family of balances whose generic point over
    Q(kappa, gamma3) runs to 50 000 characters: the text names what each long coordinate
    involves (not sqrt, not I) and its length, and says where the whole point is; short
    ones stay."""
    long = " + ".join(f"{k}*theta**{k}*sqrt(gamma3 + I)" for k in range(1, 60))
    balance = {
        "point": {"x": long, "y": "gamma3"}, "root_of": f"{long} = 0",
        "exponents": ["-1", "8"], "integer": True, "rational": True, "dimension": 1,
        "along": ["gamma3"], "painleve": {"compatible": True, "resonances": []},
    }  # fmt: skip
    text = exponents_text(
        result({"balances": [balance], "degrees": [8], "painleve": {"passes": None}})
    )
    assert text.splitlines()[1:5] == [
        f"balance 1: x = <an expression in gamma3, theta: {len(long)} characters>, y = gamma3",
        f"    theta: a root of <an expression in gamma3, theta: {len(long) + 4} characters>",
        "    (long expressions elided: registry exponents --json prints them whole)",
        "    a family of balances of dimension 1 (along gamma3)",
    ]
    assert "Painlevé (ARS) test: not made" in text
    short = {**balance, "point": {"x": "1", "y": "gamma3"}, "root_of": "theta**2 - 2 = 0"}
    untested = {"passes": None}
    text = exponents_text(result({"balances": [short], "degrees": [8], "painleve": untested}))
    assert "balance 1: x = 1, y = gamma3\n    theta: a root of theta**2 - 2 = 0\n" in text
    assert "elided" not in text


def test_a_generic_verdict_read_from_the_stratification_is_said_so():
    """The distinct-moments heavy top: its generic members' balances were not computed
    within the budget, but the complete list of sets where the test passes holds only
    Euler's top, so generic members fail; the text says where that comes from."""
    euler = {
        "when": ["x0 = 0", "y0 = 0", "z0 = 0"],
        "free": ["p", "q"],
        "exponents": [["-1", "1", "2", "2", "2", "3"]],
        "notes": [],
    }
    sets = {"passing": [euler], "complete": True, "undecided": [], "strata": 14}
    document = {"free": ["p", "q", "x0", "y0", "z0"], "balances": [], "all_integer": None,
                "painleve": {"passes": False}, "painleve_sets": sets}  # fmt: skip
    lines = exponents_text(result(document)).splitlines()
    assert lines[1] == "Painlevé (ARS) test for generic values: fails (by the sets below)"
    assert "  x0 = 0, y0 = 0, z0 = 0 (p, q free)" in lines
    unknown = {**document, "painleve": {"passes": None}}
    assert "generic values" not in exponents_text(result(unknown))
