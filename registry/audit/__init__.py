"""The audit: the checks, the audit of one case with its corrections and numeric evidence,
the outcome of an audit as typed objects, time budgets and worker processes.

Builds on the mathematics and the case language; never imports the store or the
presentation (``tests/test_layers.py``).
"""
