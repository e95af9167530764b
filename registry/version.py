"""The code version: the package's release and a digest of its sources.

Every audit run and search records it; a stored result is reused only by the same code
version, so any edit to the code (even without a release) makes the next run recompute.
"""

from __future__ import annotations

import hashlib
from functools import cache
from importlib import metadata
from pathlib import Path

#: The distribution's name on PyPI (``pip install rigid-body-registry``).
DISTRIBUTION = "rigid-body-registry"


def source_digest(folder: Path) -> str:
    """A digest of every Python source under ``folder``, sub-folders included.

    Each file contributes its path relative to ``folder`` (POSIX form) and its bytes,
    in sorted order; compiled files (``__pycache__``) are skipped. The migration
    scripts are Python files under the package, so a schema change counts too.
    """
    digest = hashlib.sha256()
    sources = (p for p in folder.rglob("*.py") if "__pycache__" not in p.parts)
    for source in sorted(sources, key=lambda p: p.relative_to(folder).as_posix()):
        data = source.read_bytes()
        name = source.relative_to(folder).as_posix().encode()
        digest.update(name + b"\0" + str(len(data)).encode() + b"\0" + data)
    return digest.hexdigest()


def release() -> str:
    """The installed package's version number (``0`` when it is not installed)."""
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "0"


@cache
def code_version() -> str:
    """This package's release and the first 12 hex digits of its sources' digest,
    as ``0.1.0+1a2b3c4d5e6f``: recorded with every run and search."""
    return f"{release()}+{source_digest(Path(__file__).parent)[:12]}"
