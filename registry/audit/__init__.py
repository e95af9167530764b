"""The audit: the checks, the audit of one case with its corrections and numeric evidence,
the outcome of an audit as typed objects, and the audit of many cases in parallel.

Builds on the mathematics, the case language and the execution layer (which runs its
workers); never imports the store or the presentation (``tests/test_layers.py``).
"""
