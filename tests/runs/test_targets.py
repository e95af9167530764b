"""What a verb works on (``registry/runs/targets.py``): a stored id is its latest version;
a file or a ``Case`` is the stored version with the same content, or none."""

from __future__ import annotations

import pytest

from registry.errors import UnknownCaseError
from registry.language.casefile import load_case, parse_case_text
from registry.runs.targets import stored_target
from registry.store.database import Store
from tests.helpers.samples import ZHUKOVSKY, case_file


def test_an_id_a_file_and_a_case_name_their_stored_versions(tmp_path):
    store = Store(tmp_path / "r.sqlite")
    path = case_file(ZHUKOVSKY)
    first = load_case(path)
    store.add_case(first)
    changed = path.read_text(encoding="utf-8").replace('title = "', 'title = "Second: ', 1)
    second = parse_case_text(changed, "second.toml")
    store.add_case(second)
    case, stored = stored_target(store, ZHUKOVSKY)
    assert stored is not None and stored.version == 2 and case.title == second.title
    case, stored = stored_target(store, path)  # the file: its own content, version 1
    assert stored is not None and stored.version == 1 and case.content_hash == first.content_hash
    other = parse_case_text(changed.replace("Second", "Third"), "third.toml")
    assert stored_target(store, other) == (other, None)  # not stored with this content
    with pytest.raises(UnknownCaseError):
        stored_target(store, "no-such-case")
    store.close()
