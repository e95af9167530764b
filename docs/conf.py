"""Sphinx configuration of the registry's documentation (``docs/``).

Build it with the ``docs`` extra, warnings as errors, as CI does (``.ci/run``)::

    python -m pip install -e '.[docs]'
    sphinx-build -W --keep-going -b html docs docs/_build/html
    sphinx-build -W -b linkcheck docs docs/_build/linkcheck   # internal links only

Why these tools:

* **Sphinx** is what numpy, scipy and sympy document themselves with: one toolchain a
  scientific-Python reader and contributor already knows, cross-references checked at
  build time (``-W`` turns a dead one into a failure), and HTML that needs no server.
* **MyST-Parser** reads Markdown, so the pages stay the Markdown they were in the README
  and in ``docs/case-format.md``: they read the same on GitHub, in an editor and on the
  built site, and the tests that check their examples (``tests/test_case_format_doc.py``,
  ``tests/test_docs_json.py``, ``tests/test_docs_examples.py``,
  ``tests/test_docs_links.py``) read the same files that Sphinx builds.
* **sphinx-click** writes the command-line reference from the click commands themselves
  (``registry.cli:main``): it cannot drift from ``registry --help``.

No external link is fetched: ``linkcheck_ignore`` skips every http(s) address, so the
``linkcheck`` builder checks the internal links and anchors only, without a network.
"""

from __future__ import annotations

import re

project = "Registry of rigid-body integrability claims"
author = "The registry developers"
copyright = "2026, The registry developers"

extensions = ["myst_parser", "sphinx_click"]

source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]

# Headings get GitHub's anchors (#a-first-case), so a link such as
# case-format.md#a-first-case works on GitHub and on the built site alike.
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

# Every reference must resolve: a dead one is a warning, and -W makes it an error.
nitpicky = True

# "--fresh" stays two hyphens, as the reader types it (no en dash)
smartquotes = False

html_theme = "alabaster"
html_title = project
html_theme_options = {"description": "every published claim re-checked symbolically"}

# The linkcheck builder checks internal links and anchors; no external address is
# fetched (CI has no network to spare, and a remote server's mood is no test of ours).
linkcheck_ignore = [r"https?://", r"mailto:"]


#: What reStructuredText would read as markup in a command's help (|gamma|^2, *, `, _).
RST_MARKUP = re.compile(r"([\\*`|_])")


def _help_as_text(app, ctx, lines: list[str]) -> None:
    """A command's help is plain text (what ``--help`` prints): sphinx-click hands it to
    reStructuredText, so escape its markup characters, keeping the ``| `` that starts
    each line of a paragraph click keeps as written (``\\b``)."""
    for i, line in enumerate(lines):
        bar = "| " if line.startswith("| ") else ""
        lines[i] = bar + RST_MARKUP.sub(r"\\\1", line[len(bar) :])


def setup(app):
    app.connect("sphinx-click-process-description", _help_as_text)
    app.connect("sphinx-click-process-epilog", _help_as_text)
