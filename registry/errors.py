"""User-facing errors: one base class, one subclass per kind of mistake.

Each subclass also inherits the matching builtin, keeps the offending pieces
as fields and builds its message from them, so the CLI can print
``Error: <message>`` and a notebook user can inspect ``err.problems``.
"""

from __future__ import annotations

from dataclasses import dataclass


class RegistryError(Exception):
    """Base class of every error a user can cause."""


@dataclass(frozen=True)
class Problem:
    """One thing wrong in a case file: where (``field``), what was written, why."""

    field: str
    message: str
    text: str | None = None

    def __str__(self) -> str:
        where = f"{self.field}: " if self.field else ""
        shown = "" if self.text is None else f": {_quote(self.text)}"
        return f"{where}{self.message}{shown}"


def _quote(text: str, limit: int = 80) -> str:
    r"""Show user text in a message: repr-quoted and cut to a readable length.

    The cut counts the escapes too: a character repr escapes takes up to ten (a lone
    surrogate is '\udc81', a line separator '\u2028'), so that a text of them
    keeps its quote within about twice ``limit``, like one of quotes and backslashes.

    >>> _quote("\u2028" * 100) == repr("\u2028" * 26 + "...")
    True
    """
    cut = len(text) > limit
    if cut:
        text = text[: limit - 3]
    while len(repr(text + "..." * cut)) > 2 * limit + 2:
        text, cut = text[:-1], True
    return repr(text + "..." * cut)


class CaseFormatError(RegistryError, ValueError):
    """A case file breaks the format of docs/case-format.md; nothing of it is stored."""

    def __init__(self, file: str, problems: list[Problem]):
        self.file = file
        self.problems = list(problems)
        super().__init__(str(self))

    def __str__(self) -> str:
        file = printable(self.file)
        return "\n".join(f"{file}: {p}" for p in self.problems)


def printable(text: str) -> str:
    """``text`` with unprintable characters escaped (a file name may hold line breaks)."""
    return "".join(c if c.isprintable() else ascii(c)[1:-1] for c in text)


class ExpressionError(RegistryError, ValueError):
    """An expression outside the case-file language (no file context yet)."""

    def __init__(self, message: str, text: str):
        self.message = message
        self.text = text
        super().__init__(f"{message}: {_quote(text)}")


class WeightedFieldError(RegistryError, ValueError):
    """A vector field and weights that admit no Kovalevskaya analysis: a component that
    is not a polynomial in the variables, a weight that is not a positive integer, or
    terms whose shift makes x = c t^(-w) impossible (``mathematics.weighted``). Every
    problem is listed, each as a ``Problem`` naming the component or weight."""

    def __init__(self, problems: list[Problem]):
        self.problems = list(problems)
        super().__init__(str(self))

    def __str__(self) -> str:
        return "\n".join(str(p) for p in self.problems)


class ExponentError(RegistryError, ValueError):
    """A Kovalevskaya analysis that cannot be made as asked (``registry exponents``): a
    system that is not polynomial in its state or declares arbitrary functions, terms
    that dominate dx/dt under the weights, a weight for a vector the state does not have,
    a free name that is not a parameter, parameters left neither free nor fixed in a
    family. Each problem is a ``Problem`` naming the field and the text, reported with
    the case's ``file`` (its path, or its id when it is stored)."""

    def __init__(self, file: str, problems: list[Problem]):
        self.file = file
        self.problems = list(problems)
        super().__init__(str(self))

    def __str__(self) -> str:
        file = printable(self.file)
        return "\n".join(f"{file}: {p}" for p in self.problems)


class UnknownCaseError(RegistryError, LookupError):
    """A case id that the registry does not hold."""

    def __init__(self, case_id: str, known: list[str] | None = None):
        self.case_id = case_id
        self.known = known or []
        hint = ""
        if self.known:
            import difflib

            close = difflib.get_close_matches(case_id, self.known, n=1)
            if close:
                hint = f" (did you mean {close[0]!r}?)"
        super().__init__(f"no case with id {case_id!r} in the registry{hint}")

    def __str__(self) -> str:
        return self.args[0]


class UnknownClaimError(RegistryError, LookupError):
    """A claim label that a case does not have."""

    def __init__(self, case_id: str, label: str, known: list[str]):
        self.case_id, self.label, self.known = case_id, label, known
        super().__init__(
            f"case {case_id!r} has no claim {label!r} (its claims: {', '.join(known) or 'none'})"
        )

    def __str__(self) -> str:
        return self.args[0]


class UnknownRunError(RegistryError, LookupError):
    """An audit run number that the registry does not hold."""

    def __init__(self, run: int):
        self.run = run
        super().__init__(f"no audit run number {run} in the registry")

    def __str__(self) -> str:
        return self.args[0]


