"""The registry of rigid-body integrability claims.

Load literature cases from TOML files, re-check every claimed integral of
motion symbolically, and query the verdicts with pandas::

    import registry
    reg = registry.open("data/registry.sqlite")
    reg.add("data/cases")
    reg.audit()
    reg.verdicts()
"""

from .api import AddResult, AuditReport, Registry, open_registry
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
from .presentation import notebook  # noqa: F401 - installs the Jupyter reprs of cases and audits

open = open_registry  # noqa: A001 - registry.open(path) reads like sqlite3.connect

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
    "audit_case",
    "load_case",
    "open",
    "open_registry",
    "parse_case_text",
]
