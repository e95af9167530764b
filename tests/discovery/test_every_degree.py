"""The two halves combined, exactly as strong as Yoshida's theorem: the degrees it allows
within or beyond a complete search, a field's leading part, a family's special sets
beside the exponents', and every hypothesis that fails named instead of a statement."""

from __future__ import annotations

from registry.discovery.every_degree import every_degree
from registry.model import (
    Equation,
    ExponentOptions,
    ExponentResult,
    IntegralSet,
    Search,
    SearchOptions,
)

WEIGHTS = (("M", 1), ("gamma", 2))


def search(degree=4, free=(), special=(), complete=True, on=(), weights=WEIGHTS):
    return Search(
        "demo",
        "h",
        SearchOptions(degree, weights, on, free),
        (),
        IntegralSet((), 0),
        tuple(special),
        complete,
        dimensions=((1, 0, 0, 0),),
    )


def analysis(degrees=(2, 3, 4), homogeneous=True, weights=WEIGHTS, **more):
    document = {
        "homogeneous": homogeneous,
        "degrees": list(degrees),
        "balances": [{"point": {}}],
        "all_integer": True,
        "parameters": [],
    } | more
    return ExponentResult("demo", "h", ExponentOptions(weights), document)


def test_degrees_within_a_complete_search_bound_every_degree():
    text = every_degree(search(4), analysis((2, 3, 4)))
    assert "allows only the degrees 2, 3, 4, all within the complete search to degree 4" in text
    assert text.endswith(
        "every polynomial first integral, of any degree, is the sum of one the search "
        "determined and of weighted-homogeneous integrals whose gradients vanish at every "
        "balance."
    )


def test_degrees_beyond_the_search_are_named_not_excluded():
    text = every_degree(search(3), analysis((2, 3, 4, 6)))
    assert "the complete search reached 3, so integrals of degree 4, 6 with a gradient not " \
        "zero at some balance are not excluded: a complete search to degree 6 would cover " \
        "every degree Yoshida allows" in text  # fmt: skip
    leading = every_degree(search(3), analysis((2, 3, 4, 6), homogeneous=False))
    assert (
        "so integrals whose leading weighted-homogeneous part has degree 4, 6 and a gradient "
        "not zero at some balance of the leading part are not excluded" in leading
    )


def test_a_leading_part_speaks_of_leading_parts():
    text = every_degree(search(4), analysis((2, 4), homogeneous=False))
    assert "applied to the field's leading part" in text
    assert "whose leading weighted-homogeneous part has a gradient not zero at some balance" in text


def test_every_failing_hypothesis_is_named():
    def why(s, a):
        return every_degree(s, a).partition(": ")[2]

    on = (Equation("s = 0", None, None),)  # type: ignore[arg-type]
    assert why(search(on=on), analysis()).startswith("the search is on a level set")
    assert why(search(complete=False), analysis()) == "the search is not complete."
    assert why(search(), None) == "no Kovalevskaya analysis under the search's weights."
    other = analysis(weights=(("M", 1), ("gamma", 1)))
    assert why(search(), other).startswith("the Kovalevskaya analysis used other weights")
    stopped = {"decided": False, "reason": "slow"}
    undecided = ExponentResult("demo", "h", ExponentOptions(WEIGHTS), stopped)
    assert why(search(), undecided) == "the Kovalevskaya analysis was not decided (slow)."
    assert every_degree(search(), None).startswith("Nothing is stated beyond degree 4")
    unmade = analysis(balances=[], all_integer=None, special=[])  # a family's, out of time
    assert why(search(), unmade).startswith("the balances of generic values were not found")
    assert why(search(), analysis(balances=[], degrees=[])).startswith(
        "the leading part has no balance"
    )


def test_a_family_sets_its_special_sets_beside_the_exponents():
    special = [IntegralSet(("lam = 2",), 1), IntegralSet(("lam = 3",), 1)]
    exponent_sets = [
        {"when": ["lam = 2"], "kind": "integer", "painleve": {"passes": True}},
        {"when": ["lam = 4"], "kind": "half-integer", "painleve": {"passes": False}},
    ]
    found = analysis(
        free=["lam"],
        special=exponent_sets,
        all_integer=False,
        complete={"integer": True, "half_integer": True, "rational": True},
    )
    text = every_degree(search(free=("lam",), special=special), found)
    assert "(for generic values of lam)" in text
    assert "generic members have exponents that are not all integers" in text
    assert "where lam = 2 the search finds more integrals and every exponent is an integer " \
        "(the ARS test passes)" in text  # fmt: skip
    assert "where lam = 3 the search finds more integrals, yet not every exponent is an " \
        "integer there" in text  # fmt: skip


def test_a_family_shown_failing_by_a_witness_says_so_beside_its_special_sets():
    """A family whose sets left its generic members' test unknown, decided by a witness at
    rational values: the combined statement says the test fails for generic members and
    where the witness is; without a witness, nothing is said of them."""
    witness = {"values": {"lam": "5/2"}, "exponents": ["-1", "1/3"]}
    found = analysis(free=["lam"], special=[], witness=witness, painleve={"passes": False})
    special = [IntegralSet(("lam = 3",), 1)]
    text = every_degree(search(free=("lam",), special=special), found)
    assert (
        "; the ARS test (Ablowitz, Ramani and Segur, J. Math. Phys. 21 (1980) 715) fails for "
        "generic members (a simple balance at lam = 5/2 has an exponent that is not an "
        "integer); where lam = 3 the search finds more integrals (not compared)." in text
    )
    unknown = analysis(free=["lam"], special=[])
    plain = every_degree(search(free=("lam",), special=special), unknown)
    assert "generic members" not in plain and "(not compared)" in plain
