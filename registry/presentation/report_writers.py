"""The writers of a run's report: Markdown, one self-contained HTML file, or LaTeX.

Each writer knows how its format writes the blocks of a report (headings,
paragraphs of text, inline math and verbatim parts, displayed equations, tables,
images); the content itself is said once, in ``report_content``. A new report
format is one more ``Writer`` in ``WRITERS``.
"""

from __future__ import annotations

import base64
import html
import re
import struct
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import sympy as sp

from . import latex
from .mathml import mathml

#: The formats ``build_report`` writes, by name (the name is also the file extension).
FORMATS = ("md", "html", "tex")


@dataclass(frozen=True)
class Math:
    """A formula, inline in a paragraph: its LaTeX, and the expression it shows (what
    the HTML writer prints as MathML; a tuple of expressions for a list of them)."""

    latex: str
    expr: sp.Basic | tuple[sp.Basic, ...] | None = None
    #: The formula in the case-file language (what a reader copies), where there is one.
    text: str | None = None


@dataclass(frozen=True)
class Code:
    """Text shown verbatim: a witness point, or an expression that did not parse."""

    text: str


@dataclass(frozen=True)
class Link:
    """Text that links to a section of the same document (by its anchor)."""

    text: str
    anchor: str


Part = str | Math | Code | Link


def anchor(*names: str) -> str:
    """A section's anchor: the names lowercased, anything but letters and digits as '-'."""
    return re.sub(r"[^a-z0-9]+", "-", "-".join(names).lower()).strip("-")


# ----------------------------------------------------------------------- writers


