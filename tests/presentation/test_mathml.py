"""Formulas as presentation MathML: well-formed XML, the registry's names as declared,
characters written as themselves, and names that could carry markup refused."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest
import sympy as sp

from registry.language.casefile import load_case
from registry.presentation.mathml import equation, mathml
from tests.helpers.samples import CASES

NS = "{http://www.w3.org/1998/Math/MathML}"


def _xml(text: str) -> ET.Element:
    """The <math> element parsed as XML (in the MathML namespace)."""
    return ET.fromstring(text.replace("<math", f'<math xmlns="{NS[1:-1]}"', 1))


def test_every_expression_of_the_catalog_is_well_formed_mathml():
    for path in sorted(CASES.rglob("*.toml")):
        case = load_case(path)
        exprs = [*case.system.torque_exprs, case.system.potential.expr]
        exprs += [c.expression.expr for c in case.claims]
        for expr in exprs:
            root = _xml(mathml(expr, display=True))
            assert root.tag == f"{NS}math" and root.get("display") == "block"
            assert "&" not in "".join(root.itertext())  # no entity left unresolved


def test_arbitrary_functions_keep_their_capital_letters():
    s = sp.Symbol("s")
    text = mathml(sp.Derivative(sp.Function("D")(s), s))
    assert "<mi>D</mi>" in text and "<mi>d</mi>" not in text
    assert "\u2146" in text and "&" not in text  # the differential d, as the character


def test_greek_names_and_subscripts():
    text = mathml(sp.Symbol("gamma3") * sp.Symbol("mu_1"))
    assert "<msub><mi>γ</mi><mi>3</mi></msub>" in text
    assert "<msub><mi>μ</mi><mi>1</mi></msub>" in text


def test_an_equation_is_not_evaluated_and_keeps_its_sides():
    text = mathml(equation(sp.Symbol("U"), sp.Integer(0)))
    assert text == "<math><mrow><mi>U</mi><mo>=</mo><mn>0</mn></mrow></math>"


def test_a_list_of_expressions_is_comma_separated():
    text = mathml([sp.Symbol("x"), sp.Symbol("y")])
    assert _xml(text).find(f"{NS}mrow") is not None
    assert text.count('<mo separator="true">,</mo>') == 1


def test_the_annotation_is_escaped():
    text = mathml(sp.Symbol("x"), annotation='x </annotation><script>"', encoding="text/plain")
    root = _xml(text)
    (note,) = root.iter(f"{NS}annotation")
    assert note.text == 'x </annotation><script>"'
    assert "<script>" not in text


@pytest.mark.parametrize("name", ["<b>x</b>", "x&y", 'a"b'])
def test_a_name_that_could_carry_markup_is_refused(name):
    with pytest.raises(ValueError, match="cannot write the name"):
        mathml(sp.Symbol(name))
