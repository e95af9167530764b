"""The one LaTeX escaper: no special character is left bare, and braces stay balanced
where another reader counts them (BibTeX fields, a notebook's \\text{...})."""

import re

from registry.presentation import latex


def _balanced(text: str) -> bool:
    depth = 0
    for char in text:
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0


def test_latex_escape_leaves_no_bare_special():
    escaped = latex.escape(r"a_b & c% {d} #e ~f ^g \h $i", balanced=True)
    assert re.search(r"(?<!\\)[&%#$_]", escaped) is None
    assert _balanced(escaped)


def test_every_special_character_of_running_text_is_escaped():
    text = "".join(latex.SPECIALS)
    escaped = latex.escape(text)
    assert escaped == "".join(latex.SPECIALS.values())
    assert latex.escape("plain text, 1.5 (x)") == "plain text, 1.5 (x)"


def test_balanced_escaping_differs_only_in_braces_and_the_text_font_characters():
    assert latex.escape("{x}") == r"\{x\}"
    assert latex.escape("{x}", balanced=True) == r"\textbraceleft{}x\textbraceright{}"
    assert latex.escape("a < b | c", balanced=True) == "a < b | c"
    assert latex.escape("a < b | c") == r"a \textless{} b \textbar{} c"
    assert latex.escape("50% & x_1", balanced=True) == latex.escape("50% & x_1")
