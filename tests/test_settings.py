"""Every setting read from the environment, in one place (``registry/settings.py``): an
option beats its variable, which beats the default; one parser of seconds for all."""

from __future__ import annotations

import pytest

from registry import settings
from registry.errors import SettingError


def test_an_option_beats_its_variable_which_beats_the_default():
    env = {settings.DB_ENV: "/tmp/x.sqlite", settings.SCHEDULER_ENV: "local:2"}
    assert settings.database("given.sqlite", env) == "given.sqlite"
    assert settings.database(None, env) == "/tmp/x.sqlite"
    assert settings.database(None, {}) == str(settings.DEFAULT_DB)
    assert settings.scheduler("tcp://h:1", env) == "tcp://h:1"
    assert settings.scheduler(None, env) == "local:2"
    assert settings.scheduler(None, {settings.SCHEDULER_ENV: "  "}) is None  # empty: not given


@pytest.mark.parametrize(
    ("read", "variable", "default"),
    [
        (settings.check_seconds, settings.BUDGET_ENV, 5.0),
        (settings.corrections_seconds, settings.CORRECTIONS_BUDGET_ENV, 20.0),
        (settings.lock_timeout, settings.LOCK_TIMEOUT_ENV, 10.0),
    ],
)
def test_every_number_of_seconds_is_read_by_one_parser(read, variable, default):
    assert read({}) == default
    assert read({variable: " 2.5 "}) == 2.5
    for bad in ("soon", "0", "-1", "inf", "nan"):
        with pytest.raises(SettingError) as caught:
            read({variable: bad})
        assert str(caught.value) == (
            f"${variable} must be a positive number of seconds, not {bad!r} "
            "(unset it for the built-in default)"
        )
