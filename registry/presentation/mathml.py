"""Formulas as presentation MathML, which browsers render natively as text.

SymPy's presentation printer (``sympy.printing.mathml``) writes the expression; this
module fixes what it gets wrong for the registry (an arbitrary function ``D(s)`` or
``U(gamma)`` keeps its capital letter) and writes character references and named
entities as the characters themselves (UTF-8; well formed XML as well as HTML, and a
third of the bytes). Used by the static site and
the HTML report.

>>> import sympy as sp
>>> mathml(sp.Symbol("gamma1") ** 2)
'<math><msup><msub><mi>γ</mi><mi>1</mi></msub><mn>2</mn></msup></math>'
"""

from __future__ import annotations

import html
import html.entities
import re
from collections.abc import Sequence
from functools import lru_cache

import sympy as sp
from sympy.printing.mathml import MathMLPresentationPrinter

#: Left-hand sides of the report's and the site's equations, by the name used in code.
NAMES: dict[str, sp.Symbol] = {
    "residual": sp.Symbol("ℛ"),
    "casimir": sp.Symbol("𝒞"),
    "phi": sp.Symbol("phi"),
    "psi": sp.Symbol("psi"),
}

_ENTITY = re.compile(r"&(?:([A-Za-z][A-Za-z0-9]*)|#([0-9]+)|#[xX]([0-9A-Fa-f]+));")
_XML_ENTITIES = {"lt", "gt", "amp", "quot", "apos"}


class _Printer(MathMLPresentationPrinter):
    """SymPy's presentation printer, with arbitrary functions named as declared."""

    def _print_AppliedUndef(self, e):  # noqa: N802 - sympy's dispatch names
        mrow = self.dom.createElement("mrow")
        mrow.appendChild(self._print(sp.Symbol(e.func.__name__)))
        mrow.appendChild(self._paren_comma_separated(*e.args))
        return mrow


def _character(match: re.Match) -> str:
    """A character reference or named entity as the character itself (the pages are
    UTF-8; a third of the bytes), except the five that XML must keep escaped."""
    name, decimal, hexadecimal = match.groups()
    if name is not None:
        if name in _XML_ENTITIES:
            return match.group(0)
        text = html.entities.html5.get(name + ";")
        if text is None:
            return match.group(0)
    else:
        text = chr(int(decimal) if decimal is not None else int(hexadecimal, 16))
    if any(c in "<>&\"'" for c in text):
        return match.group(0)
    return text


#: The names the printer may write: SymPy's printer writes them unescaped, and the case
#: language's whitelist parser only makes names of this form.
_SAFE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_']*|[ℛ𝒞]")


def _checked(expr: sp.Basic) -> None:
    """ValueError unless every name in ``expr`` is one the printer may write as it is."""
    names = [s.name for s in expr.free_symbols if isinstance(s, sp.Symbol)]
    names += [f.func.__name__ for f in expr.atoms(sp.core.function.AppliedUndef)]
    bad = [n for n in names if not _SAFE_NAME.fullmatch(n)]
    if bad:
        raise ValueError(f"cannot write the name {bad[0]!r} as MathML")


@lru_cache(maxsize=4096)
def _body(expr: sp.Basic) -> str:
    """The MathML of one expression, without the enclosing ``<math>``."""
    _checked(expr)
    printer = _Printer({"order": "none", "fold_short_frac": False})
    return _ENTITY.sub(_character, printer.doprint(expr))


def mathml(
    expr: sp.Basic | Sequence[sp.Basic],
    display: bool = False,
    annotation: str | None = None,
    encoding: str = "application/x-tex",
) -> str:
    """``expr`` as a ``<math>`` element (block-level with ``display``); a sequence of
    expressions is written separated by commas. ``annotation`` (escaped here) is the
    same formula as text in ``encoding``, kept in the markup for tools that read it."""
    if isinstance(expr, sp.Basic):
        body = _body(expr)
    else:
        body = "<mrow>" + '<mo separator="true">,</mo>'.join(_body(e) for e in expr) + "</mrow>"
    if annotation is not None:
        text = html.escape(annotation, quote=True)
        note = f'<annotation encoding="{html.escape(encoding, quote=True)}">{text}</annotation>'
        body = f"<semantics>{body}{note}</semantics>"
    block = ' display="block"' if display else ""
    return f"<math{block}>{body}</math>"


def equation(lhs: sp.Basic, rhs: sp.Basic) -> sp.Basic:
    """``lhs = rhs`` as one expression to print (never evaluated: ``U = 0`` stays)."""
    return sp.Eq(lhs, rhs, evaluate=False)
