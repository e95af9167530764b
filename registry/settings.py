"""Every setting the registry reads from its environment, with its default, read here once.

A command-line option wins over its environment variable, which wins over the built-in
default. Each value is parsed by one parser of its kind (seconds, a database address, a
Dask scheduler address), so that a bad value is refused with the same message wherever
it is read.

| variable | meaning | default |
|---|---|---|
| ``REGISTRY_DB`` | the database: a file's path or a SQLAlchemy URL | ``data/registry.sqlite`` |
| ``REGISTRY_SCHEDULER`` | a Dask scheduler for audits and searches | the local worker pool |
| ``REGISTRY_BUDGET`` | seconds allowed to each check | 5 |
| ``REGISTRY_CORRECTIONS_BUDGET`` | seconds allowed to a case's corrections | 20 |
| ``REGISTRY_LOCK_TIMEOUT`` | seconds to wait for another command's lock | 10 |
| ``REGISTRY_CACHE`` | a folder for normal forms and drift images | ``~/.cache/registry`` |
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path

from .errors import SettingError

DB_ENV = "REGISTRY_DB"
SCHEDULER_ENV = "REGISTRY_SCHEDULER"
BUDGET_ENV = "REGISTRY_BUDGET"
CORRECTIONS_BUDGET_ENV = "REGISTRY_CORRECTIONS_BUDGET"
LOCK_TIMEOUT_ENV = "REGISTRY_LOCK_TIMEOUT"
CACHE_ENV = "REGISTRY_CACHE"

#: Where the registry lives when neither --db nor $REGISTRY_DB says otherwise.
DEFAULT_DB = Path("data") / "registry.sqlite"
#: Seconds allowed to one check, and to the corrections and conditions of one case.
DEFAULT_CHECK_SECONDS = 5.0
DEFAULT_CORRECTIONS_SECONDS = 20.0
#: Seconds an integral search may take by default (``registry discover --budget``).
DEFAULT_SEARCH_SECONDS = 300.0
#: Seconds each of a survey's searches may take by default (``registry survey
#: --budget``): a sweep of the catalog does not wait minutes on one system it cannot
#: finish (its record says where it stopped; ``registry discover`` takes longer).
DEFAULT_SURVEY_SECONDS = 60.0
#: Seconds a Kovalevskaya analysis may take by default (``registry exponents --budget``),
#: and the one made beside a search (``discover``, the survey) to combine the two: short,
#: as the main job makes one per case at every code version; one that runs out is
#: recorded as not decided, and ``registry exponents`` makes it again with its own budget.
DEFAULT_EXPONENT_SECONDS = 300.0
BESIDE_SEARCH_EXPONENT_SECONDS = 10.0
#: Seconds the identification of one case with the catalog may take by default
#: (``registry identify --budget``); the cases not compared by then are named, and a
#: later identification with more time compares them.
DEFAULT_IDENTIFY_SECONDS = 60.0
#: Seconds a command waits for another's lock on the database before it gives up.
DEFAULT_LOCK_TIMEOUT = 10.0


def _value(variable: str, environ: Mapping[str, str] | None) -> str:
    """The variable's value, stripped ("" where it is unset or empty: not given)."""
    return (os.environ if environ is None else environ).get(variable, "").strip()


def seconds(variable: str, text: str) -> float:
    """The positive, finite number of seconds ``text`` (the value of ``$variable``) says,
    or SettingError.

    >>> seconds("REGISTRY_BUDGET", "2.5")
    2.5
    """
    try:
        value = float(text)
    except ValueError:
        raise SettingError(variable, text) from None
    if not (value > 0 and math.isfinite(value)):
        raise SettingError(variable, text)
    return value


def seconds_of(variable: str, default: float, environ: Mapping[str, str] | None = None) -> float:
    """``$variable`` as seconds where it is set, else ``default``."""
    text = _value(variable, environ)
    return seconds(variable, text) if text else default


def check_seconds(environ: Mapping[str, str] | None = None) -> float:
    """Seconds allowed to each check: ``$REGISTRY_BUDGET``, else 5."""
    return seconds_of(BUDGET_ENV, DEFAULT_CHECK_SECONDS, environ)


def corrections_seconds(environ: Mapping[str, str] | None = None) -> float:
    """Seconds allowed to a case's corrections: ``$REGISTRY_CORRECTIONS_BUDGET``, else 20."""
    return seconds_of(CORRECTIONS_BUDGET_ENV, DEFAULT_CORRECTIONS_SECONDS, environ)


def lock_timeout(environ: Mapping[str, str] | None = None) -> float:
    """Seconds to wait for another command's lock: ``$REGISTRY_LOCK_TIMEOUT``, else 10."""
    return seconds_of(LOCK_TIMEOUT_ENV, DEFAULT_LOCK_TIMEOUT, environ)


def database(option: str | None = None, environ: Mapping[str, str] | None = None) -> str:
    """The database a command uses: ``option`` (--db), else ``$REGISTRY_DB``, else
    ``data/registry.sqlite``."""
    return option or _value(DB_ENV, environ) or str(DEFAULT_DB)


def cache_folder(environ: Mapping[str, str] | None = None) -> Path:
    """Where what is computed once is kept between commands (the catalog's normal forms
    for identification, per case version; a report's drift images, per curve):
    ``$REGISTRY_CACHE``, else ``~/.cache/registry``. Deleting it loses nothing but time."""
    given = _value(CACHE_ENV, environ)
    return Path(given) if given else Path.home() / ".cache" / "registry"


def scheduler(option: str | None = None, environ: Mapping[str, str] | None = None) -> str | None:
    """The Dask scheduler a command uses: ``option`` (--scheduler), else
    ``$REGISTRY_SCHEDULER``, else None (the local worker pool). An empty value counts as
    not given."""
    return option or _value(SCHEDULER_ENV, environ) or None
