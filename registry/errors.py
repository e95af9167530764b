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
    """Show user text in a message: repr-quoted and cut to a readable length."""
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return repr(text)


class CaseFormatError(RegistryError, ValueError):
    """A case file breaks the format of CASE_FORMAT.md; nothing of it is stored."""

    def __init__(self, file: str, problems: list[Problem]):
        self.file = file
        self.problems = list(problems)
        super().__init__(str(self))

    def __str__(self) -> str:
        return "\n".join(f"{self.file}: {p}" for p in self.problems)


class ExpressionError(RegistryError, ValueError):
    """An expression outside the case-file language (no file context yet)."""

    def __init__(self, message: str, text: str):
        self.message = message
        self.text = text
        super().__init__(f"{message}: {_quote(text)}")


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


class StorageError(RegistryError, RuntimeError):
    """The database cannot be opened or written (missing, read-only, locked, full)."""
