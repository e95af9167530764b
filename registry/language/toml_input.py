"""Untrusted TOML: a case file's bytes and text made safe to parse, and user text made
safe to show.

A case file is untrusted input. Before ``tomllib`` sees it, its size, encoding, nesting
and number literals are checked (the parser is quadratic in dotted keys, recursive in
arrays, and refuses long integers with a traceback); its content hash is that of the
parsed data (comments and layout do not count). User text quoted in a message is cut
and escaped, so that no message is longer than a line or shows something else than what
the file holds. The schema of a case is ``casefile``'s.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import stat
import tomllib
from collections.abc import Callable
from typing import Any

from ..errors import CaseFormatError, Problem
from .limits import MAX_DIGITS

#: Largest case file, in bytes.
MAX_FILE_BYTES = 1_000_000
#: Deepest nesting of arrays, inline tables and dotted keys in the TOML (``a.b.c``
#: is 3 levels); checked before the TOML parser runs, which is slow on deep keys.
MAX_TOML_DEPTH = 10
#: Longest piece of user text (a key, a name, a value) shown in a message.
MAX_SHOWN = 40
#: Control characters (C0, DEL, C1) and the Unicode bidirectional controls, which
#: can make text display as something else; with and without tab and line breaks.
_CONTROL = "\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069"
_CONTROLS = re.compile(f"[{_CONTROL}\t\n\r]")
_CONTROLS_BUT_LINE_BREAKS = re.compile(f"[{_CONTROL}]")


def content_hash(text: str) -> str:
    """sha256 (hex) of the canonical JSON of the TOML content: comments and layout do not count."""
    return hash_data(load_toml(text, "<string>"))


def hash_data(data: dict) -> str:
    canonical = json.dumps(
        data, sort_keys=True, ensure_ascii=False, separators=(",", ":"), default=str
    )
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()


def fail(file: str, message: str) -> CaseFormatError:
    """An error about the file as a whole."""
    return CaseFormatError(file, [Problem("", message)])


def read_text(path: str | os.PathLike, file: str) -> str:
    """The file's text: at most MAX_FILE_BYTES of UTF-8 (a leading BOM is dropped)."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    try:
        # Non-blocking, so that a named pipe or a device is refused instead of waited on.
        fd = os.open(path, flags)
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise fail(file, "not a regular file")
            with open(fd, "rb", closefd=False) as handle:
                data = handle.read(MAX_FILE_BYTES + 1)
        finally:
            os.close(fd)
    except OSError as err:
        raise fail(file, f"cannot read the file ({err.strerror or err})") from None
    if len(data) > MAX_FILE_BYTES:
        raise fail(file, f"the file is too large (more than {MAX_FILE_BYTES} bytes)")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise fail(
            file, f"the file is not UTF-8 text (byte 0x{data[err.start]:02x} at offset {err.start})"
        ) from None
    return text.removeprefix("\ufeff")


def load_toml(text: str, file: str) -> dict:
    """The TOML document in ``text``, or CaseFormatError naming the line and column."""
    if not isinstance(text, str):
        raise TypeError(f"a case file text must be a str, not {type(text).__name__}")
    try:
        size = len(text.encode("utf-8"))
    except UnicodeEncodeError as err:
        code = ord(text[err.start])
        raise fail(
            file,
            f"the text is not valid Unicode (lone surrogate U+{code:04X} at offset {err.start})",
        ) from None
    if size > MAX_FILE_BYTES:
        raise fail(file, f"the file is too large (more than {MAX_FILE_BYTES} bytes)")
    if not text.strip():
        raise fail(file, "the file is empty")
    shape = toml_shape_problem(text)
    if shape:
        raise fail(file, f"invalid TOML: {shape}")
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise fail(
            file, f"invalid TOML: nested too deeply (more than {MAX_TOML_DEPTH} levels)"
        ) from None
    except ValueError as err:  # TOMLDecodeError (or anything else tomllib refuses)
        raise fail(file, f"invalid TOML: {toml_message(str(err))}") from None


def toml_message(message: str) -> str:
    """tomllib's message, escaped and cut: the keys it quotes can be as long as the file."""
    whole = re.fullmatch(r"(.*?)((?: \(at line \d+, column \d+\))?)", message, re.S)
    assert whole is not None  # the pattern matches every text
    body, where = whole.groups()

    def escaped(text: str) -> str:
        return "".join(c if " " <= c <= "~" else ascii(c)[1:-1] for c in text)

    return escaped(cut(body, 100, shown=escaped)) + where


