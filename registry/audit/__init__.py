"""The audit: the checks, the audit of one case with its repairs and numeric evidence,
the outcome of an audit as typed objects, time budgets and worker processes.

Builds on the mathematics and the case language; never imports the store or the
presentation (``tests/test_layers.py``).
"""

#: The names of the module ``registry.audit`` before it became this folder (they are in
#: ``case_audit`` now); old code that imports them from here still works.
_OLD_NAMES = ("audit_case", "failed_case", "count_checks", "claim_verdict")
_OLD_NAMES += ("DEFAULT_BUDGET", "CASE_CHECKS")


def __getattr__(name: str):
    """``registry.audit.audit_case`` and the old module's other names, with a
    DeprecationWarning naming their new module (see ``registry._moved``)."""
    if name not in _OLD_NAMES:
        raise AttributeError(f"module 'registry.audit' has no attribute {name!r}")
    import warnings

    from . import case_audit

    warnings.warn(
        f"registry.audit.{name} has moved: import it from registry.audit.case_audit",
        DeprecationWarning,
        stacklevel=2,
    )
    return getattr(case_audit, name)
