"""When the roots of polynomials over Q(p) are all integers (or rational): candidates
from the coefficients, a finite set when a pinned coefficient bounds the others,
residue classes when none does, conics for rational square discriminants."""

from __future__ import annotations

import sympy as sp

from registry.mathematics.integrality import integer_candidates, rational_candidates

p, lam = sp.symbols("p lambda")

# the symmetric heavy top A = B = 1, C = p, r = (1, 0, 0): its exponent polynomial's
# factors besides the constant ones (test_exponent_families.py)
SYMMETRIC_TOP = [lam - 2 * p + 1, lam + 2 * p - 2, p * lam**2 - p * lam + 2 * p - 2]


def test_a_pinned_coefficient_bounds_the_others_and_the_search_is_complete():
    found = integer_candidates(SYMMETRIC_TOP, p, lam)
    # 2p - 1 = m, and 2 - 2/p = 2 - 4/(m + 1) an integer: m + 1 divides 4
    assert found.complete and found.families == ()
    assert sorted(found.values) == [-2, -1, -sp.Rational(1, 2), sp.Rational(1, 2), 1, 2]


def test_a_bound_far_beyond_cauchys_is_found_from_the_real_roots():
    """Hénon and Heiles's x²y + p y³/3 under (x, y, px, py) = (2, 2, 3, 3): the exponents
    that vary are 5/2 +- sqrt(24p - 23)/2 and 5/2 +- sqrt(1 + 48/p)/2 (balances with
    x != 0 and x = 0). Doubled, their coefficients are 48 - 24p and 24 - 48/p: with
    24 - 48/p = m, 48 - 24p = 48 + 1152/(m - 24), so m - 24 divides 1152. Cauchy's bound
    on D² - R² is 1.3 million, past the enumeration's limit; its real roots bound |m| by
    1176. The values in (1/2)Z are those where both square roots are integers:
    (m² + 23)(k² - 1) = 1152 for integers m, k, that is p = 1, 2, 6 and 16."""
    balances = [lam**2 - 5 * lam + 12 - 6 * p, p * lam**2 - 5 * p * lam + 6 * p - 12]
    doubled = [sp.expand(4 * f.subs(lam, lam / 2)) for f in balances]
    found = integer_candidates(doubled, p, lam)
    assert found.complete and found.families == ()
    halves = {
        v
        for v in found.values
        if all(
            r.is_integer
            for f in doubled
            for r in sp.roots(sp.Poly(f.subs(p, v), lam), multiple=True)
        )
        and all(sp.degree(f.subs(p, v), lam) == 2 for f in doubled)
    }
    assert halves == {1, 2, 6, 16}


def test_polynomial_coefficients_give_residue_classes():
    found = integer_candidates([lam - p / 2, lam - p**2 / 4 - p / 2], p, lam)
    # p/2 = m: p = 2m, and m^2 + m is always an integer: every even p
    assert found.complete and found.values == ()
    ((expr, index, ranges),) = found.families
    assert expr in (2 * index, -2 * index) and ranges == "n in Z"
    ((expr, index, _),) = integer_candidates([lam - p / 2, lam - p / 4], p, lam).families
    assert expr in (4 * index, -4 * index)  # p/4 an integer too: p = 4n


def test_one_coefficient_linear_in_p_is_a_family_through_its_index():
    """The exponent 1 - p alone: an integer exactly at p = 1 - m (no other coefficient
    to bound m; this crashed on sympy's ``ilcm`` of one number)."""
    found = integer_candidates([lam - 1 + p], p, lam)
    assert found.complete and found.values == ()
    ((expr, index, ranges),) = found.families
    assert ranges == "n in Z" and {expr.subs(index, k) for k in range(-3, 4)} == {
        1 - k for k in range(-3, 4)
    }


def test_constant_exponents_are_integers_everywhere_or_nowhere():
    assert integer_candidates([lam - 2, lam + 1], p, lam).families == ((p, p, "every value"),)
    nowhere = integer_candidates([lam**2 - 2], p, lam)
    assert nowhere.values == () and nowhere.families == () and nowhere.complete
    assert integer_candidates([lam - sp.Rational(1, 2)], p, lam).notes == (
        "a constant coefficient is not an integer",
    )


def test_a_pinning_of_higher_degree_is_searched_not_complete():
    found = integer_candidates([lam - p**2], p, lam)
    assert not found.complete and sp.sqrt(2) in found.values and 3 in found.values


def test_rational_values_where_a_discriminant_is_a_square_form_a_conic():
    found = rational_candidates(SYMMETRIC_TOP, p, lam)
    ((expr, t, _),) = found.families
    assert found.complete
    # the discriminant 1 - 4 (2 - 2/p) = (8 - 7p)/p is a square exactly on p = 8/(t^2 + 7)
    assert sp.simplify(expr - 8 / (t**2 + 7)) == 0
    linear = rational_candidates([lam - p, lam + 1], p, lam)
    assert linear.families == ((p, p, "every rational value"),)
    assert rational_candidates([lam**2 - 2], p, lam).families == ()
    (line,) = rational_candidates([lam**2 - p], p, lam).families
    assert line[0] == line[1] ** 2
