"""What a verb that takes "a case file, a stored case's id, or a ``Case``" works on: the
case, and the stored version with the same content where the registry holds one (a
search or an analysis is recorded with that version, and reused from it)."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import UnknownCaseError
from ..language.casefile import load_case
from ..model import Case
from ..store.database import Store, StoredCase


def stored_target(store: Store, target: str | os.PathLike | Case) -> tuple[Case, StoredCase | None]:
    """The case ``target`` names and its stored version (None when not stored): a stored
    case's id is its latest version; a file or a ``Case`` is the version with the same
    content, if any. UnknownCaseError for an id the registry does not hold."""
    if isinstance(target, Case):
        case = target
    elif Path(target).is_file():
        case = load_case(target)
    else:
        (stored,) = store.case_versions([str(target)])
        return stored.parse(), stored
    try:
        versions = store.case_versions([case.id], latest_only=False)
    except UnknownCaseError:
        return case, None
    same = [s for s in versions if s.content_hash == case.content_hash]
    return case, (same[-1] if same else None)
