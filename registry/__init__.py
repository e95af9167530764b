"""The registry of rigid-body integrability claims.

Load literature cases from TOML files, re-check every claimed integral of
motion symbolically, and query the verdicts with pandas::

    import registry
    reg = registry.open("data/registry.sqlite")
    reg.add("data/cases")
    reg.audit()
    reg.verdicts()
"""

import importlib
from typing import TYPE_CHECKING, Any

#: Where each public name lives. They are imported on first use (PEP 562), so that
#: ``import registry`` and ``registry --help`` pay only for what they use.
_PUBLIC = {
    "AddResult": "api",
    "AuditReport": "api",
    "Registry": "api",
    "open_registry": "api",
    "open": "api",
    "analyse_exponents": "api",
    "audit_case": "audit.case_audit",
    "load_case": "language.casefile",
    "parse_case_text": "language.casefile",
    **{name: "model" for name in ("Case", "CaseAudit", "CheckResult", "Claim", "ClaimKind")},
    **{name: "model" for name in ("Verdict", "Witness")},
}
#: The errors are light (no sympy): imported with their module on first use too.
_ERRORS = (
    "CaseFormatError",
    "DatabaseFullError",
    "DatabaseLockedError",
    "DatabaseMissingError",
    "DatabasePermissionError",
    "DatabaseReadOnlyError",
    "ExpressionError",
    "NotADatabaseError",
    "Problem",
    "RegistryError",
    "SchemaTooNewError",
    "ServerDatabaseMissingError",
    "ServerUnavailableError",
    "StorageError",
    "UnknownCaseError",
    "UnknownRunError",
)

if TYPE_CHECKING:
    from .api import AddResult, AuditReport, Registry, analyse_exponents, open_registry
    from .api import open_registry as open  # noqa: A004 - registry.open reads like sqlite3.connect
    from .audit.case_audit import audit_case
    from .errors import (
        CaseFormatError,
        DatabaseFullError,
        DatabaseLockedError,
        DatabaseMissingError,
        DatabasePermissionError,
        DatabaseReadOnlyError,
        ExpressionError,
        NotADatabaseError,
        Problem,
        RegistryError,
        SchemaTooNewError,
        ServerDatabaseMissingError,
        ServerUnavailableError,
        StorageError,
        UnknownCaseError,
        UnknownRunError,
    )
    from .language.casefile import load_case, parse_case_text
    from .model import Case, CaseAudit, CheckResult, Claim, ClaimKind, Verdict, Witness


def __getattr__(name: str) -> Any:
    """A public name (``registry.open``, ``registry.Case``, ...), or a submodule
    (``registry.api``), imported on first use. Taking a name of the domain also
    installs the Jupyter reprs of cases and audits (``presentation.notebook``)."""
    if name in _ERRORS:
        value = getattr(importlib.import_module(".errors", __name__), name)
    elif name in _PUBLIC:
        module = importlib.import_module(f".{_PUBLIC[name]}", __name__)
        value = getattr(module, "open_registry" if name == "open" else name)
        importlib.import_module(".presentation.notebook", __name__)
    else:
        try:
            value = importlib.import_module(f".{name}", __name__)
        except ModuleNotFoundError as err:
            if err.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


__all__ = [
    "AddResult",
    "AuditReport",
    "Case",
    "CaseAudit",
    "CaseFormatError",
    "CheckResult",
    "Claim",
    "ClaimKind",
    "DatabaseFullError",
    "DatabaseLockedError",
    "DatabaseMissingError",
    "DatabasePermissionError",
    "DatabaseReadOnlyError",
    "ExpressionError",
    "NotADatabaseError",
    "Problem",
    "Registry",
    "RegistryError",
    "SchemaTooNewError",
    "ServerDatabaseMissingError",
    "ServerUnavailableError",
    "StorageError",
    "UnknownCaseError",
    "UnknownRunError",
    "Verdict",
    "Witness",
    "analyse_exponents",
    "audit_case",
    "load_case",
    "open",
    "open_registry",
    "parse_case_text",
]