# Outside strings and comments: brackets, separators, dots and long digit runs.
_TOML_EVENT = re.compile(rf"[\"'#\[\]{{}}=,.\n]|(?<!\w)[0-9][0-9_]{{{MAX_DIGITS},}}")
_TOML_STRING_END = {
    '"': re.compile(r'\\.|["\n]', re.S),
    "'": re.compile(r"['\n]"),
    '"""': re.compile(r'\\.|"""', re.S),
    "'''": re.compile(r"'''"),
}


def toml_shape_problem(text: str) -> str | None:
    """Why ``text`` is too deep or has too long a number for the TOML parser, or None.

    A linear scan that skips strings and comments. tomllib takes quadratic time in
    the parts of a dotted key and recursion in nested arrays, and raises ValueError
    on integers of more than 4300 digits, so these are refused before it runs.
    """
    depth = dots = 0
    pos = 0
    while True:
        event = _TOML_EVENT.search(text, pos)
        if event is None:
            return None
        char, pos = event.group(), event.end()
        if char in "[{":
            depth += 1
            dots = 0
        elif char in "]}":
            depth = max(depth - 1, 0)
            dots = 0
        elif char in "=,\n":
            dots = 0
        elif char == ".":
            dots += 1
        elif char == "#":
            end = text.find("\n", pos)
            pos = len(text) if end < 0 else end
        elif char in "\"'":
            quote = text[pos - 1 : pos + 2] if text[pos : pos + 2] == char * 2 else char
            closed = string_end(text, pos + len(quote) - 1, quote)
            if closed is None:
                return None  # unterminated: tomllib says where
            pos = closed
        else:
            return f"number too long (more than {MAX_DIGITS} digits){at(text, event.start())}"
        if depth + dots > MAX_TOML_DEPTH:
            return f"nested too deeply (more than {MAX_TOML_DEPTH} levels){at(text, event.start())}"


def string_end(text: str, pos: int, quote: str) -> int | None:
    """Where the TOML string opened by ``quote`` just before ``pos`` ends, or None."""
    pattern = _TOML_STRING_END[quote]
    while True:
        found = pattern.search(text, pos)
        if found is None or found.group() == "\n":
            return None
        pos = found.end()
        if found.group()[0] != "\\":
            if len(quote) == 3:
                # A multi-line string may end with one or two quotes before its closing three.
                for _ in range(2):
                    pos += text.startswith(quote[0], pos)
            return pos


def at(text: str, pos: int) -> str:
    """' (at line L, column C)', as tomllib writes positions."""
    line = text.count("\n", 0, pos) + 1
    column = pos - text.rfind("\n", 0, pos)
    return f" (at line {line}, column {column})"


def kind_of(value: Any) -> str:
    """What kind of TOML value ``value`` is, for 'expected ..., found ...' messages."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a float"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    return "a date or time"


def field_name(parent: str, key: str) -> str:
    """The field name of ``key`` inside ``parent`` (quoted when it is no bare TOML key)."""
    key = cut(key, shown=json.dumps)
    shown = key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)
    return f"{parent}.{shown}" if parent else shown


def cut(text: str, limit: int = MAX_SHOWN, shown: Callable[[str], str] = str) -> str:
    """``text`` cut to ``limit`` characters for a message, and further while it would
    take more than twice that once ``shown`` (escaped: '\\U0001f600' takes ten)."""
    cut = len(text) > limit
    if cut:
        text = text[: limit - 3]
    while len(shown(text + "..." * cut)) > 2 * limit + 2:
        text, cut = text[:-1], True
    return text + "..." * cut


def quoted(text: str) -> str:
    """User text quoted for a message: cut, with anything but printable ASCII escaped.

    Escaping shows look-alikes for what they are: 'tіtle' (Cyrillic і) is 't\\u0456tle'.
    """
    return ascii(cut(text, shown=ascii))


def char_name(char: str) -> str:
    """One character for a message: 'D', or its code point when it is not printable ASCII."""
    return repr(char) if char.isascii() and char.isprintable() else f"U+{ord(char):04X}"


def control_problem(text: str, line_breaks: bool = False) -> str | None:
    """Why ``text`` may not be shown in a terminal, or None.

    Control characters (escape sequences) and bidirectional controls could make a
    listing show something else than what is stored; ``line_breaks`` allows tab and
    line breaks.
    """
    found = (_CONTROLS_BUT_LINE_BREAKS if line_breaks else _CONTROLS).search(text)
    return f"control character {char_name(found.group())} is not allowed" if found else None