class DiscoveryError(RegistryError, ValueError):
    """An integral search that cannot be made as asked: a free name that is not a
    parameter, a system or level set that is not polynomial, an ansatz too large,
    a level set the flow does not keep."""


class StorageError(RegistryError, RuntimeError):
    """The database cannot be opened or written (missing, read-only, locked, full)."""


class DatabaseMissingError(StorageError, FileNotFoundError):
    """A command that reads the registry was pointed at a database file that does not exist."""

    def __init__(self, location: str):
        self.location = location
        super().__init__(
            f"no registry database at {location!r}; create one by adding cases "
            "(registry add FILES) or name another with --db"
        )


class ServerDatabaseMissingError(DatabaseMissingError):
    """A database server (PostgreSQL) has no database of that name. The registry never
    creates one there: that is the server administrator's job."""

    def __init__(self, location: str, database: str):
        self.location, self.database = location, database
        StorageError.__init__(
            self,
            f"the database server of {location!r} has no database {database!r}; creating "
            f"one is the server administrator's job (for example: createdb {database}), "
            "then 'registry add FILES' creates the registry's tables in it",
        )


class ServerUnavailableError(StorageError, ConnectionError):
    """The database server (PostgreSQL) cannot be reached: not running, wrong socket
    folder or host, starting up or shutting down, or out of connections."""

    def __init__(self, location: str, detail: str):
        self.location, self.detail = location, detail
        super().__init__(
            f"cannot reach the database server of {location!r} ({detail}); is the "
            "PostgreSQL server running, and are the host and socket folder in the URL right?"
        )


class DatabaseReadOnlyError(StorageError, PermissionError):
    """The database file (or its folder) cannot be written."""

    def __init__(self, location: str, doing: str = "write to it"):
        self.location = location
        super().__init__(
            f"database {location!r} is read-only, so the registry cannot {doing}; "
            "check the permissions of the file and of its folder"
        )


class DatabasePermissionError(DatabaseReadOnlyError):
    """The database server refuses this role what the registry asked (connecting, reading,
    writing or creating tables): the server's own words are kept in ``detail``."""

    def __init__(self, location: str, detail: str, role: str | None = None):
        self.location, self.detail, self.role = location, detail, role
        who = f"role {role!r}" if role else "this role"
        StorageError.__init__(
            self,
            f"the database server of {location!r} refuses {who}: {detail}; ask the "
            "server's administrator to grant the privileges the registry needs",
        )


class WritePrivilegeError(DatabasePermissionError):
    """A role that may only read the shared registry asked to change it (add, audit,
    survey, record a search): refused before anything is done, naming what it lacks."""

    def __init__(self, location: str, role: str | None, missing: str, doing: str):
        self.location, self.role, self.missing, self.doing = location, role, missing, doing
        self.detail = f"it lacks {missing}"
        who = f"role {role!r}" if role else "this role"
        grant = f"registry grant --writer {role}" if role else "registry grant --writer ROLE"
        StorageError.__init__(
            self,
            f"{who} may only read the registry at {location!r}, so it cannot {doing} (it "
            f"lacks {missing}); nothing was changed. A maintainer can allow it: {grant}",
        )


class SchemaOwnerError(DatabasePermissionError):
    """The shared registry's schema needs an upgrade that only the role owning its tables
    may make; other roles are refused before anything is changed."""

    def __init__(self, location: str, role: str | None, owner: str, found: str, needed: str):
        self.location, self.role, self.owner = location, role, owner
        self.detail = f"the schema is owned by {owner!r}"
        who = f"role {role!r}" if role else "this role"
        StorageError.__init__(
            self,
            f"the registry at {location!r} has schema revision {found} and this release "
            f"needs {needed}; only the owner of its tables, role {owner!r}, may upgrade it, "
            f"not {who} (any registry command the owner runs upgrades it, e.g. registry runs)",
        )


class RoleError(StorageError, ValueError):
    """A ``registry grant`` that cannot be made: no such role on the server, a role
    name that is not allowed, roles asked of an SQLite file, or a connection that does
    not own the registry's tables."""


class DatabaseFullError(StorageError, OSError):
    """The disk (or the database's size limit) is full; the transaction was rolled back."""

    def __init__(self, location: str):
        self.location = location
        super().__init__(
            f"the disk holding database {location!r} is full; nothing of this change was "
            "stored (free some space and run the command again)"
        )


class DatabaseLockedError(StorageError, TimeoutError):
    """Another process kept the database locked for longer than the registry waits."""

    def __init__(self, location: str, waited: float):
        self.location = location
        super().__init__(
            f"database {location!r} is locked by another process (waited {waited:g} s); "
            "run the command again when the other registry command has finished"
        )


