"""What an exponent analysis states, exactly as strong as each theorem: Yoshida's
degrees for a homogeneous field and for a leading part, what an irrational exponent
excludes, the Painlevé test passing (never a proof) or failing, and a family's lists
called exact only where they are complete."""

from __future__ import annotations

from registry.discovery.exponent_statement import family_statement, statement

BALANCE = {"point": {"x": "1", "y": "0"}}


def document(**changes):
    base = {
        "homogeneous": True,
        "balances": [BALANCE],
        "degrees": [2, 4],
        "all_integer": True,
        "all_rational": True,
        "painleve": {"passes": True, "compatible": True, "conditions": []},
    }
    return base | changes


def test_a_homogeneous_field_that_passes():
    text = statement(document(), "x: 1, y: 2")
    assert text.startswith(
        "The field is weighted-homogeneous under weights x: 1, y: 2; 1 balance(s)"
    )
    assert "a weighted-homogeneous first integral of weighted degree k >= 1 whose gradient is " \
        "not zero at a balance has k among that balance's exponents: the degrees some balance " \
        "allows are 2, 4" in text  # fmt: skip
    assert text.endswith("passes (integer exponents, every compatibility condition holds): "
                         "necessary for the Painlevé property, not a proof of it.")  # fmt: skip


def test_a_leading_part_is_named_as_such_and_generic_values_are_said():
    text = statement(document(homogeneous=False), "M: 1, gamma: 2", ["c"])
    assert text.startswith("The field is not weighted-homogeneous under weights M: 1, gamma: 2")
    assert "for generic values of c" in text
    assert "the leading weighted-homogeneous part of a polynomial first integral is a first " \
        "integral of the leading part" in text  # fmt: skip


def test_no_positive_integer_exponent_means_vanishing_gradients_not_no_integral():
    text = statement(document(degrees=[], all_integer=False), "x: 1")
    assert "no balance has a positive integer exponent, so every such integral has a " \
        "gradient that vanishes at every balance" in text  # fmt: skip
    assert "needs every exponent to be an integer: it fails" in text


def test_an_irrational_exponent_excludes_a_complete_set_of_algebraic_integrals():
    text = statement(document(all_integer=False, all_rational=False), "x: 1")
    assert "1 (the dimension less one) weighted-homogeneous algebraic first integrals" in text
    assert "so the field has no 1 such integrals independent there" in text


def failing_at(balance: int, resonance: int, condition: str = "", missing: int = 0) -> str:
    """The statement of an analysis whose one obstruction is at ``resonance``."""
    entry = {"balance": balance, "resonance": resonance, "condition": condition, "missing": missing}
    failing = {"passes": False, "compatible": False, "conditions": [entry]}
    return statement(document(painleve=failing), "x: 1")


def test_a_failing_condition_names_where_and_denies_the_painleve_property():
    text = failing_at(2, 8, condition="a = 0")
    assert "a compatibility condition fails (balance 2, resonance 8: a = 0)" in text
    assert text.endswith("the field does not have the Painlevé property.")


def test_a_missing_coefficient_is_named_as_such_and_at_the_exponent_0_claims_less():
    text = failing_at(1, 3, missing=1)
    assert "1 free coefficient(s) missing (balance 1, resonance 3)" in text
    assert text.endswith("the field does not have the Painlevé property.")

    text = failing_at(2, 0, missing=1)
    assert "at balance 2 the exponent 0 is more frequent than the dimensions" in text
    assert "the test fails" in text
    assert "Painlevé property" not in text.split("ARS")[-1]


def test_no_balance_says_nothing_is_implied():
    text = statement(document(balances=[]), "x: 1")
    assert text.endswith("Kovalevskaya's exponents, Yoshida's theorem and the Painlevé test "
                         "say nothing here.")  # fmt: skip


def family(complete, special):
    return document(all_integer=False, free=["n"], special=special, coverage=["searched"],
                    complete=complete)  # fmt: skip


def test_a_complete_family_says_exactly_and_an_incomplete_one_at_least():
    point = {"when": ["n = 2"], "kind": "integer", "painleve": {"passes": True}, "notes": []}
    done = {"integer": True, "half_integer": True, "rational": True}
    text = family_statement(family(done, [point]), "M: 1, gamma: 2")
    assert "is an integer exactly at: n = 2 (ARS test passes)" in text
    assert "no value makes every exponent of every balance half an integer" in text
    assert "not complete" not in text
    partial = {"integer": False, "half_integer": False, "rational": False}
    text = family_statement(family(partial, [point]), "M: 1, gamma: 2")
    assert "is an integer at least at: n = 2" in text and text.endswith("not complete: searched.")


def test_a_family_integer_everywhere_says_where_the_painleve_test_passes():
    every = {"when": [], "kind": "integer", "index": {"name": "a", "ranges": "every"}}
    zero = {"when": ["a = 0"], "kind": "integer", "painleve": {"passes": True}, "notes": []}
    failing = {"passes": False, "conditions": [
        {"balance": 1, "resonance": 8, "condition": "-a*f4**2 = 0", "missing": 0}]}  # fmt: skip
    done = {"integer": True, "half_integer": True, "rational": True}
    text = family_statement(
        {**family(done, [zero, every]), "painleve": failing, "free": ["a"]}, "x: 1"
    )
    assert "every exponent of every balance is an integer for every value of a" in text
    assert "for generic values a compatibility condition fails (balance 1, resonance 8: " \
        "-a*f4**2 = 0)" in text  # fmt: skip
    assert text.endswith("passes exactly at: a = 0; no value makes every exponent of every "
                         "balance half an integer (not all integers).")  # fmt: skip


def test_the_half_integer_sets_say_complete_only_where_they_are():
    """The sets where every exponent is in (1/2)Z: those with an exponent half an odd
    integer named apart; "outside these sets" only for a complete list."""
    done = {"integer": False, "half_integer": False, "rational": False}
    gc = {"when": ["c = 1/4", "z0 = 0"], "free": ["x0"], "kind": "half-integer"}
    axis = {"when": ["x0 = 0"], "free": ["c", "z0"], "kind": "integer"}
    found = {"sets": [gc, axis], "complete": True, "undecided": [], "strata": 9}
    text = family_statement({**family(done, []), "half_integer_sets": found}, "M: 1, gamma: 2")
    assert "is in (1/2)Z for the generic members of: c = 1/4, z0 = 0 (x0 free); x0 = 0 " in text
    assert "(some exponent half an odd integer on: c = 1/4, z0 = 0 (x0 free))" in text
    assert text.endswith("outside these sets some exponent is not in (1/2)Z.")
    found |= {"complete": False, "undecided": ["b**2 - 1/2 = 0: not analysed"]}
    text = family_statement({**family(done, []), "half_integer_sets": found}, "M: 1, gamma: 2")
    assert "outside these sets" not in text
    assert text.endswith("not complete: 1 set(s) were not decided.")
    found |= {"sets": []}
    text = family_statement({**family(done, []), "half_integer_sets": found}, "M: 1, gamma: 2")
    assert "no set that was analysed has every exponent in (1/2)Z" in text


def test_a_long_list_of_special_sets_names_a_few_and_counts_the_others():
    points = [
        {"when": [f"a = {k}"], "kind": "integer", "painleve": {"passes": False}, "notes": []}
        for k in range(20)
    ]
    partial = {"integer": False, "half_integer": False, "rational": False}
    text = family_statement(family(partial, points), "x: 1")
    assert "is an integer at least at: a = 0 (ARS test fails); " in text
    assert "a = 5 (ARS test fails); and 14 more (each in the list of special sets)" in text
    assert "a = 6 " not in text
