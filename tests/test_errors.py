"""User errors: one base class, each subclass also the matching builtin, its message
built from its fields (the CLI prints it after ``Error:``)."""

from __future__ import annotations

import pytest

from registry.errors import (
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
    UnknownClaimError,
    UnknownRunError,
    printable,
)


def test_a_case_format_error_lists_every_problem_with_its_file_and_field():
    err = CaseFormatError(
        "case.toml",
        [Problem("claims[0].kind", "unknown claim kind", "first"), Problem("", "no id")],
    )
    assert str(err).splitlines() == [
        "case.toml: claims[0].kind: unknown claim kind: 'first'",
        "case.toml: no id",
    ]
    assert isinstance(err, ValueError) and isinstance(err, RegistryError)
    assert err.file == "case.toml" and len(err.problems) == 2


def test_long_user_text_is_cut_and_unprintable_file_names_escaped():
    problem = Problem("title", "too long", "x" * 100)
    assert str(problem) == f"title: too long: '{'x' * 77}...'"
    assert printable("a\nb\x1b") == "a\\nb\\x1b"
    assert str(CaseFormatError("a\nb.toml", [Problem("", "bad")])) == "a\\nb.toml: bad"


def test_an_expression_error_keeps_its_message_and_text():
    err = ExpressionError("unknown name 'x'", "x + 1")
    assert (err.message, err.text, str(err)) == (
        "unknown name 'x'",
        "x + 1",
        "unknown name 'x': 'x + 1'",
    )
    assert isinstance(err, ValueError)


def test_unknown_names_suggest_the_closest_known_one():
    err = UnknownCaseError("yehia-2003-kovalevskaya", ["yehia-2003-kovalevskaya-b", "euler"])
    assert str(err) == (
        "no case with id 'yehia-2003-kovalevskaya' in the registry "
        "(did you mean 'yehia-2003-kovalevskaya-b'?)"
    )
    assert isinstance(err, LookupError)
    assert str(UnknownClaimError("c", "I9", ["I1", "I2"])) == (
        "case 'c' has no claim 'I9' (its claims: I1, I2)"
    )
    assert str(UnknownRunError(7)) == "no audit run number 7 in the registry"


@pytest.mark.parametrize(
    ("error", "builtin", "text"),
    [
        (DatabaseMissingError("r.sqlite"), FileNotFoundError, "no registry database at 'r.sqlite'"),
        (DatabaseReadOnlyError("r.sqlite"), PermissionError, "is read-only"),
        (DatabaseFullError("r.sqlite"), OSError, "is full; nothing of this change was stored"),
        (
            DatabaseLockedError("r.sqlite", 30),
            TimeoutError,
            "locked by another process (waited 30 s)",
        ),
        (NotADatabaseError("r.sqlite", "it is a folder"), StorageError, "(it is a folder)"),
        (SchemaTooNewError("r.sqlite", "revision 9", "revision 0003"), StorageError, "newer"),
    ],
)
def test_storage_errors_say_what_is_wrong_with_the_database(error, builtin, text):
    assert isinstance(error, StorageError) and isinstance(error, builtin)
    assert text in str(error) and "'r.sqlite'" in str(error)


SERVER = "postgresql+psycopg://reg@/registry?host=/run/pg"


@pytest.mark.parametrize(
    ("error", "builtin", "text"),
    [
        (
            ServerDatabaseMissingError(SERVER, "registry"),
            FileNotFoundError,
            "has no database 'registry'; creating one is the server administrator's job",
        ),
        (
            ServerUnavailableError(SERVER, "Connection refused"),
            ConnectionError,
            "cannot reach the database server of ",
        ),
        (
            DatabasePermissionError(SERVER, "permission denied for table cases", "reg"),
            PermissionError,
            "refuses role 'reg': permission denied for table cases; ask the server's",
        ),
    ],
)
def test_server_errors_say_what_the_server_refused_and_whose_job_it_is(error, builtin, text):
    assert isinstance(error, StorageError) and isinstance(error, builtin)
    assert text in str(error) and repr(SERVER) in str(error)
    assert error.location == SERVER
    # a read-only role is read-only: the registry still reads where it may not write
    assert isinstance(error, DatabaseReadOnlyError) == isinstance(error, DatabasePermissionError)
