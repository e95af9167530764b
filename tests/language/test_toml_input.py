"""Untrusted TOML (``registry/language/toml_input.py``): the content hash sees content,
not comments or layout; user text quoted in messages is cut and escaped."""

from __future__ import annotations

import hashlib

import pytest

from registry.errors import CaseFormatError
from registry.language.casefile import parse_case_text
from registry.language.toml_input import MAX_SHOWN, content_hash, cut, field_name, kind_of, quoted

FULL = """id = "hash-test"
title = "A case whose hash is taken"
[source]
citation = "X"
locator = "p. 343"
[system]
inertia = ["1", "1", "2"]
[[claims]]
label = "I"
kind = "casimir"
expression = "s"
"""


def test_content_hash_ignores_comments_and_layout():
    relaid = "# a comment\n\n" + FULL.replace("\n[", "\n\n   [").replace(
        'kind = "casimir"', 'kind    =    "casimir"   # the source says so'
    )
    assert relaid != FULL
    assert content_hash(relaid) == content_hash(FULL)
    assert parse_case_text(relaid).content_hash == parse_case_text(FULL).content_hash


def test_content_hash_sees_content():
    changed = FULL.replace('locator = "p. 343"', 'locator = "p. 344"')
    assert content_hash(changed) != content_hash(FULL)


def test_content_hash_is_sha256_of_canonical_json():
    text = 'b = 1\na = "\u00e9"  # note\n'
    canonical = '{"a":"\u00e9","b":1}'
    assert content_hash(text) == hashlib.sha256(canonical.encode("utf-8")).hexdigest()


def test_content_hash_of_bad_toml():
    with pytest.raises(CaseFormatError):
        content_hash("a = ")


def test_user_text_in_a_message_is_cut_escaped_and_named():
    assert kind_of(1.5) == "a float" and kind_of([]) == "an array" and kind_of(True) == "a boolean"
    assert field_name("parameters", "a b") == 'parameters."a b"'
    long = "x" * 100
    assert len(cut(long)) == MAX_SHOWN and cut(long).endswith("...")
    assert quoted("t\u0456tle") == "'t\\u0456tle'"  # a look-alike shown for what it is
    assert len(quoted("\U0001f600" * 50)) <= 2 * MAX_SHOWN + 4