class NotADatabaseError(StorageError):
    """The file exists but is not an SQLite database (or is damaged)."""

    def __init__(self, location: str, detail: str):
        self.location = location
        super().__init__(f"{location!r} is not a usable registry database ({detail})")


class SchemaTooNewError(StorageError):
    """The database was written by a newer release of the registry."""

    def __init__(self, location: str, found: str, supported: str):
        self.location = location
        super().__init__(
            f"database {location!r} has schema {found}, newer than this registry supports "
            f"({supported}); upgrade the registry package to open it"
        )


class CopyTargetNotEmptyError(StorageError):
    """``registry copy`` was pointed at a target that already holds a registry's rows:
    it fills only a new database or an empty registry, and changed nothing."""

    def __init__(self, location: str, holds: str):
        self.location, self.holds = location, holds
        super().__init__(
            f"the target {location!r} is not empty (it holds {holds}); registry copy fills "
            "only a new file or an empty database, so nothing was changed: name a new file, "
            "or an empty database on the server (createdb NAME)"
        )


class CopySameDatabaseError(StorageError, ValueError):
    """``registry copy`` was asked to copy a registry into itself."""

    def __init__(self, location: str):
        self.location = location
        super().__init__(
            f"source and target of the copy are the same database {location!r}; "
            "name another target (a new file, or an empty database on the server)"
        )


class CopyVerificationError(StorageError):
    """The rows ``registry copy`` wrote into the target do not verify, or differ from
    the source's: the copy was rolled back, and the target is as it was before. One
    line per problem (``problems``)."""

    def __init__(self, location: str, problems: list[str]):
        self.location, self.problems = location, list(problems)
        shown = self.problems[:20]
        if len(self.problems) > len(shown):
            shown.append(f"{len(self.problems) - len(shown)} more problems not listed")
        super().__init__(
            "\n".join(
                f"the copy into {location!r} was not committed (nothing was written): {p}"
                for p in shown
            )
        )


class SchedulerError(RegistryError):
    """A Dask scheduler that cannot be used (``--scheduler``, ``REGISTRY_SCHEDULER``)."""

    def __init__(self, address: str, message: str):
        self.address = address
        super().__init__(message)

    def __str__(self) -> str:
        return self.args[0]


class SchedulerAddressError(SchedulerError, ValueError):
    """A scheduler address that is neither ``PROTOCOL://HOST:PORT``, a scheduler file
    nor ``local:N``."""

    def __init__(self, address: str, reason: str):
        self.reason = reason
        super().__init__(
            address,
            f"bad Dask scheduler address {_quote(address)}: {reason} "
            "(expected tcp://HOST:PORT, a scheduler file FILE.json, or local:N for N local "
            "worker processes)",
        )


class SchedulerUnreachableError(SchedulerError, ConnectionError):
    """No Dask scheduler answered at the address within the time the registry waits."""

    def __init__(self, address: str, waited: float, detail: str = ""):
        self.waited = waited
        self.detail = detail
        why = f" ({detail})" if detail else ""
        super().__init__(
            address,
            f"no Dask scheduler answered at {_quote(address)} within {waited:g} s{why}; "
            "start one (dask scheduler) or check the address",
        )


class SchedulerSecurityError(SchedulerError, ConnectionError):
    """A Dask cluster that requires TLS and this command's TLS configuration do not fit:
    none given, a file it names is missing, or a certificate one side does not trust."""

    def __init__(self, address: str, problem: str, remedy: str):
        self.problem, self.remedy = problem, remedy
        super().__init__(address, f"Dask scheduler {_quote(address)}: {problem}; {remedy}")


class DaskMissingError(SchedulerError, ImportError):
    """``--scheduler`` was given but Dask distributed is not installed."""

    def __init__(self, address: str, missing: str = "distributed"):
        self.missing = missing
        super().__init__(
            address,
            f"--scheduler {_quote(address)} needs Dask distributed, which is not installed "
            f"(no module {missing!r}); install with pip install -e '.[dask]'",
        )


class SettingError(RegistryError, ValueError):
    """An environment variable meant to set a number of seconds (a time budget, the wait
    for a database lock) holds no positive number of seconds (``registry.settings``)."""

    def __init__(self, variable: str, text: str):
        self.variable, self.text = variable, text
        super().__init__(
            f"${variable} must be a positive number of seconds, not {text!r} "
            "(unset it for the built-in default)"
        )


class UsageError(RegistryError, ValueError):
    """Options that do not go together, or a value an option cannot take (``--jobs 0``,
    ``--jobs`` with ``--scheduler``)."""
