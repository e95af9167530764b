"""The case language: expressions (parser, printer, size limits), case files read into
``Case`` objects, and a corrected case written back out as a case file.

Builds on the domain model and the mechanics' symbols; never imports the audit, the
store or the presentation (``tests/test_layers.py``).
"""