class Writer:
    """Collects blocks of one document; subclasses say how each block is written."""

    def __init__(self) -> None:
        self.blocks: list[str] = []

    def inline(self, parts: Iterable[Part]) -> str:
        """A run of text, inline math and verbatim text."""
        out = []
        for p in parts:
            if isinstance(p, Math):
                out.append(self.formula(p))
            elif isinstance(p, Code):
                out.append(self.code(p.text))
            elif isinstance(p, Link):
                out.append(self.link(p.text, p.anchor))
            else:
                out.append(self.escape(p))
        return "".join(out)

    def para(self, *parts: Part) -> None:
        self.blocks.append(self.paragraph(self.inline(parts)))

    def table(self, header: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
        cells = [
            [
                self.inline([c]) if isinstance(c, Math | Code | Link) else self.escape(str(c))
                for c in row
            ]
            for row in rows
        ]
        self.blocks.append(self.tabular([self.escape(h) for h in header], cells))

    # what each format says its own way

    def escape(self, text: str) -> str:
        """Plain text, with the format's special characters escaped."""
        raise NotImplementedError

    def tex(self, expr: sp.Basic) -> str:
        """The LaTeX of an expression, for a format that writes formulas in LaTeX."""
        return _latex(expr)

    def formula(self, math: Math) -> str:
        """An inline formula (by default written from its LaTeX)."""
        return self.math(math.latex)

    def math(self, latex: str) -> str:
        """An inline formula given in LaTeX."""
        raise NotImplementedError

    def code(self, text: str) -> str:
        """Text shown verbatim, inline."""
        raise NotImplementedError

    def paragraph(self, text: str) -> str:
        """A paragraph of inline text that is already written in the format."""
        raise NotImplementedError

    def heading(self, level: int, text: str, anchor: str | None = None) -> None:
        """A heading; ``anchor`` names it for links (where the format has links)."""
        raise NotImplementedError

    def link(self, text: str, anchor: str) -> str:
        """Text linking to the heading named ``anchor`` (plain text where the format has
        no links)."""
        return self.escape(text)

    def equation(
        self,
        latex: str,
        expr: sp.Basic | tuple[sp.Basic, ...] | None = None,
        text: str | None = None,
    ) -> None:
        """A displayed formula: its LaTeX, the expression it shows and its text (``Math``)."""
        raise NotImplementedError

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        """A table whose cells are already escaped."""
        raise NotImplementedError

    def image(self, path: Path, alt: str) -> None:
        raise NotImplementedError

    def finish(self, title: str) -> str:
        """The whole document."""
        raise NotImplementedError


class MarkdownWriter(Writer):
    """Markdown with $...$ math (GitHub, Jupyter); images linked relatively."""

    def escape(self, text: str) -> str:
        return re.sub(r"([\\`*_\[\]<>|$])", r"\\\1", text)

    def math(self, latex: str) -> str:
        return f"${latex}$"

    def code(self, text: str) -> str:
        fence = "``" if "`" in text else "`"
        return f"{fence}{text}{fence}"

    def heading(self, level: int, text: str, anchor: str | None = None) -> None:
        named = f'<a id="{anchor}"></a>' if anchor else ""
        self.blocks.append(f"{'#' * level} {named}{self.escape(text)}")

    def link(self, text: str, anchor: str) -> str:
        return f"[{self.escape(text)}](#{anchor})"

    def paragraph(self, text: str) -> str:
        return text

    def equation(self, latex: str, expr=None, text=None) -> None:
        self.blocks.append(f"$$\n{latex}\n$$")

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        lines = [header, ["---"] * len(header), *rows]
        return "\n".join("| " + " | ".join(r) + " |" for r in lines)

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(f"![{self.escape(alt)}]({path.name})")

    def finish(self, title: str) -> str:
        return "\n\n".join(self.blocks) + "\n"


class HtmlWriter(Writer):
    """One self-contained HTML file: formulas as MathML (rendered by the browser, with
    their LaTeX as an annotation), plots as embedded PNG images."""

    def escape(self, text: str) -> str:
        return html.escape(text, quote=True)

    def tex(self, expr: sp.Basic) -> str:
        return ""  # formulas are MathML here: no LaTeX to compute

    def formula(self, math: Math, display: bool = False) -> str:
        if math.expr is None:
            return self.math(math.latex)
        # a displayed formula shows its text below it; an inline one keeps it annotated
        note = None if display else math.text
        try:
            return mathml(math.expr, display=display, annotation=note, encoding="text/plain")
        except ValueError:
            return self.code(math.text or "")

    def math(self, latex: str) -> str:
        return f"<code>{self.escape(latex)}</code>"

    def code(self, text: str) -> str:
        return f"<code>{self.escape(text)}</code>"

    def heading(self, level: int, text: str, anchor: str | None = None) -> None:
        named = f' id="{anchor}"' if anchor else ""
        self.blocks.append(f"<h{level}{named}>{self.escape(text)}</h{level}>")

    def link(self, text: str, anchor: str) -> str:
        return f'<a href="#{anchor}">{self.escape(text)}</a>'

    def paragraph(self, text: str) -> str:
        return f"<p>{text}</p>"

    def equation(self, latex: str, expr=None, text=None) -> None:
        shown = self.formula(Math(latex, expr, text), display=True)
        source = f'<code class="source">{self.escape(text)}</code>' if text else ""
        self.blocks.append(f'<div class="display">{shown}{source}</div>')

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        head = "".join(f"<th>{h}</th>" for h in header)
        body = "\n".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
        return f"<table>\n<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody>\n</table>"

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(f"<figure>{_img(path.read_bytes(), alt, 'plot')}</figure>")

    def finish(self, title: str) -> str:
        body = "\n".join(self.blocks)
        return (
            '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
            f"<title>{self.escape(title)}</title>\n<style>{_CSS}</style>\n</head>\n"
            f"<body>\n{body}\n</body>\n</html>\n"
        )


_CSS = """
body { font-family: sans-serif; max-width: 60em; margin: 2em auto; line-height: 1.45; }
table { border-collapse: collapse; } th, td { border: 1px solid #bbb; padding: 0.2em 0.6em; }
.display { overflow-x: auto; margin: 0.6em 0 0.6em 2em; }
img.plot { max-width: 100%; } math[display="block"] { margin: 0.3em 0; }
code.source { display: block; color: #555; font-size: 0.85em; margin: 0 0 0.6em 2em; }
code { background: #f3f3f3; overflow-wrap: anywhere; }
"""


class TexWriter(Writer):
    """A LaTeX fragment to \\input (needs amsmath and graphicx); plots next to the file."""

    _HEADINGS = {1: "section", 2: "subsection", 3: "subsubsection", 4: "paragraph"}

    def escape(self, text: str) -> str:
        return latex.escape(text)

    def math(self, latex: str) -> str:
        return f"${latex}$"

    def code(self, text: str) -> str:
        return rf"\texttt{{{self.escape(text)}}}"

    def heading(self, level: int, text: str, anchor: str | None = None) -> None:
        command = self._HEADINGS.get(level, "paragraph")
        self.blocks.append(rf"\{command}*{{{self.escape(text)}}}")

    def paragraph(self, text: str) -> str:
        return text

    def equation(self, latex: str, expr=None, text=None) -> None:
        self.blocks.append(f"\\[\n{latex}\n\\]")

    def tabular(self, header: list[str], rows: list[list[str]]) -> str:
        lines = [" & ".join(r) + r" \\" for r in [header, *rows]]
        lines.insert(1, r"\hline")
        body = "\n".join(lines)
        spec = "l" * len(header)
        return f"\\begin{{tabular}}{{{spec}}}\n\\hline\n{body}\n\\hline\n\\end{{tabular}}"

    def image(self, path: Path, alt: str) -> None:
        self.blocks.append(
            f"\\begin{{center}}\n\\includegraphics[width=0.8\\linewidth]{{{path.name}}}\n"
            f"\\end{{center}}"
        )

    def finish(self, title: str) -> str:
        head = f"% {title}\n% Needs \\usepackage{{amsmath,graphicx}} in the preamble.\n"
        return head + "\n\n".join(self.blocks) + "\n"


WRITERS: dict[str, type[Writer]] = {"md": MarkdownWriter, "html": HtmlWriter, "tex": TexWriter}


@lru_cache(maxsize=4096)
def _latex(expr: sp.Basic) -> str:
    """``sympy.latex``, once per expression (reports of one run in several formats)."""
    return sp.latex(expr)


def _img(png: bytes, alt: str, css: str, scale: float = 1.0) -> str:
    """An <img> with the PNG inline as base64 (``scale`` < 1 for high-resolution formulas)."""
    width, height = struct.unpack(">II", png[16:24])
    data = base64.b64encode(png).decode("ascii")
    return (
        f'<img class="{css}" alt="{html.escape(alt, quote=True)}" '
        f'width="{round(width * scale)}" height="{round(height * scale)}" '
        f'src="data:image/png;base64,{data}">'
    )
