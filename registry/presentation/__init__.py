"""Presentation: what users read. The verdict table and the JSON document of an audit,
reports of a run (Markdown, HTML, LaTeX), exported tables and BibTeX, drift plots and
the notebook display.

Renders the domain objects the audit returns; computes nothing itself. Never imports
the CLI (``tests/test_layers.py``). A new report format is one more writer here.
"""
